/* SPDX-License-Identifier: MIT
 * Camera paths: keyframes recorded in the viewer, played back in the window, headless
 * or by strata-bench. No GL (it lives in render/ so the viewer and the benchmark
 * share it).
 *
 * File format (JSON):
 *   { "version": 1, "keyframes": [ { "time": 0.0, "position": [x, y, z],
 *     "yaw": deg, "pitch": deg, "fov": deg }, ... ] }
 * Positions are world coordinates (metres); times are seconds, increasing.
 */
#ifndef STA_RENDER_CAMERA_PATH_H
#define STA_RENDER_CAMERA_PATH_H

#include <stddef.h>

#include "core/camera.h"
#include "core/status.h"

/* How fast a constant-speed path turns where it does not move, degrees per second. */
#define STA_CAMERA_PATH_TURN_DEG_PER_S 45.0

typedef struct sta_keyframe {
    double time_s;
    double position[3];
    double yaw, pitch, fov_y; /* radians */
} sta_keyframe;

typedef struct sta_camera_path {
    sta_keyframe *keys; /* owned, time increasing */
    size_t count;
    size_t capacity;
} sta_camera_path;

/* Loads a path file. Errors name the file and what is wrong (STA_ERR_FORMAT). */
sta_status sta_camera_path_load(const char *path, sta_camera_path *out, sta_error *err);

/* Writes a path file. */
sta_status sta_camera_path_save(const char *path, const sta_camera_path *camera_path,
                                sta_error *err);

/* Appends the camera as a keyframe at `time_s` (must exceed the last key's time). */
sta_status sta_camera_path_add(sta_camera_path *camera_path, const sta_camera *camera,
                               double time_s, sta_error *err);

/* The camera at `time_s` (clamped to the path's span): a Catmull-Rom spline through the
 * positions that respects the keys' times (tangents are neighbour differences over
 * their time apart, so uneven key times do not jerk the speed), angles interpolated the short way
 * round. Viewport and near plane are left as they are in *camera. */
void sta_camera_path_sample(const sta_camera_path *camera_path, double time_s, sta_camera *camera);

/* Retimes the path for playback at a constant `speed_mps` along it: each segment lasts
 * its length along the spline divided by the speed, but at least as long as its turn
 * takes at STA_CAMERA_PATH_TURN_DEG_PER_S (so a turn on the spot still takes time), and
 * is replaced by 16 keys at equal lengths along the original spline, so the speed holds
 * inside segments too. The first key keeps its time. STA_ERR_ARG for a speed that is not
 * positive and finite. */
sta_status sta_camera_path_set_speed(sta_camera_path *camera_path, double speed_mps,
                                     sta_error *err);

/* Duration in seconds (0 for fewer than two keys). */
double sta_camera_path_duration(const sta_camera_path *camera_path);

void sta_camera_path_release(sta_camera_path *camera_path);

#endif
