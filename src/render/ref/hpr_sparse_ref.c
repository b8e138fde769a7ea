/* SPDX-License-Identifier: MIT
 * The sparse HPR operator's copy step on the CPU: the twin of hpr_sparse_classify.comp
 * (docs/HPR.md, "Sparse operator"). */
#include <math.h>
#include <stdbool.h>
#include <string.h>

#include "render/ref/hpr_ref.h"

static bool is_point_label(float label)
{
    return label == STA_LABEL_VISIBLE || label == STA_LABEL_HIDDEN;
}

// Whether grid pixel (gx, gy) of the grid with step `stride` copies its anchors' label
// (into *out), from `label`: as the shader. Only the anchors of the pixel's own kind
// (point or empty) count; at least one must, all of them must agree, and for a point
// each must lie within the depth tolerance.
static bool copies_anchors(const sta_image *position, const sta_image *label, int stride, int gx,
                           int gy, float *out)
{
    int grid_w = (label->width + stride - 1) / stride;
    int grid_h = (label->height + stride - 1) / stride;
    int ax[2] = { gx & ~1, 0 }, ay[2] = { gy & ~1, 0 };
    int last_x = (grid_w - 1) & ~1, last_y = (grid_h - 1) & ~1;
    ax[1] = ax[0] + 2 * (gx & 1) < last_x ? ax[0] + 2 * (gx & 1) : last_x;
    ay[1] = ay[0] + 2 * (gy & 1) < last_y ? ay[0] + 2 * (gy & 1) : last_y;
    const float *own = sta_image_at(position, gx * stride, gy * stride);
    bool own_point = own[3] > 0.5f;
    if (own_point && stride > 1) {
        return false; // the coarse step refines every point
    }
    float zp = -own[2], tau = STA_HPR_SPARSE_DEPTH_TAU * zp;
    float copied = 0.0f;
    int count = 0;
    for (int j = 0; j < 2; j++) {
        for (int i = 0; i < 2; i++) {
            int x = ax[i] * stride, y = ay[j] * stride;
            float anchor = *sta_image_at(label, x, y);
            if (is_point_label(anchor) != own_point) {
                continue;
            }
            if (count == 0) {
                copied = anchor;
            }
            if (anchor != copied) {
                return false;
            }
            if (own_point && !(fabsf(-sta_image_at(position, x, y)[2] - zp) <= tau)) {
                return false;
            }
            count++;
        }
    }
    if (count == 0) {
        return false;
    }
    *out = copied;
    return true;
}

// One copy step on the grid with step `stride`, in place in `label`.
static int copy_step(const sta_image *position, sta_image *label, int stride)
{
    int refined = 0;
    int grid_w = (label->width + stride - 1) / stride;
    int grid_h = (label->height + stride - 1) / stride;
    for (int gy = 0; gy < grid_h; gy++) {
        for (int gx = 0; gx < grid_w; gx++) {
            float *out = sta_image_at(label, gx * stride, gy * stride);
            if (((gx | gy) & 1) != 0 && !copies_anchors(position, label, stride, gx, gy, out)) {
                refined++; // keeps its full label
            }
        }
    }
    return refined;
}

int sta_hpr_ref_sparse_labels(const sta_image *position, const sta_image *full_label,
                              sta_image *out_label)
{
    memcpy(out_label->data, full_label->data,
           (size_t)full_label->width * (size_t)full_label->height * sizeof(float));
    // Within a step the pixels it writes are never anchors of each other (in place).
    int refined = 0;
    for (int step = sta_hpr_anchor_stride(position->height) / 2; step >= 1; step /= 2) {
        refined += copy_step(position, out_label, step);
    }
    return refined;
}
