/* SPDX-License-Identifier: MIT
 * CPU twin of the pyramidal normal estimator: the same neighbourhoods, thresholds and
 * order of float operations as shaders/normals_pyramid_level.comp and
 * shaders/normals_pyramid_gather.comp.
 *
 * Based on: H. Bouchiba et al., Eurographics 2018, section 3.3.
 */
#include "render/ref/normals_pyramid_ref.h"

#include <math.h>
#include <stdbool.h>
#include <string.h>

void sta_normals_pyramid_params_defaults(sta_normals_pyramid_params *config)
{
    if (!(config->radius_s0 > 0.0f)) {
        config->radius_s0 = STA_NORMALS_PYRAMID_DEFAULT_RADIUS_S0;
    }
    if (!(config->jump_ratio >= 1.0f)) { // below 1 both neighbours could be dropped
        config->jump_ratio = STA_NORMALS_PYRAMID_DEFAULT_JUMP_RATIO;
    }
    if (!(config->plane_tolerance > 0.0f)) {
        config->plane_tolerance = STA_NORMALS_PYRAMID_DEFAULT_PLANE_TOLERANCE;
    }
    if (!(config->spread > 0.0f)) {
        config->spread = STA_NORMALS_PYRAMID_DEFAULT_SPREAD;
    }
    if (!(config->fine_spread > 0.0f)) {
        config->fine_spread = STA_NORMALS_PYRAMID_DEFAULT_FINE_SPREAD;
    }
}

static bool has_point(const sta_image *points, int x, int y)
{
    return x >= 0 && y >= 0 && x < points->width && y < points->height &&
           sta_image_at(points, x, y)[3] > 0.0f;
}

static float dot3(const float a[3], const float b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

// -1 where the normal n of the point p faces away from the camera at the origin, else
// 1. Edge-on, n . p is a tie within rounding: the shader (np_facing_sign in
// shaders/normals_exact.glsl) computes it `precise` in this order of terms, and C11
// without extensions does not contract a * b + c into an fma, so both break the tie
// identically (n . p == 0 keeps +n).
static float facing_sign(const float n[3], const float p[3])
{
    return dot3(n, p) > 0.0f ? -1.0f : 1.0f;
}

// d = a - b, the difference along one axis: central, one-sided or none. A neighbour
// more than sqrt(jump2) times as far from the point as the other one and as the
// texel's footprint (floor2 = its square) lies across a depth discontinuity: then the
// near side alone.
static bool difference(const sta_image *points, int x, int y, int dx, int dy, float jump2,
                       float floor2, float d[3])
{
    bool next = has_point(points, x + dx, y + dy), prev = has_point(points, x - dx, y - dy);
    const float *p = sta_image_at(points, x, y);
    if (next && prev) {
        const float *a = sta_image_at(points, x + dx, y + dy);
        const float *b = sta_image_at(points, x - dx, y - dy);
        float fa[3], fb[3];
        for (int k = 0; k < 3; k++) {
            fa[k] = a[k] - p[k];
            fb[k] = p[k] - b[k];
        }
        float la = dot3(fa, fa), lb = dot3(fb, fb);
        next = !(la > jump2 * fmaxf(lb, floor2));
        prev = !(lb > jump2 * fmaxf(la, floor2));
    }
    const float *a, *b;
    if (next && prev) {
        a = sta_image_at(points, x + dx, y + dy);
        b = sta_image_at(points, x - dx, y - dy);
    } else if (next) {
        a = sta_image_at(points, x + dx, y + dy);
        b = p;
    } else if (prev) {
        a = p;
        b = sta_image_at(points, x - dx, y - dy);
    } else {
        return false;
    }
    for (int k = 0; k < 3; k++) {
        d[k] = a[k] - b[k];
    }
    return true;
}

void sta_normals_pyramid_level_ref(const sta_image *points, float jump_ratio, float texel_m,
                                   sta_image *out)
{
    float jump2 = jump_ratio * jump_ratio;
    for (int y = 0; y < points->height; y++) {
        for (int x = 0; x < points->width; x++) {
            const float *p = sta_image_at(points, x, y);
            float *o = sta_image_at(out, x, y);
            o[0] = o[1] = o[2] = o[3] = 0.0f;
            float dx[3], dy[3];
            float footprint = texel_m * -p[2];
            float floor2 = footprint * footprint;
            if (!(p[3] > 0.0f) || !difference(points, x, y, 1, 0, jump2, floor2, dx) ||
                !difference(points, x, y, 0, 1, jump2, floor2, dy)) {
                continue;
            }
            // cross(dx, dy), in GLSL's order of terms.
            float n[3] = { dx[1] * dy[2] - dy[1] * dx[2], dx[2] * dy[0] - dy[2] * dx[0],
                           dx[0] * dy[1] - dy[0] * dx[1] };
            float n2 = dot3(n, n), dx2 = dot3(dx, dx), dy2 = dot3(dy, dy);
            // No normal from differences that are float noise (below ~3e-6 of the
            // point's distance: copies of one sample) or parallel (sin^2 below 1e-12).
            float min_d2 = 1e-11f * dot3(p, p);
            if (!(dx2 > min_d2 && dy2 > min_d2 && n2 > 1e-12f * dx2 * dy2)) {
                continue;
            }
            float len = sqrtf(n2);
            float s = facing_sign(n, p); // face the camera at the origin
            for (int k = 0; k < 3; k++) {
                o[k] = s * (n[k] / len);
            }
            o[3] = 1.0f;
        }
    }
}

// The level of detail of a normal radius of r_px pixels: lambda = log2(r_px) (at least
// 0, at most count - 1) split into its level (returned) and fraction *t. The level is
// the float's exponent, exact here and in the shader (np_level_of_detail in
// shaders/normals_exact.glsl), where log2 is an approximation: from log2 the level
// flipped where r_px lies within a few ulp of a power of 2.
static int level_of_detail(float r_px, int count, float *t)
{
    float x = fmaxf(r_px, 1.0f);
    int e;
    (void)frexpf(x, &e); // x = m * 2^e, m in [0.5, 1)
    int la = e - 1 < count - 1 ? e - 1 : count - 1;
    *t = la == count - 1 ? 0.0f : fminf(fmaxf(log2f(x) - (float)la, 0.0f), 1.0f);
    return la;
}

static int clamp_int(int v, int lo, int hi)
{
    return v < lo ? lo : (v > hi ? hi : v);
}

// Bilinear interpolation of level `normals` (scale 2^level, points `points`) at level-0
// pixel centre (x + 0.5, y + 0.5), skipping invalid texels and, at levels >= 1, texels
// whose tangent plane misses the pixel's point p by more than `tolerance_m` (step 3 of
// the header); false when nothing is left.
static bool level_normal(const sta_image *normals, const sta_image *points, int level, int x, int y,
                         const float p[3], float tolerance_m, float n[3])
{
    float s = (float)(1 << level);
    float u = ((float)x + 0.5f) / s - 0.5f, v = ((float)y + 0.5f) / s - 0.5f;
    float u0 = floorf(u), v0 = floorf(v);
    float fu = u - u0, fv = v - v0;
    int i0 = (int)u0, j0 = (int)v0;
    float acc[3] = { 0.0f, 0.0f, 0.0f };
    for (int b = 0; b < 2; b++) {
        for (int a = 0; a < 2; a++) {
            int i = clamp_int(i0 + a, 0, normals->width - 1);
            int j = clamp_int(j0 + b, 0, normals->height - 1);
            const float *m = sta_image_at(normals, i, j);
            if (!(m[3] > 0.0f)) {
                continue;
            }
            if (level > 0) {
                const float *q = sta_image_at(points, i, j);
                float off = dot3(m, p) - dot3(m, q);
                if (!(fabsf(off) <= tolerance_m)) {
                    continue;
                }
            }
            float bw = (a == 1 ? fu : 1.0f - fu) * (b == 1 ? fv : 1.0f - fv);
            for (int k = 0; k < 3; k++) {
                acc[k] += bw * m[k];
            }
        }
    }
    float a2 = dot3(acc, acc);
    if (!(a2 > 1e-12f)) {
        return false;
    }
    float len = sqrtf(a2);
    for (int k = 0; k < 3; k++) {
        n[k] = acc[k] / len;
    }
    return true;
}

// What steps 2-3 read: the view, the parameters and every level's points and normals.
typedef struct gather_input {
    const sta_view_params *view;
    const sta_pullpush_levels *levels;
    const sta_image *filled_position;
    const sta_image *normals; /* per level */
    int count;
    float radius_px_m, tolerance_m, coherence, fine_coherence;
} gather_input;

// How much of the coarser level two levels' normals with dot d may mix in: 1 where
// d >= coherence (1 - spread), falling linearly to 0 at 1 - 2 spread; 1 everywhere when
// the test is off (coherence <= -1). The shader's coherence_weight.
static float coherence_weight(float coherence, float d)
{
    if (coherence <= -1.0f) {
        return 1.0f;
    }
    float spread = 1.0f - coherence;
    float w = (d - (coherence - spread)) / spread;
    return w < 0.0f ? 0.0f : w > 1.0f ? 1.0f : w;
}

// The normal n made unit length and turned to face the camera at the origin (away
// from the pixel's point pt); false when n is (nearly) zero.
static bool orient_unit(const float n[3], const float pt[3], float o[3])
{
    float n2 = dot3(n, n);
    if (!(n2 > 1e-12f)) {
        return false;
    }
    float len = sqrtf(n2);
    float s = facing_sign(n, pt);
    for (int k = 0; k < 3; k++) {
        o[k] = s * (n[k] / len);
    }
    return true;
}

// Steps 2-3 at pixel (x, y), whose point pt has w > 0: the unit normal facing the camera,
// false where there is none.
static bool gather_pixel(const gather_input *g, int x, int y, const float pt[3], float o[3])
{
    const int count = g->count;
    float depth = fmaxf(-pt[2], g->view->near_m);
    float r_px = g->radius_px_m / depth;
    float t;
    int la = level_of_detail(r_px, count, &t);
    int lb = la + 1 < count ? la + 1 : la;
    float na[3], nb[3], n[3];
    const sta_image *pa = la == 0 ? g->filled_position : &g->levels->position[la];
    const sta_image *pb = lb == 0 ? g->filled_position : &g->levels->position[lb];
    float ta = g->tolerance_m * (float)(1 << la) * depth;
    float tb = g->tolerance_m * (float)(1 << lb) * depth;
    bool va = level_normal(&g->normals[la], pa, la, x, y, pt, ta, na);
    bool vb = level_normal(&g->normals[lb], pb, lb, x, y, pt, tb, nb);
    // No finer than the anchors' spacing: finer levels' noise showed as anchor-sized specks
    // at 1080p, and level 0 raised the street's share of normals off instead of lowering it.
    const int lf = la - 1;
    if (va && lf >= sta_normals_anchor_level(g->view->height_px) && g->fine_coherence > -1.0f) {
        // The finer level against the one below: where they disagree, la's texels reached
        // a crease or another surface that lf's do not, and la fades into lf.
        float nf[3];
        float tf = g->tolerance_m * (float)(1 << lf) * depth;
        if (level_normal(&g->normals[lf], &g->levels->position[lf], lf, x, y, pt, tf, nf)) {
            float w = coherence_weight(g->fine_coherence, dot3(na, nf));
            float m[3];
            for (int k = 0; k < 3; k++) {
                m[k] = w * na[k] + (1.0f - w) * nf[k];
            }
            float m2 = dot3(m, m);
            if (m2 > 1e-12f) { // opposite unit normals halfway: keep la's
                float len = sqrtf(m2);
                for (int k = 0; k < 3; k++) {
                    na[k] = m[k] / len;
                }
            }
        }
    }
    if (va && vb) {
        // The coarser level's share fades out as the two disagree (no seam at the switch).
        float tw = t * coherence_weight(g->coherence, dot3(na, nb));
        for (int k = 0; k < 3; k++) {
            n[k] = (1.0f - tw) * na[k] + tw * nb[k];
        }
    } else if (va || vb) {
        memcpy(n, va ? na : nb, sizeof(n)); // the finer one where the two disagree
    } else {
        // Both levels straddle a discontinuity here: the next finer level that has a
        // texel on the pixel's side.
        bool found = false;
        for (int l = la - 1; l >= 0 && !found; l--) {
            const sta_image *pl = l == 0 ? g->filled_position : &g->levels->position[l];
            float tl = g->tolerance_m * (float)(1 << l) * depth;
            found = level_normal(&g->normals[l], pl, l, x, y, pt, tl, n);
        }
        if (!found) {
            return false;
        }
    }
    return orient_unit(n, pt, o);
}

// Step 5 at pixel (x, y), whose point pt has w > 0; half: step 4's image (xyz normal,
// zero where none, w its plane offset).
static bool upsample_pixel(const gather_input *g, const sta_image *half, int x, int y,
                           const float pt[3], float o[3])
{
    float depth = fmaxf(-pt[2], g->view->near_m);
    float t;
    int lod = level_of_detail(g->radius_px_m / depth, g->count, &t);
    const int anchor_level = sta_normals_anchor_level(g->view->height_px);
    int level = lod > anchor_level ? lod : anchor_level;
    float tolerance = g->tolerance_m * (float)(1 << level) * depth;
    const int s = 1 << anchor_level;
    int i0 = x / s, j0 = y / s;
    float fu = (float)(x - s * i0) * (1.0f / (float)s),
          fv = (float)(y - s * j0) * (1.0f / (float)s);
    float n[3] = { 0.0f, 0.0f, 0.0f }, nearest[3] = { 0.0f, 0.0f, 0.0f };
    float nearest_off = 1e30f;
    for (int b = 0; b < 2; b++) {
        for (int a = 0; a < 2; a++) {
            int i = i0 + a < half->width ? i0 + a : half->width - 1;
            int j = j0 + b < half->height ? j0 + b : half->height - 1;
            const float *m = sta_image_at(half, i, j);
            float bw = (a == 1 ? fu : 1.0f - fu) * (b == 1 ? fv : 1.0f - fv);
            float off = fabsf(dot3(m, pt) - m[3]);
            bool valid = dot3(m, m) > 0.5f;
            if (valid && off <= tolerance) {
                for (int k = 0; k < 3; k++) {
                    n[k] += bw * m[k];
                }
            }
            if (valid && bw > 0.0f && off < nearest_off) {
                nearest_off = off;
                memcpy(nearest, m, sizeof(nearest));
            }
        }
    }
    if (!(dot3(n, n) > 1e-12f)) {
        memcpy(n, nearest, sizeof(n)); // no anchor on p's surface: the nearest plane's
    }
    return orient_unit(n, pt, o);
}

sta_status sta_normals_pyramid_ref(const sta_view_params *view,
                                   const sta_normals_pyramid_params *params,
                                   const sta_pullpush_levels *levels,
                                   const sta_image *filled_position, sta_image *out_normal,
                                   sta_error *err)
{
    int w = view->width_px, h = view->height_px;
    int count = sta_pullpush_level_count(w, h);
    if (count == 0 || levels->count != count || filled_position->width != w ||
        filled_position->height != h || filled_position->channels != 4 || out_normal->width != w ||
        out_normal->height != h || out_normal->channels != 4) {
        return sta_fail(err, STA_ERR_ARG,
                        "pyramidal normals: view %dx%d, pyramid of %d levels (expected %d), "
                        "filled %dx%d and normal %dx%d images do not match",
                        w, h, levels->count, count, filled_position->width, filled_position->height,
                        out_normal->width, out_normal->height);
    }
    sta_normals_pyramid_params p = params ? *params : (sta_normals_pyramid_params){ 0 };
    sta_normals_pyramid_params_defaults(&p);

    sta_image normals[STA_PULLPUSH_MAX_LEVELS], half = { 0 };
    memset(normals, 0, sizeof(normals));
    sta_status status = STA_OK;
    for (int l = 0; l < count && status == STA_OK; l++) {
        const sta_image *points = l == 0 ? filled_position : &levels->position[l];
        status = sta_image_init(&normals[l], points->width, points->height, 4, err);
        if (status == STA_OK) {
            sta_normals_pyramid_level_ref(points, p.jump_ratio,
                                          sta_normals_pyramid_texel_m(view, l), &normals[l]);
        }
    }
    gather_input g = { view,
                       levels,
                       filled_position,
                       normals,
                       count,
                       sta_normals_pyramid_radius_px_m(view, &p),
                       sta_normals_pyramid_plane_tolerance_m(view, &p),
                       sta_normals_pyramid_coherence(&p),
                       sta_normals_pyramid_fine_coherence(&p) };
    if (status == STA_OK && p.half_resolution) {
        const int s = 1 << sta_normals_anchor_level(h);
        status = sta_image_init(&half, (w + s - 1) / s, (h + s - 1) / s, 4, err);
        for (int j = 0; j < half.height && status == STA_OK; j++) {
            for (int i = 0; i < half.width; i++) {
                const float *pt = sta_image_at(filled_position, s * i, s * j);
                float *o = sta_image_at(&half, i, j);
                o[0] = o[1] = o[2] = o[3] = 0.0f;
                if (pt[3] > 0.0f && gather_pixel(&g, s * i, s * j, pt, o)) {
                    o[3] = dot3(o, pt);
                }
            }
        }
    }
    for (int y = 0; y < h && status == STA_OK; y++) {
        for (int x = 0; x < w; x++) {
            const float *pt = sta_image_at(filled_position, x, y);
            float *o = sta_image_at(out_normal, x, y);
            o[0] = o[1] = o[2] = o[3] = 0.0f;
            if (!(pt[3] > 0.0f)) {
                continue;
            }
            bool ok = p.half_resolution ? upsample_pixel(&g, &half, x, y, pt, o)
                                        : gather_pixel(&g, x, y, pt, o);
            o[3] = ok ? 1.0f : 0.0f;
            if (!ok) {
                o[0] = o[1] = o[2] = 0.0f;
            }
        }
    }
    sta_image_release(&half);
    for (int l = 0; l < count; l++) {
        sta_image_release(&normals[l]);
    }
    return status;
}
