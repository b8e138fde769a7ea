/* SPDX-License-Identifier: MIT
 * The viewer's navigation maths (core/navigation.h) and camera paths
 * (render/camera_path.h, no GL): orbit pitch limits, fly speed and acceleration, the
 * eased focus move, constant-speed playback, path files with bad input. */
#include "test_support.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "core/navigation.h"
#include "render/camera_path.h"

static sta_camera make_camera(double x, double y, double z)
{
    sta_camera c = {
        .position = { x, y, z }, .fov_y = 1.0, .near_m = 0.1, .width_px = 640, .height_px = 360
    };
    return c;
}

static double distance(const double a[3], const double b[3])
{
    return sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                (a[2] - b[2]) * (a[2] - b[2]));
}

// Far from the origin (UTM-like), so cancellation would show.
static const double pivot[3] = { 650235.25, 5401873.5, 105.125 };

static void orbit_keeps_distance_and_pitch_limits(void **state)
{
    (void)state;
    sta_camera c = make_camera(pivot[0] + 30, pivot[1], pivot[2] + 10);
    double r0 = distance(c.position, pivot);
    const double lo = 0.0, hi = 89.0 * M_PI / 180.0;
    for (int i = 0; i < 200; i++) { // drag down a long way: must stop at the pivot's horizon
        sta_nav_orbit(&c, pivot, 0.01, -0.05, lo, hi);
        assert_true(fabs(distance(c.position, pivot) - r0) < 1e-6);
        assert_true(c.position[2] >= pivot[2] - 1e-6);
    }
    assert_true(fabs(c.position[2] - pivot[2]) < 1e-6);
    for (int i = 0; i < 200; i++) { // and up: stops just short of straight above
        sta_nav_orbit(&c, pivot, 0.0, 0.05, lo, hi);
    }
    assert_true(fabs(asin((c.position[2] - pivot[2]) / r0) - hi) < 1e-9);
    // The camera looks at the pivot.
    double f[3], r[3], u[3];
    sta_camera_basis(&c, f, r, u);
    for (int a = 0; a < 3; a++) {
        assert_true(fabs(c.position[a] + f[a] * r0 - pivot[a]) < 1e-6);
    }
}

static void fly_speed_follows_the_surface_and_ramps(void **state)
{
    (void)state;
    assert_true(fabs(sta_nav_fly_speed(10.0, 500.0) - 5.0) < 1e-12);
    assert_true(fabs(sta_nav_fly_speed(1e6, 500.0) - 250.0) < 1e-12); // capped by the scene
    assert_true(fabs(sta_nav_fly_speed(0.0, 500.0) - 0.05) < 1e-12);  // never stuck
    assert_true(fabs(sta_nav_fly_speed(NAN, 500.0) - 0.05) < 1e-12);
    // Holding W for 1.5 s towards a facade 100 m away covers about half of it, not all.
    double d = 100.0, ramp = 0.0;
    for (int i = 0; i < 90; i++) {
        ramp = sta_nav_ramp(ramp, true, 1.0 / 60);
        d -= sta_nav_fly_speed(d, 500.0) * ramp / 60;
    }
    assert_true(d > 30.0 && d < 80.0);
    assert_true(ramp > 0.99 && ramp <= 1.0);
    assert_true(sta_nav_ramp(ramp, false, 1.0 / 60) == 0.0);
    double first = sta_nav_ramp(0.0, true, 1.0 / 60);
    assert_true(first > 0.0 && first < 0.1); // starts gently
}

static void focus_centres_the_point_and_blend_eases(void **state)
{
    (void)state;
    sta_camera from = make_camera(pivot[0] - 40, pivot[1] - 30, pivot[2] + 20);
    from.yaw = 3.0; // looking somewhere else
    const double point[3] = { pivot[0] + 5, pivot[1] + 7, pivot[2] + 1 };
    sta_camera to;
    sta_nav_focus(&from, point, 1.0 / 3.0, &to);
    double x, y, depth;
    assert_true(sta_camera_project(&to, point, &x, &y, &depth));
    assert_true(fabs(x - 320.0) < 1e-6 && fabs(y - 180.0) < 1e-6); // centred
    assert_true(fabs(distance(to.position, point) - distance(from.position, point) / 3) < 1e-6);
    sta_camera mid;
    sta_nav_blend(&from, &to, 0.0, &mid);
    assert_memory_equal(mid.position, from.position, sizeof(mid.position));
    sta_nav_blend(&from, &to, 1.0, &mid);
    assert_true(distance(mid.position, to.position) < 1e-9);
    assert_true(fabs(remainder(mid.yaw - to.yaw, 2 * M_PI)) < 1e-12);
    sta_nav_blend(&from, &to, 0.1, &mid); // eased: slower than linear at the start
    double moved = distance(mid.position, from.position),
           total = distance(to.position, from.position);
    assert_true(moved < 0.1 * total && moved > 0.0);
    // Yaw takes the short way round: from 3.0 rad to about -2.5 rad passes through pi.
    sta_camera a = from, b = from;
    a.yaw = 3.0;
    b.yaw = -3.0;
    sta_nav_blend(&a, &b, 0.5, &mid);
    assert_true(fabs(fabs(remainder(mid.yaw, 2 * M_PI)) - M_PI) < 1e-9);
}

static void write_text(const char *path, const char *text)
{
    sta_test_write_file(path, text, strlen(text));
}

static void constant_speed_retimes_by_length(void **state)
{
    (void)state;
    const char *file = sta_test_tmp_path("path.json");
    // Three keys on a line, 10 m then 30 m apart, with uneven recorded times, then a
    // turn on the spot.
    write_text(file, "{ \"version\": 1, \"keyframes\": ["
                     "{ \"time\": 0, \"position\": [650000, 5400000, 100], \"yaw\": 0, "
                     "\"pitch\": 0, \"fov\": 60 },"
                     "{ \"time\": 7, \"position\": [650010, 5400000, 100], \"yaw\": 0, "
                     "\"pitch\": 0, \"fov\": 60 },"
                     "{ \"time\": 8, \"position\": [650040, 5400000, 100], \"yaw\": 0, "
                     "\"pitch\": 0, \"fov\": 60 },"
                     "{ \"time\": 9, \"position\": [650040, 5400000, 100], \"yaw\": 90, "
                     "\"pitch\": 0, \"fov\": 60 } ] }");
    sta_camera_path p;
    sta_error err = { 0 };
    assert_int_equal(sta_camera_path_load(file, &p, &err), STA_OK);
    assert_int_equal(p.count, 4);
    assert_true(fabs(p.keys[1].time_s - 7.0) < 1e-12); // the file's times are honoured
    assert_int_equal(sta_camera_path_set_speed(&p, 5.0, &err), STA_OK);
    assert_int_equal(p.count, 3 * 16 + 1); // 16 keys per segment
    assert_true(fabs(p.keys[0].time_s - 0.0) < 1e-12);
    // Along a straight line the spline's length is about the chord: 10 m in 2 s, 30 m in
    // 6 s; then the turn, 90 degrees at 45 degrees per second, takes 2 s.
    assert_true(fabs(p.keys[16].time_s - 2.0) < 0.05);
    assert_true(fabs(p.keys[32].time_s - 8.0) < 0.1);
    assert_true(fabs(p.keys[48].time_s - p.keys[32].time_s - 2.0) < 1e-9);
    assert_true(fabs(p.keys[48].yaw - M_PI / 2) < 1e-12);
    // The sampled speed is 5 m/s within 5 % on the moving segments, also across the join
    // of the 10 m and 30 m segments; within 20 % next to the path's two ends, where the
    // spline starts and stops gently.
    sta_camera c0 = make_camera(0, 0, 0), c1 = make_camera(0, 0, 0);
    for (double t = 0.0; t < 7.85; t += 0.05) {
        sta_camera_path_sample(&p, t, &c0);
        sta_camera_path_sample(&p, t + 0.05, &c1);
        double v = distance(c0.position, c1.position) / 0.05;
        bool bend = t < 0.15 || t > 7.7; // the first and last keys
        double tolerance = bend ? 0.2 : 0.05;
        if (fabs(v - 5.0) > 5.0 * tolerance) {
            fail_msg("speed %.3f m/s at %.2f s", v, t);
        }
    }
    assert_int_equal(sta_camera_path_set_speed(&p, 0.0, &err), STA_ERR_ARG);
    assert_int_equal(sta_camera_path_set_speed(&p, NAN, &err), STA_ERR_ARG);
    // Saved and loaded again, the times stay.
    const char *saved = sta_test_tmp_path("saved.json");
    assert_int_equal(sta_camera_path_save(saved, &p, &err), STA_OK);
    sta_camera_path q;
    assert_int_equal(sta_camera_path_load(saved, &q, &err), STA_OK);
    assert_int_equal(q.count, p.count);
    for (size_t i = 0; i < q.count; i++) {
        assert_true(fabs(q.keys[i].time_s - p.keys[i].time_s) < 1e-6);
        assert_true(distance(q.keys[i].position, p.keys[i].position) < 1e-6);
    }
    sta_camera_path_release(&q);
    sta_camera_path_release(&p);
}

static void bad_path_files_are_named(void **state)
{
    (void)state;
    static const struct {
        const char *text;
        const char *expect;
    } cases[] = {
        { "not json", "not valid JSON" },
        { "{ \"keyframes\": [] }", "no \"keyframes\"" },
        { "{ \"keyframes\": [ { \"time\": 0, \"position\": [1, 2], \"yaw\": 0, \"pitch\": 0, "
          "\"fov\": 60 } ] }",
          "keyframe 0" },
        { "{ \"keyframes\": [ { \"time\": 0, \"position\": [1, 2, 3], \"yaw\": 0, \"pitch\": "
          "95, \"fov\": 60 } ] }",
          "pitch" },
        { "{ \"keyframes\": [ { \"time\": 1, \"position\": [1, 2, 3], \"yaw\": 0, \"pitch\": 0, "
          "\"fov\": 60 }, { \"time\": 1, \"position\": [1, 2, 3], \"yaw\": 0, \"pitch\": 0, "
          "\"fov\": 60 } ] }",
          "keyframe 1" },
    };
    for (size_t i = 0; i < sizeof(cases) / sizeof(cases[0]); i++) {
        const char *file = sta_test_tmp_path("bad.json");
        write_text(file, cases[i].text);
        sta_camera_path p;
        sta_error err = { 0 };
        assert_int_equal(sta_camera_path_load(file, &p, &err), STA_ERR_FORMAT);
        assert_non_null(strstr(err.message, "bad.json"));
        if (!strstr(err.message, cases[i].expect)) {
            fail_msg("case %zu: '%s' does not say '%s'", i, err.message, cases[i].expect);
        }
        assert_int_equal(p.count, 0);
    }
}

static const struct CMUnitTest tests[] = {
    cmocka_unit_test(orbit_keeps_distance_and_pitch_limits),
    cmocka_unit_test(fly_speed_follows_the_surface_and_ramps),
    cmocka_unit_test(focus_centres_the_point_and_blend_eases),
    cmocka_unit_test(constant_speed_retimes_by_length),
    cmocka_unit_test(bad_path_files_are_named),
};

STA_TEST_MAIN(tests)
