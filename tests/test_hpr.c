/* SPDX-License-Identifier: MIT
 * The HPR pass on llvmpipe against its CPU twin (labels and pyramid levels), against
 * known truth (a near plane in front of a far plane, rendered one pixel per point with
 * gaps), on hard cases (empty, one point, full planes, 1x1 and odd sizes, the near
 * plane and 1e5 m, coincident points), and pyramidal against exhaustive. */
#include "test_support.h"

#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/alloc.h"
#include "render/bindings.h"
#include "render/gl.h"
#include "render/gl_image.h"
#include "render/gl_staged.h"
#include "render/pass_hpr.h"
#include "render/ref/hpr_ref.h"

static sta_gl_headless gl;
static sta_hpr_pass pass;

static int setup(void **state)
{
    (void)state;
    sta_error err = { 0 };
    if (sta_gl_headless_create(&gl, &err) != STA_OK || sta_hpr_pass_init(&pass, &err) != STA_OK) {
        fprintf(stderr, "%s\n", err.message);
        return -1;
    }
    return 0;
}

static int teardown(void **state)
{
    (void)state;
    sta_hpr_pass_release(&pass);
    sta_gl_headless_destroy(&gl);
    return 0;
}

/* ---- buffers ---- */

static uint64_t rng_state;

static double rng_uniform(void)
{
    rng_state = rng_state * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(rng_state >> 11) / 9007199254740992.0;
}

static sta_view_params make_view(int w, int h)
{
    sta_view_params view = { w, h, 0.8f, 0.05f, 0.025f };
    return view;
}

// The camera-space point at `depth` on the ray through pixel (px, py)'s centre, as
// the unproject pass makes it.
static void set_point(const sta_view_params *view, sta_image *position, int px, int py, float depth)
{
    float tan_y = tanf(0.5f * view->fov_y);
    float tan_x = tan_y * (float)view->width_px / (float)view->height_px;
    float ndc_x = ((float)px + 0.5f) / (float)view->width_px * 2.0f - 1.0f;
    float ndc_y = ((float)py + 0.5f) / (float)view->height_px * 2.0f - 1.0f;
    float *p = sta_image_at(position, px, py);
    p[0] = ndc_x * tan_x * depth;
    p[1] = ndc_y * tan_y * depth;
    p[2] = -depth;
    p[3] = 1.0f;
}

static void new_image(sta_image *image, int w, int h, int channels)
{
    sta_error err = { 0 };
    assert_int_equal(sta_image_init(image, w, h, channels, &err), STA_OK);
}

// Points on a fraction `fill` of the pixels, log-uniform depths in [0.5, 200] m.
static void make_random(const sta_view_params *view, uint64_t seed, double fill, sta_image *out)
{
    new_image(out, view->width_px, view->height_px, 4);
    rng_state = seed;
    for (int y = 0; y < view->height_px; y++) {
        for (int x = 0; x < view->width_px; x++) {
            double u = rng_uniform(), v = rng_uniform();
            if (u < fill) {
                set_point(view, out, x, y, (float)(0.5 * pow(400.0, v)));
            }
        }
    }
}

// Every pixel a point of the plane through (0, 0, -depth) whose normal is tilted by
// `tilt` radians from +z about the x axis.
static void make_plane(const sta_view_params *view, float depth, float tilt, sta_image *out)
{
    new_image(out, view->width_px, view->height_px, 4);
    float tan_y = tanf(0.5f * view->fov_y);
    for (int y = 0; y < view->height_px; y++) {
        for (int x = 0; x < view->width_px; x++) {
            float ndc_y = ((float)y + 0.5f) / (float)view->height_px * 2.0f - 1.0f;
            // ray (.., ndc_y tan_y, -1) t meets n.(p - p0) = 0, n = (0, sin, cos)
            float s = sinf(tilt), c = cosf(tilt);
            float t = depth * c / (c - s * ndc_y * tan_y);
            set_point(view, out, x, y, t);
        }
    }
}

/* The known-truth scene: a near rectangle (z = -5, x in [-1.5, 1.5], y in [-1, 1])
 * partly covering a far rectangle (z = -20, |x| <= 8, |y| <= 6), both sampled on
 * jittered grids whose spacing projects to ~1.4 px (s0 = 0.025 m at 5 m, 0.1 m at
 * 20 m), drawn one pixel per point with a depth test: pixels without a point remain
 * between samples, and far points show through the gaps of the near plane. */
enum truth {
    T_NEAR,       // a near-plane point: visible
    T_FAR_OPEN,   // a far-plane point outside the near rectangle: visible
    T_FAR_HIDDEN, // a far-plane point behind the near rectangle: hidden
    T_GAP_NEAR,   // no point, inside the near rectangle: hole
    T_GAP_FAR,    // no point, inside the far rectangle only: hole
    T_SKY,        // no point, outside both: background
    T_COUNT
};

#define NEAR_Z 5.0f
#define FAR_Z  20.0f

static void splat(const sta_view_params *view, sta_image *position, float px_m, float py_m,
                  float depth)
{
    float tan_y = tanf(0.5f * view->fov_y);
    float tan_x = tan_y * (float)view->width_px / (float)view->height_px;
    float ndc_x = px_m / (depth * tan_x), ndc_y = py_m / (depth * tan_y);
    int x = (int)floorf((ndc_x + 1.0f) * 0.5f * (float)view->width_px);
    int y = (int)floorf((ndc_y + 1.0f) * 0.5f * (float)view->height_px);
    if (x < 0 || y < 0 || x >= view->width_px || y >= view->height_px) {
        return;
    }
    float *p = sta_image_at(position, x, y);
    if (p[3] == 0.0f || depth < -p[2]) {
        set_point(view, position, x, y, depth);
    }
}

static void sample_rect(const sta_view_params *view, sta_image *position, float half_w,
                        float half_h, float depth, float spacing)
{
    int nx = (int)lroundf(2.0f * half_w / spacing), ny = (int)lroundf(2.0f * half_h / spacing);
    for (int j = 0; j <= ny; j++) {
        for (int i = 0; i <= nx; i++) {
            float x = -half_w + spacing * ((float)i + 0.25f * (float)(2.0 * rng_uniform() - 1.0));
            float y = -half_h + spacing * ((float)j + 0.25f * (float)(2.0 * rng_uniform() - 1.0));
            x = fminf(fmaxf(x, -half_w), half_w);
            y = fminf(fmaxf(y, -half_h), half_h);
            splat(view, position, x, y, depth);
        }
    }
}

static void make_two_planes(const sta_view_params *view, sta_image *out, unsigned char *truth)
{
    new_image(out, view->width_px, view->height_px, 4);
    rng_state = 777;
    sample_rect(view, out, 1.5f, 1.0f, NEAR_Z, 0.025f);
    sample_rect(view, out, 8.0f, 6.0f, FAR_Z, 0.1f);
    float tan_y = tanf(0.5f * view->fov_y);
    float tan_x = tan_y * (float)view->width_px / (float)view->height_px;
    for (int y = 0; y < view->height_px; y++) {
        for (int x = 0; x < view->width_px; x++) {
            float ndc_x = ((float)x + 0.5f) / (float)view->width_px * 2.0f - 1.0f;
            float ndc_y = ((float)y + 0.5f) / (float)view->height_px * 2.0f - 1.0f;
            bool in_near =
                fabsf(ndc_x * tan_x * NEAR_Z) <= 1.5f && fabsf(ndc_y * tan_y * NEAR_Z) <= 1.0f;
            bool in_far =
                fabsf(ndc_x * tan_x * FAR_Z) <= 8.0f && fabsf(ndc_y * tan_y * FAR_Z) <= 6.0f;
            const float *p = sta_image_at(out, x, y);
            enum truth t;
            if (p[3] > 0.5f) {
                t = -p[2] < 0.5f * (NEAR_Z + FAR_Z) ? T_NEAR
                                                    : (in_near ? T_FAR_HIDDEN : T_FAR_OPEN);
            } else {
                t = in_near ? T_GAP_NEAR : (in_far ? T_GAP_FAR : T_SKY);
            }
            truth[(size_t)y * (size_t)view->width_px + (size_t)x] = (unsigned char)t;
        }
    }
}

/* ---- running both sides ---- */

// Runs the GPU pyramidal operator; out_pyramid (may be NULL) receives levels 1.. read
// back at their logical sizes (level 0 left empty).
static void gpu_pyramid(const sta_view_params *view, const sta_hpr_params *params,
                        const sta_image *position, sta_image *out_label,
                        sta_hpr_pyramid *out_pyramid)
{
    sta_error err = { 0 };
    GLuint position_tex, pyramid_tex, label_tex;
    assert_int_equal(sta_gl_texture_from_image(position, &position_tex, &err), STA_OK);
    assert_int_equal(
        sta_hpr_pyramid_texture_create(view->width_px, view->height_px, &pyramid_tex, &err),
        STA_OK);
    assert_int_equal(sta_gl_label_texture_create(view->width_px, view->height_px, &label_tex, &err),
                     STA_OK);
    sta_status status =
        sta_hpr_pass_run_pyramid(&pass, view, params, position_tex, pyramid_tex, label_tex, &err);
    if (status != STA_OK) {
        fail_msg("%s", err.message);
    }
    assert_int_equal(sta_gl_texture_to_image(label_tex, 0, 1, out_label, &err), STA_OK);
    if (out_pyramid) {
        memset(out_pyramid, 0, sizeof(*out_pyramid));
        out_pyramid->level_count = sta_hpr_pyramid_levels(view->width_px, view->height_px);
        sta_image atlas;
        assert_int_equal(sta_gl_texture_to_image(pyramid_tex, 0, 4, &atlas, &err), STA_OK);
        for (int l = 1; l < out_pyramid->level_count; l++) {
            int w = sta_hpr_level_size(view->width_px, l),
                h = sta_hpr_level_size(view->height_px, l), origin[2];
            sta_hpr_pyramid_level_origin(view->width_px, view->height_px, l, origin);
            assert_true(origin[0] + w <= atlas.width && origin[1] + h <= atlas.height);
            new_image(&out_pyramid->levels[l], w, h, 4);
            for (int y = 0; y < h; y++) {
                memcpy(sta_image_at(&out_pyramid->levels[l], 0, y),
                       sta_image_at(&atlas, origin[0], origin[1] + y),
                       (size_t)w * 4 * sizeof(float));
            }
        }
        sta_image_release(&atlas);
    }
    glDeleteTextures(1, &position_tex);
    glDeleteTextures(1, &pyramid_tex);
    glDeleteTextures(1, &label_tex);
}

static void gpu_exhaustive(const sta_view_params *view, const sta_hpr_params *params, int radius,
                           const sta_image *position, sta_image *out_label)
{
    sta_error err = { 0 };
    GLuint position_tex, label_tex;
    assert_int_equal(sta_gl_texture_from_image(position, &position_tex, &err), STA_OK);
    assert_int_equal(sta_gl_label_texture_create(view->width_px, view->height_px, &label_tex, &err),
                     STA_OK);
    sta_status status =
        sta_hpr_pass_run_exhaustive(&pass, view, params, radius, position_tex, label_tex, &err);
    if (status != STA_OK) {
        fail_msg("%s", err.message);
    }
    assert_int_equal(sta_gl_texture_to_image(label_tex, 0, 1, out_label, &err), STA_OK);
    glDeleteTextures(1, &position_tex);
    glDeleteTextures(1, &label_tex);
}

static bool is_label(float v)
{
    return v == STA_LABEL_BACKGROUND || v == STA_LABEL_VISIBLE || v == STA_LABEL_HIDDEN ||
           v == STA_LABEL_HOLE;
}

// Counts labels that differ; each must be a pixel whose twin mean lies within 1e-5 of
// the threshold (float rounding of the occlusion values may then tip it).
static int count_differences(const sta_image *twin, const sta_image *gpu, const sta_image *mean,
                             float threshold)
{
    assert_int_equal(twin->width, gpu->width);
    assert_int_equal(twin->height, gpu->height);
    int differing = 0;
    for (int i = 0; i < twin->width * twin->height; i++) {
        assert_true(is_label(twin->data[i]));
        assert_true(is_label(gpu->data[i]));
        assert_true(isfinite(mean->data[i]));
        if (twin->data[i] != gpu->data[i]) {
            assert_true(fabsf(mean->data[i] - threshold) <= 1e-5f);
            differing++;
        }
    }
    return differing;
}

typedef struct both_result {
    sta_image pyramid_label; // twin labels, pyramidal operator
    sta_image pyramid_mean;
    sta_image pyramid_level;
    sta_image exhaustive_label; // twin labels, exhaustive operator (if radius >= 0)
} both_result;

static void both_release(both_result *r)
{
    sta_image_release(&r->pyramid_label);
    sta_image_release(&r->pyramid_mean);
    sta_image_release(&r->pyramid_level);
    sta_image_release(&r->exhaustive_label);
}

/* Runs twin and shader of the pyramidal operator (and of the exhaustive one when
 * radius >= 0) on `position`; asserts equal pyramids (bit for bit) and equal labels
 * (but for near-threshold pixels, counted and printed). */
// Returns how many pyramidal labels differ between the shader and the twin.
static int run_both(const char *name, const sta_view_params *view, const sta_hpr_params *params,
                    const sta_image *position, int radius, both_result *out)
{
    memset(out, 0, sizeof(*out));
    sta_error err = { 0 };
    int w = view->width_px, h = view->height_px;
    sta_hpr_params resolved = params ? *params : (sta_hpr_params){ 0 };
    sta_hpr_params_defaults(&resolved);
    sta_hpr_pyramid twin_pyramid, gpu_pyramid_levels;
    assert_int_equal(sta_hpr_ref_build_pyramid(position, &twin_pyramid, &err), STA_OK);
    new_image(&out->pyramid_label, w, h, 1);
    new_image(&out->pyramid_mean, w, h, 1);
    new_image(&out->pyramid_level, w, h, 1);
    sta_hpr_ref_pyramid_labels(view, params, &twin_pyramid, &out->pyramid_label, &out->pyramid_mean,
                               &out->pyramid_level);
    sta_image gpu_label;
    gpu_pyramid(view, params, position, &gpu_label, &gpu_pyramid_levels);
    assert_int_equal(gpu_pyramid_levels.level_count, twin_pyramid.level_count);
    for (int l = 1; l < twin_pyramid.level_count; l++) {
        const sta_image *a = &twin_pyramid.levels[l], *b = &gpu_pyramid_levels.levels[l];
        assert_int_equal(a->width, b->width);
        assert_int_equal(a->height, b->height);
        assert_memory_equal(a->data, b->data, (size_t)a->width * (size_t)a->height * 16);
    }
    int differing =
        count_differences(&out->pyramid_label, &gpu_label, &out->pyramid_mean, resolved.threshold);
    int close = 0; // pixels whose mean is within 1e-3 of the threshold: the hard ones
    for (int i = 0; i < w * h; i++) {
        close += fabsf(out->pyramid_mean.data[i] - resolved.threshold) < 1e-3f;
    }
    printf("hpr %-14s %4dx%-4d pyramidal: %d of %d labels differ from the twin (%d levels, "
           "%d means within 1e-3 of the threshold)",
           name, w, h, differing, w * h, twin_pyramid.level_count, close);
    int pyramid_differing = differing;
    sta_image_release(&gpu_label);
    sta_hpr_ref_pyramid_release(&twin_pyramid);
    sta_hpr_ref_pyramid_release(&gpu_pyramid_levels);
    if (radius >= 0) {
        sta_image mean;
        new_image(&out->exhaustive_label, w, h, 1);
        new_image(&mean, w, h, 1);
        sta_hpr_ref_exhaustive(view, params, radius, position, &out->exhaustive_label, &mean);
        gpu_exhaustive(view, params, radius, position, &gpu_label);
        differing =
            count_differences(&out->exhaustive_label, &gpu_label, &mean, resolved.threshold);
        printf("; exhaustive r=%d: %d differ", radius, differing);
        sta_image_release(&gpu_label);
        sta_image_release(&mean);
    }
    printf("\n");
    return pyramid_differing;
}

static int count_label(const sta_image *label, float value)
{
    int n = 0;
    for (int i = 0; i < label->width * label->height; i++) {
        n += label->data[i] == value;
    }
    return n;
}

/* ---- tests ---- */

// The pyramid texture of a width x height image holds every level, no two overlapping.
static void check_pyramid_layout(int width, int height)
{
    int tw, th;
    sta_hpr_pyramid_texture_size(width, height, &tw, &th);
    int levels = sta_hpr_pyramid_levels(width, height);
    assert_true(levels >= 2);
    assert_true(sta_hpr_level_size(width, levels - 1) == 1);
    assert_true(sta_hpr_level_size(height, levels - 1) == 1);
    int box[STA_HPR_MAX_LEVELS][4];
    for (int l = 1; l < levels; l++) {
        int origin[2];
        sta_hpr_pyramid_level_origin(width, height, l, origin);
        box[l][0] = origin[0];
        box[l][1] = origin[1];
        box[l][2] = origin[0] + sta_hpr_level_size(width, l);
        box[l][3] = origin[1] + sta_hpr_level_size(height, l);
        assert_true(box[l][0] >= 0 && box[l][1] >= 0 && box[l][2] <= tw && box[l][3] <= th);
        for (int k = 1; k < l; k++) {
            bool apart = box[k][2] <= box[l][0] || box[l][2] <= box[k][0] ||
                         box[k][3] <= box[l][1] || box[l][3] <= box[k][1];
            assert_true(apart);
        }
    }
}

static void pyramid_sizes_and_levels(void **state)
{
    (void)state;
    assert_int_equal(sta_hpr_pyramid_levels(1, 1), 2);
    assert_int_equal(sta_hpr_pyramid_levels(2, 1), 2);
    assert_int_equal(sta_hpr_pyramid_levels(3, 1), 3);
    assert_int_equal(sta_hpr_pyramid_levels(1, 17), 6);
    assert_int_equal(sta_hpr_pyramid_levels(1920, 1080), 12);
    assert_int_equal(sta_hpr_pyramid_levels(32768, 5), 16);
    assert_int_equal(sta_hpr_pyramid_levels(32769, 5), 0);
    assert_int_equal(sta_hpr_pyramid_levels(0, 5), 0);
    assert_int_equal(sta_hpr_level_size(37, 1), 19);
    assert_int_equal(sta_hpr_level_size(37, 5), 2);
    assert_int_equal(sta_hpr_level_size(37, 6), 1);
    int tw, th;
    sta_hpr_pyramid_texture_size(1920, 1080, &tw, &th);
    assert_int_equal(tw, 1440);
    assert_int_equal(th, 544);
    sta_hpr_pyramid_texture_size(32769, 5, &tw, &th);
    assert_int_equal(tw, 0);
    assert_int_equal(th, 0);
    // Every level lies inside the texture and no two levels share a texel, for all
    // sizes up to 130 and a few large ones.
    for (int w = 1; w <= 130; w++) {
        for (int h = 1; h <= 130; h += (w % 7) + 1) {
            check_pyramid_layout(w, h);
        }
    }
    check_pyramid_layout(1920, 1080);
    check_pyramid_layout(1201, 1083);
    check_pyramid_layout(4097, 3);
    check_pyramid_layout(5, 2163);
}

static void sectors_follow_the_angle(void **state)
{
    (void)state;
    // The 8 direct neighbours fall in 8 different sectors, counter-clockwise from +x.
    const int ring[8][2] = { { 1, 0 },  { 1, 1 },   { 0, 1 },  { -1, 1 },
                             { -1, 0 }, { -1, -1 }, { 0, -1 }, { 1, -1 } };
    for (int s = 0; s < 8; s++) {
        assert_int_equal(sta_hpr_sector(2 * ring[s][0], 2 * ring[s][1]), s);
    }
    // Any direction: the sector whose centre is nearest in angle (atan2), away from
    // the borders by more than 1e-3 rad.
    rng_state = 99;
    int checked = 0;
    for (int i = 0; i < 20000; i++) {
        int vx = (int)(rng_uniform() * 8001.0) - 4000, vy = (int)(rng_uniform() * 8001.0) - 4000;
        if (vx == 0 && vy == 0) {
            continue;
        }
        double a = atan2((double)vy, (double)vx) / (M_PI / 4.0); // in sector widths
        double frac = a - floor(a);
        if (fabs(frac - 0.5) < 1e-3 * 4.0 / M_PI) {
            continue;
        }
        int expected = ((int)floor(a + 0.5) + 8) % 8;
        assert_int_equal(sta_hpr_sector(vx, vy), expected);
        checked++;
    }
    assert_true(checked > 19000);
}

static void adaptive_level_is_rounded_eq1(void **state)
{
    (void)state;
    sta_view_params view = make_view(1248, 768);
    sta_hpr_params p = { 0 };
    sta_hpr_params_defaults(&p);
    assert_true(p.threshold == 0.1f && p.coarse_level == 4 && p.far_m == 1.0e6f);
    assert_true(p.s_hpr == 0.0f); // derived from the view where used
    assert_true(fabsf(sta_hpr_s_hpr_m(&view, &p) - 0.25f) < 1e-7f);
    sta_hpr_params set = { .threshold = -1.0f, .s_hpr = 2.0f, .coarse_level = 2, .far_m = 9.0f };
    sta_hpr_params_defaults(&set);
    assert_true(set.threshold == -1.0f && set.s_hpr == 2.0f && set.coarse_level == 2 &&
                set.far_m == 9.0f);
    assert_true(sta_hpr_s_hpr_m(&view, &set) == 2.0f);
    int levels = sta_hpr_pyramid_levels(view.width_px, view.height_px);
    float depth[STA_HPR_MAX_LEVELS];
    sta_hpr_level_depths(&view, &p, levels, depth);
    // Eq. 1 in double: l = log2(s_hpr h / (2 tan(theta)) / z), rounded and clamped.
    double k = 0.25 * 768.0 / (2.0 * tan(0.4));
    int seen[STA_HPR_MAX_LEVELS] = { 0 };
    for (double z = 0.01; z < 1e6; z *= 1.0137) {
        double l = log2(k / z);
        if (fabs(l - floor(l) - 0.5) < 1e-4) {
            continue; // at a rounding border
        }
        long expected = lround(l);
        expected = expected < 0 ? 0 : (expected > levels - 1 ? levels - 1 : expected);
        int level = 0;
        for (int i = 1; i < levels; i++) {
            if ((float)z <= depth[i]) {
                level = i;
            }
        }
        assert_int_equal(level, expected);
        seen[level] = 1;
    }
    for (int l = 0; l < levels; l++) {
        assert_true(seen[l]);
    }
    // No s0 (0 everywhere): level 0, no NaN.
    sta_view_params flat = view;
    flat.s0 = 0.0f;
    sta_hpr_params q = { 0 };
    sta_hpr_params_defaults(&q);
    sta_hpr_level_depths(&flat, &q, levels, depth);
    for (int l = 1; l < levels; l++) {
        assert_true(depth[l] == 0.0f);
    }
}

static void shader_matches_twin_on_random_buffers(void **state)
{
    (void)state;
    const int sizes[][2] = { { 37, 23 }, { 1, 17 }, { 17, 1 }, { 97, 61 }, { 64, 64 }, { 130, 9 } };
    const double fills[] = { 0.5, 0.9, 0.1 };
    for (size_t i = 0; i < sizeof(sizes) / sizeof(sizes[0]); i++) {
        for (size_t f = 0; f < 3; f++) {
            sta_view_params view = make_view(sizes[i][0], sizes[i][1]);
            sta_image position;
            make_random(&view, 1000 + i * 10 + f, fills[f], &position);
            both_result r;
            char name[32];
            snprintf(name, sizeof(name), "random %.1f", fills[f]);
            // Defaults; other threshold, s_hpr and far depth; coarse level 2 (the
            // adaptive level then varies within a workgroup).
            sta_hpr_params params = { 0 };
            if (f == 1) {
                params = (sta_hpr_params){ .threshold = 0.3f, .s_hpr = 1.0f, .far_m = 500.0f };
            } else if (f == 2) {
                params.coarse_level = 2;
            }
            run_both(name, &view, &params, &position, 3, &r);
            both_release(&r);
            sta_image_release(&position);
        }
    }
}

// Precision and recall of `label` against the two-plane truth, for one predicted
// label and the truth classes that should get it.
static void precision_recall(const sta_image *label, const unsigned char *truth, float predicted,
                             unsigned truth_mask, double *precision, double *recall)
{
    long tp = 0, fp = 0, fn = 0;
    for (int i = 0; i < label->width * label->height; i++) {
        bool want = (truth_mask >> truth[i]) & 1u;
        bool got = label->data[i] == predicted;
        tp += want && got;
        fp += !want && got;
        fn += want && !got;
    }
    *precision = tp + fp ? (double)tp / (double)(tp + fp) : 1.0;
    *recall = tp + fn ? (double)tp / (double)(tp + fn) : 1.0;
}

typedef struct scores {
    double hidden_p, hidden_r, visible_p, visible_r, hole_p, hole_r, sky_p, sky_r;
} scores;

static scores score(const char *name, const sta_image *label, const unsigned char *truth)
{
    scores s;
    precision_recall(label, truth, STA_LABEL_HIDDEN, 1u << T_FAR_HIDDEN, &s.hidden_p, &s.hidden_r);
    precision_recall(label, truth, STA_LABEL_VISIBLE, (1u << T_NEAR) | (1u << T_FAR_OPEN),
                     &s.visible_p, &s.visible_r);
    precision_recall(label, truth, STA_LABEL_HOLE, (1u << T_GAP_NEAR) | (1u << T_GAP_FAR),
                     &s.hole_p, &s.hole_r);
    precision_recall(label, truth, STA_LABEL_BACKGROUND, 1u << T_SKY, &s.sky_p, &s.sky_r);
    printf("hpr truth %-18s HIDDEN p=%.4f r=%.4f  VISIBLE p=%.4f r=%.4f  HOLE p=%.4f r=%.4f  "
           "BACKGROUND p=%.4f r=%.4f\n",
           name, s.hidden_p, s.hidden_r, s.visible_p, s.visible_r, s.hole_p, s.hole_r, s.sky_p,
           s.sky_r);
    return s;
}

/* The second copy step on a hand-built 3 x 3 image (its anchors at the corners; the
 * empty (0, 0) leaves the first step nothing to copy into the points at the other
 * corners, which keep their full labels): a pixel copies agreeing anchors of its kind
 * at its depth; a depth edge or disagreeing anchors keep the full label (refined). */
static void sparse_copy_step_rules(void **state)
{
    (void)state;
    sta_image position, full, out;
    new_image(&position, 3, 3, 4);
    new_image(&full, 3, 3, 1);
    new_image(&out, 3, 3, 1);
    for (int i = 0; i < 9; i++) {
        position.data[4 * i + 2] = -10.0f;
        position.data[4 * i + 3] = 1.0f;
        full.data[i] = STA_LABEL_VISIBLE;
    }
    position.data[3] = 0.0f;
    full.data[0] = STA_LABEL_HOLE;
    full.data[4] = STA_LABEL_HIDDEN; // the centre: copies its visible point anchors
    const int corners = 3;           // (2, 0), (0, 2), (2, 2) refined in the first step
    assert_int_equal(sta_hpr_ref_sparse_labels(&position, &full, &out), corners);
    assert_true(out.data[4] == STA_LABEL_VISIBLE);
    position.data[4 * 4 + 2] = -10.04f; // within 0.5 % of the anchors' depth: still copied
    assert_int_equal(sta_hpr_ref_sparse_labels(&position, &full, &out), corners);
    position.data[4 * 4 + 2] = -10.1f; // 1 % behind: a depth edge, refined, keeps HIDDEN
    assert_int_equal(sta_hpr_ref_sparse_labels(&position, &full, &out), corners + 1);
    assert_true(out.data[4] == STA_LABEL_HIDDEN);
    // The empty (1, 0) copies its empty anchor (0, 0), whatever the point anchor (2, 0)
    // says and what the full operator said.
    position.data[4 * 1 + 3] = 0.0f;
    full.data[1] = STA_LABEL_BACKGROUND;
    assert_int_equal(sta_hpr_ref_sparse_labels(&position, &full, &out), corners + 1);
    assert_true(out.data[1] == STA_LABEL_HOLE);
    full.data[8] = STA_LABEL_HIDDEN; // anchor (2, 2) disagrees: (2, 1), (1, 2) refined
    assert_int_equal(sta_hpr_ref_sparse_labels(&position, &full, &out), corners + 3);
    for (int i = 0; i < 9; i += 2) { // the corners keep their own labels
        assert_true(out.data[i] == full.data[i]);
    }
    sta_image_release(&position);
    sta_image_release(&full);
    sta_image_release(&out);
}

/* The copy steps in turn on an image one anchor stride across (anchors at its corners):
 * the coarse steps copy empty pixels from the anchors and always refine points, the
 * last copies the odd pixels; an open anchor sends the pixels between it and the others
 * to refinement, down to the centre, which keeps its full label. */
static void sparse_copy_steps_in_turn(void **state)
{
    (void)state;
    assert_int_equal(sta_hpr_anchor_stride(STA_HPR_ANCHOR_HD_HEIGHT_PX - 1), STA_HPR_ANCHOR_STRIDE);
    assert_int_equal(sta_hpr_anchor_stride(STA_HPR_ANCHOR_HD_HEIGHT_PX), STA_HPR_ANCHOR_STRIDE_HD);
    const int n = STA_HPR_ANCHOR_STRIDE + 1, half = (n + 1) / 2, centre = (n / 2) * n + n / 2;
    sta_image position, full, out;
    new_image(&position, n, n, 4);
    new_image(&full, n, n, 1);
    new_image(&out, n, n, 1);
    for (int i = 0; i < n * n; i++) {
        position.data[4 * i + 2] = -10.0f;
        position.data[4 * i + 3] = 1.0f;
        full.data[i] = STA_LABEL_VISIBLE;
    }
    // Points: the even ones that are not anchors are refined, the odd ones copy them.
    assert_int_equal(sta_hpr_ref_sparse_labels(&position, &full, &out), half * half - 4);
    for (int i = 0; i < n * n; i++) {
        position.data[4 * i + 3] = 0.0f;
        full.data[i] = STA_LABEL_HOLE;
    }
    full.data[centre] = STA_LABEL_BACKGROUND; // copied from the 4 anchors
    assert_int_equal(sta_hpr_ref_sparse_labels(&position, &full, &out), 0);
    for (int i = 0; i < n * n; i++) {
        assert_true(out.data[i] == STA_LABEL_HOLE);
    }
    full.data[n * n - 1] = STA_LABEL_BACKGROUND; // the anchor at the far corner opens
    int refined = sta_hpr_ref_sparse_labels(&position, &full, &out);
    assert_true(refined > 2 && refined < n * n / 2);
    assert_true(out.data[centre] == STA_LABEL_BACKGROUND);
    assert_true(out.data[1] == STA_LABEL_HOLE && out.data[n] == STA_LABEL_HOLE);
    sta_image_release(&position);
    sta_image_release(&full);
    sta_image_release(&out);
}

/* The sparse operator on the GPU equals the twin's copy step applied to the GPU's full
 * labels (anchors and refined pixels run the unchanged operator), on the two planes at
 * an even and an odd size; it copies most non-anchor pixels and keeps the truth scores. */
static void sparse_operator_matches_twin(void **state)
{
    (void)state;
    // The third size is >= STA_HPR_ANCHOR_HD_HEIGHT_PX high: anchors 16 apart.
    const int sizes[3][2] = { { 320, 240 }, { 211, 157 }, { 1201, 1083 } };
    static unsigned char truth[1201 * 1083];
    for (int k = 0; k < 3; k++) {
        int w = sizes[k][0], h = sizes[k][1];
        sta_view_params view = make_view(w, h);
        sta_image position, full, sparse, expected;
        make_two_planes(&view, &position, truth);
        gpu_pyramid(&view, NULL, &position, &full, NULL);
        sta_hpr_params params = { .sparse = true };
        gpu_pyramid(&view, &params, &position, &sparse, NULL);
        new_image(&expected, w, h, 1);
        int refined = sta_hpr_ref_sparse_labels(&position, &full, &expected);
        assert_memory_equal(expected.data, sparse.data, (size_t)w * (size_t)h * sizeof(float));
        int differ = 0;
        for (int i = 0; i < w * h; i++) {
            differ += full.data[i] != sparse.data[i];
        }
        const int stride = sta_hpr_anchor_stride(h); // the anchors: x, y multiples of it
        assert_int_equal(stride, k == 2 ? STA_HPR_ANCHOR_STRIDE_HD : STA_HPR_ANCHOR_STRIDE);
        int others = w * h - ((w + stride - 1) / stride) * ((h + stride - 1) / stride);
        // Pixels of the grid `stride / 2` that copy a label other than their full one:
        // where the GPU would run the operator with anchors only stride / 2 apart.
        int coarse_copies = 0;
        for (int y = 0; y < h; y += stride / 2) {
            for (int x = 0; x < w; x += stride / 2) {
                coarse_copies +=
                    (x % stride || y % stride) && expected.data[y * w + x] != full.data[y * w + x];
            }
        }
        printf("hpr sparse %dx%d, anchors %d apart: %d of %d non-anchor pixels refined, %d "
               "labels differ from the full operator, %d on the first copy step's grid\n",
               w, h, stride, refined, others, differ, coarse_copies);
        assert_true(coarse_copies > 0); // so the comparison above checks the stride
        assert_true(refined > 0 && refined < others / 2);
        assert_true(differ < w * h / 50);
        if (k == 0) {
            scores s = score("sparse", &sparse, truth);
            assert_true(s.hidden_r > 0.95 && s.hidden_p > 0.95);
            assert_true(s.visible_r > 0.97 && s.visible_p > 0.97);
            assert_true(s.hole_r > 0.95 && s.hole_p > 0.95);
            assert_true(s.sky_r > 0.95 && s.sky_p > 0.95);
        }
        sta_image_release(&position);
        sta_image_release(&full);
        sta_image_release(&sparse);
        sta_image_release(&expected);
    }
}

/* Staged stores (render/gl_staged.h: the pyramid's levels through a storage buffer copied
 * into the atlas, the default on llvmpipe) and image stores (a GPU's default) build the same
 * pyramid and the same labels, bit for bit. */
static void staged_and_image_stores_build_the_same_pyramid(void **state)
{
    (void)state;
    sta_view_params view = make_view(157, 101);
    sta_image position;
    static unsigned char truth[157 * 101];
    make_two_planes(&view, &position, truth);
    sta_image label[2];
    sta_hpr_pyramid pyramid[2];
    sta_error err = { 0 };
    for (int staged = 0; staged < 2; staged++) {
        sta_hpr_pass_release(&pass);
        sta_gl_staged_stores_force(staged);
        assert_int_equal(sta_hpr_pass_init(&pass, &err), STA_OK);
        sta_gl_staged_stores_force(-1);
        assert_int_equal(pass.staged, staged);
        gpu_pyramid(&view, NULL, &position, &label[staged], &pyramid[staged]);
    }
    assert_int_equal(pyramid[0].level_count, pyramid[1].level_count);
    int points = 0;
    for (int l = 1; l < pyramid[0].level_count; l++) {
        const sta_image *a = &pyramid[0].levels[l], *b = &pyramid[1].levels[l];
        assert_memory_equal(a->data, b->data, (size_t)a->width * (size_t)a->height * 16);
        for (int i = 0; i < a->width * a->height; i++) {
            points += b->data[4 * i + 3] > 0.5f;
        }
    }
    assert_true(points > 100); // levels with points, not two empty atlases
    assert_memory_equal(label[0].data, label[1].data, (size_t)157 * 101 * sizeof(float));
    for (int staged = 0; staged < 2; staged++) {
        sta_image_release(&label[staged]);
        sta_hpr_ref_pyramid_release(&pyramid[staged]);
    }
    sta_image_release(&position);
}

static void near_plane_over_far_plane_known_truth(void **state)
{
    (void)state;
    sta_view_params view = make_view(320, 240);
    sta_image position;
    static unsigned char truth[320 * 240];
    make_two_planes(&view, &position, truth);
    int counts[T_COUNT] = { 0 };
    for (int i = 0; i < 320 * 240; i++) {
        counts[truth[i]]++;
    }
    printf("hpr truth: near %d, far open %d, far hidden %d, gaps near %d, gaps far %d, sky %d\n",
           counts[T_NEAR], counts[T_FAR_OPEN], counts[T_FAR_HIDDEN], counts[T_GAP_NEAR],
           counts[T_GAP_FAR], counts[T_SKY]);
    // The scene is what it claims: gaps everywhere, far points seen through them.
    assert_true(counts[T_FAR_HIDDEN] > 2000 && counts[T_GAP_NEAR] > 2000);
    assert_true(counts[T_SKY] > 10000 && counts[T_FAR_OPEN] > 5000);
    both_result r;
    run_both("two planes", &view, NULL, &position, 8, &r);
    // Adaptive level (eq. 1 with s_hpr = 0.25 m, K = 71 px m): 4 behind the near plane
    // (z = 5), 2 on the far plane.
    for (int i = 0; i < 320 * 240; i++) {
        float level = r.pyramid_level.data[i];
        if (truth[i] == T_NEAR) {
            assert_true(level >= 3.0f && level <= 4.0f);
        } else if (truth[i] == T_FAR_OPEN) {
            assert_true(level >= 2.0f && level <= 4.0f);
        }
    }
    scores s = score("pyramidal", &r.pyramid_label, truth);
    assert_true(s.hidden_r > 0.95 && s.hidden_p > 0.95);
    assert_true(s.visible_r > 0.97 && s.visible_p > 0.97);
    assert_true(s.hole_r > 0.95 && s.hole_p > 0.95);
    assert_true(s.sky_r > 0.95 && s.sky_p > 0.95);
    scores e = score("exhaustive r=8", &r.exhaustive_label, truth);
    assert_true(e.hidden_r > 0.9 && e.visible_r > 0.9 && e.hole_r > 0.9 && e.sky_r > 0.9);
    // Agreement of the two operators.
    int agree = 0;
    for (int i = 0; i < 320 * 240; i++) {
        agree += r.pyramid_label.data[i] == r.exhaustive_label.data[i];
    }
    printf("hpr pyramidal vs exhaustive r=8: %.4f of labels agree\n", agree / (320.0 * 240.0));
    assert_true(agree > 0.9 * 320 * 240);
    both_release(&r);
    sta_image_release(&position);
}

static int compare_floats(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return (x > y) - (x < y);
}

/* The hard test of shader = twin: thresholds set to the twin's own means, so that many
 * pixels sit exactly on the threshold and any rounding difference in the occlusion
 * values would flip them. */
static void labels_match_with_thresholds_on_the_means(void **state)
{
    (void)state;
    sta_view_params view = make_view(320, 240);
    sta_image position;
    static unsigned char truth[320 * 240];
    make_two_planes(&view, &position, truth);
    both_result r;
    run_both("two planes", &view, NULL, &position, -1, &r);
    const int n = 320 * 240;
    float *sorted = test_malloc((size_t)n * sizeof(float));
    memcpy(sorted, r.pyramid_mean.data, (size_t)n * sizeof(float));
    qsort(sorted, (size_t)n, sizeof(float), compare_floats);
    int unique = 0; // distinct means, spread evenly over their range below
    for (int i = 0; i < n; i++) {
        if (unique == 0 || sorted[i] != sorted[unique - 1]) {
            sorted[unique++] = sorted[i];
        }
    }
    int differing = 0, on_threshold = 0, runs = 0;
    for (int q = 0; q < 24; q++) {
        float threshold = sorted[(size_t)((q + 0.5) / 24.0 * unique)];
        if (!(threshold > 0.0f)) {
            continue; // 0 would mean "default"
        }
        sta_hpr_params params = { .threshold = threshold };
        sta_image gpu;
        gpu_pyramid(&view, &params, &position, &gpu, NULL);
        for (int i = 0; i < n; i++) {
            float mean = r.pyramid_mean.data[i];
            bool point = position.data[4 * i + 3] > 0.5f;
            // Empty pixels also need STA_HPR_BACKGROUND_OPEN_SECTORS open sectors.
            float empty_threshold = fmaxf(threshold, STA_HPR_BACKGROUND_OPEN_SECTORS * 0.125f);
            bool open = mean >= (point ? threshold : empty_threshold);
            float want = point ? (open ? STA_LABEL_VISIBLE : STA_LABEL_HIDDEN)
                               : (open ? STA_LABEL_BACKGROUND : STA_LABEL_HOLE);
            on_threshold += mean == threshold;
            if (gpu.data[i] != want) {
                assert_true(fabsf(mean - (point ? threshold : empty_threshold)) <= 1e-5f);
                differing++;
            }
        }
        sta_image_release(&gpu);
        runs++;
    }
    printf("hpr thresholds on the means: %d runs (of %d distinct means), %d pixel means exactly "
           "on the threshold, %d labels differ from the twin\n",
           runs, unique, on_threshold, differing);
    assert_true(runs >= 12 && on_threshold >= runs);
    test_free(sorted);
    both_release(&r);
    sta_image_release(&position);
}

static void empty_frame_is_background(void **state)
{
    (void)state;
    sta_view_params view = make_view(37, 23);
    sta_image position;
    new_image(&position, 37, 23, 4);
    both_result r;
    run_both("empty", &view, NULL, &position, 4, &r);
    assert_int_equal(count_label(&r.pyramid_label, STA_LABEL_BACKGROUND), 37 * 23);
    assert_int_equal(count_label(&r.exhaustive_label, STA_LABEL_BACKGROUND), 37 * 23);
    for (int i = 0; i < 37 * 23; i++) {
        assert_true(r.pyramid_mean.data[i] == 1.0f);
    }
    both_release(&r);
    sta_image_release(&position);
}

static void single_point_is_visible(void **state)
{
    (void)state;
    const int sizes[][2] = { { 37, 23 }, { 1, 1 } };
    for (int i = 0; i < 2; i++) {
        int w = sizes[i][0], h = sizes[i][1];
        sta_view_params view = make_view(w, h);
        sta_image position;
        new_image(&position, w, h, 4);
        set_point(&view, &position, w / 2, h / 2, 3.0f);
        both_result r;
        run_both("single point", &view, NULL, &position, 4, &r);
        assert_true(*sta_image_at(&r.pyramid_label, w / 2, h / 2) == STA_LABEL_VISIBLE);
        assert_true(*sta_image_at(&r.exhaustive_label, w / 2, h / 2) == STA_LABEL_VISIBLE);
        assert_int_equal(count_label(&r.pyramid_label, STA_LABEL_BACKGROUND), w * h - 1);
        assert_int_equal(count_label(&r.exhaustive_label, STA_LABEL_BACKGROUND), w * h - 1);
        both_release(&r);
        sta_image_release(&position);
    }
    // A 1x1 background pixel.
    sta_view_params view = make_view(1, 1);
    sta_image position;
    new_image(&position, 1, 1, 4);
    both_result r;
    run_both("1x1 empty", &view, NULL, &position, 2, &r);
    assert_true(r.pyramid_label.data[0] == STA_LABEL_BACKGROUND);
    both_release(&r);
    sta_image_release(&position);
}

static void full_planes_are_visible(void **state)
{
    (void)state;
    // Fronto-parallel and tilted by 60 deg, at ordinary depth, at the near plane and at
    // 1e5 m; odd and tiny sizes.
    const struct {
        int w, h;
        float depth, tilt;
    } cases[] = { { 64, 48, 10.0f, 0.0f },  { 64, 48, 10.0f, 1.047f },   { 37, 23, 0.05f, 0.0f },
                  { 37, 23, 1.0e5f, 0.0f }, { 37, 23, 1.0e5f, -1.047f }, { 1, 17, 2.0f, 0.5f },
                  { 1, 1, 1.0f, 0.0f } };
    for (size_t i = 0; i < sizeof(cases) / sizeof(cases[0]); i++) {
        sta_view_params view = make_view(cases[i].w, cases[i].h);
        sta_image position;
        make_plane(&view, cases[i].depth, cases[i].tilt, &position);
        both_result r;
        run_both("full plane", &view, NULL, &position, 5, &r);
        assert_int_equal(count_label(&r.pyramid_label, STA_LABEL_VISIBLE), cases[i].w * cases[i].h);
        assert_int_equal(count_label(&r.exhaustive_label, STA_LABEL_VISIBLE),
                         cases[i].w * cases[i].h);
        both_release(&r);
        sta_image_release(&position);
    }
}

static void near_plane_and_huge_depth(void **state)
{
    (void)state;
    // Left half at the near plane (0.05 m), right half at 1e5 m, a few gaps; then a
    // sparse far wall at 1e5 m behind a dense screen at 0.05 m.
    sta_view_params view = make_view(61, 41);
    sta_image position;
    new_image(&position, 61, 41, 4);
    for (int y = 0; y < 41; y++) {
        for (int x = 0; x < 61; x++) {
            if ((x * 7 + y * 3) % 11 != 0) {
                set_point(&view, &position, x, y, x < 30 ? view.near_m : 1.0e5f);
            }
        }
    }
    both_result r;
    run_both("near and 1e5", &view, NULL, &position, 6, &r);
    for (int y = 0; y < 41; y++) {
        for (int x = 0; x < 61; x++) {
            float l = *sta_image_at(&r.pyramid_label, x, y);
            float m = *sta_image_at(&r.pyramid_mean, x, y);
            assert_true(isfinite(m) && m >= 0.0f && m <= 1.0f);
            if (sta_image_at(&position, x, y)[3] > 0.5f) {
                assert_true(l == STA_LABEL_VISIBLE); // side by side, nothing in front
            } else if (x > 1 && x < 59 && y > 1 && y < 39) {
                assert_true(l == STA_LABEL_HOLE);
            }
        }
    }
    both_release(&r);
    sta_image_release(&position);
    // Every other pixel of a checkerboard at 1e5 m, the rest at the near plane: the far
    // points are seen through a screen and hidden.
    new_image(&position, 61, 41, 4);
    for (int y = 0; y < 41; y++) {
        for (int x = 0; x < 61; x++) {
            set_point(&view, &position, x, y, (x + y) % 2 ? 1.0e5f : view.near_m);
        }
    }
    run_both("screen over 1e5", &view, NULL, &position, 6, &r);
    // (Along the border a far point has open sectors outside the image.)
    for (int y = 2; y < 39; y++) {
        for (int x = 2; x < 59; x++) {
            float want = (x + y) % 2 ? STA_LABEL_HIDDEN : STA_LABEL_VISIBLE;
            assert_true(*sta_image_at(&r.pyramid_label, x, y) == want);
            assert_true(*sta_image_at(&r.exhaustive_label, x, y) == want);
        }
    }
    both_release(&r);
    sta_image_release(&position);
}

// A plane at 2 m tilted by `tilt` seen through 30 % of its pixels (a fixed hash picks
// them), with an empty disc of `gap_px` pixels' radius around (gap_x, gap_y) (none for
// gap_px <= 0).
static void make_sparse_plane(const sta_view_params *view, float tilt, int gap_x, int gap_y,
                              float gap_px, sta_image *out)
{
    make_plane(view, 2.0f, tilt, out);
    for (int y = 0; y < view->height_px; y++) {
        for (int x = 0; x < view->width_px; x++) {
            unsigned hash = ((unsigned)x * 73856093u) ^ ((unsigned)y * 19349663u);
            float dx = (float)(x - gap_x), dy = (float)(y - gap_y);
            bool in_gap = gap_px > 0.0f && dx * dx + dy * dy < gap_px * gap_px;
            if (in_gap || (hash % 1000u) >= 300u) {
                float *p = sta_image_at(out, x, y);
                p[0] = p[1] = p[2] = p[3] = 0.0f;
            }
        }
    }
}

static void surfaces_fill_to_the_image_edge(void **state)
{
    (void)state;
    // A surface that runs off-screen on every side: no empty pixel is background, in
    // particular none in the 16-px border band (before: outside the image counted as
    // open sky, and the band came out ragged and black).
    sta_view_params view = make_view(96, 64);
    sta_image position;
    make_sparse_plane(&view, 1.0f, 0, 0, 0.0f, &position);
    both_result r;
    run_both("sparse plane", &view, NULL, &position, 5, &r);
    int band_background = 0, band_empty = 0;
    for (int y = 0; y < 64; y++) {
        for (int x = 0; x < 96; x++) {
            if (sta_image_at(&position, x, y)[3] > 0.5f) {
                continue;
            }
            bool band = x < 16 || y < 16 || x >= 96 - 16 || y >= 64 - 16;
            band_empty += band;
            band_background +=
                band && *sta_image_at(&r.pyramid_label, x, y) == STA_LABEL_BACKGROUND;
        }
    }
    printf("sparse plane 96x64: %d of %d empty border-band pixels background\n", band_background,
           band_empty);
    assert_true(band_empty > 2000);
    assert_int_equal(band_background, 0);
    both_release(&r);
    sta_image_release(&position);
}

// Label changes between 4-neighbour empty pixels, on the pyramid's block lines of
// `block` pixels (between x = block i - 1 and block i, likewise y) and elsewhere, as
// rates per pair.
static void block_line_rates(const sta_image *position, const sta_image *label, int block,
                             double *on, double *off)
{
    long pairs[2] = { 0, 0 }, changes[2] = { 0, 0 };
    for (int y = 0; y < label->height; y++) {
        for (int x = 0; x < label->width; x++) {
            if (sta_image_at(position, x, y)[3] > 0.5f) {
                continue;
            }
            float l = *sta_image_at(label, x, y);
            const int next[2][2] = { { x + 1, y }, { x, y + 1 } };
            for (int d = 0; d < 2; d++) {
                int nx = next[d][0], ny = next[d][1];
                if (nx >= label->width || ny >= label->height ||
                    sta_image_at(position, nx, ny)[3] > 0.5f) {
                    continue;
                }
                int line = (d == 0 ? nx : ny) % block == 0;
                pairs[line]++;
                changes[line] += *sta_image_at(label, nx, ny) != l;
            }
        }
    }
    *off = pairs[0] ? (double)changes[0] / (double)pairs[0] : 0.0;
    *on = pairs[1] ? (double)changes[1] / (double)pairs[1] : 0.0;
}

static void gaps_have_no_block_edges(void **state)
{
    (void)state;
    // Scan-shadow-like gaps (a disc and a slanted band) in a sparse surface: the gaps
    // stay open (background), and where hole turns into background the border does not
    // follow the pyramid's block lines (a decision per block changes only there; a
    // decision per pixel as often on them as elsewhere).
    sta_view_params view = make_view(192, 144);
    view.s0 = 0.01f; // neighbourhood radius K / z about 8 px
    sta_image position;
    make_sparse_plane(&view, 0.0f, 60, 70, 30.0f, &position);
    for (int y = 0; y < 144; y++) {
        for (int x = 0; x < 192; x++) {
            int band = x - y / 2; // a band 24 px wide, slanted 2:1
            if (band >= 100 && band < 124) {
                float *p = sta_image_at(&position, x, y);
                p[0] = p[1] = p[2] = p[3] = 0.0f;
            }
        }
    }
    both_result r;
    run_both("gaps in a sparse plane", &view, NULL, &position, -1, &r);
    double on = 0.0, off = 0.0;
    block_line_rates(&position, &r.pyramid_label, 8, &on, &off);
    int gap_background = 0, gap_pixels = 0;
    for (int y = 0; y < 144; y++) {
        for (int x = 0; x < 192; x++) {
            float dx = (float)(x - 60), dy = (float)(y - 70);
            if (dx * dx + dy * dy < 15.0f * 15.0f) { // the disc's inner half
                gap_pixels++;
                gap_background += *sta_image_at(&r.pyramid_label, x, y) == STA_LABEL_BACKGROUND;
            }
        }
    }
    printf("gaps 192x144: hole/background changes per pair %.4f on 8-px block lines, %.4f "
           "elsewhere; %d of %d pixels of the disc's inner half background\n",
           on, off, gap_background, gap_pixels);
    assert_true(gap_background == gap_pixels);
    assert_true(off > 0.0);
    assert_true(on < 2.0 * off);
    both_release(&r);
    sta_image_release(&position);
}

// Distance in pixels from (x, y) to the nearest pixel for which `inside` is true
// (brute force over the image; 1e9 when there is none).
static float distance_to(const unsigned char *inside, int w, int h, int x, int y)
{
    float best = 1e9f;
    for (int j = 0; j < h; j++) {
        for (int i = 0; i < w; i++) {
            if (inside[j * w + i]) {
                float dx = (float)(i - x), dy = (float)(j - y);
                float d = sqrtf(dx * dx + dy * dy);
                best = d < best ? d : best;
            }
        }
    }
    return best;
}

// Open space between a silhouette and the image border (issue 15, part 2, twentieth
// round): a densely sampled disc whose top lies 12 px below the top border, nothing else.
// The border band's pixels above it have only their lower sectors known, which the disc
// closes; before the flank test they were holes, and fragments of fill floated over the
// silhouette (the bunny's default view). Now no empty pixel more than 8 px from the disc
// is a hole, while a surface running off the border keeps its band filled
// (surfaces_fill_to_the_image_edge).
static void border_band_leaves_open_space_beside_a_silhouette(void **state)
{
    (void)state;
    enum {
        W = 192,
        H = 144
    };
    sta_view_params view = make_view(W, H);
    view.s0 = 0.035f; // neighbourhood radius K / z about 30 px at 2 m, as the bunny's
    sta_image position;
    make_plane(&view, 2.0f, 0.0f, &position);
    static unsigned char disc[W * H];
    const float cx = 96.0f, cy = 100.0f, radius = 31.0f; // top at y = 131, border at 143
    for (int y = 0; y < H; y++) {
        for (int x = 0; x < W; x++) {
            unsigned hash = ((unsigned)x * 73856093u) ^ ((unsigned)y * 19349663u);
            float dx = (float)x - cx, dy = (float)y - cy;
            disc[y * W + x] = dx * dx + dy * dy < radius * radius && (hash % 1000u) < 600u;
            if (!disc[y * W + x]) {
                float *p = sta_image_at(&position, x, y);
                p[0] = p[1] = p[2] = p[3] = 0.0f;
            }
        }
    }
    both_result r;
    run_both("disc below the border", &view, NULL, &position, -1, &r);
    int open = 0, open_holes = 0, inner = 0, inner_holes = 0;
    for (int y = 0; y < H; y++) {
        for (int x = 0; x < W; x++) {
            if (disc[y * W + x]) {
                continue;
            }
            float dx = (float)x - cx, dy = (float)y - cy;
            bool hole = *sta_image_at(&r.pyramid_label, x, y) == STA_LABEL_HOLE;
            if (dx * dx + dy * dy < (radius - 3.0f) * (radius - 3.0f)) {
                inner++; // the disc's own holes stay holes
                inner_holes += hole;
            } else if (distance_to(disc, W, H, x, y) > 8.0f) {
                open++;
                open_holes += hole;
            }
        }
    }
    printf("disc below the border %dx%d: %d of %d empty pixels more than 8 px off the disc holes; "
           "%d of %d inside it\n",
           W, H, open_holes, open, inner_holes, inner);
    assert_true(open > 10000 && inner > 500);
    assert_int_equal(open_holes, 0);
    assert_int_equal(inner_holes, inner);
    both_release(&r);
    sta_image_release(&position);
}

// A scene of a few points (issue 15, part 2, twenty-first round): six points near the
// centre of a view whose neighbourhood radius K / z spans the whole image (s0 3 m at
// 10 m, as a 5-point LAS file's). Every border-band pixel had its known sectors, those
// facing the image, closed by the far points and the flank test's `near` (0.2 K / z)
// reached them all: the band was a hole, and pull-push painted a frame of colour round
// an empty view. `near` is now at most the band's width: no empty pixel more than the
// band's width from a point is a hole.
static void border_band_leaves_a_sparse_scene_open(void **state)
{
    (void)state;
    enum {
        W = 192,
        H = 144
    };
    sta_view_params view = make_view(W, H);
    view.s0 = 3.0f;
    sta_image position;
    new_image(&position, W, H, 4);
    static const int pts[][2] = { { 96, 72 }, { 84, 66 },  { 106, 80 },
                                  { 90, 78 }, { 101, 65 }, { 95, 86 } };
    static unsigned char point[W * H];
    memset(point, 0, sizeof(point));
    for (size_t i = 0; i < sizeof(pts) / sizeof(pts[0]); i++) {
        set_point(&view, &position, pts[i][0], pts[i][1], 10.0f);
        point[pts[i][1] * W + pts[i][0]] = 1;
    }
    both_result r;
    run_both("six points", &view, NULL, &position, -1, &r);
    float band = sta_hpr_empty_border_px(H);
    int far = 0, far_holes = 0;
    for (int y = 0; y < H; y++) {
        for (int x = 0; x < W; x++) {
            if (!point[y * W + x] && distance_to(point, W, H, x, y) > band) {
                far++;
                far_holes += *sta_image_at(&r.pyramid_label, x, y) == STA_LABEL_HOLE;
            }
        }
    }
    printf("six points %dx%d: %d of %d empty pixels more than %.0f px from a point are holes\n", W,
           H, far_holes, far, (double)band);
    assert_true(far > 10000);
    assert_int_equal(far_holes, 0);
    both_release(&r);
    sta_image_release(&position);
}

static void street_gaps_follow_the_points(void **state)
{
    (void)state;
    // The street's scan shadows (issue 15, part 2): a receding sparse surface seen from
    // near by (neighbourhood radius K / z about 25 px, top levels 4 and 5) with a gap of
    // slanted and curved borders. Where hole turns into background must follow the
    // points, not the pyramid's 16-px and 32-px block lines: each empty pixel's
    // decision is its own (the default since issue 15's sixteenth round). The gap's core
    // stays background, and the surface away from the gap has no background specks. With
    // sta_hpr_params.block_gaps the gap's border runs along block lines (about 3x as many
    // hole/background changes across 16-px lines as elsewhere).
    enum {
        W = 192,
        H = 144
    };
    sta_view_params view = make_view(W, H);
    view.s0 = 0.015f;
    sta_image position;
    make_sparse_plane(&view, 0.6f, 130, 90, 26.0f, &position);
    static unsigned char gap[W * H], surface[W * H];
    for (int y = 0; y < H; y++) {
        for (int x = 0; x < W; x++) {
            float dx = (float)(x - 130), dy = (float)(y - 90);
            int band = 2 * x - y; // a band slanted 1:2, as a pole's shadow on a facade
            gap[y * W + x] = dx * dx + dy * dy < 26.0f * 26.0f ||
                             (band >= 70 && band < 130 && y >= 20 && y < 120);
            if (gap[y * W + x]) {
                float *p = sta_image_at(&position, x, y);
                p[0] = p[1] = p[2] = p[3] = 0.0f;
            }
            surface[y * W + x] = !gap[y * W + x];
        }
    }
    both_result blocks, r;
    sta_hpr_params by_blocks = { .block_gaps = true };
    run_both("street-like gaps, by blocks", &view, &by_blocks, &position, -1, &blocks);
    run_both("street-like gaps, the default", &view, NULL, &position, -1, &r);
    double on16 = 0.0, off16 = 0.0, on32 = 0.0, off32 = 0.0;
    double block_on16 = 0.0, block_off16 = 0.0;
    block_line_rates(&position, &blocks.pyramid_label, 16, &block_on16, &block_off16);
    block_line_rates(&position, &r.pyramid_label, 16, &on16, &off16);
    block_line_rates(&position, &r.pyramid_label, 32, &on32, &off32);
    int core = 0, core_background = 0, far = 0, far_background = 0;
    for (int y = 0; y < H; y++) {
        for (int x = 0; x < W; x++) {
            bool background = *sta_image_at(&r.pyramid_label, x, y) == STA_LABEL_BACKGROUND;
            if (gap[y * W + x] && distance_to(surface, W, H, x, y) > 10.0f) {
                core++;
                core_background += background;
            } else if (!gap[y * W + x] && sta_image_at(&position, x, y)[3] <= 0.5f &&
                       distance_to(gap, W, H, x, y) > 20.0f) {
                far++;
                far_background += background;
            }
        }
    }
    printf("street-like gaps %dx%d: hole/background changes per pair on 16-px lines %.4f, "
           "elsewhere %.4f (ratio %.2f); 32-px lines %.4f, elsewhere %.4f (ratio %.2f); gap "
           "core background %d of %d; surface 20 px off the gap background %d of %d\n",
           W, H, on16, off16, on16 / off16, on32, off32, on32 / off32, core_background, core,
           far_background, far);
    assert_true(core > 100 && far > 1000);
    assert_int_equal(core_background, core);
    // A candidate counts within 2^level pixels, so where a block's nearest point lies in
    // its far corner a pixel of a sparse surface can see one wedge empty: rare specks
    // (1 here), not more than 0.05 %.
    assert_true(far_background * 2000 <= far);
    assert_true(off16 > 0.0 && off32 > 0.0);
    assert_true(on16 < 1.5 * off16);
    assert_true(on32 < 1.5 * off32);
    printf("by blocks (the default): 16-px lines %.4f, elsewhere %.4f (ratio %.2f)\n", block_on16,
           block_off16, block_on16 / block_off16);
    assert_true(block_on16 > 2.0 * block_off16);
    both_release(&blocks);
    both_release(&r);
    sta_image_release(&position);
}

static void sparse_surfaces_fill_between_far_apart_points(void **state)
{
    (void)state;
    // A surface sampled evenly but sparsely (issue 15, part 2, sixteenth round: the near
    // beige wall of the README view at 1920x1080): one point per 6 x 6 px cell at a
    // hashed place in it, so neighbouring points lie 1 .. 11 px apart, seen with a
    // neighbourhood radius K / z of 13 .. 21 px (level 4, candidates within 16 px). A
    // pixel whose candidates leave one wedge empty was called background (black
    // triangles and wedges inside the wall; 21 pixels here before); such a pixel is
    // decided again within twice the reach. No empty pixel away from the gap and the
    // border band is background; a gap of 22 px radius in the same surface stays
    // background in its core.
    enum {
        W = 192,
        H = 144,
        CELL = 6
    };
    sta_view_params view = make_view(W, H);
    view.s0 = 0.02f;
    sta_image position;
    make_plane(&view, 2.0f, 0.6f, &position);
    for (int y = 0; y < H; y++) {
        for (int x = 0; x < W; x++) {
            int cx = x / CELL, cy = y / CELL;
            unsigned hash = ((unsigned)cx * 73856093u) ^ ((unsigned)cy * 19349663u);
            float gx = (float)(x - 140), gy = (float)(y - 72);
            bool in_gap = gx * gx + gy * gy < 22.0f * 22.0f;
            if (in_gap || x % CELL != (int)(hash % CELL) || y % CELL != (int)(hash / CELL % CELL)) {
                float *p = sta_image_at(&position, x, y);
                p[0] = p[1] = p[2] = p[3] = 0.0f;
            }
        }
    }
    both_result r;
    run_both("sparse surface 6 px", &view, NULL, &position, -1, &r);
    int inside = 0, inside_background = 0, core = 0, core_background = 0;
    for (int y = 32; y < H - 32; y++) {
        for (int x = 32; x < W - 32; x++) {
            float gx = (float)(x - 140), gy = (float)(y - 72);
            float d2 = gx * gx + gy * gy;
            bool background = *sta_image_at(&r.pyramid_label, x, y) == STA_LABEL_BACKGROUND;
            if (d2 < 8.0f * 8.0f) {
                core++;
                core_background += background;
            } else if (d2 > 40.0f * 40.0f && sta_image_at(&position, x, y)[3] <= 0.5f) {
                inside++;
                inside_background += background;
            }
        }
    }
    printf("sparse surface 6 px %dx%d: %d of %d empty pixels away from the gap and the border "
           "background; gap core background %d of %d\n",
           W, H, inside_background, inside, core_background, core);
    assert_true(inside > 3000 && core > 150);
    assert_int_equal(inside_background, 0);
    assert_int_equal(core_background, core);
    both_release(&r);
    sta_image_release(&position);
}

static void early_exit_keeps_every_label(void **state)
{
    (void)state;
    // The shader stops a pixel's rings once it is HIDDEN or HOLE (coarse levels first);
    // the twin runs every level. Not one label may differ, not even near the threshold:
    // a sparse tilted plane (holes settle after one ring, points at the border keep
    // their open outside sectors), the same with a wide gap (background inside), and
    // two planes (hidden far points settle on the near plane's ring).
    sta_image position;
    both_result r;
    int differing = 0, holes = 0, hidden = 0;
    for (int scene = 0; scene < 3; scene++) {
        static unsigned char truth[320 * 240];
        sta_view_params view = scene == 2 ? make_view(320, 240) : make_view(160, 120);
        if (scene == 2) {
            make_two_planes(&view, &position, truth);
        } else {
            make_sparse_plane(&view, 1.0f, 80, 60, scene == 1 ? 25.0f : 0.0f, &position);
        }
        differing +=
            run_both(scene == 2 ? "exit: planes" : "exit: sparse", &view, NULL, &position, -1, &r);
        holes += count_label(&r.pyramid_label, STA_LABEL_HOLE);
        hidden += count_label(&r.pyramid_label, STA_LABEL_HIDDEN);
        both_release(&r);
        sta_image_release(&position);
    }
    printf("early exit: %d holes, %d hidden points, %d labels differ\n", holes, hidden, differing);
    assert_true(holes > 10000 && hidden > 100);
    assert_int_equal(differing, 0);
}

static void coincident_points_are_skipped(void **state)
{
    (void)state;
    // Every pixel holds the same point: all neighbours coincide, so every sector stays
    // open (mean 1) and nothing is NaN.
    sta_view_params view = make_view(37, 23);
    sta_image position;
    new_image(&position, 37, 23, 4);
    for (int i = 0; i < 37 * 23; i++) {
        float *p = position.data + 4 * i;
        p[0] = 0.1f;
        p[1] = -0.2f;
        p[2] = -5.0f;
        p[3] = 1.0f;
    }
    // And one point at the eye (|y| = 0), one of the points' neighbours.
    float *eye = sta_image_at(&position, 3, 3);
    eye[0] = eye[1] = eye[2] = 0.0f;
    both_result r;
    run_both("coincident", &view, NULL, &position, 4, &r);
    for (int i = 0; i < 37 * 23; i++) {
        assert_true(r.pyramid_label.data[i] == STA_LABEL_VISIBLE);
        assert_true(r.exhaustive_label.data[i] == STA_LABEL_VISIBLE);
        assert_true(isfinite(r.pyramid_mean.data[i]));
    }
    both_release(&r);
    sta_image_release(&position);
}

// A plane seen at a grazing angle (tilted 80 deg) whose points are moved along their
// rays by up to +-0.5 s0 (the depth noise of a scanned road seen from eye height), on
// 60 % of the pixels. The paper's operator (no gap, no own-surface rule) hides points
// behind their own surface's neighbours a few centimetres nearer; with the occluder gap
// (1.5 s0) every point stays visible.
static void occluder_gap_keeps_noisy_surfaces(void **state)
{
    (void)state;
    sta_view_params view = make_view(160, 120);
    view.s0 = 0.1f; // a coarse scan: 3 px apart at 5 m, noise of the order of a pixel
    sta_image plane, noisy;
    make_plane(&view, 5.0f, 1.396f, &plane);
    new_image(&noisy, 160, 120, 4);
    rng_state = 15;
    int points = 0;
    for (int y = 0; y < 120; y++) {
        for (int x = 0; x < 160; x++) {
            double u = rng_uniform(), v = rng_uniform();
            if (u < 0.6) {
                float d = -sta_image_at(&plane, x, y)[2];
                set_point(&view, &noisy, x, y, d + (float)(v - 0.5) * view.s0);
                points++;
            }
        }
    }
    sta_hpr_params paper = { .occluder_gap_s0 = -1.0f, .surface_fit_s0 = -1.0f };
    both_result off, on;
    assert_int_equal(run_both("noisy, no gap", &view, &paper, &noisy, -1, &off), 0);
    assert_int_equal(run_both("noisy, gap", &view, NULL, &noisy, -1, &on), 0);
    int hidden_off = count_label(&off.pyramid_label, STA_LABEL_HIDDEN);
    int hidden_on = count_label(&on.pyramid_label, STA_LABEL_HIDDEN);
    printf("noisy grazing plane, %d points: %d hidden without the gap, %d with\n", points,
           hidden_off, hidden_on);
    assert_true(hidden_off > points / 200); // the defect the gap removes is there
    assert_int_equal(hidden_on, 0);
    both_release(&off);
    both_release(&on);

    // Two fronto-parallel planes 3 gaps apart, near points on the even pixels, far ones
    // between them: away from the image edges every far point is hidden; with a gap
    // wider than the planes' distance, none is (nothing is nearer by more than it).
    float apart = 3.0f * STA_HPR_OCCLUDER_GAP_S0 * view.s0;
    sta_image layered;
    new_image(&layered, 160, 120, 4);
    for (int y = 0; y < 120; y++) {
        for (int x = 0; x < 160; x++) {
            set_point(&view, &layered, x, y, (x + y) % 2 == 0 ? 5.0f : 5.0f + apart);
        }
    }
    sta_hpr_params wide = { .occluder_gap_s0 = 3.5f * STA_HPR_OCCLUDER_GAP_S0 };
    assert_int_equal(run_both("layers", &view, NULL, &layered, -1, &on), 0);
    assert_int_equal(run_both("layers, wide", &view, &wide, &layered, -1, &off), 0);
    for (int y = 2; y < 118; y++) {
        for (int x = 2; x < 158; x++) {
            float want = (x + y) % 2 == 0 ? STA_LABEL_VISIBLE : STA_LABEL_HIDDEN;
            assert_true(*sta_image_at(&on.pyramid_label, x, y) == want);
        }
    }
    assert_int_equal(count_label(&off.pyramid_label, STA_LABEL_VISIBLE), 160 * 120);
    both_release(&off);
    both_release(&on);
    sta_image_release(&layered);
    sta_image_release(&plane);
    sta_image_release(&noisy);
}

// Scene of marked_points_hide_only_nearby: a dense wall at 10 m on the left (x < 100),
// sky on the right; a sparse canopy of marked points (volumetric class) at 4 m every 8
// px; a dense marked cluster over the wall at [16, 44)^2 with a wall point every 4 px
// seen through it; a dense near surface (unmarked, 2 m) at [56, 84)^2 with a marked
// point every 4 px seen through it.
enum marked_kind {
    M_WALL,
    M_CANOPY,
    M_CLUSTER_WALL,
    M_PATCH_MARKED,
    M_SKY,
    M_OTHER
};

static bool in_square(int x, int y, int lo, int hi)
{
    return x >= lo && x < hi && y >= lo && y < hi;
}

static enum marked_kind marked_point(const sta_view_params *view, sta_image *position, int x, int y)
{
    bool grid4 = x % 4 == 0 && y % 4 == 0;
    float *p = sta_image_at(position, x, y);
    if (in_square(x, y, 56, 84)) {
        set_point(view, position, x, y, grid4 ? 4.0f : 2.0f);
        p[3] = grid4 ? STA_POSITION_W_MARKED : 1.0f;
        return grid4 && in_square(x, y, 60, 80) ? M_PATCH_MARKED : M_OTHER;
    }
    if (in_square(x, y, 16, 44)) {
        set_point(view, position, x, y, grid4 ? 10.0f : 4.0f);
        p[3] = grid4 ? 1.0f : STA_POSITION_W_MARKED;
        return grid4 && in_square(x, y, 20, 40) ? M_CLUSTER_WALL : M_OTHER;
    }
    bool canopy = x % 8 == 4 && y % 8 == 4 && x >= 8 && x < 152 && y >= 8 && y < 112;
    if (canopy) {
        set_point(view, position, x, y, 4.0f);
        p[3] = STA_POSITION_W_MARKED;
        bool clear = !in_square(x, y, 12, 48) && !in_square(x, y, 52, 88);
        return clear ? M_CANOPY : M_OTHER;
    }
    if (x < 100) {
        set_point(view, position, x, y, 10.0f);
        bool clear = !in_square(x, y, 12, 48) && !in_square(x, y, 52, 88) && x >= 4 && y >= 4 &&
                     x < 96 && y < 116;
        return clear ? M_WALL : M_OTHER;
    }
    p[0] = p[1] = p[2] = p[3] = 0.0f;
    return x >= 108 && x < 152 && y >= 8 && y < 112 ? M_SKY : M_OTHER;
}

// A plane seen at a grazing angle, points on 60 % of its pixels moved along their rays
// by up to +-NOISE s0: the coarse rings bring the plane's own nearer points (the nearest
// of each block) to every pixel, and with the occluder gap alone part of the plane is
// hidden; with the own-surface rule every point stays visible. A real occluder still
// hides it: a fronto-parallel square 1 m nearer on every other pixel of its footprint
// (a wire mesh in front of a facade) hides all the plane's points behind it.
#define GRAZING_WALL_X_M 1.0f  /* the wall: the plane x = -1 m, along the view direction */
#define GRAZING_FAR_M    40.0f /* no points beyond (it would reach the horizon) */
#define GRAZING_NOISE_S0 0.5f  /* depth noise, +- this many s0 along the ray */
#define GRAZING_POLE_X   40    /* the pole's column (the wall 3.5 m away there) */

// Depth of the wall x = -GRAZING_WALL_X_M on pixel column px's rays; 0 where it misses.
static float wall_depth(const sta_view_params *view, int px)
{
    float tan_x = tanf(0.5f * view->fov_y) * (float)view->width_px / (float)view->height_px;
    float ndc_x = ((float)px + 0.5f) / (float)view->width_px * 2.0f - 1.0f;
    float d = ndc_x < 0.0f ? GRAZING_WALL_X_M / (-ndc_x * tan_x) : 0.0f;
    return d <= GRAZING_FAR_M ? d : 0.0f;
}

// Hidden points among the wall's points (position w = 1 and depth within 0.5 m of the
// wall) in columns [x0, x1) and rows 8..111.
static int wall_hidden(const sta_view_params *view, const sta_image *scene, const sta_image *label,
                       int x0, int x1, int *points)
{
    int hidden = 0;
    *points = 0;
    for (int y = 8; y < 112; y++) {
        for (int x = x0; x < x1; x++) {
            const float *p = sta_image_at(scene, x, y);
            if (p[3] > 0.5f && fabsf(-p[2] - wall_depth(view, x)) < 0.5f) {
                (*points)++;
                hidden += *sta_image_at(label, x, y) == STA_LABEL_HIDDEN;
            }
        }
    }
    return hidden;
}

// A wall along the view direction (seen at a grazing angle, as the street's facades),
// a point on every pixel moved along its ray by up to +-GRAZING_NOISE_S0 s0, and a pole
// 1 m in front of it (every other pixel of one column). With the occluder gap alone the
// wall's points on the pole's near side are hidden: the pole closes the sectors towards
// it, the wall's own nearer points (the nearest of each coarse block) all the others.
// With the own-surface rule those points stay visible. A real occluder still hides the
// wall: a square 1 m in front of it on every other pixel (a wire mesh) hides every wall
// point between its points. Shader and twin agree label for label.
static void own_surface_keeps_grazing_planes(void **state)
{
    (void)state;
    sta_view_params view = make_view(160, 120);
    sta_image scene;
    new_image(&scene, 160, 120, 4);
    rng_state = 7;
    for (int y = 0; y < 120; y++) {
        for (int x = 0; x < 160; x++) {
            float noise = (float)(rng_uniform() - 0.5) * 2.0f * GRAZING_NOISE_S0 * view.s0;
            float d = wall_depth(&view, x);
            if (x == GRAZING_POLE_X && y % 2 == 0) {
                set_point(&view, &scene, x, y, d - 1.0f);
            } else if (d > 0.0f) {
                set_point(&view, &scene, x, y, d + noise);
            }
        }
    }
    sta_hpr_params gap_only = { .surface_fit_s0 = -1.0f };
    both_result off, on;
    assert_int_equal(run_both("pole, gap only", &view, &gap_only, &scene, -1, &off), 0);
    assert_int_equal(run_both("pole, own surface", &view, NULL, &scene, -1, &on), 0);
    int near_side, all;
    int hidden_off = wall_hidden(&view, &scene, &off.pyramid_label, GRAZING_POLE_X - 6,
                                 GRAZING_POLE_X - 1, &near_side);
    int hidden_on = wall_hidden(&view, &scene, &on.pyramid_label, GRAZING_POLE_X - 6,
                                GRAZING_POLE_X - 1, &near_side);
    int hidden_all = wall_hidden(&view, &scene, &on.pyramid_label, 0, 160, &all);
    printf("wall beside the pole (2-6 px on its near side), %d points: %d hidden with the gap "
           "alone, %d with the own surface (%d of all %d wall points)\n",
           near_side, hidden_off, hidden_on, hidden_all, all);
    assert_true(hidden_off > near_side / 2); // the defect the rule removes is there
    assert_int_equal(hidden_on, 0);
    both_release(&off);
    both_release(&on);

    // The mesh: x in [44, 60) (the wall 4.0 ... 7.3 m away), y in [40, 80), on the
    // pixels with x + y even.
    for (int y = 40; y < 80; y++) {
        for (int x = 44; x < 60; x++) {
            if ((x + y) % 2 == 0) {
                set_point(&view, &scene, x, y, wall_depth(&view, x) - 1.0f);
            }
        }
    }
    assert_int_equal(run_both("mesh in front", &view, NULL, &scene, -1, &on), 0);
    int behind = 0, behind_hidden = 0;
    for (int y = 42; y < 78; y++) {
        for (int x = 46; x < 58; x++) {
            if ((x + y) % 2 == 1) {
                behind++;
                behind_hidden += *sta_image_at(&on.pyramid_label, x, y) == STA_LABEL_HIDDEN;
            }
        }
    }
    printf("mesh: %d of %d wall points behind it hidden\n", behind_hidden, behind);
    assert_int_equal(behind_hidden, behind);
    both_release(&on);
    sta_image_release(&scene);
}

// Marked points (position w = STA_POSITION_W_MARKED, a volumetric class) are labelled
// like any point but close a sector only within STA_HPR_MARKED_REACH_S0 s0 of the pixel:
// a wall behind a sparse canopy stays visible (with an unlimited reach, the rule before,
// it is hidden), a wall point seen through a dense marked cluster is still hidden, a
// marked point behind a dense surface is hidden, and the sky between canopy points is
// background, not a hole to fill. Shader and twin agree label for label.
static void marked_points_hide_only_nearby(void **state)
{
    (void)state;
    sta_view_params view = make_view(160, 120);
    view.s0 = 0.01f; // the reach at 4 m: 8 s0 = 2.8 px
    // A neighbourhood of 30 s0 (10.6 px at 4 m, candidates up to twice that), so that
    // the canopy's points 8 px apart would close every sector of the wall behind.
    sta_image position;
    new_image(&position, 160, 120, 4);
    unsigned char *kind = sta_alloc_array(160 * 120, 1);
    assert_non_null(kind);
    for (int y = 0; y < 120; y++) {
        for (int x = 0; x < 160; x++) {
            kind[y * 160 + x] = (unsigned char)marked_point(&view, &position, x, y);
        }
    }
    sta_hpr_params wide = { .s_hpr = 30.0f * view.s0 };
    // The rule before, with the empty pixels' rule before it too (by blocks): per pixel
    // (the default), the sky stays open without the reach as well (below).
    sta_hpr_params unlimited = { .s_hpr = wide.s_hpr,
                                 .marked_reach_s0 = -1.0f,
                                 .block_gaps = true };
    both_result rule, before;
    assert_int_equal(run_both("marked", &view, &wide, &position, -1, &rule), 0);
    assert_int_equal(run_both("marked, any reach", &view, &unlimited, &position, -1, &before), 0);
    int count[M_OTHER] = { 0 }, want[M_OTHER] = { 0 }, before_want[M_OTHER] = { 0 };
    const float expect[M_OTHER] = { STA_LABEL_VISIBLE, STA_LABEL_VISIBLE, STA_LABEL_HIDDEN,
                                    STA_LABEL_HIDDEN, STA_LABEL_BACKGROUND };
    for (int i = 0; i < 160 * 120; i++) {
        if (kind[i] == M_OTHER) {
            continue;
        }
        count[kind[i]]++;
        want[kind[i]] += rule.pyramid_label.data[i] == expect[kind[i]];
        before_want[kind[i]] += before.pyramid_label.data[i] == expect[kind[i]];
    }
    const char *names[M_OTHER] = { "wall behind canopy visible", "canopy visible",
                                   "wall in cluster hidden", "marked behind surface hidden",
                                   "sky between canopy background" };
    for (int k = 0; k < M_OTHER; k++) {
        printf("%-32s %4d of %4d (any reach: %4d)\n", names[k], want[k], count[k], before_want[k]);
        assert_true(count[k] > 0);
    }
    // Every wall point and canopy point visible, every sky pixel background; the
    // cluster's wall points and the marked points behind the surface hidden.
    for (int k = 0; k < M_OTHER; k++) {
        assert_int_equal(want[k], count[k]);
    }
    // Before the rule the canopy hid most of the wall and closed the sky. (Since issue 15
    // part 2, by default, empty pixels count candidates within 2^level pixels
    // only: the crown points lie farther apart, so the sky stays open there without the
    // reach as well.)
    assert_true(before_want[M_WALL] < count[M_WALL] / 2);
    assert_true(before_want[M_SKY] < count[M_SKY] / 2);
    // The sparse operator's anchor and refinement programs apply the rule too: the
    // GPU's sparse labels are the twin's copy steps over the GPU's full labels, and the
    // wall behind the canopy stays visible there as well.
    sta_image full, sparse, expected;
    gpu_pyramid(&view, &wide, &position, &full, NULL);
    assert_memory_equal(full.data, rule.pyramid_label.data, sizeof(float) * 160 * 120);
    sta_hpr_params wide_sparse = wide;
    wide_sparse.sparse = true;
    gpu_pyramid(&view, &wide_sparse, &position, &sparse, NULL);
    new_image(&expected, 160, 120, 1);
    sta_hpr_ref_sparse_labels(&position, &full, &expected);
    assert_memory_equal(expected.data, sparse.data, sizeof(float) * 160 * 120);
    for (int i = 0; i < 160 * 120; i++) {
        if (kind[i] == M_WALL) {
            assert_true(sparse.data[i] == STA_LABEL_VISIBLE);
        }
    }
    sta_image_release(&full);
    sta_image_release(&sparse);
    sta_image_release(&expected);
    both_release(&rule);
    both_release(&before);
    sta_image_release(&position);
    sta_free(kind);
}

// See-through returns (issue 15, sixteenth round): a wall at 10 m with a window
// ([40, 120) x [30, 90)) whose glass answers one pulse in nine (position w =
// STA_POSITION_W_SEE_THROUGH on every third pixel of every third row) and a room wall at
// 14 m seen through it on the other pixels; left of the window, in [34, 40), room points
// show on every other pixel of the wall (the scanner saw them through the window from its
// angle; from here they lie behind the wall). Glass kinds: how the window's sparse
// returns are marked, or left out.
enum glass_kind {
    GLASS_SEE_THROUGH,
    GLASS_PLAIN, // w = 1: what the pipeline wrote before the rule (and GL_POINTS writes)
    GLASS_NONE   // the room point on those pixels too
};

#define WINDOW_X0       40
#define WINDOW_X1       120
#define WINDOW_Y0       30
#define WINDOW_Y1       90
#define WINDOW_STRIP_X0 34

static void glass_scene(const sta_view_params *view, enum glass_kind glass, sta_image *position)
{
    for (int y = 0; y < view->height_px; y++) {
        for (int x = 0; x < view->width_px; x++) {
            bool rows = y >= WINDOW_Y0 && y < WINDOW_Y1;
            bool window = rows && x >= WINDOW_X0 && x < WINDOW_X1;
            bool strip = rows && x >= WINDOW_STRIP_X0 && x < WINDOW_X0 && (x + y) % 2 == 1;
            bool pane = window && x % 3 == 0 && y % 3 == 0 && glass != GLASS_NONE;
            set_point(view, position, x, y, (window && !pane) || strip ? 14.0f : 10.0f);
            if (pane && glass == GLASS_SEE_THROUGH) {
                sta_image_at(position, x, y)[3] = STA_POSITION_W_SEE_THROUGH;
            }
        }
    }
}

// Visible room points in the window's interior (12 px and more from its edges, beyond
// the wall's candidates) and in the strip's two columns next to the window.
static void glass_counts(const sta_image *position, const sta_image *label, int *interior,
                         int *interior_visible, int *strip, int *strip_visible)
{
    *interior = *interior_visible = *strip = *strip_visible = 0;
    for (int y = WINDOW_Y0; y < WINDOW_Y1; y++) {
        for (int x = WINDOW_STRIP_X0; x < WINDOW_X1; x++) {
            const float *p = sta_image_at(position, x, y);
            if (!(p[2] < -12.0f)) {
                continue; // not a room point
            }
            bool visible = *sta_image_at(label, x, y) == STA_LABEL_VISIBLE;
            if (x >= WINDOW_X0 + 12 && x < WINDOW_X1 - 12 && y >= WINDOW_Y0 + 12 &&
                y < WINDOW_Y1 - 12) {
                (*interior)++;
                *interior_visible += visible;
            } else if (x >= WINDOW_X0 - 2 && x < WINDOW_X0) {
                (*strip)++;
                *strip_visible += visible;
            }
        }
    }
}

// Room points seen through sparse see-through glass stay visible (with the glass as
// plain points, the rule off, they are hidden), and room points behind the wall beside
// the window are still hidden: the wall is a solid candidate there, so the glass closes
// their sectors towards the window (with no glass at all they show). Shader and twin
// agree label for label; the sparse operator's programs apply the rule too.
static void see_through_glass_needs_a_solid_wall(void **state)
{
    (void)state;
    sta_view_params view = make_view(160, 120);
    sta_image position[3];
    both_result r[3];
    int interior[3], interior_visible[3], strip[3], strip_visible[3];
    const char *names[3] = { "glass see-through", "glass plain", "no glass" };
    for (int g = 0; g < 3; g++) {
        new_image(&position[g], 160, 120, 4);
        glass_scene(&view, (enum glass_kind)g, &position[g]);
        assert_int_equal(run_both(names[g], &view, NULL, &position[g], -1, &r[g]), 0);
        glass_counts(&position[g], &r[g].pyramid_label, &interior[g], &interior_visible[g],
                     &strip[g], &strip_visible[g]);
        printf("%-18s room points visible: window interior %d of %d, beside the window %d of "
               "%d\n",
               names[g], interior_visible[g], interior[g], strip_visible[g], strip[g]);
        assert_true(interior[g] > 500 && strip[g] > 50);
    }
    // Through the glass every room point shows; without the rule most are hidden.
    assert_int_equal(interior_visible[GLASS_SEE_THROUGH], interior[GLASS_SEE_THROUGH]);
    assert_true(interior_visible[GLASS_PLAIN] < interior[GLASS_PLAIN] / 2);
    // Beside the window the rule frees none (those visible with plain glass too lie on
    // rows without a pane next to them: the sector operator's own limit), where no glass
    // at all would free them all.
    assert_int_equal(strip_visible[GLASS_SEE_THROUGH], strip_visible[GLASS_PLAIN]);
    assert_true(strip_visible[GLASS_SEE_THROUGH] <= strip[GLASS_SEE_THROUGH] / 4);
    assert_int_equal(strip_visible[GLASS_NONE], strip[GLASS_NONE]);
    // The sparse operator: its labels are the twin's copy steps over the GPU's full ones.
    sta_hpr_params sparse_params = { .sparse = true };
    sta_image full, sparse, expected;
    gpu_pyramid(&view, NULL, &position[GLASS_SEE_THROUGH], &full, NULL);
    assert_memory_equal(full.data, r[GLASS_SEE_THROUGH].pyramid_label.data,
                        sizeof(float) * 160 * 120);
    gpu_pyramid(&view, &sparse_params, &position[GLASS_SEE_THROUGH], &sparse, NULL);
    new_image(&expected, 160, 120, 1);
    sta_hpr_ref_sparse_labels(&position[GLASS_SEE_THROUGH], &full, &expected);
    assert_memory_equal(expected.data, sparse.data, sizeof(float) * 160 * 120);
    sta_image_release(&full);
    sta_image_release(&sparse);
    sta_image_release(&expected);
    for (int g = 0; g < 3; g++) {
        both_release(&r[g]);
        sta_image_release(&position[g]);
    }
}

// Without the see-through rule (sta_hpr_params.no_see_through: positions from depth, the
// GL_POINTS path, hold no see-through returns; issue 15, sixteenth round, cost margin) the
// programs leave the rule out: on positions without see-through returns they give the
// rule's labels exactly (every pixel and the sparse operator), and on glass marked
// see-through the returns count as plain points, in the shader as in the twin.
static void no_see_through_rule_when_positions_hold_none(void **state)
{
    (void)state;
    sta_view_params view = make_view(160, 120);
    const size_t bytes = sizeof(float) * 160 * 120;
    sta_image position, with_rule, without_rule;
    new_image(&position, 160, 120, 4);
    for (int sparse = 0; sparse < 2; sparse++) {
        glass_scene(&view, GLASS_PLAIN, &position);
        sta_hpr_params on = { .sparse = sparse },
                       off = { .sparse = sparse, .no_see_through = true };
        gpu_pyramid(&view, &on, &position, &with_rule, NULL);
        gpu_pyramid(&view, &off, &position, &without_rule, NULL);
        assert_memory_equal(with_rule.data, without_rule.data, bytes);
        sta_image_release(&with_rule);
        sta_image_release(&without_rule);
    }
    // Glass marked see-through, the rule off: shader = twin, and the room behind the glass
    // is hidden as behind plain glass (the rule on shows all of it:
    // see_through_glass_needs_a_solid_wall).
    glass_scene(&view, GLASS_SEE_THROUGH, &position);
    sta_hpr_params off = { .no_see_through = true };
    both_result r;
    assert_int_equal(run_both("glass, rule off", &view, &off, &position, -1, &r), 0);
    int interior, interior_visible, strip, strip_visible;
    glass_counts(&position, &r.pyramid_label, &interior, &interior_visible, &strip, &strip_visible);
    printf("rule off: room points visible in the window interior %d of %d\n", interior_visible,
           interior);
    assert_true(interior > 500);
    assert_true(interior_visible < interior / 2);
    both_release(&r);
    sta_image_release(&position);
}

static void allocation_failures_are_clean(void **state)
{
    (void)state;
    // Every allocation of the twin failing in turn: STA_ERR_NOMEM, nothing leaked
    // (LeakSanitizer), the pyramid zeroed.
    sta_view_params view = make_view(37, 23);
    sta_image position, label;
    make_random(&view, 5, 0.5, &position);
    new_image(&label, 37, 23, 1);
    int failures = 0;
    for (long n = 0;; n++) {
        sta_error err = { 0 };
        sta_alloc_fail_after(n);
        sta_status status = sta_hpr_ref_pyramid(&view, NULL, &position, &label, &err);
        sta_alloc_fail_after(-1);
        if (status == STA_OK) {
            break;
        }
        assert_int_equal(status, STA_ERR_NOMEM);
        failures++;
    }
    assert_int_equal(failures, sta_hpr_pyramid_levels(37, 23)); // one image per level
    sta_image_release(&label);
    sta_image_release(&position);
}

// Label textures are R16F (STA_GL_LABEL_FORMAT): every STA_LABEL_* value goes there and
// back unchanged, and an image of other than 1 channel is refused.
static void label_texture_round_trip(void **state)
{
    (void)state;
    sta_error err = { 0 };
    const float labels[] = { STA_LABEL_VISIBLE, STA_LABEL_HIDDEN, STA_LABEL_HOLE,
                             STA_LABEL_BACKGROUND };
    sta_image in, out;
    new_image(&in, 7, 5, 1);
    for (int i = 0; i < 7 * 5; i++) {
        in.data[i] = labels[(i * 7 / 3) % 4];
    }
    GLuint texture = 0;
    assert_int_equal(sta_gl_label_texture_from_image(&in, &texture, &err), STA_OK);
    GLint format = 0;
    glGetTextureLevelParameteriv(texture, 0, GL_TEXTURE_INTERNAL_FORMAT, &format);
    assert_int_equal(format, STA_GL_LABEL_FORMAT);
    assert_int_equal(sta_gl_texture_to_image(texture, 0, 1, &out, &err), STA_OK);
    assert_memory_equal(out.data, in.data, sizeof(float) * 7 * 5);
    glDeleteTextures(1, &texture);
    sta_image_release(&out);
    sta_image_release(&in);
    sta_image rgb;
    new_image(&rgb, 2, 2, 3);
    assert_int_equal(sta_gl_label_texture_from_image(&rgb, &texture, &err), STA_ERR_ARG);
    assert_non_null(strstr(err.message, "1-channel"));
    sta_image_release(&rgb);
}

static void bad_arguments_are_refused(void **state)
{
    (void)state;
    sta_error err = { 0 };
    GLuint texture = 0;
    assert_int_equal(sta_hpr_pyramid_texture_create(0, 10, &texture, &err), STA_ERR_ARG);
    assert_int_equal(texture, 0);
    sta_view_params view = make_view(40, 30);
    GLuint position_tex, small_pyramid, label_tex;
    assert_int_equal(sta_gl_texture_create(40, 30, 4, 1, &position_tex, &err), STA_OK);
    assert_int_equal(sta_hpr_pyramid_texture_create(20, 30, &small_pyramid, &err), STA_OK);
    assert_int_equal(sta_gl_label_texture_create(40, 30, &label_tex, &err), STA_OK);
    assert_int_equal(
        sta_hpr_pass_run_pyramid(&pass, &view, NULL, position_tex, small_pyramid, label_tex, &err),
        STA_ERR_ARG);
    printf("hpr refused: %s\n", err.message);
    assert_int_equal(
        sta_hpr_pass_run_exhaustive(&pass, &view, NULL, -1, position_tex, label_tex, &err),
        STA_ERR_ARG);
    glDeleteTextures(1, &position_tex);
    glDeleteTextures(1, &small_pyramid);
    glDeleteTextures(1, &label_tex);
    sta_image wrong;
    new_image(&wrong, 4, 4, 1);
    sta_hpr_pyramid pyramid;
    assert_int_equal(sta_hpr_ref_build_pyramid(&wrong, &pyramid, &err), STA_ERR_ARG);
    sta_hpr_ref_pyramid_release(&pyramid);
    sta_image_release(&wrong);
}

static const struct CMUnitTest tests[] = {
    cmocka_unit_test(pyramid_sizes_and_levels),
    cmocka_unit_test(sectors_follow_the_angle),
    cmocka_unit_test(adaptive_level_is_rounded_eq1),
    cmocka_unit_test_setup_teardown(shader_matches_twin_on_random_buffers, setup, teardown),
    cmocka_unit_test_setup_teardown(near_plane_over_far_plane_known_truth, setup, teardown),
    cmocka_unit_test_setup_teardown(staged_and_image_stores_build_the_same_pyramid, setup,
                                    teardown),
    cmocka_unit_test(sparse_copy_step_rules),
    cmocka_unit_test(sparse_copy_steps_in_turn),
    cmocka_unit_test_setup_teardown(sparse_operator_matches_twin, setup, teardown),
    cmocka_unit_test_setup_teardown(labels_match_with_thresholds_on_the_means, setup, teardown),
    cmocka_unit_test_setup_teardown(empty_frame_is_background, setup, teardown),
    cmocka_unit_test_setup_teardown(single_point_is_visible, setup, teardown),
    cmocka_unit_test_setup_teardown(full_planes_are_visible, setup, teardown),
    cmocka_unit_test_setup_teardown(near_plane_and_huge_depth, setup, teardown),
    cmocka_unit_test_setup_teardown(coincident_points_are_skipped, setup, teardown),
    cmocka_unit_test_setup_teardown(early_exit_keeps_every_label, setup, teardown),
    cmocka_unit_test_setup_teardown(surfaces_fill_to_the_image_edge, setup, teardown),
    cmocka_unit_test_setup_teardown(border_band_leaves_a_sparse_scene_open, setup, teardown),
    cmocka_unit_test_setup_teardown(border_band_leaves_open_space_beside_a_silhouette, setup,
                                    teardown),
    cmocka_unit_test_setup_teardown(gaps_have_no_block_edges, setup, teardown),
    cmocka_unit_test_setup_teardown(street_gaps_follow_the_points, setup, teardown),
    cmocka_unit_test_setup_teardown(sparse_surfaces_fill_between_far_apart_points, setup, teardown),
    cmocka_unit_test_setup_teardown(occluder_gap_keeps_noisy_surfaces, setup, teardown),
    cmocka_unit_test_setup_teardown(marked_points_hide_only_nearby, setup, teardown),
    cmocka_unit_test_setup_teardown(own_surface_keeps_grazing_planes, setup, teardown),
    cmocka_unit_test_setup_teardown(see_through_glass_needs_a_solid_wall, setup, teardown),
    cmocka_unit_test_setup_teardown(no_see_through_rule_when_positions_hold_none, setup, teardown),
    cmocka_unit_test(allocation_failures_are_clean),
    cmocka_unit_test_setup_teardown(label_texture_round_trip, setup, teardown),
    cmocka_unit_test_setup_teardown(bad_arguments_are_refused, setup, teardown),
};

STA_TEST_MAIN(tests)
