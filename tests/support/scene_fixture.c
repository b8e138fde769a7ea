/* SPDX-License-Identifier: MIT
 * The GL tests' scene fixture. */
#include "scene_fixture.h"

#include "test_support.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "convert.h"
#include "core/bytes.h"
#include "render/gl.h"

/* A test scene: a sphere in front of a wall, points on a 2^-10 m lattice so every
 * coordinate is exact in double at any offset. Colour encodes the point's index. */
static size_t make_scene_points(double (*xyz)[3], uint8_t (*rgb)[3], size_t count)
{
    uint64_t state = 12345;
    for (size_t i = 0; i < count; i++) {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        double u = (double)(state >> 11) / 9007199254740992.0;
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        double v = (double)(state >> 11) / 9007199254740992.0;
        double p[3];
        if (i % 3 == 0) { // wall at y = 20, x in [-15, 15], z in [-10, 10]
            p[0] = -15.0 + 30.0 * u;
            p[1] = 20.0;
            p[2] = -10.0 + 20.0 * v;
        } else { // sphere of radius 5 at (0, 10, 0)
            double z = 2.0 * u - 1.0, phi = 6.283185307179586 * v, r = sqrt(1.0 - z * z);
            p[0] = 5.0 * r * cos(phi);
            p[1] = 10.0 + 5.0 * r * sin(phi);
            p[2] = 5.0 * z;
        }
        for (int a = 0; a < 3; a++) {
            xyz[i][a] = round(p[a] * 1024.0) / 1024.0;
        }
        uint32_t id = (uint32_t)i + 1;
        rgb[i][0] = (uint8_t)id;
        rgb[i][1] = (uint8_t)(id >> 8);
        rgb[i][2] = (uint8_t)(id >> 16);
    }
    return count;
}

// Writes a binary little-endian PLY with double x, y, z and uchar colour.
static void write_ply(const char *path, double (*xyz)[3], uint8_t (*rgb)[3], size_t count,
                      const double offset[3])
{
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    fprintf(f,
            "ply\nformat binary_little_endian 1.0\nelement vertex %zu\nproperty double x\n"
            "property double y\nproperty double z\nproperty uchar red\nproperty uchar green\n"
            "property uchar blue\nend_header\n",
            count);
    for (size_t i = 0; i < count; i++) {
        uint8_t record[27];
        for (int a = 0; a < 3; a++) {
            sta_store_f64le(record + 8 * a, xyz[i][a] + offset[a]);
        }
        memcpy(record + 24, rgb[i], 3);
        assert_int_equal(fwrite(record, 1, sizeof(record), f), sizeof(record));
    }
    fclose(f);
}

enum {
    POINTS = 30000,
    W = 320,
    H = 240
};

void sta_fixture_build_scene(const char *name, size_t points, const double offset[3],
                             char *out_path, size_t size)
{
    double(*xyz)[3] = malloc(points * sizeof(*xyz));
    uint8_t(*rgb)[3] = malloc(points * sizeof(*rgb));
    assert_non_null(xyz);
    assert_non_null(rgb);
    make_scene_points(xyz, rgb, points);
    char ply[4096];
    snprintf(ply, sizeof(ply), "%s/%s.ply", sta_test_tmpdir(), name);
    write_ply(ply, xyz, rgb, points, offset);
    free(xyz);
    free(rgb);
    snprintf(out_path, size, "%s/%s.strata", sta_test_tmpdir(), name);
    const char *inputs[] = { ply };
    sta_convert_options o = { .inputs = inputs,
                              .input_count = 1,
                              .output = out_path,
                              .force = true,
                              .leaf_capacity = 2000,
                              .compress_level = 1 };
    sta_error err = { 0 };
    if (sta_convert(&o, NULL, &err) != STA_OK) {
        fail_msg("%s", err.message);
    }
}

sta_camera sta_fixture_camera(const double offset[3], int width_px, int height_px)
{
    sta_camera c;
    memset(&c, 0, sizeof(c));
    c.position[0] = offset[0] + 3.0;
    c.position[1] = offset[1] - 12.0;
    c.position[2] = offset[2] + 2.0;
    c.yaw = 1.5707963267948966 - 0.1;
    c.pitch = -0.08;
    c.fov_y = 1.0;
    c.near_m = 0.01;
    c.width_px = width_px;
    c.height_px = height_px;
    return c;
}

static sta_gl_headless fixture_gl;

int sta_fixture_gl_setup(void **state)
{
    (void)state;
    sta_error err = { 0 };
    if (sta_gl_headless_create(&fixture_gl, &err) != STA_OK) {
        fprintf(stderr, "%s\n", err.message);
        return -1;
    }
    return 0;
}

int sta_fixture_gl_teardown(void **state)
{
    (void)state;
    sta_gl_headless_destroy(&fixture_gl);
    return 0;
}

sta_frame_stats sta_fixture_render_complete(sta_scene *scene, const sta_camera *camera,
                                            sta_render_target *target)
{
    sta_frame_stats stats;
    memset(&stats, 0, sizeof(stats));
    sta_error err = { 0 };
    for (int frame = 0; frame < 5000; frame++) {
        if (sta_scene_render(scene, camera, target, &stats, &err) != STA_OK) {
            fail_msg("%s", err.message);
        }
        if (stats.complete) {
            return stats;
        }
        struct timespec nap = { 0, 2000000 };
        nanosleep(&nap, NULL);
    }
    fail_msg("the view never finished loading");
    return stats;
}
