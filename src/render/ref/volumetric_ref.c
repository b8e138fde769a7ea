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

void sta_volumetric_mark_ref(const sta_volumetric_input *in, sta_image *position)
{
    for (int y = 0; y < position->height; y++) {
        for (int x = 0; x < position->width; x++) {
            size_t i = (size_t)y * (size_t)position->width + (size_t)x;
            float *q = sta_image_at(position, x, y);
            if (!(q[3] > 0.0f && q[2] < 0.0f)) {
                continue; // no point drawn here
            }
            int cls = pixel_class(in, i);
            if (cls >= 0 && sta_volumetric_has_class(in->class_set, (uint32_t)cls)) {
                q[3] = STA_POSITION_W_MARKED;
            }
        }
    }
}

void sta_volumetric_overlay_ref(const sta_image *position, const sta_image *colour, sta_image *out)
{
    const int r = STA_VOLUMETRIC_SPLAT_RADIUS_PX;
    for (int y = 0; y < out->height; y++) {
        for (int x = 0; x < out->width; x++) {
            float best = 0.0f, occluder = 0.0f;
            int bx = x, by = y;
            for (int dy = -r; dy <= r; dy++) {
                for (int dx = -r; dx <= r; dx++) {
                    const float *v = at_or_null(position, x + dx, y + dy);
                    if (!v || !(v[3] > 0.0f && -v[2] > 0.0f)) {
                        continue;
                    }
                    float d = -v[2];
                    if (v[3] == STA_POSITION_W_MARKED) {
                        if (best <= 0.0f || d < best) {
                            best = d;
                            bx = x + dx;
                            by = y + dy;
                        }
                    } else if (occluder <= 0.0f || d < occluder) {
                        occluder = d;
                    }
                }
            }
            if (!(best > 0.0f) || (occluder > 0.0f && occluder <= best)) {
                continue;
            }
            float *o = sta_image_at(out, x, y);
            const float *c = sta_image_at(colour, bx, by);
            for (int k = 0; k < 3; k++) {
                o[k] = sta_unorm8(c[k]);
            }
            o[3] = 1.0f;
        }
    }
}
