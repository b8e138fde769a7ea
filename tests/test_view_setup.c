/* SPDX-License-Identifier: MIT
 * Tests for the viewer's default camera (src/app/view_setup.c, view_sample.c, compiled
 * in): a street is seen along its axis from its end; an airborne strip and an elongated
 * solid across; a round scene from the south-west; the sample it frames follows the points'
 * density, not the root node's even spread in space.
 */
#include "test_support.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app/view_sample.h"
#include "app/view_setup.h"
#include "convert.h"
#include "core/alloc.h"
#include "core/camera.h"
#include "core/camera_frame.h"
#include "format/strata_reader.h"
#include "synth/synth.h"

static const double degrees = 3.14159265358979323846 / 180.0;

// Angle between two axes (yaws either way along them), in degrees, 0..90.
static double axis_gap_deg(double yaw_a, double yaw_b)
{
    double d = fmod(fabs(yaw_a - yaw_b), 180.0 * degrees);
    return fmin(d, 180.0 * degrees - d) / degrees;
}

static sta_camera z_up_camera(void)
{
    sta_camera c;
    memset(&c, 0, sizeof(c));
    c.up_axis = STA_CAMERA_UP_Z;
    c.width_px = 640;
    c.height_px = 360;
    c.fov_y = 60.0 * degrees;
    return c;
}

// Box of n points: x in [0, length), y in [0, width), z in [0, height), a lattice.
static double *box_points(size_t n, double length, double width, double height)
{
    double *p = malloc(3 * n * sizeof(double));
    assert_non_null(p);
    uint64_t rng = 12345;
    for (size_t i = 0; i < n; i++) {
        p[3 * i] = length * (double)sta_test_frand(&rng);
        p[3 * i + 1] = width * (double)sta_test_frand(&rng);
        p[3 * i + 2] = height * (double)sta_test_frand(&rng);
    }
    return p;
}

// A street between facades: 4000 points on the ground (0..length x 0..width) and on two
// walls at y = 0 and y = width, 0..height high; a third on each.
static double *corridor_points(double length, double width, double height)
{
    double *p = malloc(3 * 4000 * sizeof(double));
    assert_non_null(p);
    uint64_t rng = 777;
    for (size_t i = 0; i < 4000; i++) {
        double u = length * (double)sta_test_frand(&rng), v = (double)sta_test_frand(&rng);
        double *q = p + 3 * i;
        q[0] = u;
        q[1] = i % 3 == 0 ? width * v : (i % 3 == 1 ? 0.0 : width);
        q[2] = i % 3 == 0 ? 0.0 : height * v;
    }
    return p;
}

// The default direction (yaw, *pitch) for 4000 points, then freed.
static double default_direction(double *points, double *pitch)
{
    sta_camera c = z_up_camera();
    sta_view_direction d = sta_view_default_direction(&c, points, 4000);
    free(points);
    *pitch = d.pitch;
    return d.yaw;
}

static void corridor_is_seen_along_from_its_end(void **state)
{
    (void)state;
    double pitch = 0.0; // 100 m long, 30 m across, 20 m high
    double yaw = default_direction(corridor_points(100.0, 30.0, 20.0), &pitch);
    assert_true(fabs(pitch - STA_VIEW_ALONG_PITCH_DEG * degrees) < 1e-12);
    assert_true(axis_gap_deg(yaw, 0.0) < 3.0);
    // Looking west along an east-west axis: yaw in [90, 270) degrees.
    assert_true(yaw >= 90.0 * degrees && yaw < 270.0 * degrees);
}

// As elongated and as tall, but solid: an elongated model (the dragon), seen across.
static void elongated_solid_is_seen_across(void **state)
{
    (void)state;
    double pitch = 0.0;
    double yaw = default_direction(box_points(4000, 100.0, 30.0, 20.0), &pitch);
    assert_true(fabs(pitch - STA_VIEW_DEFAULT_PITCH_DEG * degrees) < 1e-12);
    assert_true(fabs(axis_gap_deg(yaw, 0.0) - (90.0 - STA_VIEW_ACROSS_TURN_DEG)) < 3.0);
}

static void flat_strip_is_seen_across(void **state)
{
    (void)state;
    double pitch = 0.0; // 1000 m by 300 m, 30 m of relief: an airborne strip
    double yaw = default_direction(box_points(4000, 1000.0, 300.0, 30.0), &pitch);
    assert_true(fabs(pitch - STA_VIEW_DEFAULT_PITCH_DEG * degrees) < 1e-12);
    assert_true(fabs(axis_gap_deg(yaw, 0.0) - (90.0 - STA_VIEW_ACROSS_TURN_DEG)) < 3.0);
}

static void round_scene_is_seen_from_the_south_west(void **state)
{
    (void)state;
    double pitch = 0.0;
    double yaw = default_direction(box_points(4000, 100.0, 90.0, 40.0), &pitch);
    assert_true(fabs(yaw - STA_VIEW_DEFAULT_YAW_DEG * degrees) < 1e-12);
    assert_true(fabs(pitch - STA_VIEW_DEFAULT_PITCH_DEG * degrees) < 1e-12);
}

static void convert_or_fail(const char *in, const char *out)
{
    const char *inputs[] = { in };
    sta_convert_options o = {
        .inputs = inputs, .input_count = 1, .output = out, .force = true, .compress_level = 1
    };
    sta_error err = { 0 };
    if (sta_convert(&o, NULL, &err) != STA_OK) {
        fail_msg("%s", err.message);
    }
}

// 95 % of the points in a 10 m square, 5 % along a 400 m streak from it: the root
// node holds the streak's cells as often as the square's.
static void density_sample_follows_the_points(void **state)
{
    (void)state;
    enum {
        N = 60000
    };
    char ply[4096], strata[4096];
    snprintf(ply, sizeof(ply), "%s", sta_test_tmp_path("view_setup_streak.ply"));
    snprintf(strata, sizeof(strata), "%s", sta_test_tmp_path("view_setup_streak.strata"));
    FILE *f = fopen(ply, "w");
    assert_non_null(f);
    fprintf(f,
            "ply\nformat ascii 1.0\nelement vertex %d\nproperty float x\nproperty float y\n"
            "property float z\nend_header\n",
            N);
    uint64_t rng = 99;
    for (int i = 0; i < N; i++) {
        bool square = i % 20 != 0;
        double x = square ? 10.0 * (double)sta_test_frand(&rng)
                          : 10.0 + 400.0 * (double)sta_test_frand(&rng);
        double y =
            square ? 10.0 * (double)sta_test_frand(&rng) : 4.0 * (double)sta_test_frand(&rng);
        fprintf(f, "%.3f %.3f %.3f\n", x, y, (double)sta_test_frand(&rng));
    }
    fclose(f);
    convert_or_fail(ply, strata);

    sta_strata_reader *reader = NULL;
    sta_error err = { 0 };
    assert_int_equal(sta_strata_open(strata, NULL, &reader, &err), STA_OK);
    const sta_strata_info *info = sta_strata_reader_info(reader);
    sta_view_sample samples;
    assert_true(sta_view_sample_build(reader, info->bounds_min, info->bounds_max, &samples));
    size_t count = samples.weighted_count;
    double(*sample)[3] = samples.weighted;
    assert_true(count > 100);
    // The file's axes are the PLY's (a y-up model keeps its coordinates).
    size_t in_square = 0;
    for (size_t i = 0; i < count; i++) {
        in_square += sample[i][0] < 10.5;
    }
    // The root node itself: mostly the streak.
    sta_strata_decoder *decoder = NULL;
    sta_strata_points root;
    assert_int_equal(sta_strata_decoder_create(&decoder, &err), STA_OK);
    assert_int_equal(sta_strata_decode_node(reader, 0, decoder, &root, &err), STA_OK);
    size_t root_in_square = 0;
    for (size_t i = 0; i < root.count; i++) {
        root_in_square += sta_grid_apply(&info->geometry.grid, 0, root.points[i].X) < 10.5;
    }
    double share = (double)in_square / (double)count;
    double root_share = (double)root_in_square / (double)root.count;
    print_message("square: %.3f of the sample, %.3f of the root's %zu points\n", share, root_share,
                  root.count);
    assert_true(root_share < 0.5);
    assert_true(share > 0.85 && share < 1.0);
    sta_strata_decoder_destroy(decoder);
    sta_view_sample_release(&samples);
    sta_strata_close(reader);
}

// The synth's street (a profile scanner driving it, ground streaks down the cross
// streets): the default camera looks along the axis of all its points, from beyond
// the end of most of them, with its eye above the street. (Before: the root node's
// even spread made the street with its streaks round, and it was seen from the
// south-west over the backs of one side's houses.)
static void street_default_view_looks_along_it(void **state)
{
    (void)state;
    char las[4096], strata[4096];
    snprintf(las, sizeof(las), "%s", sta_test_tmp_path("view_setup_street.las"));
    snprintf(strata, sizeof(strata), "%s", sta_test_tmp_path("view_setup_street.strata"));
    sta_synth_params p = { .kind = STA_SYNTH_STREET, .seed = 1, .point_count = 200000 };
    sta_error err = { 0 };
    assert_int_equal(sta_synth_generate(&p, las, NULL, NULL, &err), STA_OK);
    convert_or_fail(las, strata);

    sta_strata_reader *reader = NULL;
    assert_int_equal(sta_strata_open(strata, NULL, &reader, &err), STA_OK);
    const sta_strata_info *info = sta_strata_reader_info(reader);
    sta_view_args args;
    memset(&args, 0, sizeof(args));
    args.width_px = 640;
    args.height_px = 360;
    args.camera[5] = 60.0;
    sta_camera c;
    memset(&c, 0, sizeof(c));
    char why[256];
    sta_view_initial_camera(&args, info, info->bounds_min, info->bounds_max, &c, why, sizeof(why));
    print_message("street: %s\n", why);

    // Every point of the file: its mean and principal horizontal axis.
    sta_strata_decoder *decoder = NULL;
    assert_int_equal(sta_strata_decoder_create(&decoder, &err), STA_OK);
    double *all = malloc(3 * info->point_count * sizeof(double));
    assert_non_null(all);
    size_t n = 0;
    for (uint32_t node = 0; node < info->node_count; node++) {
        sta_strata_points pts;
        assert_int_equal(sta_strata_decode_node(reader, node, decoder, &pts, &err), STA_OK);
        for (size_t i = 0; i < pts.count; i++, n++) {
            const int32_t xyz[3] = { pts.points[i].X, pts.points[i].Y, pts.points[i].Z };
            for (int a = 0; a < 3; a++) {
                all[3 * n + a] = sta_grid_apply(&info->geometry.grid, a, xyz[a]);
            }
        }
    }
    double elongation = 0.0;
    double axis = sta_camera_points_long_yaw(&c, all, n, &elongation);
    print_message("street: axis %.1f deg (elongation %.2f), camera yaw %.1f pitch %.1f\n",
                  axis / degrees, elongation, c.yaw / degrees, c.pitch / degrees);
    assert_true(elongation > STA_VIEW_ELONGATED_RATIO);
    assert_true(fabs(c.pitch - STA_VIEW_ALONG_PITCH_DEG * degrees) < 1e-9);
    assert_true(axis_gap_deg(c.yaw, axis) < 10.0);

    // In the view's frame: along (forward) and across; the eye behind 95 % of the
    // points, and between them across the axis (30-70 % on either side).
    double fwd[2] = { cos(c.yaw), sin(c.yaw) }, side[2] = { -sin(c.yaw), cos(c.yaw) };
    size_t behind = 0;
    double *across = malloc(n * sizeof(double));
    assert_non_null(across);
    for (size_t i = 0; i < n; i++) {
        double dx = all[3 * i] - c.position[0], dy = all[3 * i + 1] - c.position[1];
        behind += dx * fwd[0] + dy * fwd[1] > 0.0;
        across[i] = dx * side[0] + dy * side[1];
    }
    size_t below = 0;
    for (size_t i = 0; i < n; i++) {
        below += across[i] < 0.0;
    }
    double ahead_share = (double)behind / (double)n, left_share = (double)below / (double)n;
    print_message("street: %.3f of the points ahead of the eye, %.3f on one side\n", ahead_share,
                  left_share);
    assert_true(ahead_share > 0.95);
    assert_true(left_share > 0.3 && left_share < 0.7);
    double ground = info->bounds_min[2];
    assert_true(c.position[2] > ground + 5.0);
    free(across);
    free(all);
    sta_strata_decoder_destroy(decoder);
    sta_strata_close(reader);
}

int main(int argc, char **argv)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(corridor_is_seen_along_from_its_end),
        cmocka_unit_test(elongated_solid_is_seen_across),
        cmocka_unit_test(flat_strip_is_seen_across),
        cmocka_unit_test(round_scene_is_seen_from_the_south_west),
        cmocka_unit_test(density_sample_follows_the_points),
        cmocka_unit_test(street_default_view_looks_along_it),
    };
    return sta_test_run("view_setup", tests, sizeof(tests) / sizeof(tests[0]), argc, argv);
}
