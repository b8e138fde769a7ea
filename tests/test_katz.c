/* SPDX-License-Identifier: MIT
 * Katz et al. HPR through Qhull against analytic visibility: a sphere seen from outside
 * (visible iff dot(p - c, v - p) > 0), a small sphere inside a closed box (all hidden),
 * a small plane in front of a large one (the far points behind it hidden). Degenerate
 * input (points at the viewpoint, duplicates, planes and lines through the viewpoint,
 * fewer than 4 points, NaN and infinity) gives a defined result and Qhull stays silent.
 * Perturbation (Braga et al.) is deterministic per seed; its effect and the time for
 * 10k and 100k points are printed, not asserted. */
#include "test_support.h"

#include <fcntl.h>
#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/alloc.h"
#include "visibility/katz_hpr.h"

#define PI 3.14159265358979323846

typedef double point3[3];

static uint64_t rng_state;

static double rng_uniform(void)
{
    rng_state = rng_state * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(rng_state >> 11) / 9007199254740992.0;
}

static point3 *new_points(size_t count)
{
    point3 *points = sta_alloc_array(count ? count : 1, sizeof(*points));
    assert_non_null(points);
    return points;
}

static uint8_t *new_flags(size_t count)
{
    uint8_t *flags = sta_calloc(count ? count : 1, 1);
    assert_non_null(flags);
    return flags;
}

// Uniform random points on a sphere.
static void fill_sphere(point3 *out, size_t count, const double centre[3], double radius)
{
    for (size_t i = 0; i < count; i++) {
        double z = 2.0 * rng_uniform() - 1.0;
        double phi = 2.0 * PI * rng_uniform();
        double r = sqrt(1.0 - z * z);
        out[i][0] = centre[0] + radius * r * cos(phi);
        out[i][1] = centre[1] + radius * r * sin(phi);
        out[i][2] = centre[2] + radius * z;
    }
}

// Truth for a convex sphere: the outward normal at p faces the viewpoint.
static bool sphere_sees(const double p[3], const double centre[3], const double v[3])
{
    double d = 0.0;
    for (int k = 0; k < 3; k++) {
        d += (p[k] - centre[k]) * (v[k] - p[k]);
    }
    return d > 0.0;
}

typedef struct score {
    size_t true_pos, false_pos, false_neg, true_neg;
} score;

static void add_score(score *s, bool truth, bool got)
{
    if (truth && got) {
        s->true_pos++;
    } else if (!truth && got) {
        s->false_pos++;
    } else if (truth) {
        s->false_neg++;
    } else {
        s->true_neg++;
    }
}

static double precision(const score *s)
{
    return (double)s->true_pos / (double)(s->true_pos + s->false_pos);
}

static double recall(const score *s)
{
    return (double)s->true_pos / (double)(s->true_pos + s->false_neg);
}

static sta_katz_stats run_ok(const point3 *points, size_t count, const double v[3],
                             const sta_katz_params *params, uint8_t *visible)
{
    sta_error err = { 0 };
    sta_katz_stats stats;
    memset(&stats, 0xAB, sizeof(stats));
    sta_status status = sta_katz_visible(points, count, v, params, visible, &stats, &err);
    if (status != STA_OK) {
        fail_msg("sta_katz_visible: %s", err.message);
    }
    assert_int_equal(err.code, STA_OK);
    size_t visible_count = 0;
    for (size_t i = 0; i < count; i++) {
        assert_true(visible[i] <= 1);
        visible_count += visible[i];
    }
    assert_int_equal(stats.visible_count, visible_count);
    return stats;
}

/* ---- analytic scenes ---- */

static void sphere_from_outside(void **state)
{
    (void)state;
    rng_state = 11;
    const size_t n = 10000;
    const double centre[3] = { 100.0, -50.0, 20.0 };
    const double v[3] = { 103.0, -49.7, 20.2 }; // about 3 radii from the centre
    point3 *points = new_points(n);
    uint8_t *visible = new_flags(n);
    fill_sphere(points, n, centre, 1.0);
    const double gammas[] = { 1.0, 2.0, 3.0, 4.0 };
    for (size_t g = 0; g < sizeof(gammas) / sizeof(gammas[0]); g++) {
        sta_katz_params params = { .radius_factor = pow(10.0, gammas[g]) };
        sta_katz_stats stats = run_ok((const point3 *)points, n, v, &params, visible);
        score s = { 0 };
        for (size_t i = 0; i < n; i++) {
            add_score(&s, sphere_sees(points[i], centre, v), visible[i]);
        }
        printf("sphere %zu points, gamma %.0f: precision %.4f recall %.4f (visible %zu, "
               "truth %zu), hull %.1f ms\n",
               n, gammas[g], precision(&s), recall(&s), stats.visible_count,
               s.true_pos + s.false_neg, stats.hull_ms);
        assert_int_equal(stats.hull_dim, 3);
        assert_int_equal(stats.degenerate, 0);
        assert_true(recall(&s) > 0.99); // a convex surface: its near cap is all on the hull
        if (gammas[g] <= 3.0) {
            assert_true(precision(&s) > 0.9);
        }
        if (gammas[g] == 2.0) {
            // The default parameters are gamma 2.
            uint8_t *again = new_flags(n);
            run_ok((const point3 *)points, n, v, NULL, again);
            assert_memory_equal(visible, again, n);
            sta_free(again);
        }
    }
    sta_free(visible);
    sta_free(points);
}

// A closed box [-2, 2]^3 (points on its faces) with a sphere of radius 0.5 inside.
static size_t fill_nested(point3 *points, size_t box_count, size_t sphere_count, const double v[3],
                          uint8_t *truth)
{
    for (size_t i = 0; i < box_count; i++) {
        int face = (int)(rng_uniform() * 6.0);
        int axis = face / 2;
        double side = (face & 1) ? 2.0 : -2.0;
        points[i][axis] = side;
        points[i][(axis + 1) % 3] = 4.0 * rng_uniform() - 2.0;
        points[i][(axis + 2) % 3] = 4.0 * rng_uniform() - 2.0;
        truth[i] = side > 0.0 ? v[axis] > side : v[axis] < side;
    }
    const double origin[3] = { 0.0, 0.0, 0.0 };
    fill_sphere(points + box_count, sphere_count, origin, 0.5);
    memset(truth + box_count, 0, sphere_count);
    return box_count + sphere_count;
}

static void nested_sphere_in_box(void **state)
{
    (void)state;
    rng_state = 12;
    const size_t box_count = 12000;
    const size_t sphere_count = 3000;
    const double v[3] = { 6.0, 2.5, 1.5 }; // sees the +x and +y faces
    point3 *points = new_points(box_count + sphere_count);
    uint8_t *truth = new_flags(box_count + sphere_count);
    uint8_t *visible = new_flags(box_count + sphere_count);
    size_t n = fill_nested(points, box_count, sphere_count, v, truth);
    sta_katz_stats stats = run_ok((const point3 *)points, n, v, NULL, visible);
    score box = { 0 };
    size_t inner_visible = 0;
    for (size_t i = 0; i < n; i++) {
        if (i < box_count) {
            add_score(&box, truth[i], visible[i]);
        } else {
            inner_visible += visible[i];
        }
    }
    double inner_fraction = (double)inner_visible / (double)sphere_count;
    printf("nested: inner sphere visible %.4f (%zu of %zu); box precision %.4f recall %.4f; "
           "hull %.1f ms\n",
           inner_fraction, inner_visible, sphere_count, precision(&box), recall(&box),
           stats.hull_ms);
    assert_true(inner_fraction < 0.01);
    assert_true(precision(&box) > 0.9);
    assert_true(recall(&box) > 0.99);
    sta_free(visible);
    sta_free(truth);
    sta_free(points);
}

// A near square z = 0, |x|, |y| <= 1 and a far square z = -1, |x|, |y| <= 3, seen from
// v = (0.3, 0.2, 3): a far point is hidden iff the segment to v crosses the near square.
static size_t fill_planes(point3 *points, size_t per_plane, const double v[3], uint8_t *truth)
{
    for (size_t i = 0; i < per_plane; i++) {
        points[i][0] = 2.0 * rng_uniform() - 1.0;
        points[i][1] = 2.0 * rng_uniform() - 1.0;
        points[i][2] = 0.0;
        truth[i] = 1;
    }
    for (size_t i = per_plane; i < 2 * per_plane; i++) {
        points[i][0] = 6.0 * rng_uniform() - 3.0;
        points[i][1] = 6.0 * rng_uniform() - 3.0;
        points[i][2] = -1.0;
        double t = v[2] / (v[2] - points[i][2]); // where the segment meets z = 0
        double x = v[0] + t * (points[i][0] - v[0]);
        double y = v[1] + t * (points[i][1] - v[1]);
        truth[i] = !(fabs(x) <= 1.0 && fabs(y) <= 1.0);
    }
    return 2 * per_plane;
}

static void parallel_planes(void **state)
{
    (void)state;
    rng_state = 13;
    const size_t per_plane = 8000;
    const double v[3] = { 0.3, 0.2, 3.0 };
    point3 *points = new_points(2 * per_plane);
    uint8_t *truth = new_flags(2 * per_plane);
    uint8_t *visible = new_flags(2 * per_plane);
    size_t n = fill_planes(points, per_plane, v, truth);
    sta_katz_stats stats = run_ok((const point3 *)points, n, v, NULL, visible);
    size_t near_visible = 0;
    size_t behind = 0;
    size_t behind_visible = 0;
    size_t open = 0;
    size_t open_visible = 0;
    for (size_t i = 0; i < n; i++) {
        if (i < per_plane) {
            near_visible += visible[i];
        } else if (truth[i]) {
            open++;
            open_visible += visible[i];
        } else {
            behind++;
            behind_visible += visible[i];
        }
    }
    double behind_fraction = (double)behind_visible / (double)behind;
    double near_fraction = (double)near_visible / (double)per_plane;
    double open_fraction = (double)open_visible / (double)open;
    printf("planes: far points behind the near plane visible %.4f (%zu of %zu); near plane "
           "visible %.4f; far points in the open visible %.4f; hull %.1f ms\n",
           behind_fraction, behind_visible, behind, near_fraction, open_fraction, stats.hull_ms);
    assert_true(behind_fraction < 0.05);
    assert_true(near_fraction > 0.95);
    assert_true(open_fraction > 0.8);
    sta_free(visible);
    sta_free(truth);
    sta_free(points);
}

/* ---- degenerate input ---- */

static void points_at_viewpoint(void **state)
{
    (void)state;
    rng_state = 21;
    const size_t n = 2000;
    const double centre[3] = { 0.0, 0.0, 0.0 };
    const double v[3] = { 0.0, 0.0, 3.0 };
    point3 *points = new_points(n + 3);
    uint8_t *base = new_flags(n);
    uint8_t *visible = new_flags(n + 3);
    fill_sphere(points, n, centre, 1.0);
    run_ok((const point3 *)points, n, v, NULL, base);
    // Insert three copies of the viewpoint at the front, middle and end.
    point3 *with = new_points(n + 3);
    size_t at[3] = { 0, n / 2 + 1, n + 2 };
    for (size_t i = 0, j = 0; i < n + 3; i++) {
        if (i == at[0] || i == at[1] || i == at[2]) {
            memcpy(with[i], v, sizeof(point3));
        } else {
            memcpy(with[i], points[j++], sizeof(point3));
        }
    }
    sta_katz_stats stats = run_ok((const point3 *)with, n + 3, v, NULL, visible);
    assert_int_equal(stats.at_viewpoint_count, 3);
    assert_true(stats.degenerate & STA_KATZ_AT_VIEWPOINT);
    assert_int_equal(stats.hull_input_count, n);
    for (size_t i = 0, j = 0; i < n + 3; i++) {
        if (i == at[0] || i == at[1] || i == at[2]) {
            assert_int_equal(visible[i], 1);
        } else {
            assert_int_equal(visible[i], base[j++]); // set aside, not hulled: no effect
        }
    }
    // Every point at the viewpoint: all visible, no hull.
    point3 same[5];
    for (int i = 0; i < 5; i++) {
        memcpy(same[i], v, sizeof(point3));
    }
    stats = run_ok((const point3 *)same, 5, v, NULL, visible);
    assert_int_equal(stats.visible_count, 5);
    assert_int_equal(stats.hull_dim, 0);
    sta_free(with);
    sta_free(visible);
    sta_free(base);
    sta_free(points);
}

static void duplicate_points(void **state)
{
    (void)state;
    rng_state = 22;
    const size_t n = 2000;
    const double centre[3] = { 1.0, 2.0, 3.0 };
    const double v[3] = { 4.0, 2.5, 3.5 };
    point3 *points = new_points(n);
    uint8_t *base = new_flags(n);
    fill_sphere(points, n, centre, 1.0);
    run_ok((const point3 *)points, n, v, NULL, base);
    // Three copies of each point in a shuffled order.
    size_t total = 3 * n;
    point3 *copies = new_points(total);
    size_t *source = sta_alloc_array(total, sizeof(*source));
    uint8_t *visible = new_flags(total);
    assert_non_null(source);
    for (size_t i = 0; i < total; i++) {
        source[i] = i % n;
    }
    for (size_t i = total - 1; i > 0; i--) {
        size_t j = (size_t)(rng_uniform() * (double)(i + 1));
        size_t swap = source[i];
        source[i] = source[j];
        source[j] = swap;
    }
    for (size_t i = 0; i < total; i++) {
        memcpy(copies[i], points[source[i]], sizeof(point3));
    }
    sta_katz_stats stats = run_ok((const point3 *)copies, total, v, NULL, visible);
    assert_int_equal(stats.duplicate_count, 2 * n);
    assert_int_equal(stats.hull_input_count, n);
    assert_true(stats.degenerate & STA_KATZ_DUPLICATES);
    for (size_t i = 0; i < total; i++) {
        assert_int_equal(visible[i], base[source[i]]);
    }
    sta_free(visible);
    sta_free(source);
    sta_free(copies);
    sta_free(base);
    sta_free(points);
}

static void fewer_than_four_points(void **state)
{
    (void)state;
    const double v[3] = { 0.0, 0.0, 0.0 };
    // Collinear with the viewpoint on purpose: still all visible below 4 points.
    point3 points[6] = { { 1, 0, 0 }, { 2, 0, 0 }, { 3, 0, 0 },
                         { 1, 0, 0 }, { 2, 0, 0 }, { 1, 0, 0 } };
    uint8_t visible[6];
    sta_katz_stats stats = run_ok(NULL, 0, v, NULL, visible);
    assert_int_equal(stats.visible_count, 0);
    for (size_t n = 1; n <= 3; n++) {
        memset(visible, 0, sizeof(visible));
        stats = run_ok((const point3 *)points, n, v, NULL, visible);
        assert_int_equal(stats.visible_count, n);
        assert_true(stats.degenerate & STA_KATZ_FEW_POINTS);
        assert_int_equal(stats.hull_dim, 0);
    }
    // Six points, three distinct (-0.0 equals 0.0).
    points[4][1] = -0.0;
    stats = run_ok((const point3 *)points, 6, v, NULL, visible);
    assert_int_equal(stats.visible_count, 6);
    assert_int_equal(stats.hull_input_count, 3);
    assert_int_equal(stats.duplicate_count, 3);
    assert_true(stats.degenerate & STA_KATZ_FEW_POINTS);
}

// A plane that misses the viewpoint flips to a curved sheet: an ordinary 3-d hull.
static void plane_facing_viewpoint(void **state)
{
    (void)state;
    const size_t side = 60;
    point3 *points = new_points(side * side);
    uint8_t *visible = new_flags(side * side);
    for (size_t i = 0; i < side * side; i++) {
        points[i][0] = (double)(i % side) / (double)(side - 1) * 2.0 - 1.0;
        points[i][1] = (double)(i / side) / (double)(side - 1) * 2.0 - 1.0;
        points[i][2] = 0.0;
    }
    const double v[3] = { 0.2, 0.1, 2.0 };
    sta_katz_stats stats = run_ok((const point3 *)points, side * side, v, NULL, visible);
    double fraction = (double)stats.visible_count / (double)(side * side);
    printf("grid plane seen from above: visible %.4f, hull dim %d\n", fraction, stats.hull_dim);
    assert_int_equal(stats.hull_dim, 3);
    assert_true(fraction > 0.99); // nothing occludes a plane seen from one side
    sta_free(visible);
    sta_free(points);
}

// Orthonormal basis of a tilted plane, so the flat case is not axis aligned.
static void tilted_basis(double e1[3], double e2[3])
{
    const double a[3] = { 1.0, 2.0, 0.5 };
    const double b[3] = { -2.0, 1.0, 3.0 };
    double la = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    double d = (a[0] * b[0] + a[1] * b[1] + a[2] * b[2]) / (la * la);
    double c[3] = { b[0] - d * a[0], b[1] - d * a[1], b[2] - d * a[2] };
    double lc = sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
    for (int k = 0; k < 3; k++) {
        e1[k] = a[k] / la;
        e2[k] = c[k] / lc;
    }
}

// A circle and the viewpoint in one tilted plane: Qhull cannot take a 3-d hull, the
// operator takes the 2-d one in that plane (Katz's operator in 2-d).
static void plane_through_viewpoint(void **state)
{
    (void)state;
    rng_state = 23;
    const size_t n = 1000;
    double e1[3];
    double e2[3];
    tilted_basis(e1, e2);
    const double v[3] = { 5.0, -3.0, 7.0 };
    double centre[3];
    for (int k = 0; k < 3; k++) {
        centre[k] = v[k] + 3.0 * e1[k] + 0.5 * e2[k];
    }
    point3 *points = new_points(n);
    uint8_t *visible = new_flags(n);
    for (size_t i = 0; i < n; i++) {
        double phi = 2.0 * PI * rng_uniform();
        for (int k = 0; k < 3; k++) {
            points[i][k] = centre[k] + cos(phi) * e1[k] + sin(phi) * e2[k];
        }
    }
    sta_katz_stats stats = run_ok((const point3 *)points, n, v, NULL, visible);
    score s = { 0 };
    for (size_t i = 0; i < n; i++) {
        add_score(&s, sphere_sees(points[i], centre, v), visible[i]);
    }
    printf("circle in a plane through the viewpoint: hull dim %d, precision %.4f recall %.4f\n",
           stats.hull_dim, precision(&s), recall(&s));
    assert_int_equal(stats.hull_dim, 2);
    assert_true(stats.degenerate & STA_KATZ_PLANE);
    assert_true(precision(&s) > 0.9);
    assert_true(recall(&s) > 0.99);
    sta_free(visible);
    sta_free(points);
}

// A line that misses the viewpoint spans a plane with it: 2-d hull, nothing occluded.
static void line_off_viewpoint(void **state)
{
    (void)state;
    const size_t n = 101;
    double e1[3];
    double e2[3];
    tilted_basis(e1, e2);
    const double v[3] = { 1.0, 1.0, 1.0 };
    point3 *points = new_points(n);
    uint8_t *visible = new_flags(n);
    for (size_t i = 0; i < n; i++) {
        double t = (double)i / (double)(n - 1) * 10.0 - 5.0;
        for (int k = 0; k < 3; k++) {
            points[i][k] = v[k] + t * e1[k] + 1.0 * e2[k];
        }
    }
    sta_katz_stats stats = run_ok((const point3 *)points, n, v, NULL, visible);
    printf("line off the viewpoint: hull dim %d, visible %zu of %zu\n", stats.hull_dim,
           stats.visible_count, n);
    assert_int_equal(stats.hull_dim, 2);
    assert_int_equal(stats.visible_count, n);
    sta_free(visible);
    sta_free(points);
}

// Points on one line through the viewpoint: only the nearest on each side is visible.
static void line_through_viewpoint(void **state)
{
    (void)state;
    double e1[3];
    double e2[3];
    tilted_basis(e1, e2);
    const double v[3] = { -2.0, 4.0, 1.0 };
    const double ts[] = { 3.0, 1.0, 7.0, -1.5, 2.0, -4.0, 10.0, -2.5, 5.0 };
    const size_t n = sizeof(ts) / sizeof(ts[0]);
    point3 points[sizeof(ts) / sizeof(ts[0])];
    uint8_t visible[sizeof(ts) / sizeof(ts[0])];
    for (size_t i = 0; i < n; i++) {
        for (int k = 0; k < 3; k++) {
            points[i][k] = v[k] + ts[i] * e1[k];
        }
    }
    sta_katz_stats stats = run_ok((const point3 *)points, n, v, NULL, visible);
    assert_int_equal(stats.hull_dim, 1);
    assert_true(stats.degenerate & STA_KATZ_LINE);
    for (size_t i = 0; i < n; i++) {
        assert_int_equal(visible[i], ts[i] == 1.0 || ts[i] == -1.5);
    }
}

static void expect_error(const point3 *points, size_t count, const double v[3],
                         const sta_katz_params *params, sta_status code, const char *needle)
{
    sta_error err = { 0 };
    uint8_t visible[8];
    memset(visible, 7, sizeof(visible));
    sta_katz_stats stats = { .visible_count = 12345 };
    assert_int_equal(
        sta_katz_visible(points, count, v, params, count ? visible : NULL, &stats, &err), code);
    assert_int_equal(err.code, code);
    printf("expected error: %s\n", err.message);
    if (!strstr(err.message, needle)) {
        fail_msg("message '%s' lacks '%s'", err.message, needle);
    }
    assert_int_equal(visible[0], 7); // outputs untouched on failure
    assert_int_equal(stats.visible_count, 12345);
}

static void nonfinite_input(void **state)
{
    (void)state;
    point3 points[6] = { { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 },
                         { 1, 1, 1 }, { 2, 1, 0 }, { 0, 2, 1 } };
    const double v[3] = { 5.0, 5.0, 5.0 };
    points[3][1] = nan("");
    expect_error((const point3 *)points, 6, v, NULL, STA_ERR_ARG, "point 3");
    points[3][1] = HUGE_VAL;
    expect_error((const point3 *)points, 6, v, NULL, STA_ERR_ARG, "point 3");
    points[3][1] = 1.0;
    const double bad_v[3] = { 0.0, -HUGE_VAL, 0.0 };
    expect_error((const point3 *)points, 6, bad_v, NULL, STA_ERR_ARG, "viewpoint");
    // Finite, but the distance to the viewpoint (or its square) overflows.
    points[4][0] = 1.7e308;
    expect_error((const point3 *)points, 6, v, NULL, STA_ERR_ARG, "point 4");
    points[4][0] = 1e160;
    expect_error((const point3 *)points, 6, v, NULL, STA_ERR_ARG, "point 4");
    // Finite distances, but R = radius_factor * max distance is too large for Qhull.
    points[4][0] = 1e140;
    sta_katz_params huge = { .radius_factor = 1e12 };
    expect_error((const point3 *)points, 6, v, &huge, STA_ERR_ARG, "radius");
    points[4][0] = 2.0;
    sta_katz_params params = { .radius_factor = 0.5 };
    expect_error((const point3 *)points, 6, v, &params, STA_ERR_ARG, "radius_factor");
    params = (sta_katz_params){ .radius_factor = nan("") };
    expect_error((const point3 *)points, 6, v, &params, STA_ERR_ARG, "radius_factor");
    params = (sta_katz_params){ .perturbation = -0.01 };
    expect_error((const point3 *)points, 6, v, &params, STA_ERR_ARG, "perturbation");
    expect_error(NULL, 6, v, NULL, STA_ERR_ARG, "points");
    expect_error((const point3 *)points, 6, NULL, NULL, STA_ERR_ARG, "viewpoint");
}

// Runs the degenerate cases with stdout and stderr sent to files: Qhull must print
// nothing (its messages go to a stream of ours).
static void qhull_is_silent(void **state)
{
    (void)state;
    rng_state = 24;
    const size_t n = 400;
    point3 *points = new_points(n);
    uint8_t *visible = new_flags(n);
    double e1[3];
    double e2[3];
    tilted_basis(e1, e2);
    const double v[3] = { 0.0, 0.0, 0.0 };
    const char *out_path = sta_test_tmp_path("katz_stdout.txt");
    char saved_out_path[4096];
    snprintf(saved_out_path, sizeof(saved_out_path), "%s", out_path);
    const char *err_path = sta_test_tmp_path("katz_stderr.txt");
    fflush(stdout);
    fflush(stderr);
    int saved_out = dup(1);
    int saved_err = dup(2);
    int fd_out = open(saved_out_path, O_WRONLY | O_CREAT | O_TRUNC, 0600);
    int fd_err = open(err_path, O_WRONLY | O_CREAT | O_TRUNC, 0600);
    assert_true(saved_out >= 0 && saved_err >= 0 && fd_out >= 0 && fd_err >= 0);
    dup2(fd_out, 1);
    dup2(fd_err, 2);
    // Nearly flat through the viewpoint at several thicknesses (around both our
    // flatness tolerance and Qhull's), and exactly flat.
    const double thickness[] = { 0.0, 1e-14, 1e-12, 1e-10, 1e-9, 1e-7 };
    int dims[sizeof(thickness) / sizeof(thickness[0])];
    unsigned degenerate[sizeof(thickness) / sizeof(thickness[0])];
    sta_status status = STA_OK;
    sta_error err = { 0 };
    for (size_t t = 0; t < sizeof(thickness) / sizeof(thickness[0]) && status == STA_OK; t++) {
        double normal[3] = { e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                             e1[0] * e2[1] - e1[1] * e2[0] };
        for (size_t i = 0; i < n; i++) {
            double a = 4.0 * rng_uniform() + 1.0;
            double b = 4.0 * rng_uniform() - 2.0;
            double c = thickness[t] * (2.0 * rng_uniform() - 1.0);
            for (int k = 0; k < 3; k++) {
                points[i][k] = a * e1[k] + b * e2[k] + c * normal[k];
            }
        }
        sta_katz_stats stats = { 0 };
        status = sta_katz_visible((const point3 *)points, n, v, NULL, visible, &stats, &err);
        dims[t] = stats.hull_dim;
        degenerate[t] = stats.degenerate;
    }
    fflush(stdout);
    fflush(stderr);
    dup2(saved_out, 1);
    dup2(saved_err, 2);
    close(saved_out);
    close(saved_err);
    close(fd_out);
    close(fd_err);
    if (status != STA_OK) {
        fail_msg("nearly flat input: %s", err.message);
    }
    for (size_t t = 0; t < sizeof(thickness) / sizeof(thickness[0]); t++) {
        printf("flat through viewpoint, relative thickness %g: hull dim %d, degenerate 0x%x\n",
               thickness[t] / 5.0, dims[t], degenerate[t]);
    }
    assert_int_equal(dims[0], 2);
    struct stat st;
    assert_int_equal(stat(saved_out_path, &st), 0);
    assert_int_equal(st.st_size, 0);
    assert_int_equal(stat(err_path, &st), 0);
    assert_int_equal(st.st_size, 0);
    sta_free(visible);
    sta_free(points);
}

// Fails each allocation in turn (ours and Qhull's context): an error, never a leak.
static void allocation_failures(void **state)
{
    (void)state;
    rng_state = 25;
    const size_t n = 300;
    point3 *points = new_points(n + 2);
    uint8_t *visible = new_flags(n + 2);
    const double centre[3] = { 0.0, 0.0, 0.0 };
    const double v[3] = { 0.0, 3.0, 0.0 };
    fill_sphere(points, n, centre, 1.0);
    memcpy(points[n], points[0], sizeof(point3));
    memcpy(points[n + 1], v, sizeof(point3));
    sta_katz_params params = { .perturbation = 0.001 };
    sta_status status = STA_ERR_NOMEM;
    long failures = 0;
    for (long after = 0; status != STA_OK; after++) {
        sta_error err = { 0 };
        sta_alloc_fail_after(after);
        status = sta_katz_visible((const point3 *)points, n + 2, v, &params, visible, NULL, &err);
        sta_alloc_fail_after(-1);
        if (status != STA_OK) {
            assert_int_equal(status, STA_ERR_NOMEM);
            assert_true(strstr(err.message, "memory") != NULL);
            failures++;
        }
        assert_true(after < 100);
    }
    printf("allocation failures handled: %ld\n", failures);
    assert_true(failures >= 4);
    sta_free(visible);
    sta_free(points);
}

/* ---- perturbation and time ---- */

static void perturbation_is_deterministic(void **state)
{
    (void)state;
    rng_state = 31;
    const size_t box_count = 8000;
    const size_t sphere_count = 2000;
    const size_t n = box_count + sphere_count;
    const double v[3] = { 6.0, 2.5, 1.5 };
    point3 *points = new_points(n);
    uint8_t *truth = new_flags(n);
    uint8_t *exact = new_flags(n);
    uint8_t *first = new_flags(n);
    uint8_t *second = new_flags(n);
    fill_nested(points, box_count, sphere_count, v, truth);
    sta_katz_stats off = run_ok((const point3 *)points, n, v, NULL, exact);
    sta_katz_params params = { .perturbation = STA_KATZ_BRAGA_PERTURBATION, .seed = 5 };
    sta_katz_stats on = run_ok((const point3 *)points, n, v, &params, first);
    run_ok((const point3 *)points, n, v, &params, second);
    assert_memory_equal(first, second, n);
    assert_true(on.perturbation_abs > 0.0);
    assert_true(off.perturbation_abs == 0.0);
    params.seed = 6;
    run_ok((const point3 *)points, n, v, &params, second);
    size_t seed_differ = 0;
    size_t agree = 0;
    score s_off = { 0 };
    score s_on = { 0 };
    for (size_t i = 0; i < n; i++) {
        seed_differ += first[i] != second[i];
        agree += first[i] == exact[i];
        add_score(&s_off, truth[i], exact[i]);
        add_score(&s_on, truth[i], first[i]);
    }
    printf("perturbation %.2f (a = %.4f): seeds 5 and 6 differ on %zu of %zu points; agrees "
           "with exact on %.4f\n",
           STA_KATZ_BRAGA_PERTURBATION, on.perturbation_abs, seed_differ, n,
           (double)agree / (double)n);
    printf("  exact:     precision %.4f recall %.4f, hull %.1f ms (cpu %.1f)\n", precision(&s_off),
           recall(&s_off), off.hull_ms, off.hull_cpu_ms);
    printf("  perturbed: precision %.4f recall %.4f, hull %.1f ms (cpu %.1f)\n", precision(&s_on),
           recall(&s_on), on.hull_ms, on.hull_cpu_ms);
    // The noise follows the sorted distinct points, so the input order does not matter.
    point3 *reversed = new_points(n);
    for (size_t i = 0; i < n; i++) {
        memcpy(reversed[i], points[n - 1 - i], sizeof(point3));
    }
    params.seed = 5;
    run_ok((const point3 *)reversed, n, v, &params, second);
    for (size_t i = 0; i < n; i++) {
        assert_int_equal(second[n - 1 - i], first[i]);
    }
    sta_free(reversed);
    sta_free(second);
    sta_free(first);
    sta_free(exact);
    sta_free(truth);
    sta_free(points);
}

static void timing(void **state)
{
    (void)state;
    const size_t sizes[] = { 10000, 100000 };
    const double v[3] = { 6.0, 2.5, 1.5 };
    for (size_t k = 0; k < 2; k++) {
        rng_state = 41;
        size_t box_count = sizes[k] * 4 / 5;
        size_t n = box_count + sizes[k] / 5;
        point3 *points = new_points(n);
        uint8_t *truth = new_flags(n);
        uint8_t *visible = new_flags(n);
        fill_nested(points, box_count, n - box_count, v, truth);
        for (int pert = 0; pert < 2; pert++) {
            sta_katz_params params = { .perturbation = pert ? STA_KATZ_BRAGA_PERTURBATION : 0.0 };
            sta_katz_stats stats = run_ok((const point3 *)points, n, v, &params, visible);
            score s = { 0 };
            for (size_t i = 0; i < n; i++) {
                add_score(&s, truth[i], visible[i]);
            }
            printf("timing: %zu points (box + inner sphere), perturbation %.2f: hull %.1f ms "
                   "(cpu %.1f), total %.1f ms, %zu hull vertices; precision %.4f recall "
                   "%.4f\n",
                   n, params.perturbation, stats.hull_ms, stats.hull_cpu_ms, stats.total_ms,
                   stats.hull_vertex_count, precision(&s), recall(&s));
        }
        sta_free(visible);
        sta_free(truth);
        sta_free(points);
    }
}

static void defaults_fill_only_zero_fields(void **state)
{
    (void)state;
    sta_katz_params params = { 0 };
    sta_katz_params_defaults(&params);
    assert_true(params.radius_factor == STA_KATZ_DEFAULT_RADIUS_FACTOR);
    assert_true(params.perturbation == 0.0 && params.seed == STA_KATZ_DEFAULT_SEED);
    params = (sta_katz_params){ .radius_factor = 3.0, .perturbation = 0.01, .seed = 9 };
    sta_katz_params_defaults(&params);
    assert_true(params.radius_factor == 3.0 && params.perturbation == 0.01 && params.seed == 9);
}

// A front square seen on a fine pixel grid (pitch 1e-3 rad, about 1080p at 60 degrees)
// with depth roughness of +-1 cm, every fourth direction of it showing a far plane 2 m
// behind through a one-pixel gap, and the far plane in the open around it. With R from a
// fixed ratio (100 times the farthest point) the roughness exceeds R a^2 and most of the
// surface is lost (the recall loss at large image sizes); with sta_katz_view_radius for
// the pitch the surface comes back as the tolerance grows (2 cm: the roughness itself,
// 20 cm: ten times it) while the far points in the gaps stay hidden.
static void view_radius_keeps_fine_surfaces(void **state)
{
    (void)state;
    enum {
        SIDE = 160
    };
    const double pitch = 1e-3;
    point3 *points = new_points((size_t)SIDE * SIDE);
    uint8_t *truth = new_flags((size_t)SIDE * SIDE);
    uint8_t *flags = new_flags((size_t)SIDE * SIDE);
    rng_state = 7;
    size_t n = 0;
    for (int row = 0; row < SIDE; row++) {
        for (int col = 0; col < SIDE; col++) {
            double ax = (col - SIDE / 2) * pitch;
            double ay = (row - SIDE / 2) * pitch;
            bool in_front = abs(col - SIDE / 2) < SIDE / 4 && abs(row - SIDE / 2) < SIDE / 4;
            bool gap = in_front && row % 2 == 0 && col % 2 == 0;
            double depth = in_front && !gap ? 10.0 + 0.02 * (rng_uniform() - 0.5) : 12.0;
            double dir[3] = { tan(ax), tan(ay), -1.0 };
            double len = sqrt(dir[0] * dir[0] + dir[1] * dir[1] + 1.0);
            for (int a = 0; a < 3; a++) {
                points[n][a] = dir[a] / len * depth;
            }
            truth[n] = !gap;
            n++;
        }
    }
    const double eye[3] = { 0.0, 0.0, 0.0 };
    sta_katz_params rules[3] = {
        { 0 },
        { .radius_m = sta_katz_view_radius(0.02, pitch) },
        { .radius_m = sta_katz_view_radius(0.2, pitch) },
    };
    assert_true(rules[1].radius_m > 1.99e4 && rules[1].radius_m < 2.01e4);
    double found[3], leaked[3];
    for (int k = 0; k < 3; k++) {
        sta_katz_stats stats;
        assert_int_equal(
            sta_katz_visible((const double(*)[3])points, n, eye, &rules[k], flags, &stats, NULL),
            STA_OK);
        size_t tp = 0, visible_truth = 0, fp = 0, hidden_truth = 0;
        for (size_t i = 0; i < n; i++) {
            visible_truth += truth[i];
            hidden_truth += !truth[i];
            tp += truth[i] && flags[i];
            fp += !truth[i] && flags[i];
        }
        found[k] = (double)tp / (double)visible_truth;
        leaked[k] = (double)fp / (double)hidden_truth;
        printf("R %.4g m: recall %.3f, hidden points shown %.3f\n", stats.radius, found[k],
               leaked[k]);
        assert_true(leaked[k] < 0.01);
    }
    assert_true(found[0] < 0.3);
    assert_true(found[1] > 0.8);
    assert_true(found[2] > 0.95);
    assert_true(sta_katz_view_radius(0.0, pitch) == 0.0);
    assert_true(sta_katz_view_radius(0.02, 0.0) == 0.0);
    sta_free(points);
    sta_free(truth);
    sta_free(flags);
}

// An absolute radius below the farthest point is raised to hold every point; one out of
// range is refused with a message naming it.
static void radius_m_is_checked(void **state)
{
    (void)state;
    point3 pts[4] = { { 1, 0, -5 }, { -1, 0, -5 }, { 0, 1, -5 }, { 0, -1, -6 } };
    uint8_t flags[4];
    sta_katz_stats stats;
    const double eye[3] = { 0, 0, 0 };
    sta_katz_params small = { .radius_m = 1.0 };
    assert_int_equal(sta_katz_visible((const double(*)[3])pts, 4, eye, &small, flags, &stats, NULL),
                     STA_OK);
    assert_true(stats.radius >= STA_KATZ_MIN_RADIUS_FACTOR * 6.0);
    sta_katz_params bad = { .radius_m = -1.0 };
    sta_error err = { 0 };
    assert_int_equal(sta_katz_visible((const double(*)[3])pts, 4, eye, &bad, flags, &stats, &err),
                     STA_ERR_ARG);
    assert_non_null(strstr(err.message, "radius_m"));
}

static const struct CMUnitTest tests[] = {
    cmocka_unit_test(sphere_from_outside),
    cmocka_unit_test(nested_sphere_in_box),
    cmocka_unit_test(parallel_planes),
    cmocka_unit_test(points_at_viewpoint),
    cmocka_unit_test(duplicate_points),
    cmocka_unit_test(fewer_than_four_points),
    cmocka_unit_test(plane_facing_viewpoint),
    cmocka_unit_test(plane_through_viewpoint),
    cmocka_unit_test(line_off_viewpoint),
    cmocka_unit_test(line_through_viewpoint),
    cmocka_unit_test(nonfinite_input),
    cmocka_unit_test(qhull_is_silent),
    cmocka_unit_test(allocation_failures),
    cmocka_unit_test(perturbation_is_deterministic),
    cmocka_unit_test(defaults_fill_only_zero_fields),
    cmocka_unit_test(view_radius_keeps_fine_surfaces),
    cmocka_unit_test(radius_m_is_checked),
    cmocka_unit_test(timing),
};

STA_TEST_MAIN(tests)
