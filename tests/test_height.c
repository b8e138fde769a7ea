/* SPDX-License-Identifier: MIT
 * The height-above-ground colour mode end to end (GL, llvmpipe): a sloped scene far from
 * the origin with a building and trees, converted and rendered with both rasterisers;
 * each pixel's point (from the id target) must have the colour of its height above the
 * ground model (stream/ground.h) on the CPU ramp, so roofs and tree tops are told from
 * the terrain that rises under them. */
#include "scene_fixture.h"
#include "test_support.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "convert.h"
#include "core/bytes.h"
#include "format/strata_reader.h"
#include "render/bindings.h"
#include "render/gl.h"
#include "render/scene.h"
#include "stream/gpu_points.h"
#include "stream/ground.h"
#include "stream/lod_tree.h"

enum {
    W = 320,
    H = 200
};
#define X0 650000.0
#define Y0 5400000.0

static double terrain(double x)
{
    return 100.0 + 0.15 * (x - X0); // 15 % slope: 30 m across the scene
}

// Terrain on a 1 m lattice, a 24 m building 10 m high, trees 14 m high; binary PLY.
static void write_scene(const char *ply)
{
    FILE *f = fopen(ply, "wb");
    assert_non_null(f);
    size_t count = 0;
    for (int pass = 0; pass < 2; pass++) {
        if (pass == 1) {
            fprintf(f,
                    "ply\nformat binary_little_endian 1.0\nelement vertex %zu\n"
                    "property double x\nproperty double y\nproperty double z\nend_header\n",
                    count);
        }
        count = 0;
        for (int iy = 0; iy < 200; iy++) {
            for (int ix = 0; ix < 200; ix++) {
                double x = X0 + ix, y = Y0 + iy, z = terrain(x);
                bool roof = ix >= 88 && ix < 112 && iy >= 88 && iy < 112;
                bool tree = ix % 40 == 20 && iy % 40 == 20 && !roof;
                double points[3][3] = { { x, y, roof ? terrain(X0 + 88) + 10.0 : z },
                                        { x + 0.25, y + 0.25, z + 14.0 },
                                        { x + 0.5, y + 0.25, z + 13.5 } };
                int n = tree ? 3 : 1;
                for (int k = 0; k < n; k++) {
                    if (pass == 1) {
                        uint8_t record[24];
                        for (int a = 0; a < 3; a++) {
                            sta_store_f64le(record + 8 * a, points[k][a]);
                        }
                        assert_int_equal(fwrite(record, 1, sizeof(record), f), sizeof(record));
                    }
                    count++;
                }
            }
        }
    }
    fclose(f);
}

// The shader's ramp (geometry_colour.glsl), on the CPU.
static void ramp(double t, double out[3])
{
    t = fmin(1.0, fmax(0.0, t));
    const double a[3] = { 0.27, 0.00, 0.33 }, b[3] = { 0.13, 0.57, 0.55 },
                 c[3] = { 0.99, 0.91, 0.14 };
    for (int i = 0; i < 3; i++) {
        out[i] = t < 0.5 ? a[i] + (b[i] - a[i]) * t * 2.0 : b[i] + (c[i] - b[i]) * (t * 2.0 - 1.0);
    }
}

static void check_raster(const char *strata, int raster, const sta_ground *ground)
{
    sta_scene *scene = NULL;
    sta_error err = { 0 };
    sta_scene_options options = { .loader_threads = 2 };
    assert_int_equal(sta_scene_open(strata, &options, &scene, &err), STA_OK);
    sta_geometry_options geometry = { .raster = raster };
    sta_scene_set_raster(scene, &geometry);
    sta_scene_set_colour_mode(scene, STA_COLOUR_HEIGHT);
    // Looking down the slope at the building from the south-west, 60 m up.
    sta_camera camera = { .position = { X0 - 40, Y0 - 40, 160 },
                          .yaw = 45 * M_PI / 180,
                          .pitch = -30 * M_PI / 180,
                          .fov_y = 60 * M_PI / 180,
                          .near_m = 0.5,
                          .width_px = W,
                          .height_px = H };
    sta_render_target target = { 0 };
    sta_fixture_render_complete(scene, &camera, &target);
    uint8_t *rgba = malloc((size_t)W * H * 4);
    uint32_t *ids = malloc((size_t)W * H * 2 * sizeof(uint32_t));
    assert_true(rgba && ids);
    sta_render_target_read_rgba(&target, rgba);
    sta_render_target_read_ids(&target, ids);

    sta_strata_reader *reader = NULL;
    sta_strata_decoder *decoder = NULL;
    assert_int_equal(sta_strata_open(strata, NULL, &reader, &err), STA_OK);
    assert_int_equal(sta_strata_decoder_create(&decoder, &err), STA_OK);
    const sta_strata_info *info = sta_strata_reader_info(reader);
    size_t covered = 0, matched = 0, high = 0;
    for (int p = 0; p < W * H; p++) {
        uint32_t node = ids[2 * p], index = ids[2 * p + 1];
        if (node == STA_TARGET_NO_POINT) {
            continue;
        }
        covered++;
        sta_strata_points pts;
        assert_int_equal(sta_strata_decode_node(reader, node, decoder, &pts, &err), STA_OK);
        assert_true(index < pts.count);
        sta_gpu_node_frame frame;
        sta_gpu_node_frame_init(&frame, &info->geometry, sta_strata_reader_node(reader, node)->key);
        uint8_t gpu[STA_GPU_POINT_SIZE];
        sta_gpu_points_encode(&frame, &pts.points[index], 1, 0, gpu);
        double world[3], expected[3];
        sta_gpu_point_position(&frame, gpu, world);
        double height = world[2] - sta_ground_at(ground, world[0], world[1]);
        high += height > 5.0;
        ramp(height / ground->height_span_m, expected);
        bool ok = true;
        for (int c = 0; c < 3; c++) {
            ok = ok && fabs(rgba[4 * p + c] - expected[c] * 255.0) <= 3.0;
        }
        matched += ok;
    }
    printf("raster %d: %zu covered pixels, %zu match the CPU height colour, %zu above 5 m\n",
           raster, covered, matched, high);
    assert_true(covered > W * H / 20);
    assert_true(high > 100);                    // roofs and crowns are in view
    assert_true(matched >= covered * 99 / 100); // float ramp and 8-bit rounding aside
    sta_strata_decoder_destroy(decoder);
    sta_strata_close(reader);
    free(rgba);
    free(ids);
    sta_render_target_release(&target);
    sta_scene_close(scene);
}

static void height_colours_follow_the_ground_model(void **state)
{
    (void)state;
    const char *ply = sta_test_tmp_path("slope.ply");
    write_scene(ply);
    char strata[4096];
    snprintf(strata, sizeof(strata), "%s/slope.strata", sta_test_tmpdir());
    const char *inputs[] = { ply };
    sta_convert_options o = { .inputs = inputs, .input_count = 1, .output = strata, .force = true };
    sta_error err = { 0 };
    if (sta_convert(&o, NULL, &err) != STA_OK) {
        fail_msg("%s", err.message);
    }
    sta_strata_reader *reader = NULL;
    assert_int_equal(sta_strata_open(strata, NULL, &reader, &err), STA_OK);
    sta_lod_tree tree;
    assert_int_equal(sta_lod_tree_init(&tree, reader, &err), STA_OK);
    sta_ground ground;
    assert_int_equal(sta_ground_build(reader, &tree, &ground, &err), STA_OK);
    assert_false(ground.from_class); // PLY: no classes, the opening finds the ground
    // The model follows the slope, not the roof.
    assert_true(fabs(sta_ground_at(&ground, X0 + 100, Y0 + 100) - terrain(X0 + 100)) < 1.0);
    sta_lod_tree_release(&tree);
    sta_strata_close(reader);
    check_raster(strata, STA_RASTER_COMPUTE, &ground);
    check_raster(strata, STA_RASTER_POINTS, &ground);
    sta_ground_release(&ground);
}

static const struct CMUnitTest tests[] = {
    cmocka_unit_test_setup_teardown(height_colours_follow_the_ground_model, sta_fixture_gl_setup,
                                    sta_fixture_gl_teardown),
};

STA_TEST_MAIN(tests)
