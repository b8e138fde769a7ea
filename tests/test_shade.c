/* SPDX-License-Identifier: MIT
 * Shading and eye-dome lighting on llvmpipe against their CPU twins, and their
 * meaning on simple buffers. */
#include "test_support.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "render/gl.h"
#include "render/gl_image.h"
#include "render/pass_shade.h"
#include "render/ref/screen_space.h"
#include "render/ref/shade_ref.h"

static sta_gl_headless gl;

static int setup(void **state)
{
    (void)state;
    sta_error err = { 0 };
    return sta_gl_headless_create(&gl, &err) == STA_OK ? 0 : -1;
}

static int teardown(void **state)
{
    (void)state;
    sta_gl_headless_destroy(&gl);
    return 0;
}

// Random buffers: ~20% background, some pixels without a normal, a few at huge depth.
static void make_buffers(int w, int h, sta_image *position, sta_image *colour, sta_image *normal)
{
    sta_error err = { 0 };
    assert_int_equal(sta_image_init(position, w, h, 4, &err), STA_OK);
    assert_int_equal(sta_image_init(colour, w, h, 4, &err), STA_OK);
    assert_int_equal(sta_image_init(normal, w, h, 4, &err), STA_OK);
    uint64_t s = 99;
    for (int y = 0; y < h; y++) {
        for (int x = 0; x < w; x++) {
            float *p = sta_image_at(position, x, y), *c = sta_image_at(colour, x, y),
                  *n = sta_image_at(normal, x, y);
            if (sta_test_frand(&s) < 0.2f) {
                continue;
            }
            float depth = (x % 13 == 0) ? 1e5f : 1.0f + 20.0f * sta_test_frand(&s);
            p[0] = (sta_test_frand(&s) - 0.5f) * depth;
            p[1] = (sta_test_frand(&s) - 0.5f) * depth;
            p[2] = -depth;
            p[3] = 1.0f;
            c[0] = sta_test_frand(&s);
            c[1] = sta_test_frand(&s);
            c[2] = sta_test_frand(&s);
            if (sta_test_frand(&s) < 0.9f) {
                float v[3] = { sta_test_frand(&s) - 0.5f, sta_test_frand(&s) - 0.5f,
                               sta_test_frand(&s) };
                float len = sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
                n[0] = v[0] / len;
                n[1] = v[1] / len;
                n[2] = v[2] / len;
                n[3] = 1.0f;
            }
        }
    }
    // Pixels where the volumetric overlay drew a marked point (filled colour alpha 1,
    // screen_space.h), some of them on background: shaded unlit, as they are.
    for (int i = 0; i < w * h; i += 7) {
        float *c = colour->data + 4 * i;
        c[0] = 0.25f + 0.5f * sta_test_frand(&s);
        c[1] = sta_test_frand(&s);
        c[2] = 0.75f;
        c[3] = 1.0f;
    }
}

// The colour as the pipeline's RGBA8 filled colour holds it (screen_space.h).
static void round_to_rgba8(sta_image *colour)
{
    size_t n = (size_t)colour->width * (size_t)colour->height * 4;
    for (size_t i = 0; i < n; i++) {
        colour->data[i] = sta_unorm8(colour->data[i]);
    }
}

static GLuint rgba8_texture(int w, int h)
{
    GLuint t;
    glCreateTextures(GL_TEXTURE_2D, 1, &t);
    glTextureStorage2D(t, 1, GL_RGBA8, w, h);
    return t;
}

// Largest difference in 8-bit steps between the GPU output and the twin.
static int max_difference(GLuint texture, const sta_image *expected)
{
    int w = expected->width, h = expected->height;
    uint8_t *got = malloc((size_t)w * h * 4);
    assert_non_null(got);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glGetTextureImage(texture, 0, GL_RGBA, GL_UNSIGNED_BYTE, w * h * 4, got);
    int worst = 0;
    for (int i = 0; i < w * h * 4; i++) {
        int e = (int)lroundf(expected->data[i] * 255.0f);
        int d = abs(e - (int)got[i]);
        worst = d > worst ? d : worst;
    }
    free(got);
    return worst;
}

static void shaders_match_twins(void **state)
{
    (void)state;
    const int w = 45, h = 31;
    sta_image position, colour, normal, expected;
    make_buffers(w, h, &position, &colour, &normal);
    sta_error err = { 0 };
    assert_int_equal(sta_image_init(&expected, w, h, 4, &err), STA_OK);
    round_to_rgba8(&colour);
    GLuint tp, tc, tc8, tn, out = rgba8_texture(w, h);
    assert_int_equal(sta_gl_texture_from_image(&position, &tp, &err), STA_OK);
    assert_int_equal(sta_gl_texture_from_image(&colour, &tc, &err), STA_OK);
    assert_int_equal(sta_gl_texture_rgba8_from_image(&colour, &tc8, &err), STA_OK);
    assert_int_equal(sta_gl_texture_from_image(&normal, &tn, &err), STA_OK);
    sta_shade_pass pass;
    assert_int_equal(sta_shade_pass_init(&pass, &err), STA_OK);

    sta_shade_params shade = { .background = { 0.1f, 0.2f, 0.3f } };
    sta_shade_params_defaults(&shade);
    sta_shade_ref(&shade, &position, &colour, &normal, &expected);
    sta_shade_pass_run(&pass, &shade, w, h, tp, tc8, tn, NULL, out);
    // Tolerance: one 8-bit step (rounding of values computed in float on both sides).
    assert_true(max_difference(out, &expected) <= 1);
    // The overlay's pixels (alpha 1) come out as their colour, exactly.
    uint8_t *got = malloc((size_t)w * h * 4);
    assert_non_null(got);
    glGetTextureImage(out, 0, GL_RGBA, GL_UNSIGNED_BYTE, w * h * 4, got);
    int overlaid = 0;
    for (int i = 0; i < w * h; i++) {
        if (colour.data[4 * i + 3] == 1.0f) {
            for (int k = 0; k < 3; k++) {
                assert_int_equal(got[4 * i + k], lrintf(colour.data[4 * i + k] * 255.0f));
                assert_true(expected.data[4 * i + k] == colour.data[4 * i + k]);
            }
            overlaid++;
        }
    }
    assert_int_equal(overlaid, (w * h + 6) / 7);
    free(got);

    sta_edl_params edl = { .background = { 0.0f, 0.0f, 0.0f } };
    sta_edl_params_defaults(&edl);
    sta_edl_ref(&edl, &position, &colour, &expected);
    sta_edl_pass_run(&pass, &edl, w, h, tp, tc, out);
    assert_true(max_difference(out, &expected) <= 1);

    sta_shade_pass_release(&pass);
    GLuint textures[5] = { tp, tc, tc8, tn, out };
    glDeleteTextures(5, textures);
    sta_image_release(&position);
    sta_image_release(&colour);
    sta_image_release(&normal);
    sta_image_release(&expected);
}

static void lighting_means_what_it_should(void **state)
{
    (void)state;
    // Three pixels: a surface facing the eye, one at 80 degrees, background.
    sta_image position, colour, normal, out;
    sta_error err = { 0 };
    assert_int_equal(sta_image_init(&position, 3, 1, 4, &err), STA_OK);
    assert_int_equal(sta_image_init(&colour, 3, 1, 4, &err), STA_OK);
    assert_int_equal(sta_image_init(&normal, 3, 1, 4, &err), STA_OK);
    assert_int_equal(sta_image_init(&out, 3, 1, 4, &err), STA_OK);
    for (int x = 0; x < 2; x++) {
        float *p = sta_image_at(&position, x, 0), *c = sta_image_at(&colour, x, 0),
              *n = sta_image_at(&normal, x, 0);
        p[2] = -5.0f;
        p[3] = 1.0f;
        c[0] = c[1] = c[2] = 0.5f;
        float angle = x == 0 ? 0.0f : 80.0f * 3.14159265f / 180.0f;
        n[0] = sinf(angle);
        n[2] = cosf(angle);
        n[3] = 1.0f;
    }
    sta_shade_params shade = { .background = { 0.0f, 0.0f, 1.0f } };
    sta_shade_params_defaults(&shade);
    sta_shade_ref(&shade, &position, &colour, &normal, &out);
    float facing = sta_image_at(&out, 0, 0)[0], grazing = sta_image_at(&out, 1, 0)[0];
    assert_true(facing > grazing + 0.2f);
    assert_float_equal(sta_image_at(&out, 2, 0)[2], 1.0f, 0.0f); // background colour
    // EDL: a far pixel beside a near one darkens; a flat neighbourhood does not.
    sta_image_at(&position, 1, 0)[2] = -50.0f; // pixel 1 far behind pixel 0
    sta_edl_params edl = { .radius_px = 1.0f };
    sta_edl_params_defaults(&edl);
    sta_edl_ref(&edl, &position, &colour, &out);
    assert_true(sta_image_at(&out, 1, 0)[0] < 0.25f);             // occluded by its neighbour
    assert_float_equal(sta_image_at(&out, 0, 0)[0], 0.5f, 1e-6f); // nothing nearer around it
    sta_image_release(&position);
    sta_image_release(&colour);
    sta_image_release(&normal);
    sta_image_release(&out);
}

static void defaults_fill_only_zero_fields(void **state)
{
    (void)state;
    sta_shade_params shade = { .specular = 0.5f, .background = { 0.1f, 0.2f, 0.3f } };
    sta_shade_params_defaults(&shade);
    assert_true(shade.ambient == STA_SHADE_DEFAULT_AMBIENT);
    assert_true(shade.diffuse == STA_SHADE_DEFAULT_DIFFUSE);
    assert_true(shade.specular == 0.5f);
    assert_true(shade.shininess == STA_SHADE_DEFAULT_SHININESS);
    assert_true(shade.background[0] == 0.1f && shade.background[2] == 0.3f);
    sta_edl_params edl = { .strength = 5.0f };
    sta_edl_params_defaults(&edl);
    assert_true(edl.radius_px == STA_EDL_DEFAULT_RADIUS_PX && edl.strength == 5.0f);
}

static void empty_frame_is_background(void **state)
{
    (void)state;
    const int w = 9, h = 7;
    sta_image position, colour, normal, expected;
    sta_error err = { 0 };
    assert_int_equal(sta_image_init(&position, w, h, 4, &err), STA_OK);
    assert_int_equal(sta_image_init(&colour, w, h, 4, &err), STA_OK);
    assert_int_equal(sta_image_init(&normal, w, h, 4, &err), STA_OK);
    assert_int_equal(sta_image_init(&expected, w, h, 4, &err), STA_OK);
    GLuint tp, tc, tn, out = rgba8_texture(w, h);
    assert_int_equal(sta_gl_texture_from_image(&position, &tp, &err), STA_OK);
    assert_int_equal(sta_gl_texture_rgba8_from_image(&colour, &tc, &err), STA_OK);
    assert_int_equal(sta_gl_texture_from_image(&normal, &tn, &err), STA_OK);
    sta_shade_pass pass;
    assert_int_equal(sta_shade_pass_init(&pass, &err), STA_OK);
    sta_shade_params shade = { .background = { 0.2f, 0.4f, 0.6f } };
    sta_shade_pass_run(&pass, &shade, w, h, tp, tc, tn, NULL, out);
    for (int i = 0; i < w * h; i++) {
        float *e = expected.data + 4 * i;
        e[0] = 0.2f;
        e[1] = 0.4f;
        e[2] = 0.6f;
        e[3] = 1.0f;
    }
    assert_true(max_difference(out, &expected) <= 1);
    sta_shade_pass_release(&pass);
    GLuint textures[4] = { tp, tc, tn, out };
    glDeleteTextures(4, textures);
    sta_image_release(&position);
    sta_image_release(&colour);
    sta_image_release(&normal);
    sta_image_release(&expected);
}

static const struct CMUnitTest tests[] = {
    cmocka_unit_test_setup_teardown(shaders_match_twins, setup, teardown),
    cmocka_unit_test(lighting_means_what_it_should),
    cmocka_unit_test(defaults_fill_only_zero_fields),
    cmocka_unit_test_setup_teardown(empty_frame_is_background, setup, teardown),
};

STA_TEST_MAIN(tests)
