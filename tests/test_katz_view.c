/* SPDX-License-Identifier: MIT
 * The live Katz mode of the viewer (render/pass_katz.h) on Mesa llvmpipe through headless
 * EGL, on the GL tests' scene (a sphere in front of a wall): the published set agrees
 * with the analytic visibility (the sphere's front, the wall outside its shadow), the
 * picture holds only the set's visible points, the frame reports the set as current once
 * it is, and turning the mode off gives the ordinary picture back. */
#include "scene_fixture.h"
#include "test_support.h"

#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "render/bindings.h"
#include "render/gl.h"
#include "render/scene.h"

enum {
    POINTS = 30000,
    W = 320,
    H = 240
};

// Analytic visibility from `eye`: sphere (radius 5 at (0, 10, 0)) points facing the eye;
// wall (y = 20) points whose ray from the eye misses the sphere. Points within 2 cm of
// the sphere's silhouette or shadow edge count as either.
static int truth(const double eye[3], const double p[3])
{
    const double c[3] = { 0.0, 10.0, 0.0 };
    const double radius = 5.0;
    double n[3], v[3];
    for (int a = 0; a < 3; a++) {
        n[a] = p[a] - c[a];
        v[a] = eye[a] - p[a];
    }
    double vn = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (fabs(p[1] - 20.0) > 1e-3) { // positions come back as float
        double facing = (n[0] * v[0] + n[1] * v[1] + n[2] * v[2]) / (radius * vn);
        return fabs(facing) < 0.004 ? -1 : facing > 0;
    }
    // Distance from the sphere's centre to the ray eye -> p.
    double d[3] = { -v[0] / vn, -v[1] / vn, -v[2] / vn };
    double w[3] = { c[0] - eye[0], c[1] - eye[1], c[2] - eye[2] };
    double t = w[0] * d[0] + w[1] * d[1] + w[2] * d[2];
    double miss = sqrt(fmax(0.0, w[0] * w[0] + w[1] * w[1] + w[2] * w[2] - t * t));
    return fabs(miss - radius) < 0.02 ? -1 : miss > radius;
}

static void katz_set_matches_analytic_visibility(void **state)
{
    (void)state;
    const double origin[3] = { 0, 0, 0 };
    char path[4096];
    sta_fixture_build_scene("katz", POINTS, origin, path, sizeof(path));
    sta_camera camera = sta_fixture_camera(origin, W, H);
    sta_scene *scene = NULL;
    sta_error err = { 0 };
    sta_scene_options options = { .loader_threads = 2 };
    if (sta_scene_open(path, &options, &scene, &err) != STA_OK) {
        fail_msg("%s", err.message);
    }
    sta_scene_set_colour_mode(scene, STA_COLOUR_RGB);
    sta_render_target target = { 0 };
    sta_frame_stats plain = sta_fixture_render_complete(scene, &camera, &target);
    assert_int_equal(plain.katz.generation, 0);
    uint8_t *before = malloc((size_t)W * H * 4);
    uint8_t *rgba = malloc((size_t)W * H * 4);
    assert_true(before && rgba);
    sta_render_target_read_rgba(&target, before);

    sta_katz_view_options katz = { .enabled = true, .sample_points = 12000 };
    sta_scene_set_katz(scene, &katz);
    sta_frame_stats stats = sta_fixture_render_complete(scene, &camera, &target);
    assert_true(stats.katz.current);
    assert_true(stats.katz.generation >= 1);
    const sta_pass_katz *pass = sta_scene_katz(scene);
    const sta_katz_set *set = sta_pass_katz_set(pass);
    assert_non_null(set);
    assert_int_equal(set->generation, stats.katz.generation);
    assert_true(set->count >= 10000 && set->count <= 12000);
    assert_int_equal(stats.katz.points, set->count);
    size_t tp = 0, fp = 0, fn = 0;
    for (size_t i = 0; i < set->count; i++) {
        double p[3];
        for (int a = 0; a < 3; a++) {
            p[a] = (double)set->points[i][a] + pass->origin[a];
        }
        int t = truth(camera.position, p);
        if (t < 0) {
            continue;
        }
        tp += t && set->visible[i];
        fp += !t && set->visible[i];

        fn += t && !set->visible[i];
    }
    double precision = (double)tp / (double)(tp + fp);
    double recall = (double)tp / (double)(tp + fn);
    printf("live katz: %zu points, R %.4g m, precision %.3f, recall %.3f\n", set->count,
           stats.katz.radius_m, precision, recall);
    assert_true(precision > 0.95);
    assert_true(recall > 0.95);

    // The picture: only the set's visible points (one pixel each, some sharing a pixel).
    sta_render_target_read_rgba(&target, rgba);
    size_t lit = 0;
    for (size_t i = 0; i < (size_t)W * H; i++) {
        lit += rgba[4 * i] || rgba[4 * i + 1] || rgba[4 * i + 2];
    }
    printf("lit pixels %zu, visible points %" PRIu64 "\n", lit, stats.katz.visible);
    assert_true(lit <= stats.katz.visible);
    assert_true(lit > stats.katz.visible / 2);

    // Still camera: no new submission, the set stays current and grows older.
    sta_frame_stats again;
    assert_int_equal(sta_scene_render(scene, &camera, &target, &again, &err), STA_OK);
    assert_int_equal(again.katz.generation, stats.katz.generation);
    assert_true(again.katz.current);
    assert_int_equal(again.katz.age_frames, stats.katz.age_frames + 1);

    // A new camera: the old set is drawn (not current) until the new one arrives.
    sta_camera moved = camera;
    moved.position[0] -= 2.0;
    assert_int_equal(sta_scene_render(scene, &moved, &target, &again, &err), STA_OK);
    if (again.katz.generation == stats.katz.generation) {
        assert_false(again.katz.current);
    }
    sta_frame_stats after_move = sta_fixture_render_complete(scene, &moved, &target);
    assert_true(after_move.katz.generation > stats.katz.generation);

    // Off: the ordinary picture again, pixel for pixel.
    katz.enabled = false;
    sta_scene_set_katz(scene, &katz);
    sta_fixture_render_complete(scene, &camera, &target);
    sta_render_target_read_rgba(&target, rgba);
    assert_memory_equal(rgba, before, (size_t)W * H * 4);

    free(before);
    free(rgba);
    sta_render_target_release(&target);
    sta_scene_close(scene);
}

static const struct CMUnitTest tests[] = {
    cmocka_unit_test_setup_teardown(katz_set_matches_analytic_visibility, sta_fixture_gl_setup,
                                    sta_fixture_gl_teardown),
};

STA_TEST_MAIN(tests)
