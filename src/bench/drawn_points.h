/* SPDX-License-Identifier: MIT
 * The points a view really drew, one per pixel: the point id target (node, index in the
 * node) read back after the geometry pass, decoded through the .strata reader at the
 * position the GPU drew (the node's quantisation). The Katz reference is fed these
 * instead of pixel centres unprojected at the depth buffer's depth (docs/KATZ.md,
 * "Which points are fed"). CPU only, no GL; one thread.
 */
#ifndef STA_BENCH_DRAWN_POINTS_H
#define STA_BENCH_DRAWN_POINTS_H

#include <stdint.h>

#include "bench/view_eval.h"
#include "core/camera.h"
#include "core/status.h"
#include "format/strata_reader.h"

/* Replaces each point's world position in `points` (made by sta_view_points_from_depth
 * from the same frame) by the position of the point drawn in its pixel. `ids` holds
 * (node, index) pairs, top row first, as sta_render_target_read_ids gives them. Errors
 * name `path`: STA_ERR_FORMAT when a pixel's id is no point of the file or the point does
 * not project into its pixel (ids of another view), the reader's errors, STA_ERR_NOMEM. */
sta_status sta_drawn_points_apply(const sta_strata_reader *reader, const char *path,
                                  const sta_camera *camera, const uint32_t *ids,
                                  sta_view_points *points, sta_error *err);

#endif
