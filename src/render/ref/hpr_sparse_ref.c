/* SPDX-License-Identifier: MIT
 * The sparse HPR operator's copy step on the CPU: the twin of hpr_sparse_classify.comp
 * (docs/HPR.md, "Sparse operator"). */
#include <math.h>
#include <stdbool.h>

#include "render/ref/hpr_ref.h"

static bool is_point_label(float label)
{
    return label == STA_LABEL_VISIBLE || label == STA_LABEL_HIDDEN;
}

// Whether pixel (x, y) copies its anchors' label (into *out): as the shader. Only the
// anchors of the pixel's own kind (point or empty) count; at least one must, all of
// them must agree, and for a point each must lie within the depth tolerance.
static bool copies_anchors(const sta_image *position, const sta_image *full_label, int x, int y,
                           float *out)
{
    int w = full_label->width, h = full_label->height;
    int ax[2] = { x & ~1, 0 }, ay[2] = { y & ~1, 0 };
    int last_x = (w - 1) & ~1, last_y = (h - 1) & ~1;
    ax[1] = ax[0] + 2 * (x & 1) < last_x ? ax[0] + 2 * (x & 1) : last_x;
    ay[1] = ay[0] + 2 * (y & 1) < last_y ? ay[0] + 2 * (y & 1) : last_y;
    const float *own = sta_image_at(position, x, y);
    bool own_point = own[3] > 0.5f;
    float zp = -own[2], tau = STA_HPR_SPARSE_DEPTH_TAU * zp;
    float label = 0.0f;
    int count = 0;
    for (int j = 0; j < 2; j++) {
        for (int i = 0; i < 2; i++) {
            float anchor = *sta_image_at(full_label, ax[i], ay[j]);
            if (is_point_label(anchor) != own_point) {
                continue;
            }
            if (count == 0) {
                label = anchor;
            }
            if (anchor != label) {
                return false;
            }
            if (own_point && !(fabsf(-sta_image_at(position, ax[i], ay[j])[2] - zp) <= tau)) {
                return false;
            }
            count++;
        }
    }
    if (count == 0) {
        return false;
    }
    *out = label;
    return true;
}

int sta_hpr_ref_sparse_labels(const sta_image *position, const sta_image *full_label,
                              sta_image *out_label)
{
    int refined = 0;
    for (int y = 0; y < full_label->height; y++) {
        for (int x = 0; x < full_label->width; x++) {
            float label = *sta_image_at(full_label, x, y);
            if (((x | y) & 1) != 0 && !copies_anchors(position, full_label, x, y, &label)) {
                refined++;
            }
            *sta_image_at(out_label, x, y) = label;
        }
    }
    return refined;
}
