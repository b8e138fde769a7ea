/* SPDX-License-Identifier: MIT
 * The views a benchmark renders: an orbit around the scene, a street-level
 * fly-through, or the keyframes of a viewer camera path. No GL.
 */
#ifndef STA_BENCH_BENCH_CAMERAS_H
#define STA_BENCH_BENCH_CAMERAS_H

#include <stddef.h>

#include "bench/bench_truth.h"
#include "core/camera.h"
#include "core/status.h"

/* `count` views of the box [min, max] from yaw 360 i / count degrees (plus 45), 30
 * degrees above the horizon, each framing the whole box (sta_camera_frame_box).
 * Width, height and fov come from `base`. out: `count` cameras. */
void sta_bench_orbit(const sta_camera *base, const double min[3], const double max[3], int count,
                     sta_camera *out);

/* `count` views at eye height 1.7 m above the box's floor (min z), spread from 10 % to
 * 90 % along its longest horizontal axis through the middle of the other, looking
 * along that axis and 5 degrees down. With a street truth (`truth` not NULL and its
 * gps_time span set) the views follow the synthetic scanner's path instead, 0.8 m
 * below the scanner head (1.7 m above the road), looking along the drive. */
void sta_bench_street(const sta_camera *base, const double min[3], const double max[3], int count,
                      sta_bench_truth *truth, sta_camera *out);

/* The views at each keyframe of a viewer camera path file. *out_cameras is owned by
 * the caller (sta_free). */
sta_status sta_bench_path_cameras(const char *path, const sta_camera *base,
                                  sta_camera **out_cameras, size_t *out_count, sta_error *err);

#endif
