/* SPDX-License-Identifier: MIT
 * Which pixels and drawn points each truth metric of one view scores. */
#include "bench/pixel_masks.h"

#include <math.h>
#include <stdbool.h>
#include <string.h>

#include "core/alloc.h"

void sta_pixel_masks_release(sta_pixel_masks *m)
{
    sta_free(m->sampled);
    sta_free(m->counted);
    sta_free(m->sampled_counted);
    sta_free(m->face_counted);
    sta_free(m->hpr_face);
    sta_free(m->hpr_face_glass);
    sta_free(m->hpr_volumetric);
    memset(m, 0, sizeof(*m));
}

sta_status sta_pixel_masks_compute(const sta_view_truth *v, const sta_camera *camera,
                                   const sta_view_points *points, double tolerance_m,
                                   const uint32_t *volumetric, int words, sta_pixel_masks *out,
                                   sta_error *err)
{
    memset(out, 0, sizeof(*out));
    const size_t n = (size_t)v->width * (size_t)v->height, bytes = n ? n : 1;
    out->sampled = sta_alloc_array(bytes, 1);
    out->sampled_counted = sta_alloc_array(bytes, 1);
    out->face_counted = sta_alloc_array(bytes, 1);
    out->hpr_face = sta_alloc_array(bytes, 1);
    out->hpr_face_glass = sta_alloc_array(bytes, 1);
    if (volumetric) {
        out->counted = sta_alloc_array(bytes, 1);
        out->hpr_volumetric = sta_alloc_array(bytes, 1);
    }
    if (!out->sampled || !out->sampled_counted || !out->face_counted || !out->hpr_face ||
        !out->hpr_face_glass || (volumetric && (!out->counted || !out->hpr_volumetric))) {
        sta_pixel_masks_release(out);
        return sta_fail(err, STA_ERR_NOMEM, "out of memory for the scored pixels of %dx%d",
                        v->width, v->height);
    }
    sta_status s = sta_view_truth_sampled(v, camera, points, tolerance_m, out->sampled, err);
    if (s == STA_OK) {
        // The raw face mask first: it decides the HPR face rule (the occluders' faces).
        s = sta_view_truth_face_sampled(v, camera, points, tolerance_m, out->face_counted, err);
    }
    if (s != STA_OK) {
        sta_pixel_masks_release(out);
        return s;
    }
    memset(out->hpr_face, 1, n);
    memset(out->hpr_face_glass, 1, n);
    for (size_t k = 0; k < points->count; k++) {
        uint32_t p = points->pixel[k];
        bool visible = points->visible[k];
        bool behind_glass = v->glass_depth_m && v->glass_depth_m[p] < v->depth_m[p];
        out->hpr_face[p] = visible || out->face_counted[p];
        out->hpr_face_glass[p] = out->hpr_face[p] && !(visible && behind_glass);
    }
    memcpy(out->sampled_counted, out->sampled, n);
    if (volumetric) {
        out->left_out = sta_view_truth_leave_out_classes(v, volumetric, words, out->counted,
                                                         out->sampled_counted);
        for (size_t i = 0; i < n; i++) {
            out->face_counted[i] = out->face_counted[i] && out->counted[i];
        }
        memset(out->hpr_volumetric, 1, n);
        for (size_t k = 0; k < points->count; k++) {
            uint32_t p = points->pixel[k];
            out->hpr_volumetric[p] = points->visible[k] || out->counted[p];
        }
    }
    return STA_OK;
}
