/* SPDX-License-Identifier: MIT
 * Tests for a box's plane by Newton's method and a cross product (preprocess/box_plane.c)
 * against Kopp's solver (core/eigen3.h): planes in every orientation, with anisotropic grid
 * steps, give the same normal and eigenvalues; an exact plane, too; a line, a blob, two
 * close smallest eigenvalues, a zero, indefinite or non-finite matrix are refused and
 * leave the outputs untouched. */
#include "test_support.h"

#include <math.h>
#include <string.h>

#include "box_plane.h"
#include "core/eigen3.h"

#define CASES 2000

// m2 (upper triangle) of R diag(l) R^T in grid units^2, R a rotation from three angles.
static void covariance(const double angles[3], const double l[3], double m2[6])
{
    double ca = cos(angles[0]), sa = sin(angles[0]), cb = cos(angles[1]), sb = sin(angles[1]);
    double cc = cos(angles[2]), sc = sin(angles[2]);
    const double r[3][3] = { { ca * cb, ca * sb * sc - sa * cc, ca * sb * cc + sa * sc },
                             { sa * cb, sa * sb * sc + ca * cc, sa * sb * cc - ca * sc },
                             { -sb, cb * sc, cb * cc } };
    for (int i = 0, t = 0; i < 3; i++) {
        for (int j = i; j < 3; j++, t++) {
            m2[t] = 0.0;
            for (int k = 0; k < 3; k++) {
                m2[t] += r[i][k] * l[k] * r[j][k];
            }
        }
    }
}

// Kopp's solver on m2 scaled as sta_box_plane scales it.
static void kopp(const double scale[3], const double m2[6], double w[3], double v[3][3])
{
    double cov[9] = { 0 };
    for (int r = 0, t = 0; r < 3; r++) {
        for (int c = r; c < 3; c++, t++) {
            cov[3 * r + c] = m2[t] * scale[r] * scale[c];
        }
    }
    sta_eigen3_sym_d(cov, w, v);
}

static double uniform(uint64_t *seed)
{
    return (double)sta_test_frand(seed);
}

static void planes_match_kopps_solver(void **state)
{
    (void)state;
    const double scales[2][3] = { { 0.001, 0.001, 0.001 }, { 0.001, 0.002, 0.0005 } };
    uint64_t seed = 5;
    int answered = 0;
    for (int i = 0; i < CASES; i++) {
        const double *scale = scales[i % 2];
        double angles[3], l[3], m2[6];
        for (int a = 0; a < 3; a++) {
            angles[a] = 6.283185307179586 * uniform(&seed);
        }
        l[2] = 1e6 * (1.0 + 100.0 * uniform(&seed)); // a box's spread, units^2 x n
        l[1] = l[2] * (0.06 + 0.94 * uniform(&seed));
        l[0] = l[1] * 0.9 * uniform(&seed) * uniform(&seed);
        covariance(angles, l, m2);
        double n[3], w[3], kw[3], kv[3][3];
        kopp(scale, m2, kw, kv);
        if (!sta_box_plane(scale, m2, n, w)) {
            // (anisotropic steps can close the gap: then only where Kopp's says so)
            assert_true(kw[1] - kw[0] <= STA_BOX_PLANE_GAP * kw[2] * (1.0 + 1e-9));
            continue;
        }
        answered++;
        double dot = fabs(n[0] * kv[0][0] + n[1] * kv[0][1] + n[2] * kv[0][2]);
        assert_true(dot > 1.0 - 1e-12);
        assert_true(fabs(n[0] * n[0] + n[1] * n[1] + n[2] * n[2] - 1.0) < 1e-14);
        for (int k = 0; k < 3; k++) {
            assert_true(fabs(w[k] - kw[k]) <= 1e-10 * kw[2]);
        }
    }
    assert_true(answered > CASES * 9 / 10);
}

static void an_exact_plane(void **state)
{
    (void)state;
    const double scale[3] = { 0.001, 0.001, 0.001 }, angles[3] = { 0.3, -0.7, 1.1 };
    const double l[3] = { 0.0, 3e6, 5e6 };
    double m2[6], n[3], w[3], kw[3], kv[3][3];
    covariance(angles, l, m2);
    kopp(scale, m2, kw, kv);
    assert_true(sta_box_plane(scale, m2, n, w));
    assert_true(fabs(n[0] * kv[0][0] + n[1] * kv[0][1] + n[2] * kv[0][2]) > 1.0 - 1e-12);
    assert_true(w[0] >= 0.0 && w[0] < 1e-9 * w[2]);
    assert_true(fabs(w[1] - 3.0) < 1e-9 && fabs(w[2] - 5.0) < 1e-9);
}

// Refused: the outputs keep what they held.
static void refused(const double m2[6])
{
    const double scale[3] = { 0.001, 0.001, 0.001 };
    double n[3] = { 7, 7, 7 }, w[3] = { 7, 7, 7 };
    assert_false(sta_box_plane(scale, m2, n, w));
    for (int a = 0; a < 3; a++) {
        assert_true(n[a] == 7.0 && w[a] == 7.0);
    }
}

static void ill_conditioned_boxes_are_refused(void **state)
{
    (void)state;
    const double angles[3] = { 0.4, 0.9, -0.2 };
    const double shapes[4][3] = {
        { 0.0, 0.0, 4e6 },   // a line
        { 1e-3, 2e-3, 4e6 }, // nearly a line
        { 2e6, 2e6, 2e6 },   // a blob
        { 1e6, 1.1e6, 4e6 }, // two smallest within the gap
    };
    for (int s = 0; s < 4; s++) {
        double m2[6];
        covariance(angles, shapes[s], m2);
        refused(m2);
    }
    const double zero[6] = { 0 }, indefinite[6] = { 1e6, 0, 0, -1e6, 0, 1e6 };
    const double nan_entry[6] = { 1e6, NAN, 0, 1e6, 0, 1e6 };
    const double inf_entry[6] = { 1e6, 0, 0, INFINITY, 0, 1e6 };
    refused(zero);
    refused(indefinite);
    refused(nan_entry);
    refused(inf_entry);
}

static const struct CMUnitTest tests[] = {
    cmocka_unit_test(planes_match_kopps_solver),
    cmocka_unit_test(an_exact_plane),
    cmocka_unit_test(ill_conditioned_boxes_are_refused),
};

STA_TEST_MAIN(tests)
