/* SPDX-License-Identifier: MIT
 * Volumetric classes shown as points: the CPU twin. */
#include "render/ref/volumetric_ref.h"

#include <math.h>

#include "render/ref/screen_space.h"

// The class of the point drawn in pixel i, or -1 when there is none or the id is bad.
static int pixel_class(const sta_volumetric_input *in, size_t i)
{
    uint32_t slot = in->ids[2 * i], index = in->ids[2 * i + 1];
    if (slot >= in->node_count) {
        return -1; // includes the empty pixel's id (all ones)
    }
    uint32_t offset = in->nodes[2 * slot], count = in->nodes[2 * slot + 1];
    if (index >= count || offset >= in->arena_points || index >= in->arena_points - offset) {
        return -1;
    }
    return in->classes[offset + index];
}

// The pixel (x, y) of `im`, or NULL outside it.
static const float *at_or_null(const sta_image *im, int x, int y)
{
    return x >= 0 && y >= 0 && x < im->width && y < im->height ? sta_image_at(im, x, y) : NULL;
}

void sta_volumetric_mark_ref(const sta_volumetric_input *in, const sta_image *position,
                             const sta_image *colour, sta_image *label, sta_image *points)
{
    for (int y = 0; y < label->height; y++) {
        for (int x = 0; x < label->width; x++) {
            size_t i = (size_t)y * (size_t)label->width + (size_t)x;
            float *l = sta_image_at(label, x, y), *p = sta_image_at(points, x, y);
            const float *c = sta_image_at(colour, x, y), *q = sta_image_at(position, x, y);
            bool drawn =
                (*l == STA_LABEL_VISIBLE || *l == STA_LABEL_HIDDEN) && q[3] > 0.0f && q[2] < 0.0f;
            int cls = drawn ? pixel_class(in, i) : -1;
            bool marked = cls >= 0 && sta_volumetric_has_class(in->class_set, (uint32_t)cls);
            for (int k = 0; k < 4; k++) {
                p[k] = marked ? (k < 3 ? c[k] : -q[2]) : 0.0f;
            }
            if (marked) {
                *l = STA_LABEL_HIDDEN;
            } else if (drawn && *l == STA_LABEL_VISIBLE) {
                p[3] = q[2]; // an occluder: minus its distance
            }
        }
    }
}

void sta_volumetric_overlay_ref(const sta_image *points, sta_image *out)
{
    const int r = STA_VOLUMETRIC_SPLAT_RADIUS_PX;
    for (int y = 0; y < out->height; y++) {
        for (int x = 0; x < out->width; x++) {
            const float *best = NULL;
            float occluder = 0.0f;
            for (int dy = -r; dy <= r; dy++) {
                for (int dx = -r; dx <= r; dx++) {
                    const float *v = at_or_null(points, x + dx, y + dy);
                    if (!v) {
                        continue;
                    }
                    if (v[3] > 0.0f && (!best || v[3] < best[3])) {
                        best = v;
                    } else if (v[3] < 0.0f && (occluder <= 0.0f || -v[3] < occluder)) {
                        occluder = -v[3];
                    }
                }
            }
            if (!best || (occluder > 0.0f && occluder <= best[3])) {
                continue;
            }
            float *o = sta_image_at(out, x, y);
            for (int k = 0; k < 3; k++) {
                o[k] = fminf(fmaxf(best[k], 0.0f), 1.0f);
            }
            o[3] = 1.0f;
        }
    }
}
