/* SPDX-License-Identifier: MIT
 * The splats method's errors (issue 12) on the same terms as the screen-space
 * pipeline's: depth from the splat frame's depth buffer (the surface the splats close,
 * as pull-push's filled buffer), unprojected as the pipeline unprojects; normals as
 * drawn, per pixel from the splat arena (render/splat_normals.h).
 */
#ifndef STA_BENCH_SPLAT_SCORE_H
#define STA_BENCH_SPLAT_SCORE_H

#include "bench/metrics.h"
#include "bench/view_eval.h"
#include "core/camera.h"
#include "core/status.h"
#include "render/scene.h"
#include "render/target.h"

/* Scores the splat frame in `target` (just rendered by `scene` from `camera`). */
sta_status sta_bench_score_splats(const sta_scene *scene, const sta_render_target *target,
                                  const sta_camera *camera, const sta_view_truth *view_truth,
                                  sta_error_summary *out_depth, sta_error_summary *out_normal,
                                  sta_error *err);

#endif
