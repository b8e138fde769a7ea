/* SPDX-License-Identifier: MIT
 * The unproject pass on llvmpipe against its CPU twin, and against the camera maths. */
#include "test_support.h"

#include <math.h>
#include <string.h>

#include "core/camera.h"
#include "render/gl.h"
#include "render/gl_image.h"
#include "render/pass_unproject.h"
#include "render/ref/unproject_ref.h"

static void shader_matches_cpu_twin_and_camera(void **state)
{
    (void)state;
    sta_gl_headless gl = { 0 };
    sta_error err = { 0 };
    assert_int_equal(sta_gl_headless_create(&gl, &err), STA_OK);
    const int w = 37, h = 23; // odd sizes: partial workgroups
    sta_view_params view = { w, h, 0.9f, 0.05f, 0.01f };
    sta_image depth;
    assert_int_equal(sta_image_init(&depth, w, h, 1, &err), STA_OK);
    for (int y = 0; y < h; y++) {
        for (int x = 0; x < w; x++) {
            // Empty pixels, the near plane (1), far away (tiny values) and in between.
            float d = (x + y) % 7 == 0 ? 0.0f : (x == 0 ? 1.0f : 0.05f / (0.5f + 3.0f * x + y));
            *sta_image_at(&depth, x, y) = d;
        }
    }
    sta_image expected, got;
    assert_int_equal(sta_image_init(&expected, w, h, 4, &err), STA_OK);
    sta_unproject_ref(&view, &depth, &expected);
    GLuint depth_texture, position_texture;
    assert_int_equal(sta_gl_texture_from_image(&depth, &depth_texture, &err), STA_OK);
    assert_int_equal(sta_gl_texture_create(w, h, 4, 1, &position_texture, &err), STA_OK);
    sta_unproject_pass pass;
    assert_int_equal(sta_unproject_pass_init(&pass, &err), STA_OK);
    sta_unproject_pass_run(&pass, &view, depth_texture, position_texture);
    assert_int_equal(sta_gl_texture_to_image(position_texture, 0, 4, &got, &err), STA_OK);
    // Tolerance: 4 float ulps relative (same formula, same order).
    for (int i = 0; i < w * h * 4; i++) {
        float a = expected.data[i], b = got.data[i];
        assert_true(fabsf(a - b) <= 5e-7f * fmaxf(1.0f, fabsf(a)));
    }
    // The twin agrees with the camera: a position projects back to its pixel centre.
    sta_camera camera = { { 0, 0, 0 }, 0, 0, view.fov_y, view.near_m, w, h, STA_CAMERA_UP_Z };
    double f[3], r[3], u[3];
    sta_camera_basis(&camera, f, r, u);
    for (int y = 0; y < h; y++) {
        for (int x = 0; x < w; x++) {
            const float *p = sta_image_at(&expected, x, y);
            if (p[3] == 0.0f) {
                continue;
            }
            // camera space (x right, y up, -z forward) -> world with this basis
            double world[3];
            for (int a = 0; a < 3; a++) {
                world[a] = r[a] * (double)p[0] + u[a] * (double)p[1] - f[a] * (double)p[2];
            }
            double px, py, pz;
            assert_true(sta_camera_project(&camera, world, &px, &py, &pz));
            assert_true(fabs(px - (x + 0.5)) < 1e-3);
            assert_true(fabs((h - py) - (y + 0.5)) < 1e-3); // project counts rows from the top
            assert_true(fabs(pz + (double)p[2]) < 1e-5 * fabs((double)p[2]));
        }
    }
    sta_unproject_pass_release(&pass);
    glDeleteTextures(1, &depth_texture);
    glDeleteTextures(1, &position_texture);
    sta_image_release(&depth);
    sta_image_release(&expected);
    sta_image_release(&got);
    sta_gl_headless_destroy(&gl);
}

static const struct CMUnitTest tests[] = {
    cmocka_unit_test(shader_matches_cpu_twin_and_camera),
};

STA_TEST_MAIN(tests)
