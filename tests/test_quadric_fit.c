/* SPDX-License-Identifier: MIT
 * Tests for the algebraic quadric from moment tensors (preprocess/quadric_fit.c) against
 * analytic truth: a pole seen from one side gets exact radial normals along its axis too
 * (where the sphere tilts), a box's edge gets each face's normal beside it and a vanishing
 * gradient on it, a sphere cap radial normals, a plane its normal wherever the gradient
 * does not vanish; too few points, one point repeated, points on a line and sums that may
 * have overflowed are refused, never NaN. */
#include "test_support.h"

#include <math.h>
#include <string.h>

#include "quadric_fit.h"

#define PI 3.14159265358979323846

enum {
    MAX_POINTS = 4096
};

// The tensor sums of the points d (grid units from the sums' corner, >= 0), as a box's
// points give them (sta_tensor_sums_add, checked against the monomials in test_tensor_sums).
static sta_tensor_sums sums_of(const int64_t (*d)[3], size_t n)
{
    sta_tensor_sums s = { { 0 } };
    for (size_t i = 0; i < n; i++) {
        const uint64_t u[3] = { (uint64_t)d[i][0], (uint64_t)d[i][1], (uint64_t)d[i][2] };
        sta_tensor_sums_add(&s, u);
    }
    return s;
}

// Degrees between two unit vectors, unoriented.
static double angle_deg(const double a[3], const double b[3])
{
    double c = fabs(a[0] * b[0] + a[1] * b[1] + a[2] * b[2]);
    return acos(c > 1.0 ? 1.0 : c) * 180.0 / PI;
}

static void unit(double v[3])
{
    double len = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    for (int a = 0; a < 3; a++) {
        v[a] /= len;
    }
}

// The pole of test_sphere_fit.c (110 units' radius, its front 160 degrees, a box 100 units
// tall), where the sphere's normals tilt by up to 24 degrees along the axis: the quadric
// is the cylinder, its normals radial everywhere (the grid's rounding is the only error).
static void cylinder_side_gets_radial_normals(void **state)
{
    (void)state;
    static int64_t d[MAX_POINTS][3];
    const double centre[3] = { 300.0, 300.0, 300.0 };
    size_t n = sta_test_pole_side(d, centre);
    sta_tensor_sums sums = sums_of((const int64_t(*)[3])d, n);
    sta_quadric q;
    assert_true(sta_quadric_fit(&sums, 1024.0, &q));
    double worst = 0.0, weakest = INFINITY;
    for (size_t i = 0; i < n; i++) {
        const double p[3] = { (double)d[i][0], (double)d[i][1], (double)d[i][2] };
        double got[3], length, truth[3] = { p[0] - centre[0], p[1] - centre[1], 0.0 };
        unit(truth);
        assert_true(sta_quadric_normal(&q, p, got, &length));
        double e = angle_deg(got, truth);
        worst = e > worst ? e : worst;
        weakest = length < weakest ? length : weakest;
    }
    assert_true(worst < 1.0);
    assert_true(weakest > 0.5); // (a cylinder's gradient is the same all over it)
    assert_true(q.residual < 1e-4);
}

// A car's edge: two faces at 90 degrees meeting along a line (x = 200 for y < 200, y = 200
// for x < 200, 0 <= z < 160, a lattice of 10 units). The quadric is the product of the
// faces' planes: beside the edge each point gets its own face's normal, on the edge's line
// the gradient vanishes (the rule falls back there).
static void box_edge_gets_each_face_normal(void **state)
{
    (void)state;
    static int64_t d[MAX_POINTS][3];
    size_t n = 0;
    for (int k = 0; k < 16; k++) {
        for (int j = 0; j < 20; j++) {
            const int64_t z = 10 * k, t = 10 * j + 5;
            d[n][0] = 200, d[n][1] = t, d[n][2] = z, n++; // face x = 200
            d[n][0] = t, d[n][1] = 200, d[n][2] = z, n++; // face y = 200
        }
    }
    sta_tensor_sums sums = sums_of((const int64_t(*)[3])d, n);
    sta_quadric q;
    assert_true(sta_quadric_fit(&sums, 256.0, &q));
    const double nx[3] = { 1, 0, 0 }, ny[3] = { 0, 1, 0 };
    double worst = 0.0, beside = INFINITY;
    for (size_t i = 0; i < n; i++) {
        const double p[3] = { (double)d[i][0], (double)d[i][1], (double)d[i][2] };
        double got[3], length;
        assert_true(sta_quadric_normal(&q, p, got, &length));
        double e = angle_deg(got, d[i][0] == 200 ? nx : ny);
        worst = e > worst ? e : worst;
        beside = length < beside ? length : beside;
    }
    assert_true(worst < 1e-3);
    // The gradient grows with the distance from the edge: 5 units beside it (the lattice's
    // nearest) it is small, on the edge's line it vanishes.
    assert_true(beside < 0.2);
    const double on_edge[3] = { 200.0, 200.0, 80.0 };
    double got[3], length = 1.0;
    if (sta_quadric_normal(&q, on_edge, got, &length)) {
        assert_true(length < 1e-6);
    }
    assert_true(q.residual < 1e-9);
}

// A cap of a sphere (a leaf cluster): a sphere is a quadric, its normals radial.
static void sphere_cap_gets_radial_normals(void **state)
{
    (void)state;
    static int64_t d[MAX_POINTS][3];
    const double centre[3] = { 520.0, 480.0, 100.0 };
    size_t n = 1500;
    for (size_t i = 0; i < n; i++) {
        double z = 1.0 - (1.0 - cos(50.0 * PI / 180.0)) * ((double)i + 0.5) / (double)n;
        double phi = (double)i * 2.399963229728653, xy = sqrt(1.0 - z * z);
        const double dir[3] = { xy * cos(phi), xy * sin(phi), z };
        for (int a = 0; a < 3; a++) {
            d[i][a] = (int64_t)llround(centre[a] + 300.0 * dir[a]);
        }
    }
    sta_tensor_sums sums = sums_of((const int64_t(*)[3])d, n);
    sta_quadric q;
    assert_true(sta_quadric_fit(&sums, 1024.0, &q));
    double worst = 0.0;
    for (size_t i = 0; i < n; i++) {
        const double p[3] = { (double)d[i][0], (double)d[i][1], (double)d[i][2] };
        double got[3], length, truth[3] = { p[0] - centre[0], p[1] - centre[1], p[2] - centre[2] };
        unit(truth);
        assert_true(sta_quadric_normal(&q, p, got, &length));
        double e = angle_deg(got, truth);
        worst = e > worst ? e : worst;
    }
    assert_true(worst < 0.5);
}

// A tilted plane: the quadrics through it are its plane times any linear function (not
// one quadric), but wherever the fitted one's gradient does not vanish it is the plane's
// normal, and nothing is NaN.
static void plane_gets_its_normal(void **state)
{
    (void)state;
    static int64_t d[MAX_POINTS][3];
    double truth[3];
    size_t n = sta_test_tilted_plane(d, truth);
    sta_tensor_sums sums = sums_of((const int64_t(*)[3])d, n);
    sta_quadric q;
    assert_true(sta_quadric_fit(&sums, 1024.0, &q));
    for (int i = 0; i < 10; i++) {
        assert_false(isnan(q.v[i]));
    }
    size_t used = 0;
    for (size_t i = 0; i < n; i++) {
        const double p[3] = { (double)d[i][0], (double)d[i][1], (double)d[i][2] };
        double got[3], length;
        if (sta_quadric_normal(&q, p, got, &length) && length > 0.1) {
            assert_true(angle_deg(got, truth) < 0.01);
            used++;
        }
    }
    assert_true(used > n / 2);
    assert_true(q.residual < 1e-9);
}

// Too few points, one point many times, points on a line, no points and sums whose
// fourth powers may pass 2^62 decide no quadric: a refusal, never a NaN.
static void degenerate_input_is_refused(void **state)
{
    (void)state;
    static int64_t d[MAX_POINTS][3];
    sta_quadric q;
    memset(&q, 0, sizeof(q));
    // ten points of a cylinder (9 unknowns: one spare is asked for)
    for (size_t i = 0; i < 10; i++) {
        double phi = 0.3 * (double)i;
        d[i][0] = (int64_t)llround(300.0 + 100.0 * cos(phi));
        d[i][1] = (int64_t)llround(300.0 + 100.0 * sin(phi));
        d[i][2] = 20 * (int64_t)(i % 3);
    }
    sta_tensor_sums sums = sums_of((const int64_t(*)[3])d, 10);
    assert_false(sta_quadric_fit(&sums, 1024.0, &q));
    // one point repeated
    for (size_t i = 0; i < 50; i++) {
        d[i][0] = 7, d[i][1] = 8, d[i][2] = 9;
    }
    sums = sums_of((const int64_t(*)[3])d, 50);
    assert_false(sta_quadric_fit(&sums, 1024.0, &q));
    // a line
    for (size_t i = 0; i < 50; i++) {
        d[i][0] = 3 * (int64_t)i, d[i][1] = 2 * (int64_t)i, d[i][2] = 5;
    }
    sums = sums_of((const int64_t(*)[3])d, 50);
    assert_false(sta_quadric_fit(&sums, 1024.0, &q));
    // no points
    sta_tensor_sums none = { { 0 } };
    assert_false(sta_quadric_fit(&none, 1024.0, &q));
    // 2^16 points in a box of 2^12: n extent^4 = 2^64 may have wrapped
    sta_tensor_sums big = { { 0 } };
    big.s[0] = (uint64_t)1 << 16;
    assert_false(sta_quadric_fit(&big, 4096.0, &q));
    // a gradient asked where it vanishes: the fitted sphere's centre
    size_t n = 0;
    for (int i = 0; i < 30; i++) {
        for (int j = 0; j < 30; j++, n++) {
            double th = PI * ((double)i + 0.5) / 30.0, phi = 2.0 * PI * (double)j / 30.0;
            d[n][0] = (int64_t)llround(500.0 + 200.0 * sin(th) * cos(phi));
            d[n][1] = (int64_t)llround(500.0 + 200.0 * sin(th) * sin(phi));
            d[n][2] = (int64_t)llround(500.0 + 200.0 * cos(th));
        }
    }
    sums = sums_of((const int64_t(*)[3])d, n);
    assert_true(sta_quadric_fit(&sums, 1024.0, &q));
    const double centre[3] = { 500.0, 500.0, 500.0 };
    double g[3], length = 1.0;
    if (sta_quadric_normal(&q, centre, g, &length)) {
        assert_true(length < 0.02); // (the grid's rounding moves the centre a little)
    }
    assert_false(isnan(length));
}

static const struct CMUnitTest tests[] = {
    cmocka_unit_test(cylinder_side_gets_radial_normals),
    cmocka_unit_test(box_edge_gets_each_face_normal),
    cmocka_unit_test(sphere_cap_gets_radial_normals),
    cmocka_unit_test(plane_gets_its_normal),
    cmocka_unit_test(degenerate_input_is_refused),
};

STA_TEST_MAIN(tests)
