/* SPDX-License-Identifier: MIT
 * Tests for src/core: errors, allocation hook, growable arrays, clocks, byte helpers, file
 * maps. */
#include "test_support.h"

#include <math.h>
#include <pthread.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/alloc.h"
#include "core/array.h"
#include "core/bytes.h"
#include "core/camera.h"
#include "core/camera_frame.h"
#include "core/clock.h"
#include "core/file_map.h"
#include "core/json_out.h"
#include "core/status.h"

static void fail_formats_message_and_returns_code(void **state)
{
    (void)state;
    sta_error err = { 0 };
    sta_status s = sta_fail(&err, STA_ERR_FORMAT, "%s: point count %d", "a.las", 42);
    assert_int_equal(s, STA_ERR_FORMAT);
    assert_int_equal(err.code, STA_ERR_FORMAT);
    assert_string_equal(err.message, "a.las: point count 42");
    assert_int_equal(sta_error_prefix(&err, "reading %s", "x"), STA_ERR_FORMAT);
    assert_string_equal(err.message, "reading x: a.las: point count 42");
    // A NULL error is allowed and still returns the code.
    assert_int_equal(sta_fail(NULL, STA_ERR_IO, "x"), STA_ERR_IO);
    assert_string_equal(sta_status_str(STA_ERR_UNSUPPORTED), "unsupported");
}

static void alloc_hook_fails_the_nth_allocation(void **state)
{
    (void)state;
    sta_alloc_fail_after(2);
    void *a = sta_malloc(8);
    void *b = sta_malloc(8);
    void *c = sta_malloc(8);
    sta_alloc_fail_after(-1);
    assert_non_null(a);
    assert_non_null(b);
    assert_null(c);
    sta_free(a);
    sta_free(b);
    void *d = sta_malloc(8);
    assert_non_null(d);
    sta_free(d);
}

static void alloc_array_rejects_overflow(void **state)
{
    (void)state;
    assert_null(sta_alloc_array(SIZE_MAX / 2 + 2, 2));
    assert_null(sta_calloc(SIZE_MAX / 4, 8));
    void *p = sta_alloc_array(10, 4);
    assert_non_null(p);
    assert_null(sta_realloc_array(p, SIZE_MAX, 16));
    sta_free(p); // still valid after the failed resize
}

static void array_reserve_grows_from_empty(void **state)
{
    (void)state;
    int *items = NULL;
    size_t capacity = 0;
    // Nothing needed: nothing allocated.
    assert_int_equal(sta_array_reserve((void **)&items, &capacity, 0, sizeof(*items), 16, NULL),
                     STA_OK);
    assert_null(items);
    assert_int_equal(capacity, 0);
    // The first growth takes first_count, or `needed` when that is larger.
    assert_int_equal(sta_array_reserve((void **)&items, &capacity, 1, sizeof(*items), 16, NULL),
                     STA_OK);
    assert_non_null(items);
    assert_int_equal(capacity, 16);
    for (int i = 0; i < 16; i++) {
        items[i] = i;
    }
    sta_free(items);
    items = NULL;
    capacity = 0;
    assert_int_equal(sta_array_reserve((void **)&items, &capacity, 40, sizeof(*items), 16, NULL),
                     STA_OK);
    assert_int_equal(capacity, 40);
    sta_free(items);
    items = NULL;
    capacity = 0;
    assert_int_equal(sta_array_reserve((void **)&items, &capacity, 3, sizeof(*items), 0, NULL),
                     STA_OK);
    assert_int_equal(capacity, 3);
    sta_free(items);
}

static void array_reserve_exact_fit_allocates_nothing(void **state)
{
    (void)state;
    size_t capacity = 16;
    int *items = sta_alloc_array(capacity, sizeof(*items));
    assert_non_null(items);
    int *before = items;
    sta_alloc_fail_after(0); // any allocation would now fail
    sta_status s = sta_array_reserve((void **)&items, &capacity, 16, sizeof(*items), 4, NULL);
    sta_alloc_fail_after(-1);
    assert_int_equal(s, STA_OK);
    assert_ptr_equal(items, before);
    assert_int_equal(capacity, 16);
    sta_free(items);
}

static void array_reserve_doubles_and_keeps_elements(void **state)
{
    (void)state;
    int *items = NULL;
    size_t capacity = 0, count = 0;
    size_t growths = 0;
    for (int i = 0; i < 1000; i++) {
        size_t old = capacity;
        assert_int_equal(
            sta_array_reserve((void **)&items, &capacity, count + 1, sizeof(*items), 4, NULL),
            STA_OK);
        if (capacity != old) {
            assert_int_equal(capacity, old ? 2 * old : 4);
            growths++;
        }
        items[count++] = i;
    }
    assert_int_equal(capacity, 1024);
    assert_int_equal(growths, 9); // 4, 8, ..., 1024
    for (int i = 0; i < 1000; i++) {
        assert_int_equal(items[i], i);
    }
    // A jump past twice the capacity grows to exactly what is needed.
    assert_int_equal(sta_array_reserve((void **)&items, &capacity, 5000, sizeof(*items), 4, NULL),
                     STA_OK);
    assert_int_equal(capacity, 5000);
    assert_int_equal(items[999], 999);
    sta_free(items);
}

static void array_reserve_refuses_overflow(void **state)
{
    (void)state;
    sta_error err = { 0 };
    size_t capacity = 4;
    uint64_t *items = sta_alloc_array(capacity, sizeof(*items));
    assert_non_null(items);
    uint64_t *before = items;
    // needed * item_size overflows size_t: refused before any allocation.
    sta_status s = sta_array_reserve((void **)&items, &capacity, SIZE_MAX / sizeof(*items) + 1,
                                     sizeof(*items), 4, &err);
    assert_int_equal(s, STA_ERR_NOMEM);
    assert_int_equal(err.code, STA_ERR_NOMEM);
    assert_non_null(strstr(err.message, "out of memory"));
    assert_ptr_equal(items, before);
    assert_int_equal(capacity, 4);
    assert_int_equal(sta_array_reserve((void **)&items, &capacity, SIZE_MAX, SIZE_MAX, 4, NULL),
                     STA_ERR_NOMEM);
    assert_ptr_equal(items, before);
    // When doubling would overflow, the growth falls back to `needed` (the failed attempt's
    // message names the count it asked for; the hook fails it without a huge allocation).
    size_t huge = SIZE_MAX / 8 / 2 + 1; // twice this, in 8-byte elements, overflows
    size_t fake_capacity = huge;
    char expected[64];
    snprintf(expected, sizeof(expected), "for %zu elements of 8 bytes", huge + 1);
    sta_alloc_fail_after(0);
    s = sta_array_reserve((void **)&items, &fake_capacity, huge + 1, 8, 4, &err);
    sta_alloc_fail_after(-1);
    assert_int_equal(s, STA_ERR_NOMEM);
    assert_non_null(strstr(err.message, expected));
    assert_int_equal(fake_capacity, huge);
    assert_ptr_equal(items, before);
    sta_free(items);
}

static void array_reserve_failure_keeps_old_array(void **state)
{
    (void)state;
    size_t capacity = 0;
    int *items = NULL;
    assert_int_equal(sta_array_reserve((void **)&items, &capacity, 16, sizeof(*items), 16, NULL),
                     STA_OK);
    for (int i = 0; i < 16; i++) {
        items[i] = 100 + i;
    }
    int *before = items;
    sta_error err = { 0 };
    sta_alloc_fail_after(0);
    sta_status s = sta_array_reserve((void **)&items, &capacity, 17, sizeof(*items), 16, &err);
    sta_alloc_fail_after(-1);
    assert_int_equal(s, STA_ERR_NOMEM);
    assert_int_equal(err.code, STA_ERR_NOMEM);
    assert_non_null(strstr(err.message, "32 elements"));
    assert_ptr_equal(items, before);
    assert_int_equal(capacity, 16);
    for (int i = 0; i < 16; i++) {
        assert_int_equal(items[i], 100 + i);
    }
    // With memory back, the same call succeeds and keeps the elements.
    assert_int_equal(sta_array_reserve((void **)&items, &capacity, 17, sizeof(*items), 16, NULL),
                     STA_OK);
    assert_int_equal(capacity, 32);
    assert_int_equal(items[15], 115);
    sta_free(items);
}

static void clock_is_monotonic_and_non_negative(void **state)
{
    (void)state;
    double s0 = sta_clock_s();
    double ms0 = sta_clock_ms();
    double cpu0 = sta_clock_thread_cpu_ms();
    assert_true(s0 >= 0.0);
    assert_true(ms0 >= 0.0);
    assert_true(cpu0 >= 0.0);
    // Burn a little CPU so the thread clock has something to count.
    volatile double sink = 0.0;
    double s = s0, ms = ms0;
    for (int i = 0; i < 200000; i++) {
        sink = sink + (double)i * 0.5;
        if (i % 1000 == 0) {
            double s1 = sta_clock_s(), ms1 = sta_clock_ms();
            assert_true(s1 >= s);
            assert_true(ms1 >= ms);
            s = s1;
            ms = ms1;
        }
    }
    (void)sink;
    double s_end = sta_clock_s();
    double ms_end = sta_clock_ms();
    double cpu_end = sta_clock_thread_cpu_ms();
    assert_true(s_end >= s);
    assert_true(cpu_end >= cpu0);
    // Seconds and milliseconds read the same clock.
    assert_true(ms_end >= s0 * 1e3);
    assert_true(ms_end <= sta_clock_s() * 1e3 + 1e-3);
}

// Burns CPU on its own thread until that thread's clock has counted *arg ms.
static void *burn_cpu(void *arg)
{
    double want = *(const double *)arg, start = sta_clock_thread_cpu_ms();
    volatile double sink = 0.0;
    while (sta_clock_thread_cpu_ms() - start < want) {
        for (int i = 0; i < 10000; i++) {
            sink = sink + (double)i * 0.5;
        }
    }
    (void)sink;
    return NULL;
}

static void process_clock_counts_other_threads(void **state)
{
    (void)state;
    // The per-pass CPU timing (strata-view --stats-clock cpu) relies on this: work done
    // by another thread (llvmpipe's) shows in the process clock, not the caller's.
    double want = 40.0;
    double process0 = sta_clock_process_cpu_ms(), thread0 = sta_clock_thread_cpu_ms();
    pthread_t worker;
    assert_int_equal(pthread_create(&worker, NULL, burn_cpu, &want), 0);
    assert_int_equal(pthread_join(worker, NULL), 0);
    double process = sta_clock_process_cpu_ms() - process0;
    double thread = sta_clock_thread_cpu_ms() - thread0;
    assert_true(process0 >= 0.0);
    assert_true(process >= want - 1.0);
    assert_true(thread < want / 2.0); // joining waits without spinning
}

static void bytes_round_trip_little_endian(void **state)
{
    (void)state;
    uint8_t buf[8];
    sta_store_u32le(buf, 0x11223344u);
    assert_int_equal(buf[0], 0x44);
    assert_int_equal(sta_load_u32le(buf), 0x11223344u);
    sta_store_i32le(buf, -5);
    assert_int_equal(sta_load_i32le(buf), -5);
    sta_store_f64le(buf, -1.25e300);
    assert_true(sta_load_f64le(buf) == -1.25e300);
    sta_store_f32le(buf, NAN);
    assert_true(isnan(sta_load_f32le(buf)));
    const uint8_t be[4] = { 0x3f, 0x80, 0x00, 0x00 };
    assert_int_equal(sta_load_u32be(be), 0x3f800000u);
    sta_store_u64le(buf, 0x0102030405060708ull);
    assert_int_equal(buf[7], 0x01);
    assert_true(sta_load_u64le(buf) == 0x0102030405060708ull);
}

static void file_map_reads_file_and_names_missing_one(void **state)
{
    (void)state;
    const char *path = sta_test_tmp_path("map.bin");
    sta_test_write_file(path, "hello", 5);
    sta_file_map map = { 0 };
    sta_error err = { 0 };
    assert_int_equal(sta_file_map_open(path, &map, &err), STA_OK);
    assert_int_equal(map.size, 5);
    assert_memory_equal(map.data, "hello", 5);
    sta_file_map_close(&map);
    sta_file_map_close(&map); // closing twice is harmless

    const char *empty = sta_test_tmp_path("empty.bin");
    sta_test_write_file(empty, "", 0);
    assert_int_equal(sta_file_map_open(empty, &map, &err), STA_OK);
    assert_int_equal(map.size, 0);
    assert_null(map.data);
    sta_file_map_close(&map);

    assert_int_equal(sta_file_map_open("/nonexistent/x.las", &map, &err), STA_ERR_IO);
    assert_non_null(strstr(err.message, "/nonexistent/x.las"));
    assert_int_equal(sta_file_map_open(sta_test_tmpdir(), &map, &err), STA_ERR_IO);
    assert_non_null(strstr(err.message, "not a regular file"));
}

static void format_double_is_shortest_exact(void **state)
{
    (void)state;
    char buf[40];
    assert_string_equal(sta_format_double(637012.24, buf, sizeof(buf)), "637012.24");
    assert_string_equal(sta_format_double(5400000.0, buf, sizeof(buf)), "5400000");
    assert_string_equal(sta_format_double(-0.001, buf, sizeof(buf)), "-0.001");
    assert_string_equal(sta_format_double(1e-9, buf, sizeof(buf)), "1e-09");
    assert_string_equal(sta_format_double(NAN, buf, sizeof(buf)), "nan");
    // Every printed value reads back to the same double.
    const double hard[] = { 0.1 + 0.2, 1.16451354e-06, 6378137.123456789, 1e300, -2.5e-320 };
    for (size_t i = 0; i < sizeof(hard) / sizeof(hard[0]); i++) {
        sta_format_double(hard[i], buf, sizeof(buf));
        assert_true(strtod(buf, NULL) == hard[i]);
    }
}

static void json_writer_nests_and_escapes(void **state)
{
    (void)state;
    char text[256] = { 0 };
    FILE *f = fmemopen(text, sizeof(text) - 1, "w");
    assert_non_null(f);
    sta_json_out json;
    sta_json_init(&json, f, false);
    sta_json_begin_object(&json);
    sta_json_key(&json, "a");
    sta_json_begin_array(&json);
    sta_json_int(&json, -1);
    sta_json_double(&json, 0.5);
    sta_json_double(&json, INFINITY);
    sta_json_end_array(&json);
    sta_json_key(&json, "s\"");
    sta_json_string_n(&json, "x\n\0y", 4);
    sta_json_key(&json, "e");
    sta_json_begin_object(&json);
    sta_json_end_object(&json);
    sta_json_end_object(&json);
    fclose(f);
    assert_string_equal(text, "{\"a\":[-1,0.5,null],\"s\\\"\":\"x\\n\\u0000y\",\"e\":{}}");
}

// With +Y up, yaw 0 pitch 0 looks along +X with +Y up on screen and +Z to the right
// (a right-handed turn of the z-up frame); a point above the eye shows in the upper
// half, one to +Z on the right; frame conversions invert each other.
static void camera_y_up_basis(void **state)
{
    (void)state;
    sta_camera c = {
        .fov_y = 1.0, .near_m = 0.01, .width_px = 200, .height_px = 100, .up_axis = STA_CAMERA_UP_Y
    };
    double f[3], r[3], u[3];
    sta_camera_basis(&c, f, r, u);
    const double ef[3] = { 1, 0, 0 }, er[3] = { 0, 0, 1 }, eu[3] = { 0, 1, 0 };
    for (int a = 0; a < 3; a++) {
        assert_true(fabs(f[a] - ef[a]) < 1e-12 && fabs(r[a] - er[a]) < 1e-12 &&
                    fabs(u[a] - eu[a]) < 1e-12);
    }
    double x, y, d;
    const double above[3] = { 10, 2, 0 }, right[3] = { 10, 0, 2 };
    assert_true(sta_camera_project(&c, above, &x, &y, &d));
    assert_true(y < 50.0 && fabs(x - 100.0) < 1e-9 && fabs(d - 10.0) < 1e-9);
    assert_true(sta_camera_project(&c, right, &x, &y, &d));
    assert_true(x > 100.0 && fabs(y - 50.0) < 1e-9);
    const double v[3] = { 0.3, -1.7, 2.9 };
    double frame[3], back[3];
    sta_camera_to_frame(&c, v, frame);
    assert_true(fabs(frame[2] - v[1]) < 1e-15); // up is the frame's z
    sta_camera_from_frame(&c, frame, back);
    for (int a = 0; a < 3; a++) {
        assert_true(fabs(back[a] - v[a]) < 1e-15);
    }
    // Pitching up looks up: +Y.
    c.pitch = 0.5;
    sta_camera_basis(&c, f, r, u);
    assert_true(f[1] > 0.4 && fabs(f[2]) < 1e-12);
}

// A cloud 10 times longer along x than along y: its long axis is found, and framed it
// fills the view without a point outside.
static void camera_frames_points(void **state)
{
    (void)state;
    enum {
        N = 2000
    };
    double *p = malloc(N * 3 * sizeof(double));
    assert_non_null(p);
    uint64_t seed = 7;
    for (int i = 0; i < N; i++) {
        for (int a = 0; a < 3; a++) {
            seed = seed * 6364136223846793005ULL + 1442695040888963407ULL;
            double t = (double)(seed >> 11) / 9007199254740992.0 - 0.5;
            p[3 * i + a] = (a == 0 ? 100.0 : a == 1 ? 10.0 : 5.0) * t + 1000.0;
        }
    }
    sta_camera c = { .fov_y = 1.0, .width_px = 320, .height_px = 240 };
    double elongation = 0.0;
    double yaw = sta_camera_points_long_yaw(&c, p, N, &elongation);
    assert_true(fabs(sin(yaw)) < 0.02);
    assert_true(elongation > 8.0 && elongation < 12.0);
    c.yaw = yaw + 1.2;
    c.pitch = -0.5;
    const double centre[3] = { 1010.0, 995.0, 1000.0 }; // off the cloud's middle
    const sta_camera_frame_rule all = { .keep = 1.0 };
    sta_camera_frame_points(&c, centre, p, N, &all);
    double lo[2] = { 1e9, 1e9 }, hi[2] = { -1e9, -1e9 };
    for (int i = 0; i < N; i++) {
        double x, y, d;
        assert_true(sta_camera_project(&c, p + 3 * i, &x, &y, &d));
        assert_true(x >= 0.0 && y >= 0.0 && x <= 320.0 && y <= 240.0);
        lo[0] = fmin(lo[0], x), hi[0] = fmax(hi[0], x);
        lo[1] = fmin(lo[1], y), hi[1] = fmax(hi[1], y);
    }
    // Tight on one axis (5 % margin) and centred on both.
    assert_true(hi[0] - lo[0] > 0.85 * 320.0 || hi[1] - lo[1] > 0.85 * 240.0);
    assert_true(fabs(0.5 * (lo[0] + hi[0]) - 160.0) < 8.0);
    assert_true(fabs(0.5 * (lo[1] + hi[1]) - 120.0) < 8.0);
    assert_true(c.near_m > 0.0);
    // No points: one metre back, no crash.
    sta_camera_frame_points(&c, centre, NULL, 0, &all);
    assert_true(isfinite(c.position[0]));
    free(p);
}

// A ball of 4000 points with an ear of 30 points (0.7 %) sticking up 1.5 radii and one
// stray 40 radii out: keeping 99.5 % at each edge cuts the ear's tip; the stray-gap rule
// takes the ear back in and still cuts the stray, and the margin keeps the whole framed
// set that many pixels inside the view.
static void camera_frame_keeps_extremities_and_cuts_strays(void **state)
{
    (void)state;
    enum {
        BALL = 4000,
        EAR = 30,
        N = BALL + EAR + 1
    };
    double *p = malloc(N * 3 * sizeof(double));
    assert_non_null(p);
    uint64_t seed = 11;
    for (int i = 0; i < BALL; i++) {
        double v[3], len2;
        do { // uniform in the unit ball, by rejection
            len2 = 0.0;
            for (int a = 0; a < 3; a++) {
                seed = seed * 6364136223846793005ULL + 1442695040888963407ULL;
                v[a] = 2.0 * ((double)(seed >> 11) / 9007199254740992.0) - 1.0;
                len2 += v[a] * v[a];
            }
        } while (len2 > 1.0);
        for (int a = 0; a < 3; a++) {
            p[3 * i + a] = 500.0 + v[a];
        }
    }
    for (int i = 0; i < EAR; i++) { // straight up from the ball's top, to 2.5 radii
        double *q = p + 3 * (BALL + i);
        q[0] = 500.0, q[1] = 500.0, q[2] = 501.0 + 1.5 * (i + 1) / EAR;
    }
    double *stray = p + 3 * (N - 1);
    stray[0] = 500.0, stray[1] = 540.0, stray[2] = 500.0; // across the view
    const double centre[3] = { 500.0, 500.0, 500.0 };
    const double *tip = p + 3 * (N - 2);
    enum {
        W = 640,
        H = 360
    };
    sta_camera c = { .fov_y = 1.0, .width_px = W, .height_px = H, .yaw = 0.0, .pitch = -0.4 };
    double x, y, d;

    const sta_camera_frame_rule share = { .keep = 0.995 };
    sta_camera_frame_points(&c, centre, p, N, &share);
    assert_true(sta_camera_project(&c, tip, &x, &y, &d));
    assert_true(y < 0.0); // the ear's tip cut at the top edge

    const sta_camera_frame_rule model = { .keep = 0.995, .stray_gap = 0.05, .margin_px = 40.0 };
    sta_camera_frame_points(&c, centre, p, N, &model);
    double lo[2] = { 1e9, 1e9 }, hi[2] = { -1e9, -1e9 };
    for (int i = 0; i < N - 1; i++) {
        assert_true(sta_camera_project(&c, p + 3 * i, &x, &y, &d));
        lo[0] = fmin(lo[0], x), hi[0] = fmax(hi[0], x);
        lo[1] = fmin(lo[1], y), hi[1] = fmax(hi[1], y);
    }
    // Every point but the stray at least 40 px inside (half a pixel for rounding), the
    // ear's tip on top, and tight: one edge within a few pixels of the margin.
    assert_true(lo[0] >= 39.5 && lo[1] >= 39.5 && hi[0] <= W - 39.5 && hi[1] <= H - 39.5);
    assert_true(sta_camera_project(&c, tip, &x, &y, &d));
    assert_true(fabs(y - lo[1]) < 1.0);
    assert_true(lo[1] < 46.0 || hi[1] > H - 46.0);
    bool stray_seen =
        sta_camera_project(&c, stray, &x, &y, &d) && x >= 0.0 && x <= W && y >= 0.0 && y <= H;
    assert_false(stray_seen);
    free(p);
}

static const struct CMUnitTest tests[] = {
    cmocka_unit_test(format_double_is_shortest_exact),
    cmocka_unit_test(json_writer_nests_and_escapes),
    cmocka_unit_test(fail_formats_message_and_returns_code),
    cmocka_unit_test(alloc_hook_fails_the_nth_allocation),
    cmocka_unit_test(alloc_array_rejects_overflow),
    cmocka_unit_test(array_reserve_grows_from_empty),
    cmocka_unit_test(array_reserve_exact_fit_allocates_nothing),
    cmocka_unit_test(array_reserve_doubles_and_keeps_elements),
    cmocka_unit_test(array_reserve_refuses_overflow),
    cmocka_unit_test(array_reserve_failure_keeps_old_array),
    cmocka_unit_test(clock_is_monotonic_and_non_negative),
    cmocka_unit_test(process_clock_counts_other_threads),
    cmocka_unit_test(bytes_round_trip_little_endian),
    cmocka_unit_test(file_map_reads_file_and_names_missing_one),
    cmocka_unit_test(camera_y_up_basis),
    cmocka_unit_test(camera_frames_points),
    cmocka_unit_test(camera_frame_keeps_extremities_and_cuts_strays),
};

STA_TEST_MAIN(tests)
