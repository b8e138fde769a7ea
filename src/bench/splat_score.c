/* SPDX-License-Identifier: MIT
 * Splat frame errors: depth and normals against the per-pixel truth. */
#include "bench/splat_score.h"

#include "core/alloc.h"
#include "render/ref/unproject_ref.h"
#include "render/splat_normals.h"

// The target's depth as positions (camera space, w = 1 where drawn), GL row order.
static sta_status positions(const sta_render_target *target, const sta_camera *camera,
                            sta_image *out, sta_error *err)
{
    const int w = target->width_px, h = target->height_px;
    sta_image depth = { 0 };
    sta_status s = sta_image_init(&depth, w, h, 1, err);
    float *rows = s == STA_OK ? sta_alloc_array((size_t)w * (size_t)h, sizeof(float)) : NULL;
    if (s == STA_OK && !rows) {
        s = sta_fail(err, STA_ERR_NOMEM, "out of memory for a %dx%d depth buffer", w, h);
    }
    if (s == STA_OK) {
        s = sta_image_init(out, w, h, 4, err);
    }
    if (s == STA_OK) {
        sta_render_target_read_depth(target, rows); // top row first
        for (int y = 0; y < h; y++) {
            for (int x = 0; x < w; x++) {
                depth.data[(size_t)y * (size_t)w + (size_t)x] =
                    rows[(size_t)(h - 1 - y) * (size_t)w + (size_t)x];
            }
        }
        const sta_view_params view = { w, h, (float)camera->fov_y, (float)camera->near_m, 1.0f };
        sta_unproject_ref(&view, &depth, out);
    }
    sta_free(rows);
    sta_image_release(&depth);
    return s;
}

sta_status sta_bench_score_splats(const sta_scene *scene, const sta_render_target *target,
                                  const sta_camera *camera, const sta_view_truth *view_truth,
                                  sta_error_summary *out_depth, sta_error_summary *out_normal,
                                  sta_error *err)
{
    sta_image image = { 0 };
    sta_status s = positions(target, camera, &image, err);
    if (s == STA_OK) {
        s = sta_eval_depth(view_truth, &image, NULL, out_depth, err);
    }
    sta_image_release(&image);
    if (s == STA_OK) {
        s = sta_splat_normal_image(sta_scene_gpu_cache(scene), target, camera, &image, err);
    }
    if (s == STA_OK) {
        s = sta_eval_normals(view_truth, &image, NULL, out_normal, err);
    }
    sta_image_release(&image);
    return s;
}
