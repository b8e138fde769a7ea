/* SPDX-License-Identifier: MIT
 * CPU twin of the geometry pass's rasterisers. */
#include "render/ref/raster_ref.h"

#include <math.h>
#include <stdbool.h>
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

// Window position of one axis snapped to 1 / 2^bits pixel.
static long snapped_of(float ndc, int size, int subpixel_bits)
{
    float half = (float)size * 0.5f;
    // llvmpipe's fused viewport transform, computed as the shader does (in double: the
    // product is exact, the sum rounds once, then the float).
    float window = (float)((double)ndc * (double)half + (double)half);
    float scale = (float)(1 << subpixel_bits);
    return (long)floorf(window * scale + 0.5f);
}

// Pixel whose centre lies in [x - 0.5, x + 0.5): floor((snapped - 1) / 2^bits), also
// for negative values.
static long centre_pixel(long snapped, int subpixel_bits)
{
    long s = snapped - 1;
    return s >= 0 ? s >> subpixel_bits : -((-s + (1L << subpixel_bits) - 1) >> subpixel_bits);
}

// Clip position of a camera-relative point, or false when outside the clip volume.
static bool clip_of(const sta_raster_ref_view *v, const float relative[3], float clip[4])
{
    float eye[4];
    const float position[4] = { relative[0], relative[1], relative[2], 1.0f };
    transform(v->view, position, eye);
    transform(v->projection, eye, clip);
    float w = clip[3];
    // Written as the shaders reject, so that a NaN behaves alike.
    return !(!(w > 0.0f) || fabsf(clip[0]) > w || fabsf(clip[1]) > w || clip[2] < 0.0f ||
             clip[2] > w);
}

long sta_raster_ref_project(const sta_raster_ref_view *v, const float relative[3], float *out_depth)
{
    float clip[4];
    if (!clip_of(v, relative, clip)) {
        return -1;
    }
    float inverse = 1.0f / clip[3];
    long x = centre_pixel(snapped_of(clip[0] * inverse, v->width_px, v->subpixel_bits),
                          v->subpixel_bits);
    long y = centre_pixel(snapped_of(clip[1] * inverse, v->height_px, v->subpixel_bits),
                          v->subpixel_bits);
    if (x < 0 || y < 0 || x >= v->width_px || y >= v->height_px) {
        return -1;
    }
    *out_depth = clip[2] * inverse;
    return x + y * (long)v->width_px;
}

void sta_raster_ref_node_rows(const sta_raster_ref_view *v, const float origin[3],
                              const float step[3], sta_raster_ref_rows *out)
{
    // m = projection * view * [diag(step) origin; 0 1], in double.
    double m[4][4];
    for (int r = 0; r < 4; r++) {
        double a[4]; // row r of projection * view (view: no translation)
        for (int j = 0; j < 4; j++) {
            a[j] = 0.0;
            for (int k = 0; k < 4; k++) {
                a[j] += (double)v->projection[4 * k + r] * (double)v->view[4 * j + k];
            }
        }
        m[r][3] = a[3];
        for (int j = 0; j < 3; j++) {
            m[r][j] = a[j] * (double)step[j];
            m[r][3] += a[j] * (double)origin[j];
        }
    }
    // Snapped window = floor(window * 2^bits + 0.5), window = (x / w) * h + h: the
    // numerator of the fraction over w is scale * h * x + (scale * h + 0.5) * w.
    double scale = (double)(1 << v->subpixel_bits);
    double hx = scale * (double)v->width_px * 0.5, hy = scale * (double)v->height_px * 0.5;
    const float *c = v->clip_plane;
    for (int j = 0; j < 4; j++) {
        out->x[j] = (float)(hx * m[0][j] + (hx + 0.5) * m[3][j]);
        out->y[j] = (float)(hy * m[1][j] + (hy + 0.5) * m[3][j]);
        out->w[j] = (float)m[3][j];
        out->plane[j] = j < 3 ? (float)((double)c[j] * (double)step[j]) : 0.0f;
    }
    out->z = (float)m[2][3];
    out->unused[0] = out->unused[1] = out->unused[2] = 0.0f;
    out->plane[3] = (float)((double)c[0] * (double)origin[0] + (double)c[1] * (double)origin[1] +
                            (double)c[2] * (double)origin[2] + (double)c[3]);
}

// One row at (q, 1), summed as the shader does.
static float row_at(const float r[4], const float q[3])
{
    float sum = r[0] * q[0];
    sum = sum + r[1] * q[1];
    sum = sum + r[2] * q[2];
    return sum + r[3];
}

long sta_raster_ref_project_rows(const sta_raster_ref_view *v, const sta_raster_ref_rows *rows,
                                 const float q[3], float *out_depth)
{
    if (row_at(rows->plane, q) < 0.0f) {
        return -1;
    }
    float w = row_at(rows->w, q);
    if (!(w > 0.0f)) {
        return -1;
    }
    float inverse = 1.0f / w;
    float depth = rows->z * inverse;
    float sx = row_at(rows->x, q) * inverse;
    float sy = row_at(rows->y, q) * inverse;
    float scale = (float)(1 << v->subpixel_bits);
    // Written as the shader rejects, so that a NaN behaves alike.
    if (!(depth >= 0.0f && depth <= 1.0f && sx >= 1.0f && sy >= 1.0f &&
          sx < scale * (float)v->width_px + 1.0f && sy < scale * (float)v->height_px + 1.0f)) {
        return -1;
    }
    long x = ((long)sx - 1) >> v->subpixel_bits, y = ((long)sy - 1) >> v->subpixel_bits;
    *out_depth = depth;
    return x + y * (long)v->width_px;
}

typedef struct raster_out {
    float *depth;
    uint32_t *ids;
} raster_out;

// Strictly greater: an equal depth keeps the earlier point (GL_GREATER).
static void keep(raster_out *out, long pixel, float depth, uint32_t slot, uint32_t index)
{
    if (depth > out->depth[pixel]) {
        out->depth[pixel] = depth;
        out->ids[2 * pixel] = slot;
        out->ids[2 * pixel + 1] = index;
    }
}

// The disk of one point (the rule in the header), as shaders/point_footprint.glsl.
static void draw_wide(const sta_raster_ref_view *v, const sta_raster_ref_node *node,
                      const float relative[3], uint32_t index, raster_out *out)
{
    const sta_raster_ref_footprint *f = &v->footprint;
    float clip[4];
    if (!clip_of(v, relative, clip)) {
        return;
    }
    int bits = v->subpixel_bits;
    float inverse = 1.0f / clip[3];
    float depth = clip[2] * inverse;
    long s[2] = { snapped_of(clip[0] * inverse, v->width_px, bits),
                  snapped_of(clip[1] * inverse, v->height_px, bits) };
    long c[2] = { centre_pixel(s[0], bits), centre_pixel(s[1], bits) };
    float radius = f->radius_px;
    if (f->adaptive) {
        radius = fminf(fmaxf(node->spacing * f->spacing_to_px * inverse, f->min_radius_px),
                       f->max_radius_px);
    }
    long r = (long)(radius * (float)(1 << bits));
    long r2 = r * r;
    long n = (long)radius + 1;
    float k = radius * f->depth_per_px;
    for (long oy = -n; oy <= n; oy++) {
        for (long ox = -n; ox <= n; ox++) {
            long px = c[0] + ox, py = c[1] + oy;
            if (px < 0 || py < 0 || px >= v->width_px || py >= v->height_px) {
                continue;
            }
            long dx = px * (1L << bits) + (1L << (bits - 1)) - s[0];
            long dy = py * (1L << bits) + (1L << (bits - 1)) - s[1];
            long d2 = dx * dx + dy * dy;
            if (d2 > r2 && (ox != 0 || oy != 0)) {
                continue;
            }
            float t = r2 > 0 ? 1.0f - fminf((float)d2 * (1.0f / (float)r2), 1.0f) : 0.0f;
            float scale = 1.0f / (1.0f - k * t);
            keep(out, px + py * (long)v->width_px, depth * scale, node->slot, index);
        }
    }
}

void sta_raster_ref_draw(const sta_raster_ref_view *v, const sta_raster_ref_node *nodes,
                         size_t node_count, float *depth, uint32_t *ids)
{
    size_t pixels = (size_t)v->width_px * (size_t)v->height_px;
    memset(depth, 0, pixels * sizeof(float));
    memset(ids, 0xFF, pixels * 2 * sizeof(uint32_t));
    raster_out out = { depth, ids };
    bool rows_rule = v->node_rows && !v->footprint.wide;
    for (size_t n = 0; n < node_count; n++) {
        const sta_raster_ref_node *node = &nodes[n];
        sta_raster_ref_rows rows;
        if (rows_rule) {
            sta_raster_ref_node_rows(v, node->origin, node->step, &rows);
        }
        for (uint32_t i = 0; i < node->count; i++) {
            const uint8_t *p = node->points + (size_t)i * 16;
            if (p[14] & v->hide_flags) {
                continue;
            }
            if (rows_rule) {
                float q[3], d;
                for (int axis = 0; axis < 3; axis++) {
                    q[axis] = (float)((uint32_t)p[2 * axis] | (uint32_t)p[2 * axis + 1] << 8);
                }
                long pixel = sta_raster_ref_project_rows(v, &rows, q, &d);
                if (pixel >= 0) {
                    keep(&out, pixel, d, node->slot, i);
                }
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
            if (v->footprint.wide) {
                draw_wide(v, node, relative, i, &out);
                continue;
            }
            float d;
            long pixel = sta_raster_ref_project(v, relative, &d);
            if (pixel >= 0) {
                keep(&out, pixel, d, node->slot, i);
            }
        }
    }
}
