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

void sta_volumetric_mark_ref(const sta_volumetric_input *in, const sta_image *position,
                             const sta_image *colour, sta_image *label, sta_image *points)
{
    for (int y = 0; y < label->height; y++) {
        for (int x = 0; x < label->width; x++) {
            size_t i = (size_t)y * (size_t)label->width + (size_t)x;
            float *l = sta_image_at(label, x, y), *p = sta_image_at(points, x, y);
            const float *c = sta_image_at(colour, x, y), *q = sta_image_at(position, x, y);
            int cls = pixel_class(in, i);
            bool marked = cls >= 0 && (*l == STA_LABEL_VISIBLE || *l == STA_LABEL_HIDDEN) &&
                          q[3] > 0.0f && q[2] < 0.0f &&
                          sta_volumetric_has_class(in->class_set, (uint32_t)cls);
            for (int k = 0; k < 4; k++) {
                p[k] = marked ? (k < 3 ? c[k] : -q[2]) : 0.0f;
            }
            if (marked) {
                *l = STA_LABEL_HIDDEN;
            }
        }
    }
}

// The nearest marked point in the splat window around (x, y), or NULL.
static const float *nearest_point(const sta_image *points, int x, int y)
{
    const int r = STA_VOLUMETRIC_SPLAT_RADIUS_PX;
    const float *best = NULL;
    for (int dy = -r; dy <= r; dy++) {
        for (int dx = -r; dx <= r; dx++) {
            int u = x + dx, v = y + dy;
            if (u < 0 || v < 0 || u >= points->width || v >= points->height) {
                continue;
            }
            const float *p = sta_image_at(points, u, v);
            if (p[3] > 0.0f && (!best || p[3] < best[3])) {
                best = p;
            }
        }
    }
    return best;
}

// True when a visible point (of a class that is not volumetric: those are hidden
// after mark) in the splat window around (x, y) is at distance <= d.
static bool behind_surface(const sta_image *label, const sta_image *position, int x, int y, float d)
{
    const int r = STA_VOLUMETRIC_SPLAT_RADIUS_PX;
    for (int dy = -r; dy <= r; dy++) {
        for (int dx = -r; dx <= r; dx++) {
            int u = x + dx, v = y + dy;
            if (u < 0 || v < 0 || u >= label->width || v >= label->height) {
                continue;
            }
            if (*sta_image_at(label, u, v) == STA_LABEL_VISIBLE &&
                -sta_image_at(position, u, v)[2] <= d) {
                return true;
            }
        }
    }
    return false;
}

// Eye-dome lighting factor of a splat at distance `d` drawn in pixel (x, y).
static float edl_shade(const sta_image *position, int x, int y, float d)
{
    float response = 0.0f;
    for (int dy = -1; dy <= 1; dy++) {
        for (int dx = -1; dx <= 1; dx++) {
            int u = x + dx, v = y + dy;
            if ((dx == 0 && dy == 0) || u < 0 || v < 0 || u >= position->width ||
                v >= position->height) {
                continue;
            }
            const float *o = sta_image_at(position, u, v);
            if (o[3] > 0.0f && o[2] < 0.0f) {
                response += fmaxf(0.0f, log2f(d) - log2f(-o[2]));
            }
        }
    }
    return expf(-STA_VOLUMETRIC_EDL_STRENGTH * response / 8.0f);
}

void sta_volumetric_overlay_ref(const sta_image *points, const sta_image *label,
                                const sta_image *position, sta_image *out)
{
    for (int y = 0; y < out->height; y++) {
        for (int x = 0; x < out->width; x++) {
            const float *p = nearest_point(points, x, y);
            if (p && !behind_surface(label, position, x, y, p[3])) {
                float *o = sta_image_at(out, x, y), shade = edl_shade(position, x, y, p[3]);
                for (int k = 0; k < 3; k++) {
                    o[k] = fminf(fmaxf(p[k] * shade, 0.0f), 1.0f);
                }
                o[3] = 1.0f;
            }
        }
    }
}
