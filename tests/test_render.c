/* SPDX-License-Identifier: MIT
 * GL tests of the viewer's rendering on Mesa llvmpipe through headless EGL: the
 * geometry pass against a CPU projection, precision far from the origin, budget and
 * cache caps, corrupt nodes, the compute rasteriser's positions. Scenes are made here
 * (PLY -> strata-convert). */
#include "scene_fixture.h"
#include "test_support.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "convert.h"
#include "core/bytes.h"
#include "core/camera.h"
#include "format/strata_reader.h"
#include "render/bindings.h"
#include "render/gl.h"
#include "render/gl_image.h"
#include "render/pass_unproject.h"
#include "render/scene.h"
#include "stream/gpu_points.h"

enum {
    POINTS = 30000,
    W = 320,
    H = 240
};

static void build_scene(const char *name, const double offset[3], char *out_path, size_t size)
{
    sta_fixture_build_scene(name, POINTS, offset, out_path, size);
}

static sta_camera test_camera(const double offset[3])
{
    return sta_fixture_camera(offset, W, H);
}

static uint8_t *render_image(const char *path, const sta_camera *camera, sta_frame_stats *stats)
{
    sta_scene *scene = NULL;
    sta_error err = { 0 };
    sta_scene_options options = { .loader_threads = 2 };
    if (sta_scene_open(path, &options, &scene, &err) != STA_OK) {
        fail_msg("%s", err.message);
    }
    sta_scene_set_colour_mode(scene, STA_COLOUR_RGB);
    sta_render_target target = { 0 };
    *stats = sta_fixture_render_complete(scene, camera, &target);
    uint8_t *rgba = malloc((size_t)W * H * 4);
    assert_non_null(rgba);
    sta_render_target_read_rgba(&target, rgba);
    sta_render_target_release(&target);
    sta_scene_close(scene);
    return rgba;
}

static void geometry_pass_matches_cpu_projection(void **state)
{
    (void)state;
    const double origin[3] = { 0, 0, 0 };
    char path[4096];
    build_scene("cpu", origin, path, sizeof(path));
    sta_camera camera = test_camera(origin);
    sta_frame_stats stats;
    uint8_t *rgba = render_image(path, &camera, &stats);
    assert_int_equal(stats.points_drawn, POINTS);

    // CPU reference: every point as the GPU sees it (dequantised), projected in double;
    // nearest per pixel. Ambiguous pixels (a point within 0.01 px of a pixel edge or
    // two depths within 1e-5) are left out of the comparison: ties aside.
    double *best = malloc(sizeof(double) * W * H), *second = malloc(sizeof(double) * W * H);
    uint32_t *id = calloc((size_t)W * H, sizeof(uint32_t));
    uint8_t *ambiguous = calloc((size_t)W * H, 1);
    assert_true(best && second && id && ambiguous);
    for (int i = 0; i < W * H; i++) {
        best[i] = second[i] = INFINITY;
    }
    sta_strata_reader *reader = NULL;
    sta_strata_decoder *decoder = NULL;
    sta_error err = { 0 };
    assert_int_equal(sta_strata_open(path, NULL, &reader, &err), STA_OK);
    assert_int_equal(sta_strata_decoder_create(&decoder, &err), STA_OK);
    const sta_strata_info *info = sta_strata_reader_info(reader);
    size_t projected = 0;
    for (uint32_t n = 0; n < info->node_count; n++) {
        sta_strata_points pts;
        assert_int_equal(sta_strata_decode_node(reader, n, decoder, &pts, &err), STA_OK);
        sta_gpu_node_frame frame;
        sta_gpu_node_frame_init(&frame, &info->geometry, sta_strata_reader_node(reader, n)->key);
        for (size_t i = 0; i < pts.count; i++) {
            uint8_t gpu[STA_GPU_POINT_SIZE];
            sta_gpu_points_encode(&frame, &pts.points[i], 1, 0, gpu);
            double world[3], x, y, z;
            sta_gpu_point_position(&frame, gpu, world);
            if (!sta_camera_project(&camera, world, &x, &y, &z) || x < 0 || y < 0 || x >= W ||
                y >= H) {
                continue;
            }
            projected++;
            int px = (int)x, py = (int)y, pixel = py * W + px;
            double fx = x - px, fy = y - py;
            if (fx < 0.01 || fx > 0.99 || fy < 0.01 || fy > 0.99) {
                ambiguous[pixel] = 1;
                // The neighbour it might land in instead is ambiguous too.
                int nx = fx < 0.5 ? px - 1 : px + 1, ny = fy < 0.5 ? py - 1 : py + 1;
                if (nx >= 0 && nx < W) {
                    ambiguous[py * W + nx] = 1;
                }
                if (ny >= 0 && ny < H) {
                    ambiguous[ny * W + px] = 1;
                }
            }
            uint32_t point_id = (uint32_t)gpu[8] | (uint32_t)gpu[9] << 8 | (uint32_t)gpu[10] << 16;
            if (z < best[pixel]) {
                second[pixel] = best[pixel];
                best[pixel] = z;
                id[pixel] = point_id;
            } else if (z < second[pixel]) {
                second[pixel] = z;
            }
        }
    }
    assert_true(projected > POINTS / 2); // the view really shows the scene
    size_t compared = 0, mismatched = 0, lit = 0;
    for (int i = 0; i < W * H; i++) {
        if (ambiguous[i] || (isfinite(second[i]) && second[i] - best[i] < 1e-5 * best[i])) {
            continue;
        }
        uint32_t got = (uint32_t)rgba[4 * i] | (uint32_t)rgba[4 * i + 1] << 8 |
                       (uint32_t)rgba[4 * i + 2] << 16;
        compared++;
        lit += got != 0;
        if (got != id[i]) {
            mismatched++;
        }
    }
    printf("compared %zu pixels (%zu lit), %zu mismatched\n", compared, lit, mismatched);
    assert_true(compared > (size_t)W * H * 9 / 10);
    assert_true(lit > 5000);
    assert_int_equal(mismatched, 0);
    sta_strata_decoder_destroy(decoder);
    sta_strata_close(reader);
    free(best);
    free(second);
    free(id);
    free(ambiguous);
    free(rgba);
}

static void same_image_at_origin_utm_and_ecef(void **state)
{
    (void)state;
    const double offsets[3][3] = { { 0, 0, 0 },
                                   { 650000, 5400000, 100 },
                                   { 4200000, 170000, 4780000 } };
    uint8_t *images[3];
    for (int k = 0; k < 3; k++) {
        char name[16], path[4096];
        snprintf(name, sizeof(name), "offset%d", k);
        build_scene(name, offsets[k], path, sizeof(path));
        sta_camera camera = test_camera(offsets[k]);
        sta_frame_stats stats;
        images[k] = render_image(path, &camera, &stats);
        assert_int_equal(stats.points_drawn, POINTS);
    }
    // Stated tolerance: identical, pixel for pixel (0 differing pixels).
    for (int k = 1; k < 3; k++) {
        size_t differing = 0;
        for (int i = 0; i < W * H; i++) {
            differing += memcmp(images[0] + 4 * i, images[k] + 4 * i, 4) != 0;
        }
        printf("offset %d: %zu pixels differ from the origin's image\n", k, differing);
        assert_int_equal(differing, 0);
    }
    for (int k = 0; k < 3; k++) {
        free(images[k]);
    }
}

/* The shaded pipeline with the compute rasteriser takes its camera-space positions from
 * the rasteriser's resolve instead of the unproject pass: they are the unproject pass's
 * positions from the same depth, bit for bit; with GL_POINTS the pass runs as before. */
static void raster_positions_equal_unproject(void **state)
{
    (void)state;
    const double origin[3] = { 0, 0, 0 };
    char path[4096];
    build_scene("positions", origin, path, sizeof(path));
    sta_camera camera = test_camera(origin);
    sta_error err = { 0 };
    sta_unproject_pass unproject;
    assert_int_equal(sta_unproject_pass_init(&unproject, &err), STA_OK);
    for (int raster = STA_RASTER_COMPUTE; raster <= STA_RASTER_POINTS; raster++) {
        sta_scene *scene = NULL;
        sta_scene_options options = { 0 };
        assert_int_equal(sta_scene_open(path, &options, &scene, &err), STA_OK);
        sta_geometry_options geometry = { .raster = raster };
        sta_scene_set_raster(scene, &geometry);
        sta_pipeline_options pipeline = { .mode = STA_PIPELINE_SHADED };
        sta_scene_set_pipeline(scene, &pipeline);
        sta_render_target target = { 0 };
        sta_frame_stats stats = sta_fixture_render_complete(scene, &camera, &target);
        assert_int_equal(stats.raster_positions, raster == STA_RASTER_COMPUTE);
        GLuint expected;
        assert_int_equal(sta_gl_texture_create(W, H, 4, 1, &expected, &err), STA_OK);
        sta_view_params view = { W, H, (float)camera.fov_y, (float)camera.near_m, 0.0f };
        assert_int_equal(sta_unproject_pass_run(&unproject, &view, target.depth, expected, &err),
                         STA_OK);
        sta_image got, want;
        assert_int_equal(
            sta_gl_texture_to_image(sta_scene_pipeline(scene)->position, 0, 4, &got, &err), STA_OK);
        assert_int_equal(sta_gl_texture_to_image(expected, 0, 4, &want, &err), STA_OK);
        int drawn = 0;
        for (int i = 0; i < W * H; i++) {
            drawn += want.data[4 * i + 3] > 0.0f;
        }
        printf("%s: %d pixels with a point\n", raster == STA_RASTER_COMPUTE ? "compute" : "points",
               drawn);
        assert_true(drawn > W * H / 20);
        assert_memory_equal(got.data, want.data, (size_t)W * H * 4 * sizeof(float));
        sta_image_release(&got);
        sta_image_release(&want);
        glDeleteTextures(1, &expected);
        sta_render_target_release(&target);
        sta_scene_close(scene);
    }
    sta_unproject_pass_release(&unproject);
}

static void budget_and_gpu_cap_hold(void **state)
{
    (void)state;
    const double origin[3] = { 0, 0, 0 };
    char path[4096];
    build_scene("budget", origin, path, sizeof(path));
    sta_camera camera = test_camera(origin);
    // A budget below the scene's size, and a GPU cap a little above it (22000 points),
    // so looking two ways in turn must evict.
    const uint64_t budget = 20000, cap = 22000 * STA_GPU_POINT_SIZE;
    sta_scene *scene = NULL;
    sta_error err = { 0 };
    sta_scene_options options = { .budget_points = budget, .gpu_bytes_cap = cap };
    assert_int_equal(sta_scene_open(path, &options, &scene, &err), STA_OK);
    sta_render_target target = { 0 };
    sta_frame_stats stats;
    for (int frame = 0; frame < 400; frame++) {
        assert_int_equal(sta_scene_render(scene, &camera, &target, &stats, &err), STA_OK);
        assert_true(stats.points_selected <= budget);
        assert_true(stats.points_drawn <= stats.points_selected);
        assert_true(stats.gpu_bytes <= cap);
        if (stats.complete) {
            break;
        }
        struct timespec nap = { 0, 2000000 };
        nanosleep(&nap, NULL);
    }
    assert_true(stats.complete);
    assert_true(stats.points_drawn > 0);
    assert_int_equal(stats.points_drawn, stats.points_selected); // all wanted are resident
    sta_camera other = camera; // from behind the wall, near its left end
    other.position[0] = -12.0;
    other.position[1] = 26.0;
    other.yaw = -1.5707963267948966 - 0.3;
    for (int turn = 0; turn < 6; turn++) {
        const sta_camera *c = turn % 2 ? &camera : &other;
        for (int frame = 0; frame < 400; frame++) {
            assert_int_equal(sta_scene_render(scene, c, &target, &stats, &err), STA_OK);
            assert_true(stats.points_drawn <= budget);
            assert_true(stats.gpu_bytes <= cap);
            if (stats.complete) {
                break;
            }
            struct timespec nap = { 0, 2000000 };
            nanosleep(&nap, NULL);
        }
        assert_true(stats.complete);
        printf("view %d: %llu points selected in %u nodes, %u resident, %.0f KiB\n", turn % 2,
               (unsigned long long)stats.points_selected, stats.nodes_selected,
               stats.nodes_resident, (double)stats.gpu_bytes / 1024.0);
    }
    assert_true(stats.evictions > 0); // the cap was reached and held
    // Unlimited: every node becomes resident and every point is drawn.
    sta_scene_close(scene);
    sta_scene_options open = { 0 };
    assert_int_equal(sta_scene_open(path, &open, &scene, &err), STA_OK);
    stats = sta_fixture_render_complete(scene, &camera, &target);
    assert_int_equal(stats.points_drawn, POINTS);
    assert_int_equal(stats.nodes_resident, sta_scene_info(scene)->node_count);
    sta_render_target_release(&target);
    sta_scene_close(scene);
}

static void corrupt_node_is_skipped_not_drawn(void **state)
{
    (void)state;
    const double origin[3] = { 0, 0, 0 };
    char path[4096];
    build_scene("corrupt", origin, path, sizeof(path));
    // Flip a byte inside the payload of the last node (a leaf).
    sta_strata_reader *reader = NULL;
    sta_error err = { 0 };
    assert_int_equal(sta_strata_open(path, NULL, &reader, &err), STA_OK);
    const sta_strata_info *info = sta_strata_reader_info(reader);
    uint32_t victim = info->node_count - 1;
    const sta_strata_node *node = sta_strata_reader_node(reader, victim);
    uint64_t at = node->payload.offset + node->payload.stored_size / 2;
    uint64_t victim_points = node->point_count;
    assert_true(victim_points > 0);
    sta_strata_close(reader);
    size_t size;
    uint8_t *bytes = sta_test_read_file(path, &size);
    bytes[at] ^= 0x10;
    sta_test_write_file(path, bytes, size);
    free(bytes);

    sta_scene *scene = NULL;
    sta_scene_options options = { 0 };
    assert_int_equal(sta_scene_open(path, &options, &scene, &err), STA_OK);
    sta_camera camera = test_camera(origin);
    sta_render_target target = { 0 };
    sta_frame_stats stats = sta_fixture_render_complete(scene, &camera, &target);
    assert_int_equal(stats.bad_nodes, 1);
    assert_int_equal(stats.points_drawn, POINTS - victim_points);
    // It is not asked for again: more frames keep the count at one.
    for (int i = 0; i < 5; i++) {
        assert_int_equal(sta_scene_render(scene, &camera, &target, &stats, &err), STA_OK);
    }
    assert_int_equal(stats.bad_nodes, 1);
    sta_render_target_release(&target);
    sta_scene_close(scene);
}

// Reverse-Z with a float depth buffer: two planes 1 cm apart seen from 1 km with the near
// plane at 1 cm never z-fight, and a point 50 km away is still drawn.
static void no_z_fighting_at_one_kilometre(void **state)
{
    (void)state;
    char ply[4096], strata[4096];
    snprintf(ply, sizeof(ply), "%s/planes.ply", sta_test_tmpdir());
    snprintf(strata, sizeof(strata), "%s/planes.strata", sta_test_tmpdir());
    enum {
        GRID = 201
    };
    FILE *f = fopen(ply, "wb");
    assert_non_null(f);
    fprintf(f,
            "ply\nformat binary_little_endian 1.0\nelement vertex %d\nproperty double x\n"
            "property double y\nproperty double z\nproperty uchar red\nproperty uchar green\n"
            "property uchar blue\nend_header\n",
            2 * GRID * GRID + 1);
    for (int layer = 0; layer < 2; layer++) { // front (red) at z = 0, back (blue) 1 cm below
        for (int j = 0; j < GRID; j++) {
            for (int i = 0; i < GRID; i++) {
                uint8_t record[27];
                sta_store_f64le(record, -20.0 + 0.2 * i);
                sta_store_f64le(record + 8, -20.0 + 0.2 * j);
                sta_store_f64le(record + 16, layer ? -0.01 : 0.0);
                record[24] = layer ? 0 : 255;
                record[25] = 0;
                record[26] = layer ? 255 : 0;
                assert_int_equal(fwrite(record, 1, sizeof(record), f), sizeof(record));
            }
        }
    }
    uint8_t far_point[27] = { 0 };
    sta_store_f64le(far_point, 50000.0);
    sta_store_f64le(far_point + 16, 1000.0);
    far_point[25] = 255; // green
    assert_int_equal(fwrite(far_point, 1, sizeof(far_point), f), sizeof(far_point));
    fclose(f);
    const char *inputs[] = { ply };
    sta_convert_options o = { .inputs = inputs, .input_count = 1, .output = strata, .force = true };
    sta_error err = { 0 };
    assert_int_equal(sta_convert(&o, NULL, &err), STA_OK);

    sta_camera down = { { 0.0, 0.0, 1000.0 },
                        1.5707963267948966,
                        -1.5707963267948966,
                        2.0 * 3.14159265358979 / 180.0,
                        0.01,
                        160,
                        160,
                        STA_CAMERA_UP_Z };
    sta_scene *scene = NULL;
    sta_scene_options options = { 0 };
    assert_int_equal(sta_scene_open(strata, &options, &scene, &err), STA_OK);
    sta_scene_set_colour_mode(scene, STA_COLOUR_RGB);
    sta_render_target target = { 0 };
    sta_frame_stats stats = sta_fixture_render_complete(scene, &down, &target);
    assert_true(stats.points_drawn >= 2 * GRID * GRID);
    uint8_t *rgba = malloc(160 * 160 * 4);
    assert_non_null(rgba);
    sta_render_target_read_rgba(&target, rgba);
    size_t red = 0, blue = 0;
    for (int i = 0; i < 160 * 160; i++) {
        red += rgba[4 * i] > 200 && rgba[4 * i + 2] < 50;
        blue += rgba[4 * i + 2] > 200 && rgba[4 * i] < 50;
    }
    printf("looking down from 1 km: %zu red (front) pixels, %zu blue (back)\n", red, blue);
    assert_true(red > 160 * 160 * 9 / 10);
    assert_int_equal(blue, 0);

    // The point 50 km away along +x at the camera's height is drawn at the centre.
    sta_camera ahead = { { 0.0, 0.0, 1000.0 }, 0.0, 0.0, 0.5, 0.01, 65, 65, STA_CAMERA_UP_Z };
    stats = sta_fixture_render_complete(scene, &ahead, &target);
    sta_render_target_read_rgba(&target, rgba);
    const uint8_t *centre = rgba + 4 * (32 * 65 + 32);
    assert_true(centre[1] > 200);
    free(rgba);
    sta_render_target_release(&target);
    sta_scene_close(scene);
}

static const struct CMUnitTest tests[] = {
    cmocka_unit_test_setup_teardown(no_z_fighting_at_one_kilometre, sta_fixture_gl_setup,
                                    sta_fixture_gl_teardown),
    cmocka_unit_test_setup_teardown(geometry_pass_matches_cpu_projection, sta_fixture_gl_setup,
                                    sta_fixture_gl_teardown),
    cmocka_unit_test_setup_teardown(same_image_at_origin_utm_and_ecef, sta_fixture_gl_setup,
                                    sta_fixture_gl_teardown),
    cmocka_unit_test_setup_teardown(raster_positions_equal_unproject, sta_fixture_gl_setup,
                                    sta_fixture_gl_teardown),
    cmocka_unit_test_setup_teardown(budget_and_gpu_cap_hold, sta_fixture_gl_setup,
                                    sta_fixture_gl_teardown),
    cmocka_unit_test_setup_teardown(corrupt_node_is_skipped_not_drawn, sta_fixture_gl_setup,
                                    sta_fixture_gl_teardown),
};

STA_TEST_MAIN(tests)
