/* SPDX-License-Identifier: MIT
 * The unproject pass on llvmpipe against its CPU twin, and against the camera maths. */
#include "test_support.h"

#include <math.h>
#include <string.h>

#include "core/camera.h"
#include "render/gl.h"
#include "render/gl_image.h"
#include "render/gl_staged.h"
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
    assert_int_equal(sta_unproject_pass_run(&pass, &view, depth_texture, position_texture, &err),
                     STA_OK);
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

// The positions of a pass initialised with staging forced to `staged` (gl_staged.h).
static void unproject_with(bool staged, const sta_view_params *view, GLuint depth_texture,
                           sta_image *out)
{
    sta_error err = { 0 };
    sta_gl_staged_stores_force(staged);
    sta_unproject_pass pass;
    assert_int_equal(sta_unproject_pass_init(&pass, &err), STA_OK);
    sta_gl_staged_stores_force(-1);
    assert_int_equal(pass.staged, staged);
    GLuint position_texture;
    assert_int_equal(
        sta_gl_texture_create(view->width_px, view->height_px, 4, 1, &position_texture, &err),
        STA_OK);
    // Twice, the second time at a smaller size into the same buffer: the copy takes the
    // view's rows, not the buffer's.
    sta_view_params small = *view;
    small.width_px = view->width_px / 2;
    small.height_px = view->height_px / 2;
    assert_int_equal(sta_unproject_pass_run(&pass, view, depth_texture, position_texture, &err),
                     STA_OK);
    assert_int_equal(sta_gl_texture_to_image(position_texture, 0, 4, out, &err), STA_OK);
    GLuint small_texture;
    assert_int_equal(
        sta_gl_texture_create(small.width_px, small.height_px, 4, 1, &small_texture, &err), STA_OK);
    assert_int_equal(sta_unproject_pass_run(&pass, &small, depth_texture, small_texture, &err),
                     STA_OK);
    sta_image half;
    assert_int_equal(sta_gl_texture_to_image(small_texture, 0, 4, &half, &err), STA_OK);
    sta_image expected;
    assert_int_equal(sta_image_init(&expected, small.width_px, small.height_px, 4, &err), STA_OK);
    sta_image depth;
    assert_int_equal(sta_gl_texture_to_image(depth_texture, 0, 1, &depth, &err), STA_OK);
    sta_image depth_small;
    assert_int_equal(sta_image_init(&depth_small, small.width_px, small.height_px, 1, &err),
                     STA_OK);
    for (int y = 0; y < small.height_px; y++) {
        for (int x = 0; x < small.width_px; x++) {
            *sta_image_at(&depth_small, x, y) = *sta_image_at(&depth, x, y);
        }
    }
    sta_unproject_ref(&small, &depth_small, &expected);
    for (int i = 0; i < small.width_px * small.height_px * 4; i++) {
        float a = expected.data[i], b = half.data[i];
        assert_true(fabsf(a - b) <= 5e-7f * fmaxf(1.0f, fabsf(a)));
    }
    sta_image_release(&half);
    sta_image_release(&expected);
    sta_image_release(&depth);
    sta_image_release(&depth_small);
    glDeleteTextures(1, &small_texture);
    glDeleteTextures(1, &position_texture);
    sta_unproject_pass_release(&pass);
}

// Staged stores (a storage buffer copied into the texture; the default on llvmpipe) and
// image stores (a GPU's default) write the same floats, bit for bit.
static void staged_and_image_stores_write_the_same_positions(void **state)
{
    (void)state;
    sta_gl_headless gl = { 0 };
    sta_error err = { 0 };
    assert_int_equal(sta_gl_headless_create(&gl, &err), STA_OK);
    const int w = 45, h = 31;
    sta_view_params view = { w, h, 1.1f, 0.02f, 0.01f };
    sta_image depth;
    assert_int_equal(sta_image_init(&depth, w, h, 1, &err), STA_OK);
    int drawn = 0;
    for (int y = 0; y < h; y++) {
        for (int x = 0; x < w; x++) {
            float d = (x * 3 + y) % 5 == 0 ? 0.0f : 0.02f / (0.3f + 0.7f * x + 1.3f * y);
            *sta_image_at(&depth, x, y) = d;
            drawn += d > 0.0f;
        }
    }
    GLuint depth_texture;
    assert_int_equal(sta_gl_texture_from_image(&depth, &depth_texture, &err), STA_OK);
    sta_image by_image, by_buffer;
    unproject_with(false, &view, depth_texture, &by_image);
    unproject_with(true, &view, depth_texture, &by_buffer);
    assert_memory_equal(by_image.data, by_buffer.data, (size_t)w * h * 4 * sizeof(float));
    int written = 0;
    for (int i = 0; i < w * h; i++) {
        written += by_buffer.data[4 * i + 3] > 0.0f;
    }
    assert_int_equal(written, drawn);
    sta_image_release(&by_image);
    sta_image_release(&by_buffer);
    sta_image_release(&depth);
    glDeleteTextures(1, &depth_texture);
    sta_gl_headless_destroy(&gl);
}

// STRATA_STAGED_STORES: "1" and "0" force staging; none, an empty value or a wrong one
// leaves it to the renderer (a wrong one is named on stderr).
static void staged_stores_setting_reads_only_0_and_1(void **state)
{
    (void)state;
    assert_int_equal(sta_gl_staged_stores_from_env("1"), 1);
    assert_int_equal(sta_gl_staged_stores_from_env("0"), 0);
    assert_int_equal(sta_gl_staged_stores_from_env(NULL), -1);
    assert_int_equal(sta_gl_staged_stores_from_env(""), -1);
    assert_int_equal(sta_gl_staged_stores_from_env("yes"), -1);
    assert_int_equal(sta_gl_staged_stores_from_env("10"), -1);
}

static const struct CMUnitTest tests[] = {
    cmocka_unit_test(staged_stores_setting_reads_only_0_and_1),
    cmocka_unit_test(shader_matches_cpu_twin_and_camera),
    cmocka_unit_test(staged_and_image_stores_write_the_same_positions),
};

STA_TEST_MAIN(tests)
