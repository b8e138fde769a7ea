/* SPDX-License-Identifier: MIT
 * Mirror rendering on llvmpipe: the synthetic room (strata-synth mirror, UTM origin)
 * converted with its mirrors, rendered from inside with the east-wall mirror drawn by
 * reflection. Inside the mirror's outline the frame must match, flipped left to right,
 * a render of the real geometry (the room only: the wall and the ghosts behind it
 * clipped away) from the mirrored camera; without the mirror pass the same pixels are
 * dark (ghosts hidden, nothing behind the wall). Both rasterisers. */
#include "test_support.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "convert.h"
#include "mirror/mirror_camera.h"
#include "render/scene.h"
#include "scene_fixture.h"
#include "synth/synth.h"

#define W 320
#define H 200

static char scene_path[4096], mirrors_path[4096];
static sta_synth_georef georef;

static void build_room(void)
{
    if (scene_path[0]) {
        return;
    }
    sta_synth_params p = { .kind = STA_SYNTH_MIRROR, .point_count = 1500000, .seed = 5 };
    sta_synth_georef_init(p.origin, &georef);
    char las[4096];
    snprintf(las, sizeof(las), "%s", sta_test_tmp_path("mroom.las"));
    snprintf(mirrors_path, sizeof(mirrors_path), "%s", sta_test_tmp_path("mroom.mirrors.json"));
    snprintf(scene_path, sizeof(scene_path), "%s", sta_test_tmp_path("mroom.strata"));
    sta_error err = { 0 };
    if (sta_synth_generate(&p, las, NULL, NULL, &err) != STA_OK) {
        fail_msg("%s", err.message);
    }
    const char *inputs[] = { las };
    sta_convert_options o = { .inputs = inputs,
                              .input_count = 1,
                              .output = scene_path,
                              .force = true,
                              .mirrors = mirrors_path };
    if (sta_convert(&o, NULL, &err) != STA_OK) {
        fail_msg("%s", err.message);
    }
}

/* Renders the scene until complete; rgba top row first. */
static void render(const sta_scene_options *options, const sta_mirror_set *mirrors, int raster,
                   const sta_camera *camera, uint8_t *rgba)
{
    sta_scene *scene = NULL;
    sta_error err = { 0 };
    if (sta_scene_open(scene_path, options, &scene, &err) != STA_OK) {
        fail_msg("%s", err.message);
    }
    sta_geometry_options g = { .raster = raster };
    sta_scene_set_raster(scene, &g);
    sta_scene_set_mirrors(scene, mirrors, mirrors != NULL);
    sta_render_target target = { 0 };
    sta_fixture_render_complete(scene, camera, &target);
    sta_render_target_read_rgba(&target, rgba);
    sta_render_target_release(&target);
    sta_scene_close(scene);
}

/* Whether pixel (x, y) (top-left origin) and its four neighbours see `m` (front). */
static bool in_mirror(const sta_mirror *m, const sta_camera *c, int x, int y)
{
    double f[3], r[3], u[3];
    sta_camera_basis(c, f, r, u);
    double t = tan(c->fov_y * 0.5), aspect = (double)c->width_px / c->height_px;
    static const int dx[5] = { 0, 1, -1, 0, 0 }, dy[5] = { 0, 0, 0, 1, -1 };
    for (int k = 0; k < 5; k++) {
        double sx = ((x + dx[k] + 0.5) / c->width_px * 2.0 - 1.0) * t * aspect;
        double sy = (1.0 - (y + dy[k] + 0.5) / c->height_px * 2.0) * t;
        double d[3];
        for (int a = 0; a < 3; a++) {
            d[a] = f[a] + sx * r[a] + sy * u[a];
        }
        double hit;
        if (!sta_mirror_ray_hit(m, c->position, d, 0.0, 1e9, &hit)) {
            return false;
        }
    }
    return true;
}

static void mirror_region_matches_the_mirrored_camera(void **state)
{
    (void)state;
    build_room();
    sta_mirror_set mirrors;
    sta_error err = { 0 };
    assert_int_equal(sta_mirror_set_load(mirrors_path, &mirrors, &err), STA_OK);
    const sta_mirror *east = &mirrors.mirrors[0];
    sta_camera c = { .position = { georef.origin[0] + 5.0, georef.origin[1] + 4.0,
                                   georef.origin[2] + 1.6 },
                     .yaw = 0.05,
                     .pitch = 0.02,
                     .fov_y = 75.0 * M_PI / 180.0,
                     .near_m = 0.1,
                     .width_px = W,
                     .height_px = H };
    sta_camera mirrored;
    assert_true(sta_mirror_reflect_camera(east, &c, &mirrored));
    // Everything loaded (fine spacing, budget above the scene): the cuts agree.
    sta_scene_options all = { .min_spacing_px = 0.01 };
    sta_scene_options room = all; // the real geometry: the room without the east wall
    room.clip.has_box = true;
    for (int a = 0; a < 3; a++) {
        room.clip.box_min[a] = georef.origin[a] - 1.0;
        room.clip.box_max[a] = georef.origin[a] + 20.0;
    }
    room.clip.box_max[0] = georef.origin[0] + 11.97;
    static uint8_t with[W * H * 4], without[W * H * 4], truth[W * H * 4];
    const int methods[2] = { STA_RASTER_COMPUTE, STA_RASTER_POINTS };
    for (int m = 0; m < 2; m++) {
        render(&all, &mirrors, methods[m], &c, with);
        render(&all, NULL, methods[m], &c, without);
        render(&room, NULL, methods[m], &mirrored, truth);
        size_t region = 0, equal = 0, dark = 0;
        double error = 0.0;
        for (int y = 0; y < H; y++) {
            for (int x = 0; x < W; x++) {
                if (!in_mirror(east, &c, x, y)) {
                    continue;
                }
                region++;
                const uint8_t *a = with + 4 * (y * W + x);
                const uint8_t *b = truth + 4 * (y * W + (W - 1 - x));
                const uint8_t *n = without + 4 * (y * W + x);
                int worst = 0;
                for (int k = 0; k < 3; k++) {
                    int d = abs((int)a[k] - (int)b[k]);
                    worst = d > worst ? d : worst;
                    error += d / 255.0 / 3.0;
                }
                equal += worst <= 2;
                dark += n[0] + n[1] + n[2] < 30;
            }
        }
        error /= (double)(region ? region : 1);
        printf("%s: mirror region %zu pixels, %zu equal to the mirrored camera's (%.2f %%), mean "
               "error %.4f; without the pass %zu dark\n",
               sta_raster_method_name(methods[m]), region, equal, 100.0 * equal / region, error,
               dark);
        assert_true(region > 800);
        assert_true(dark > region * 9 / 10); // the hole the pass fills
        assert_true(equal >= region * 98 / 100);
        assert_true(error < 0.01);
    }
    sta_mirror_set_release(&mirrors);
}

static const struct CMUnitTest tests[] = {
    cmocka_unit_test_setup_teardown(mirror_region_matches_the_mirrored_camera, sta_fixture_gl_setup,
                                    sta_fixture_gl_teardown),
};

STA_TEST_MAIN(tests)
