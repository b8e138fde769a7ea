/* SPDX-License-Identifier: MIT
 * Point size options (render/point_size.h, no GL): defaults and zero fields, parsing
 * with clear errors, the window's size steps, the labels, and the per-frame footprint's
 * figures against the camera's projection. */
#include "test_support.h"

#include <math.h>
#include <string.h>

#include "render/point_size.h"

static void zero_is_one_pixel_and_defaults_resolve(void **state)
{
    (void)state;
    sta_point_size zero = { 0 }, d, r;
    assert_true(sta_point_size_is_one_pixel(&zero));
    sta_point_size_defaults(&d);
    assert_true(sta_point_size_is_one_pixel(&d));
    sta_point_size_resolve(&zero, &r);
    assert_true(r.mode == STA_POINT_SIZE_FIXED && r.size_px == STA_POINT_SIZE_DEFAULT_PX);
    assert_true(r.min_px == STA_POINT_SIZE_DEFAULT_MIN_PX);
    assert_true(r.max_px == STA_POINT_SIZE_DEFAULT_MAX_PX);
    // Out of range diameters are clamped, a maximum below the minimum raised to it.
    sta_point_size odd = { .mode = STA_POINT_SIZE_ADAPTIVE, .min_px = 12, .max_px = 3 };
    sta_point_size_resolve(&odd, &r);
    assert_true(r.min_px == 12 && r.max_px == 12);
    odd = (sta_point_size){ .size_px = 500 };
    sta_point_size_resolve(&odd, &r);
    assert_true(r.size_px == STA_POINT_SIZE_LIMIT_PX);
    // The one-pixel footprint is all zero: the rasterisers' exact one-pixel rule.
    sta_camera camera = { .fov_y = 1.0, .near_m = 0.1, .width_px = 640, .height_px = 360 };
    sta_raster_ref_footprint f;
    sta_point_size_footprint(&d, &camera, &f);
    sta_raster_ref_footprint none = { 0 };
    assert_memory_equal(&f, &none, sizeof(f));
}

static void parse_accepts_sizes_and_adaptive(void **state)
{
    (void)state;
    sta_point_size s;
    sta_point_size_defaults(&s);
    sta_error err = { 0 };
    assert_int_equal(sta_point_size_parse("2.5", &s, &err), STA_OK);
    assert_true(s.mode == STA_POINT_SIZE_FIXED && s.size_px == 2.5);
    assert_int_equal(sta_point_size_parse("adaptive", &s, &err), STA_OK);
    assert_int_equal(s.mode, STA_POINT_SIZE_ADAPTIVE);
    assert_true(s.size_px == 2.5); // kept for the way back to fixed
    const char *bad[] = { "0", "0.99", "65", "3px", "", "nan", "inf", "adaptiv" };
    for (size_t i = 0; i < sizeof(bad) / sizeof(bad[0]); i++) {
        sta_point_size before = s;
        assert_int_equal(sta_point_size_parse(bad[i], &s, &err), STA_ERR_ARG);
        assert_non_null(strstr(err.message, bad[i]));
        assert_non_null(strstr(err.message, "adaptive"));
        assert_memory_equal(&s, &before, sizeof(s));
    }
}

static void steps_and_labels(void **state)
{
    (void)state;
    sta_point_size s;
    sta_point_size_defaults(&s);
    char text[64];
    sta_point_size_describe(&s, text, sizeof(text));
    assert_string_equal(text, "1 px");
    sta_point_size_step(&s, -1); // no smaller than one pixel
    assert_true(s.size_px == 1.0);
    sta_point_size_step(&s, +1);
    sta_point_size_step(&s, +1);
    assert_true(s.size_px == 3.0);
    s.size_px = 7.0; // between steps: up to the next, down to the one below
    sta_point_size_step(&s, +1);
    assert_true(s.size_px == 8.0);
    s.size_px = 7.0;
    sta_point_size_step(&s, -1);
    assert_true(s.size_px == 6.0);
    s.size_px = 16.0; // the keys' largest step
    sta_point_size_step(&s, +1);
    assert_true(s.size_px == 16.0);
    s.size_px = STA_POINT_SIZE_LIMIT_PX; // from the command line: kept going up, stepped down
    sta_point_size_step(&s, +1);
    assert_true(s.size_px == STA_POINT_SIZE_LIMIT_PX);
    sta_point_size_step(&s, -1);
    assert_true(s.size_px == 16.0);
    s.mode = STA_POINT_SIZE_ADAPTIVE;
    s.min_px = 2;
    s.max_px = 6;
    sta_point_size_describe(&s, text, sizeof(text));
    assert_string_equal(text, "adaptive 2-6 px");
    sta_point_size_step(&s, +1); // a step leaves adaptive, from its largest size
    assert_int_equal(s.mode, STA_POINT_SIZE_FIXED);
    assert_true(s.size_px == 8.0);
}

// A length L at distance w spans L * (height / 2) / tan(fov / 2) / w pixels: the
// adaptive radius of a spacing is half of that, and the paraboloid's relative depth
// offset per pixel of radius is the pixel's size at 1 m.
static void footprint_follows_the_projection(void **state)
{
    (void)state;
    sta_camera camera = { .fov_y = M_PI / 3, .near_m = 0.1, .width_px = 640, .height_px = 360 };
    sta_point_size s = { .mode = STA_POINT_SIZE_ADAPTIVE, .min_px = 2, .max_px = 10 };
    sta_raster_ref_footprint f;
    sta_point_size_footprint(&s, &camera, &f);
    double pixels_per_metre = 180.0 / tan(M_PI / 6); // at 1 m
    assert_int_equal(f.wide, 1);
    assert_int_equal(f.adaptive, 1);
    assert_true(fabs((double)f.spacing_to_px - 0.5 * pixels_per_metre) < 1e-3);
    assert_float_equal(f.min_radius_px, 1.0, 0);
    assert_float_equal(f.max_radius_px, 5.0, 0);
    assert_true(fabs((double)f.depth_per_px - 1.0 / pixels_per_metre) < 1e-9);
    s = (sta_point_size){ .size_px = 5 };
    sta_point_size_footprint(&s, &camera, &f);
    assert_int_equal(f.adaptive, 0);
    assert_float_equal(f.radius_px, 2.5, 0);
}

static const struct CMUnitTest tests[] = {
    cmocka_unit_test(zero_is_one_pixel_and_defaults_resolve),
    cmocka_unit_test(parse_accepts_sizes_and_adaptive),
    cmocka_unit_test(steps_and_labels),
    cmocka_unit_test(footprint_follows_the_projection),
};

STA_TEST_MAIN(tests)
