/* SPDX-License-Identifier: MIT
 * Tests for the algebraic sphere from moments (preprocess/sphere_fit.c) against analytic
 * truth: points on a sphere cap get their exact radial normals and the sphere's radius,
 * also through the cells' exact higher sums (cell_moments.c) at a coarse level; a
 * cylinder seen from one side gets radial normals across its axis; a plane gets its
 * normal and no curvature; too few points, one point repeated and points on a line are
 * refused (the plane decides), never NaN; sums that may have overflowed are refused. */
#include "test_support.h"

#include <math.h>
#include <string.h>

#include "cell_moments.h"
#include "sphere_fit.h"

#define PI 3.14159265358979323846

enum {
    MAX_POINTS = 4096
};

// The sums of the points d (grid units from the sums' corner), as the cells keep them.
static sta_moment_sums sums_of(const int64_t (*d)[3], size_t n)
{
    sta_moment_sums m = { 0 };
    for (size_t i = 0; i < n; i++) {
        m.n++;
        for (int a = 0; a < 3; a++) {
            m.s1[a] += d[i][a];
        }
        for (int r = 0, t = 0; r < 3; r++) {
            for (int c = r; c < 3; c++, t++) {
                m.s2[t] += d[i][r] * d[i][c];
            }
        }
        uint64_t dd = (uint64_t)(d[i][0] * d[i][0] + d[i][1] * d[i][1] + d[i][2] * d[i][2]);
        for (int a = 0; a < 3; a++) {
            m.s3[a] += (uint64_t)d[i][a] * dd;
        }
        m.s4 += dd * dd;
    }
    return m;
}

// Degrees between two unit vectors, unoriented.
static double angle_deg(const double a[3], const double b[3])
{
    double c = fabs(a[0] * b[0] + a[1] * b[1] + a[2] * b[2]);
    return acos(c > 1.0 ? 1.0 : c) * 180.0 / PI;
}

// A cap of a sphere of `radius` units around `centre`, within `half_angle` of +z, on a
// spiral (rounded to the grid).
static size_t sphere_cap(int64_t (*d)[3], size_t n, const double centre[3], double radius,
                         double half_angle)
{
    for (size_t i = 0; i < n; i++) {
        double z = 1.0 - (1.0 - cos(half_angle)) * ((double)i + 0.5) / (double)n;
        double phi = (double)i * 2.399963229728653; // golden angle
        double xy = sqrt(1.0 - z * z);
        const double dir[3] = { xy * cos(phi), xy * sin(phi), z };
        for (int a = 0; a < 3; a++) {
            d[i][a] = (int64_t)llround(centre[a] + radius * dir[a]);
        }
    }
    return n;
}

// Every point's sphere normal against the direction from the centre; the largest error.
static double worst_radial(const sta_sphere *s, const int64_t (*d)[3], size_t n,
                           const double centre[3], const double axis_mask[3])
{
    double worst = 0.0;
    for (size_t i = 0; i < n; i++) {
        const double p[3] = { (double)d[i][0], (double)d[i][1], (double)d[i][2] };
        double truth[3], len = 0.0, got[3];
        for (int a = 0; a < 3; a++) {
            truth[a] = (p[a] - centre[a]) * axis_mask[a];
            len += truth[a] * truth[a];
        }
        for (int a = 0; a < 3; a++) {
            truth[a] /= sqrt(len);
        }
        assert_true(sta_sphere_normal(s, p, got));
        double e = angle_deg(got, truth);
        worst = e > worst ? e : worst;
    }
    return worst;
}

static void sphere_cap_gets_radial_normals(void **state)
{
    (void)state;
    static int64_t d[MAX_POINTS][3];
    const double centre[3] = { 520.0, 480.0, 100.0 }, all[3] = { 1, 1, 1 };
    // A 0.3 m leaf cluster on a 1 mm grid, a box of 0.5 m: a cap of 50 degrees.
    size_t n = sphere_cap(d, 1500, centre, 300.0, 50.0 * PI / 180.0);
    sta_moment_sums sums = sums_of((const int64_t(*)[3])d, n);
    sta_sphere_moments m;
    assert_true(sta_sphere_moments_of(&sums, 1024.0, &m));
    sta_sphere s;
    assert_true(sta_sphere_fit(&m, &s));
    // (the grid's rounding, half a unit on 300, is the only error)
    assert_true(worst_radial(&s, (const int64_t(*)[3])d, n, centre, all) < 0.2);
    assert_true(fabs(sta_sphere_radius(&s) * s.spread - 300.0) < 1.0);
    assert_true(s.residual < 1e-4);
}

// The same cap summed by cells of level 8 and read as the vertex box around it: the
// higher sums moved between corners in 64-bit integers give the same sphere.
static void sphere_from_cell_moments(void **state)
{
    (void)state;
    static int64_t d[MAX_POINTS][3];
    static int32_t grid[MAX_POINTS][3];
    const double centre[3] = { 69888.0, 70144.0, 69632.0 }, all[3] = { 1, 1, 1 }; // vertices
    size_t n = sphere_cap(d, 2000, centre, 180.0, 70.0 * PI / 180.0);
    int32_t lo[3] = { INT32_MAX, INT32_MAX, INT32_MAX },
            hi[3] = { INT32_MIN, INT32_MIN, INT32_MIN };
    for (size_t i = 0; i < n; i++) {
        for (int a = 0; a < 3; a++) {
            grid[i][a] = (int32_t)d[i][a];
            lo[a] = grid[i][a] < lo[a] ? grid[i][a] : lo[a];
            hi[a] = grid[i][a] > hi[a] ? grid[i][a] : hi[a];
        }
    }
    const int64_t origin[3] = { 0, 0, 0 };
    const int level = 8; // cells of 256 units: the cap lies around one vertex
    sta_cell_moments cells;
    sta_error err = { 0 };
    assert_int_equal(sta_cell_moments_init(&cells, level, origin, lo, hi, &err), STA_OK);
    cells.higher = true;
    assert_int_equal(sta_cell_moments_add(&cells, (const int32_t(*)[3])grid, n, NULL, NULL, &err),
                     STA_OK);
    int64_t v[3], corner[3];
    double local_centre[3];
    for (int a = 0; a < 3; a++) {
        v[a] = ((int64_t)llround(centre[a]) + 128) >> level;
        corner[a] = (v[a] - 1) << level;
        local_centre[a] = centre[a] - (double)corner[a];
    }
    sta_moment_sums sums;
    sta_cell_moments_vertex(&cells, v, &sums);
    assert_int_equal(sums.n, (int64_t)n); // every point inside the box
    for (size_t i = 0; i < n; i++) {
        for (int a = 0; a < 3; a++) {
            d[i][a] -= corner[a];
        }
    }
    sta_moment_sums direct = sums_of((const int64_t(*)[3])d, n);
    assert_memory_equal(&sums, &direct, sizeof(sums));
    sta_sphere_moments m;
    assert_true(sta_sphere_moments_of(&sums, (double)(2 << level), &m));
    sta_sphere s;
    assert_true(sta_sphere_fit(&m, &s));
    assert_true(worst_radial(&s, (const int64_t(*)[3])d, n, local_centre, all) < 0.3);
    sta_cell_moments_release(&cells);
}

// A pole of 110 units' radius seen from one side (its front 160 degrees), a box 100 units
// tall: the normals point away from the axis across it; the sphere cannot follow the axis,
// so they tilt along it as a sphere's centred on the axis would, by atan(height / radius):
// 24.4 degrees at the box's ends.
static void cylinder_side_gets_radial_normals_across(void **state)
{
    (void)state;
    static int64_t d[MAX_POINTS][3];
    const double centre[3] = { 300.0, 300.0, 300.0 }, across[3] = { 1, 1, 0 };
    size_t n = sta_test_pole_side(d, centre);
    sta_moment_sums sums = sums_of((const int64_t(*)[3])d, n);
    sta_sphere_moments m;
    assert_true(sta_sphere_moments_of(&sums, 1024.0, &m));
    sta_sphere s;
    assert_true(sta_sphere_fit(&m, &s));
    double worst_across = 0.0, worst = 0.0;
    for (size_t i = 0; i < n; i++) {
        const double p[3] = { (double)d[i][0], (double)d[i][1], (double)d[i][2] };
        double got[3], flat[3], truth[3];
        assert_true(sta_sphere_normal(&s, p, got));
        double len = hypot(got[0], got[1]), rlen = hypot(p[0] - centre[0], p[1] - centre[1]);
        for (int a = 0; a < 3; a++) {
            flat[a] = got[a] * across[a] / len;
            truth[a] = (p[a] - centre[a]) * across[a] / rlen;
        }
        double e = angle_deg(flat, truth);
        worst_across = e > worst_across ? e : worst_across;
        e = angle_deg(got, truth);
        worst = e > worst ? e : worst;
    }
    assert_true(worst_across < 1.0);
    assert_true(worst < atan(50.0 / 110.0) * 180.0 / PI + 1.0);
}

// A tilted plane (points on a lattice, rounded): the sphere is the plane, its normal the
// plane's at every point.
static void plane_gets_its_normal(void **state)
{
    (void)state;
    static int64_t d[MAX_POINTS][3];
    double truth[3];
    size_t n = sta_test_tilted_plane(d, truth);
    sta_moment_sums sums = sums_of((const int64_t(*)[3])d, n);
    sta_sphere_moments m;
    assert_true(sta_sphere_moments_of(&sums, 1024.0, &m));
    sta_sphere s;
    assert_true(sta_sphere_fit(&m, &s));
    for (size_t i = 0; i < n; i += 7) {
        const double p[3] = { (double)d[i][0], (double)d[i][1], (double)d[i][2] };
        double got[3];
        assert_true(sta_sphere_normal(&s, p, got));
        assert_true(angle_deg(got, truth) < 1e-4);
    }
    assert_true(sta_sphere_radius(&s) > 1e4);
    assert_true(s.residual < 1e-9);
}

// Too few points, one point many times and points on a line decide no sphere; the
// result is a refusal, never a NaN.
static void degenerate_input_is_refused(void **state)
{
    (void)state;
    static int64_t d[MAX_POINTS][3];
    sta_sphere_moments m;
    sta_sphere s;
    // four points of a sphere
    const double centre[3] = { 500, 500, 500 };
    size_t n = sphere_cap(d, 4, centre, 200.0, PI / 2.0);
    sta_moment_sums sums = sums_of((const int64_t(*)[3])d, n);
    assert_true(sta_sphere_moments_of(&sums, 1024.0, &m));
    assert_false(sta_sphere_fit(&m, &s));
    // one point repeated
    for (size_t i = 0; i < 50; i++) {
        d[i][0] = 7, d[i][1] = 8, d[i][2] = 9;
    }
    sums = sums_of((const int64_t(*)[3])d, 50);
    assert_true(sta_sphere_moments_of(&sums, 1024.0, &m));
    assert_false(sta_sphere_fit(&m, &s));
    // a line
    for (size_t i = 0; i < 50; i++) {
        d[i][0] = 3 * (int64_t)i, d[i][1] = 2 * (int64_t)i, d[i][2] = 5;
    }
    sums = sums_of((const int64_t(*)[3])d, 50);
    assert_true(sta_sphere_moments_of(&sums, 1024.0, &m));
    assert_false(sta_sphere_fit(&m, &s));
    // no points
    sta_moment_sums none = { 0 };
    assert_false(sta_sphere_moments_of(&none, 1024.0, &m));
    // a sphere fitted, then asked at its centre: no gradient
    n = sphere_cap(d, 500, centre, 200.0, PI / 2.0);
    sums = sums_of((const int64_t(*)[3])d, n);
    assert_true(sta_sphere_moments_of(&sums, 1024.0, &m));
    assert_true(sta_sphere_fit(&m, &s));
    double cx[3], g[3];
    for (int a = 0; a < 3; a++) {
        cx[a] = s.mean[a] - s.u[a] * s.spread / (2.0 * s.u4); // the fitted centre
    }
    assert_false(sta_sphere_normal(&s, cx, g));
}

// Sums whose |d|^4 may pass 2^62 are refused (the cells keep them modulo 2^64); the
// bound depends on the count and the box's edge only.
static void overflowing_sums_are_refused(void **state)
{
    (void)state;
    sta_moment_sums sums = { .n = 1 << 16 };
    sums.s1[0] = sums.s1[1] = sums.s1[2] = (int64_t)1 << 20;
    sums.s2[0] = sums.s2[3] = sums.s2[5] = (int64_t)1 << 30;
    sta_sphere_moments m;
    assert_true(sta_sphere_moments_of(&sums, 1024.0, &m));  // 2^16 * 9 * 2^40 < 2^62
    assert_false(sta_sphere_moments_of(&sums, 4096.0, &m)); // 2^16 * 9 * 2^48
    const double iso[3] = { 0.001, 0.001, 0.001 }, aniso[3] = { 0.001, 0.001, 0.01 };
    assert_true(sta_sphere_isotropic(iso));
    assert_false(sta_sphere_isotropic(aniso));
}

static const struct CMUnitTest tests[] = {
    cmocka_unit_test(sphere_cap_gets_radial_normals),
    cmocka_unit_test(sphere_from_cell_moments),
    cmocka_unit_test(cylinder_side_gets_radial_normals_across),
    cmocka_unit_test(plane_gets_its_normal),
    cmocka_unit_test(degenerate_input_is_refused),
    cmocka_unit_test(overflowing_sums_are_refused),
};

STA_TEST_MAIN(tests)
