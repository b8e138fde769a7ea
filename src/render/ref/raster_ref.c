/* SPDX-License-Identifier: MIT
 * CPU twin of the geometry pass's rasterisers. */
#include "render/ref/raster_ref.h"

#include <math.h>
#include <string.h>

// column-major m * v, summed as the shader's matrix product: column 0 first.
static void transform(const float m[16], const float v[4], float out[4])
{
    for (int r = 0; r < 4; r++) {
        float sum = m[r] * v[0];
        sum = sum + m[4 + r] * v[1];
        sum = sum + m[8 + r] * v[2];
        sum = sum + m[12 + r] * v[3];
        out[r] = sum;
    }
}

// Pixel of one axis: window position snapped, then ceil - 1; -1 when outside.
static long pixel_of(float ndc, int size, int subpixel_bits)
{
    float half = (float)size * 0.5f;
    // llvmpipe's fused viewport transform, computed as the shader does (in double: the
    // product is exact, the sum rounds once, then the float).
    float window = (float)((double)ndc * (double)half + (double)half);
    float scale = (float)(1 << subpixel_bits);
    long snapped = (long)floorf(window * scale + 0.5f);
    // floor((snapped - 1) / 2^bits) for negative values too.
    long p = (snapped - 1) >= 0 ? (snapped - 1) >> subpixel_bits
                                : -((-(snapped - 1) + (1L << subpixel_bits) - 1) >> subpixel_bits);
    return p >= 0 && p < size ? p : -1;
}

long sta_raster_ref_project(const sta_raster_ref_view *v, const float relative[3], float *out_depth)
{
    float eye[4], clip[4];
    const float position[4] = { relative[0], relative[1], relative[2], 1.0f };
    transform(v->view, position, eye);
    transform(v->projection, eye, clip);
    float w = clip[3];
    if (!(w > 0.0f) || fabsf(clip[0]) > w || fabsf(clip[1]) > w || clip[2] < 0.0f || clip[2] > w) {
        return -1;
    }
    float inverse = 1.0f / w;
    long x = pixel_of(clip[0] * inverse, v->width_px, v->subpixel_bits);
    long y = pixel_of(clip[1] * inverse, v->height_px, v->subpixel_bits);
    if (x < 0 || y < 0) {
        return -1;
    }
    *out_depth = clip[2] * inverse;
    return x + y * (long)v->width_px;
}

void sta_raster_ref_draw(const sta_raster_ref_view *v, const sta_raster_ref_node *nodes,
                         size_t node_count, float *depth, uint32_t *ids)
{
    size_t pixels = (size_t)v->width_px * (size_t)v->height_px;
    memset(depth, 0, pixels * sizeof(float));
    memset(ids, 0xFF, pixels * 2 * sizeof(uint32_t));
    for (size_t n = 0; n < node_count; n++) {
        const sta_raster_ref_node *node = &nodes[n];
        for (uint32_t i = 0; i < node->count; i++) {
            const uint8_t *p = node->points + (size_t)i * 16;
            if (p[14] & v->hide_flags) {
                continue;
            }
            float relative[3];
            for (int axis = 0; axis < 3; axis++) {
                float q = (float)((uint32_t)p[2 * axis] | (uint32_t)p[2 * axis + 1] << 8);
                relative[axis] = node->origin[axis] + q * node->step[axis];
            }
            const float *c = v->clip_plane;
            if (c[0] * relative[0] + c[1] * relative[1] + c[2] * relative[2] + c[3] < 0.0f) {
                continue;
            }
            float d;
            long pixel = sta_raster_ref_project(v, relative, &d);
            // Strictly greater: an equal depth keeps the earlier point (GL_GREATER).
            if (pixel >= 0 && d > depth[pixel]) {
                depth[pixel] = d;
                ids[2 * pixel] = node->slot;
                ids[2 * pixel + 1] = i;
            }
        }
    }
}
