/* SPDX-License-Identifier: MIT
 * CPU twin of shaders/normals_screen.comp and shaders/normals_smooth.comp: the same
 * samples, the same order of accumulation, the same thresholds, in float.
 *
 * Based on: D. Schiffner, M. Ritter, W. Benger, "Fast Normal Approximation of Point
 * Clouds in Screen Space", WSCG 2015, sec. 3.
 */
#include "render/ref/normals_screen_ref.h"

#include <float.h>
#include <math.h>
#include <stdbool.h>
#include <stdlib.h>

#include "core/eigen3.h"

/* The sampling schemes (docs/NORMALS.md): sample 0 is the centre, then groups of four
 * (two opposite pairs through the centre, the second pair a quarter turn
 * counter-clockwise from the first): diagonals at radius 1, axes at radius 1,
 * diagonals at 2, axes at 2, diagonals at 3, axes at 3. The N-sample scheme uses the
 * first N entries: 5 = 3x3 diagonals, 9 = full 3x3, 17 = 5x5 star, 25 = 7x7 star. */
static const int scheme[25][2] = {
    { 0, 0 },                                   // centre
    { -1, -1 }, { 1, 1 }, { 1, -1 }, { -1, 1 }, // radius 1 diagonals
    { -1, 0 },  { 1, 0 }, { 0, -1 }, { 0, 1 },  // radius 1 axes
    { -2, -2 }, { 2, 2 }, { 2, -2 }, { -2, 2 }, // radius 2 diagonals
    { -2, 0 },  { 2, 0 }, { 0, -2 }, { 0, 2 },  // radius 2 axes
    { -3, -3 }, { 3, 3 }, { 3, -3 }, { -3, 3 }, // radius 3 diagonals
    { -3, 0 },  { 3, 0 }, { 0, -3 }, { 0, 3 },  // radius 3 axes
};

/* PC's fans: unit directions counter-clockwise (x right, y up), scaled by the ring's
 * radius. The 5-sample scheme has only its four diagonals. */
static const int ring8[8][2] = { { 1, 0 },  { 1, 1 },   { 0, 1 },  { -1, 1 },
                                 { -1, 0 }, { -1, -1 }, { 0, -1 }, { 1, -1 } };
static const int ring4[4][2] = { { 1, 1 }, { -1, 1 }, { -1, -1 }, { 1, -1 } };

/* Thresholds shared with the shaders. */
#define MIN_SIN2         1e-6f  /* |sum of a x b|^2 must exceed this times sum |a|^2 |b|^2 */
#define MIN_TI_RATIO     1e-4f  /* TI: middle / largest eigenvalue below this = collinear */
#define MIN_TI_DISTANCE2 1e-30f /* TI: coincident samples (no direction) are skipped */
#define MIN_SMOOTH_LEN2  1e-6f  /* smoothing: |sum|^2 must exceed this times weight^2 */

typedef struct v3 {
    float x, y, z;
} v3;

static v3 sub(v3 a, v3 b)
{
    return (v3){ a.x - b.x, a.y - b.y, a.z - b.z };
}

static v3 add(v3 a, v3 b)
{
    return (v3){ a.x + b.x, a.y + b.y, a.z + b.z };
}

static v3 scale(v3 a, float s)
{
    return (v3){ a.x * s, a.y * s, a.z * s };
}

static float dot(v3 a, v3 b)
{
    return a.x * b.x + a.y * b.y + a.z * b.z;
}

static v3 cross(v3 a, v3 b)
{
    return (v3){ a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x };
}

/* One pixel's view of the position buffer. */
typedef struct pixel_ctx {
    const sta_image *position;
    float max_distance2;
    int x, y;
    v3 centre;
} pixel_ctx;

static v3 position_at(const sta_image *image, int x, int y)
{
    const float *p = sta_image_at(image, x, y);
    return (v3){ p[0], p[1], p[2] };
}

// The sample at the centre + (dx, dy) if it is inside the image, valid (w > 0) and
// within the maximum distance of the centre.
static bool fetch(const pixel_ctx *k, int dx, int dy, v3 *out)
{
    int qx = k->x + dx, qy = k->y + dy;
    *out = (v3){ 0, 0, 0 };
    if (qx < 0 || qy < 0 || qx >= k->position->width || qy >= k->position->height) {
        return false;
    }
    const float *p = sta_image_at(k->position, qx, qy);
    *out = (v3){ p[0], p[1], p[2] };
    v3 d = sub(*out, k->centre);
    return p[3] > 0.0f && dot(d, d) <= k->max_distance2;
}

// A unit normal from an accumulated vector n unless |n|^2 <= limit2 (degenerate);
// faced towards the camera at the origin.
static void finish(v3 n, float limit2, v3 centre, float out[4])
{
    float n2 = dot(n, n);
    if (!(n2 > limit2) || !(n2 <= FLT_MAX)) {
        return;
    }
    n = scale(n, 1.0f / sqrtf(n2));
    if (dot(n, centre) > 0.0f) {
        n = scale(n, -1.0f);
    }
    out[0] = n.x;
    out[1] = n.y;
    out[2] = n.z;
    out[3] = 1.0f;
}

// LD: forward differences to the right and upper neighbours (the dFdx / dFdy of a
// fragment shader), backward differences where the forward neighbour is missing.
static void normal_ld(const pixel_ctx *k, float out[4])
{
    v3 r, l, u, d;
    bool hr = fetch(k, 1, 0, &r), hl = fetch(k, -1, 0, &l);
    bool hu = fetch(k, 0, 1, &u), hd = fetch(k, 0, -1, &d);
    if (!(hr || hl) || !(hu || hd)) {
        return;
    }
    v3 dx = hr ? sub(r, k->centre) : sub(k->centre, l);
    v3 dy = hu ? sub(u, k->centre) : sub(k->centre, d);
    finish(cross(dx, dy), MIN_SIN2 * (dot(dx, dx) * dot(dy, dy)), k->centre, out);
}

// PD's direction through samples i and i + 1 (opposite each other): s_i - s_{i+1},
// or the half through the centre when one of them is missing.
static bool diameter(const pixel_ctx *k, int i, v3 *out)
{
    v3 a, b;
    bool ha = fetch(k, scheme[i][0], scheme[i][1], &a);
    bool hb = fetch(k, scheme[i + 1][0], scheme[i + 1][1], &b);
    *out = ha && hb ? sub(a, b) : (ha ? sub(a, k->centre) : sub(k->centre, b));
    return ha || hb;
}

// PD: n = sum over groups g of d_{4g+1} x d_{4g+3}, d_i = s_i - s_{i+1}.
static void normal_pd(const pixel_ctx *k, int samples, float out[4])
{
    v3 n = { 0, 0, 0 };
    float s = 0.0f;
    for (int g = 0; g < (samples - 1) / 4; g++) {
        v3 a, b;
        bool ha = diameter(k, 1 + 4 * g, &a);
        bool hb = diameter(k, 3 + 4 * g, &b);
        if (ha && hb) {
            n = add(n, cross(a, b));
            s += dot(a, a) * dot(b, b);
        }
    }
    finish(n, MIN_SIN2 * s, k->centre, out);
}

// PC: n = sum over consecutive counter-clockwise samples of (s_k - c) x (s_k+1 - c).
static void normal_pc(const pixel_ctx *k, int samples, float out[4])
{
    int rings = samples == 5 ? 1 : (samples - 1) / 8;
    int count = samples == 5 ? 4 : 8;
    const int(*dir)[2] = samples == 5 ? ring4 : ring8;
    v3 n = { 0, 0, 0 };
    float s = 0.0f;
    for (int r = 1; r <= rings; r++) {
        v3 first, prev;
        bool has_first = fetch(k, dir[0][0] * r, dir[0][1] * r, &first);
        bool has_prev = has_first;
        prev = first;
        for (int i = 1; i <= count; i++) {
            v3 cur = first;
            bool has_cur = has_first;
            if (i < count) {
                has_cur = fetch(k, dir[i][0] * r, dir[i][1] * r, &cur);
            }
            if (has_prev && has_cur) {
                v3 a = sub(prev, k->centre), b = sub(cur, k->centre);
                n = add(n, cross(a, b));
                s += dot(a, a) * dot(b, b);
            }
            prev = cur;
            has_prev = has_cur;
        }
    }
    finish(n, MIN_SIN2 * s, k->centre, out);
}

// TI: CM = sum_k w_k d_k d_k^T with d_k = c - s_k, w_k = 1 / |d_k|^2 (the paper's 1/N
// changes no eigenvector); the normal is the eigenvector of the smallest eigenvalue.
static void normal_ti(const pixel_ctx *k, int samples, float out[4])
{
    float m00 = 0, m01 = 0, m02 = 0, m11 = 0, m12 = 0, m22 = 0;
    int count = 0;
    for (int i = 1; i < samples; i++) {
        v3 sample;
        if (!fetch(k, scheme[i][0], scheme[i][1], &sample)) {
            continue;
        }
        v3 d = sub(k->centre, sample);
        float d2 = dot(d, d);
        if (!(d2 > MIN_TI_DISTANCE2)) {
            continue;
        }
        float inv = 1.0f / d2;
        m00 += d.x * d.x * inv;
        m01 += d.x * d.y * inv;
        m02 += d.x * d.z * inv;
        m11 += d.y * d.y * inv;
        m12 += d.y * d.z * inv;
        m22 += d.z * d.z * inv;
        count++;
    }
    if (count < 2) {
        return;
    }
    const float a[9] = { m00, m01, m02, m01, m11, m12, m02, m12, m22 };
    float w[3], v[3][3];
    sta_eigen3_sym_f(a, w, v);
    if (!(w[1] > MIN_TI_RATIO * w[2])) {
        return; // rank 1: all directions on one line, no plane
    }
    v3 n = { v[0][0], v[0][1], v[0][2] };
    if (dot(n, k->centre) > 0.0f) {
        n = scale(n, -1.0f);
    }
    out[0] = n.x;
    out[1] = n.y;
    out[2] = n.z;
    out[3] = 1.0f;
}

void sta_normals_screen_params_defaults(sta_normals_screen_params *config)
{
    if (config->method == STA_NORMALS_SCREEN_DEFAULT) {
        config->method = STA_NORMALS_SCREEN_DEFAULT_METHOD;
    }
    if (config->samples == 0) {
        config->samples = STA_NORMALS_SCREEN_DEFAULT_SAMPLES;
    }
}

sta_status sta_normals_screen_params_check(const sta_normals_screen_params *config, sta_error *err)
{
    int method = config->method, samples = config->samples;
    if (method < STA_NORMALS_SCREEN_DEFAULT || method > STA_NORMALS_SCREEN_TI) {
        return sta_fail(err, STA_ERR_ARG, "screen-space normals: unknown method %d", method);
    }
    if (samples != 0 && samples != 5 && samples != 9 && samples != 17 && samples != 25) {
        return sta_fail(err, STA_ERR_ARG,
                        "screen-space normals: samples %d is not a scheme (5, 9, 17 or 25)",
                        samples);
    }
    if (isnan(config->max_distance_m)) {
        return sta_fail(err, STA_ERR_ARG, "screen-space normals: max_distance_m is NaN");
    }
    return STA_OK;
}

float sta_normals_screen_max_distance2(const sta_view_params *view,
                                       const sta_normals_screen_params *config)
{
    float d = config->max_distance_m;
    if (d == 0.0f) {
        d = view->s0 > 0.0f ? STA_NORMALS_SCREEN_DEFAULT_DISTANCE_S0 * view->s0 : INFINITY;
    } else if (d < 0.0f) {
        d = INFINITY;
    }
    float d2 = d * d;
    return d2 <= FLT_MAX ? d2 : FLT_MAX;
}

const char *sta_normals_screen_method_name(int method)
{
    static const char *const names[] = { "?", "LD", "PD", "PC", "TI" };
    if (method == STA_NORMALS_SCREEN_DEFAULT) {
        method = STA_NORMALS_SCREEN_DEFAULT_METHOD;
    }
    return method > 0 && method < STA_NORMALS_SCREEN_METHOD_COUNT ? names[method] : "?";
}

// `params` through sta_normals_screen_params_check and _defaults.
static sta_status resolve(const sta_normals_screen_params *params, sta_normals_screen_params *out,
                          sta_error *err)
{
    *out = *params;
    sta_normals_screen_params_defaults(out);
    return sta_normals_screen_params_check(out, err);
}

static sta_status check_image(const sta_image *image, const sta_image *position, const char *what,
                              sta_error *err)
{
    if (image->channels != 4 || image->width != position->width ||
        image->height != position->height || !image->data) {
        return sta_fail(
            err, STA_ERR_ARG, "screen-space normals: %s image is %dx%dx%d, expected %dx%dx4", what,
            image->width, image->height, image->channels, position->width, position->height);
    }
    return STA_OK;
}

sta_status sta_normals_screen_ref(const sta_view_params *view,
                                  const sta_normals_screen_params *params,
                                  const sta_image *position, sta_image *out, sta_error *err)
{
    sta_normals_screen_params p;
    sta_status status = resolve(params, &p, err);
    if (status == STA_OK) {
        status = check_image(position, position, "position", err);
    }
    if (status == STA_OK) {
        status = check_image(out, position, "normal", err);
    }
    if (status != STA_OK) {
        return status;
    }
    pixel_ctx k = { position, sta_normals_screen_max_distance2(view, &p), 0, 0, { 0, 0, 0 } };
    for (k.y = 0; k.y < position->height; k.y++) {
        for (k.x = 0; k.x < position->width; k.x++) {
            float *o = sta_image_at(out, k.x, k.y);
            o[0] = o[1] = o[2] = o[3] = 0.0f;
            if (!(sta_image_at(position, k.x, k.y)[3] > 0.0f)) {
                continue;
            }
            k.centre = position_at(position, k.x, k.y);
            switch (p.method) {
            case STA_NORMALS_SCREEN_LD:
                normal_ld(&k, o);
                break;
            case STA_NORMALS_SCREEN_PD:
                normal_pd(&k, p.samples, o);
                break;
            case STA_NORMALS_SCREEN_PC:
                normal_pc(&k, p.samples, o);
                break;
            default:
                normal_ti(&k, p.samples, o);
                break;
            }
        }
    }
    return STA_OK;
}

sta_status sta_normals_smooth_ref(const sta_view_params *view,
                                  const sta_normals_screen_params *params,
                                  const sta_image *position, const sta_image *normal,
                                  sta_image *out, sta_error *err)
{
    sta_normals_screen_params p;
    sta_status status = resolve(params, &p, err);
    if (status == STA_OK) {
        status = check_image(position, position, "position", err);
    }
    if (status == STA_OK) {
        status = check_image(normal, position, "normal", err);
    }
    if (status == STA_OK) {
        status = check_image(out, position, "smoothed normal", err);
    }
    if (status == STA_OK && out->data == normal->data) {
        status = sta_fail(err, STA_ERR_ARG, "screen-space normals: smoothing cannot run in place");
    }
    if (status != STA_OK) {
        return status;
    }
    float max_distance2 = sta_normals_screen_max_distance2(view, &p);
    for (int y = 0; y < position->height; y++) {
        for (int x = 0; x < position->width; x++) {
            float *o = sta_image_at(out, x, y);
            o[0] = o[1] = o[2] = o[3] = 0.0f;
            if (!(sta_image_at(position, x, y)[3] > 0.0f)) {
                continue;
            }
            v3 c = position_at(position, x, y);
            v3 sum = { 0, 0, 0 };
            float weight = 0.0f;
            for (int dy = -1; dy <= 1; dy++) {
                for (int dx = -1; dx <= 1; dx++) {
                    int qx = x + dx, qy = y + dy;
                    if (qx < 0 || qy < 0 || qx >= position->width || qy >= position->height) {
                        continue;
                    }
                    const float *n = sta_image_at(normal, qx, qy);
                    v3 d = sub(position_at(position, qx, qy), c);
                    if (sta_image_at(position, qx, qy)[3] > 0.0f && n[3] > 0.0f &&
                        dot(d, d) <= max_distance2) {
                        float w = (float)((2 - abs(dx)) * (2 - abs(dy))); // 4, 2, 1
                        sum = add(sum, scale((v3){ n[0], n[1], n[2] }, w));
                        weight += w;
                    }
                }
            }
            finish(sum, MIN_SMOOTH_LEN2 * (weight * weight), c, o);
        }
    }
    return STA_OK;
}
