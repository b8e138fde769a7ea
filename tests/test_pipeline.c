/* SPDX-License-Identifier: MIT
 * The whole screen-space pipeline inside the viewer, on llvmpipe: every mode runs on a
 * real rendered scene and does what it is for (HPR removes the wall seen through the
 * sphere, pull-push fills the gaps, shading lights the sphere from the eye), and an
 * empty frame stays background in every mode. */
#include "scene_fixture.h"
#include "test_support.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "render/bindings.h"
#include "render/gl.h"
#include "render/image_io.h"
#include "render/scene.h"

enum {
    W = 240,
    H = 180,
    POINTS = 20000
};

static sta_gl_headless gl;
static char scene_path[4096];

static int setup(void **state)
{
    (void)state;
    sta_error err = { 0 };
    if (sta_gl_headless_create(&gl, &err) != STA_OK) {
        return -1;
    }
    const double origin[3] = { 0, 0, 0 };
    sta_fixture_build_scene("pipeline", POINTS, origin, scene_path, sizeof(scene_path));
    return 0;
}

static int teardown(void **state)
{
    (void)state;
    sta_gl_headless_destroy(&gl);
    return 0;
}

// Renders (fully loaded) in `mode` and returns the RGBA image (caller frees).
static uint8_t *render_mode(int mode, int normals, const sta_camera *camera,
                            sta_frame_stats *out_stats)
{
    sta_scene *scene = NULL;
    sta_error err = { 0 };
    sta_scene_options options = { 0 };
    assert_int_equal(sta_scene_open(scene_path, &options, &scene, &err), STA_OK);
    sta_pipeline_options pipeline = { .mode = mode, .normals = normals };
    sta_scene_set_pipeline(scene, &pipeline);
    sta_scene_set_timing(scene, true);
    // Elevation colours never come near the HPR label colours (pure red, dark green).
    sta_scene_set_colour_mode(scene, STA_COLOUR_ELEVATION);
    sta_render_target target = { 0 };
    sta_frame_stats stats = sta_fixture_render_complete(scene, camera, &target);
    uint8_t *rgba = malloc((size_t)W * H * 4);
    assert_non_null(rgba);
    sta_render_target_read_rgba(&target, rgba);
    const char *keep = getenv("STA_TEST_IMAGES"); // a folder to keep the pictures in
    if (keep) {
        char path[4096];
        snprintf(path, sizeof(path), "%s/pipeline_%s_%s.png", keep, sta_pipeline_mode_name(mode),
                 sta_normal_method_name(normals));
        sta_png_write_rgba(path, rgba, W, H, NULL);
    }
    sta_render_target_release(&target);
    sta_scene_close(scene);
    *out_stats = stats;
    return rgba;
}

static size_t lit_pixels(const uint8_t *rgba)
{
    size_t n = 0;
    for (int i = 0; i < W * H; i++) {
        n += rgba[4 * i] || rgba[4 * i + 1] || rgba[4 * i + 2];
    }
    return n;
}

static void every_mode_does_its_job(void **state)
{
    (void)state;
    const double origin[3] = { 0, 0, 0 };
    sta_camera camera = sta_fixture_camera(origin, W, H);
    sta_frame_stats stats;
    uint8_t *raw = render_mode(STA_PIPELINE_RAW, 0, &camera, &stats);
    size_t raw_lit = lit_pixels(raw);
    assert_true(raw_lit > 1000);

    // HPR: wall points seen through the sphere's gaps are hidden (pure red pixels),
    // and there are some; most lit points stay visible.
    uint8_t *hpr = render_mode(STA_PIPELINE_HPR, 0, &camera, &stats);
    assert_true(stats.timing.ms[STA_PASS_HPR] > 0.0);
    size_t hidden = 0, holes = 0;
    for (int i = 0; i < W * H; i++) {
        const uint8_t *p = hpr + 4 * i;
        hidden += p[0] > 200 && p[1] < 40 && p[2] < 40;
        holes += p[0] < 40 && p[1] > 70 && p[1] < 110 && p[2] < 40;
    }
    printf("raw lit %zu, hidden %zu, holes %zu\n", raw_lit, hidden, holes);
    assert_true(hidden > 50);
    assert_true(hidden < raw_lit / 2);
    assert_true(holes > 1000);

    // Fill: the gaps between the wall's points are filled: inside the wall's outline
    // (less a 3-pixel border) nearly every pixel is lit, against few in the raw image.
    uint8_t *fill = render_mode(STA_PIPELINE_FILL, 0, &camera, &stats);
    const double corner_a[3] = { -15, 20, -10 }, corner_b[3] = { 15, 20, 10 };
    double ax, ay, bx, by, depth;
    assert_true(sta_camera_project(&camera, corner_a, &ax, &ay, &depth));
    assert_true(sta_camera_project(&camera, corner_b, &bx, &by, &depth));
    int x0 = (int)fmin(ax, bx) + 3, x1 = (int)fmax(ax, bx) - 3;
    int y0 = (int)fmin(ay, by) + 3, y1 = (int)fmax(ay, by) - 3;
    x0 = x0 < 0 ? 0 : x0;
    y0 = y0 < 0 ? 0 : y0;
    x1 = x1 >= W ? W - 1 : x1;
    y1 = y1 >= H ? H - 1 : y1;
    size_t inside = 0, filled = 0, raw_inside = 0;
    for (int y = y0; y <= y1; y++) {
        for (int x = x0; x <= x1; x++) {
            const uint8_t *f = fill + 4 * ((size_t)y * W + (size_t)x);
            const uint8_t *r = raw + 4 * ((size_t)y * W + (size_t)x);
            inside++;
            filled += f[0] || f[1] || f[2];
            raw_inside += r[0] || r[1] || r[2];
        }
    }
    printf("wall outline: %zu pixels, raw lit %zu, filled %zu\n", inside, raw_inside, filled);
    assert_true(inside > 5000);
    assert_true(filled > inside * 97 / 100);
    assert_true(raw_inside < inside * 3 / 4);

    // Normals (pyramid and TI): the sphere's centre faces the camera (blue-ish, z up in
    // camera space maps to the blue channel), the sky stays black.
    for (int method = STA_NORMAL_PYRAMID; method <= STA_NORMAL_TI; method += 4) {
        uint8_t *normals = render_mode(STA_PIPELINE_NORMALS, method, &camera, &stats);
        double cx, cy;
        const double centre[3] = { 0, 10, 0 };
        assert_true(sta_camera_project(&camera, centre, &cx, &cy, &depth));
        // Rows come top first in the image.
        const uint8_t *c = normals + 4 * ((size_t)cy * W + (size_t)cx);
        printf("normal colour at the sphere centre (%s): %u %u %u\n",
               sta_normal_method_name(method), c[0], c[1], c[2]);
        assert_true(c[2] > 200);
        assert_true(abs((int)c[0] - 128) < 50 && abs((int)c[1] - 128) < 50);
        free(normals);
    }

    // Shaded: the sphere's centre, facing the headlight, is brighter than near its rim.
    uint8_t *shaded = render_mode(STA_PIPELINE_SHADED, 0, &camera, &stats);
    assert_true(stats.timing.ms[STA_PASS_SHADE] > 0.0);
    assert_true(lit_pixels(shaded) >= filled);
    sta_camera c = camera;
    double cx, cy, rx, ry;
    const double centre[3] = { 0, 10, 0 }, rim[3] = { 4.6, 10, 0 };
    assert_true(sta_camera_project(&c, centre, &cx, &cy, &depth));
    assert_true(sta_camera_project(&c, rim, &rx, &ry, &depth));
    // Brightness relative to the point's own colour is what the light changes; the
    // colours encode indices, so compare the luminance ratio against the fill image.
    const uint8_t *sc = shaded + 4 * ((size_t)cy * W + (size_t)cx);
    const uint8_t *fc = fill + 4 * ((size_t)cy * W + (size_t)cx);
    const uint8_t *sr = shaded + 4 * ((size_t)ry * W + (size_t)rx);
    const uint8_t *fr = fill + 4 * ((size_t)ry * W + (size_t)rx);
    double centre_gain = (sc[0] + sc[1] + sc[2] + 1.0) / (fc[0] + fc[1] + fc[2] + 1.0);
    double rim_gain = (sr[0] + sr[1] + sr[2] + 1.0) / (fr[0] + fr[1] + fr[2] + 1.0);
    printf("light gain: centre %.2f, rim %.2f\n", centre_gain, rim_gain);
    assert_true(centre_gain > rim_gain);

    uint8_t *edl = render_mode(STA_PIPELINE_EDL, 0, &camera, &stats);
    assert_true(lit_pixels(edl) <= raw_lit); // EDL only darkens the raw points
    assert_true(lit_pixels(edl) > raw_lit / 2);
    free(raw);
    free(hpr);
    free(fill);
    free(shaded);
    free(edl);
}

static void empty_frame_in_every_mode(void **state)
{
    (void)state;
    const double origin[3] = { 0, 0, 0 };
    sta_camera camera = sta_fixture_camera(origin, W, H);
    camera.yaw += 3.14159265358979; // looking away from everything
    for (int mode = 0; mode < STA_PIPELINE_MODE_COUNT; mode++) {
        sta_frame_stats stats;
        uint8_t *rgba = render_mode(mode, 0, &camera, &stats);
        assert_int_equal(stats.points_drawn, 0);
        assert_int_equal(lit_pixels(rgba), 0);
        free(rgba);
    }
}

static const struct CMUnitTest tests[] = {
    cmocka_unit_test_setup_teardown(every_mode_does_its_job, setup, teardown),
    cmocka_unit_test_setup_teardown(empty_frame_in_every_mode, setup, teardown),
};

STA_TEST_MAIN(tests)
