/* SPDX-License-Identifier: MIT
 * The circular cylinder of an elongated set from its exact moment tensors: the axis from
 * the covariance, Taubin's circle across it, and its normal at a point. */
#include "cylinder_fit.h"

#include <math.h>
#include <string.h>

#include "core/eigen3.h"
#include "quadric_fit.h"

/* Fewer points cannot tell a circle (3 unknowns) from the noise. */
#define CYLINDER_POINTS 10.0
/* n extent^4 below this: every sum fits an int64 (2^62: with a margin). */
#define CYLINDER_EXACT  4.611686018427387904e18
/* The cross-section's 2 x 2 moments' determinant over their trace squared below this:
 * its points lie on a line (a strip seen edge-on, a wire). */
#define CYLINDER_LINE   1e-9
/* rho^2's coefficient below this (the gradient's mean square being 1): a line, no circle. */
#define CYLINDER_FLAT   1e-12

// A polynomial in the three scaled coordinates up to the fourth degree, by the terms of
// sta_tensor_exponent.
typedef struct poly {
    double c[STA_TENSOR_TERMS];
} poly;

typedef struct term_index {
    int8_t of[5][5][5];
} term_index;

// a * b (of degrees summing to at most 4), over their nonzero terms.
static void poly_mul(const poly *a, const poly *b, const term_index *ti, poly *out)
{
    int ia[STA_TENSOR_TERMS], ib[STA_TENSOR_TERMS], na = 0, nb = 0;
    for (int t = 0; t < STA_TENSOR_TERMS; t++) {
        ia[na] = t;
        na += a->c[t] != 0.0;
        ib[nb] = t;
        nb += b->c[t] != 0.0;
    }
    memset(out, 0, sizeof(*out));
    for (int i = 0; i < na; i++) {
        const uint8_t *ei = sta_tensor_exponent[ia[i]];
        for (int j = 0; j < nb; j++) {
            const uint8_t *ej = sta_tensor_exponent[ib[j]];
            if (ei[0] + ei[1] + ei[2] + ej[0] + ej[1] + ej[2] <= 4) {
                out->c[ti->of[ei[0] + ej[0]][ei[1] + ej[1]][ei[2] + ej[2]]] +=
                    a->c[ia[i]] * b->c[ib[j]];
            }
        }
    }
}

// The mean of polynomial p over the points (k: their scaled moments).
static double mean_of(const poly *p, const double k[STA_TENSOR_TERMS])
{
    double s = 0.0;
    for (int t = 0; t < STA_TENSOR_TERMS; t++) {
        s += p->c[t] * k[t];
    }
    return s;
}

// The linear form d . x (terms 1..3 are x, y, z).
static void linear(const double d[3], poly *out)
{
    memset(out, 0, sizeof(*out));
    for (int a = 0; a < 3; a++) {
        out->c[1 + a] = d[a];
    }
}

bool sta_cylinder_fit(const sta_tensor_sums *sums, double extent, sta_cylinder *out)
{
    double n = (double)sums->s[0], e2 = extent * extent;
    if (!(n >= CYLINDER_POINTS) || !(n * e2 * e2 < CYLINDER_EXACT)) {
        return false;
    }
    term_index ti;
    for (int t = 0; t < STA_TENSOR_TERMS; t++) {
        const uint8_t *e = sta_tensor_exponent[t];
        ti.of[e[0]][e[1]][e[2]] = (int8_t)t;
    }
    double k[STA_TENSOR_TERMS];
    if (!sta_tensor_moments_scaled(sums, out->mean, &out->spread, k)) {
        return false;
    }
    const double cov[9] = { k[ti.of[2][0][0]],
                            k[ti.of[1][1][0]],
                            k[ti.of[1][0][1]],
                            0.0,
                            k[ti.of[0][2][0]],
                            k[ti.of[0][1][1]],
                            0.0,
                            0.0,
                            k[ti.of[0][0][2]] };
    double w[3], v[3][3];
    sta_eigen3_path path = sta_eigen3_sym_d(cov, w, v);
    if (path == STA_EIGEN3_ZERO || path == STA_EIGEN3_INVALID || !(w[1] > 0.0)) {
        return false;
    }
    out->elongation = w[2] / w[1];
    memcpy(out->axis, v[2], sizeof(v[2]));
    memcpy(out->e[0], v[1], sizeof(v[1]));
    memcpy(out->e[1], v[0], sizeof(v[0]));
    // X, Y across the axis; rho^2 = X^2 + Y^2; their means over the points.
    poly x, y, xx, xy, yy, r2, xr, yr, rr;
    linear(out->e[0], &x);
    linear(out->e[1], &y);
    poly_mul(&x, &x, &ti, &xx);
    poly_mul(&x, &y, &ti, &xy);
    poly_mul(&y, &y, &ti, &yy);
    for (int t = 0; t < STA_TENSOR_TERMS; t++) {
        r2.c[t] = xx.c[t] + yy.c[t];
    }
    poly_mul(&x, &r2, &ti, &xr);
    poly_mul(&y, &r2, &ti, &yr);
    poly_mul(&r2, &r2, &ti, &rr);
    double a11 = mean_of(&xx, k), a12 = mean_of(&xy, k), a22 = mean_of(&yy, k);
    double t1 = mean_of(&xr, k), t2 = mean_of(&yr, k), s2 = mean_of(&r2, k);
    double s4 = mean_of(&rr, k);
    if (!(a11 * a22 - a12 * a12 > CYLINDER_LINE * (a11 + a22) * (a11 + a22))) {
        return false;
    }
    // Centred (the means of X and Y are 0): mean q^2 = A^2 (s4 - s2^2) + 2 A B.t + B^T S B
    // and mean |grad q|^2 = 4 A^2 s2 + |B|^2; with A = a h, h = 1 / (2 sqrt(s2)), both
    // quadratic forms of (a, B), the second the identity.
    double h = 1.0 / (2.0 * sqrt(s2));
    const double m[9] = { (s4 - s2 * s2) * h * h, t1 * h, t2 * h, 0.0, a11, a12, 0.0, 0.0, a22 };
    double mw[3], mv[3][3];
    path = sta_eigen3_sym_d(m, mw, mv);
    if (path == STA_EIGEN3_ZERO || path == STA_EIGEN3_INVALID) {
        return false;
    }
    double a = mv[0][0] * h;
    if (!(fabs(a) > CYLINDER_FLAT)) {
        return false;
    }
    // q = 0: |X - c|^2 = R^2 with c = -B / (2 A), R^2 = |c|^2 + s2.
    double c1 = -mv[0][1] / (2.0 * a), c2 = -mv[0][2] / (2.0 * a);
    double r = sqrt(c1 * c1 + c2 * c2 + s2);
    if (!isfinite(r) || !(r > 0.0)) {
        return false;
    }
    out->centre[0] = c1;
    out->centre[1] = c2;
    out->radius = r;
    out->residual = fmax(mw[0], 0.0);
    return true;
}

// p (grid units from the sums' corner) in the cross-section, from the circle's centre.
static void cross_section(const sta_cylinder *c, const double p[3], double *px, double *py)
{
    double x[3];
    for (int a = 0; a < 3; a++) {
        x[a] = (p[a] - c->mean[a]) / c->spread;
    }
    *px = x[0] * c->e[0][0] + x[1] * c->e[0][1] + x[2] * c->e[0][2] - c->centre[0];
    *py = x[0] * c->e[1][0] + x[1] * c->e[1][1] + x[2] * c->e[1][2] - c->centre[1];
}

// The unit normal along (qx, qy) of the cross-section; false when it is (near) zero.
static bool radial(const sta_cylinder *c, double qx, double qy, double n[3])
{
    double len = sqrt(qx * qx + qy * qy);
    if (!(len > 1e-9 * c->radius) || !isfinite(len)) {
        return false;
    }
    for (int a = 0; a < 3; a++) {
        n[a] = (qx * c->e[0][a] + qy * c->e[1][a]) / len;
    }
    return true;
}

bool sta_cylinder_normal(const sta_cylinder *c, const double p[3], double n[3], double *off)
{
    double px, py;
    cross_section(c, p, &px, &py);
    *off = fabs(sqrt(px * px + py * py) - c->radius) / c->radius;
    return radial(c, px, py, n);
}

bool sta_cylinder_normal_seen(const sta_cylinder *c, const double p[3], const double from[3],
                              double n[3], double *off)
{
    if (!sta_cylinder_normal(c, p, n, off)) {
        return false;
    }
    double px, py, d[3];
    cross_section(c, p, &px, &py);
    for (int a = 0; a < 3; a++) {
        d[a] = p[a] - from[a];
    }
    double dx = d[0] * c->e[0][0] + d[1] * c->e[0][1] + d[2] * c->e[0][2];
    double dy = d[0] * c->e[1][0] + d[1] * c->e[1][1] + d[2] * c->e[1][2];
    double across = sqrt(dx * dx + dy * dy), full = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    if (!(across > 1e-6 * full)) {
        return true; // (a ray along the axis, or from p itself: the radial normal)
    }
    dx /= across;
    dy /= across;
    // |P + t D|^2 = R^2: the ray's entry (the smaller t). Where it misses, p's radial
    // normal: the ray's nearest pass, across it, took the street's poles' p95 from 15.1 to
    // 17.0 degrees (4 M street).
    double b = px * dx + py * dy, q = px * px + py * py - c->radius * c->radius;
    double disc = b * b - q;
    if (!(disc >= 0.0)) {
        return true;
    }
    double t = -b - sqrt(disc), seen[3];
    if (radial(c, px + t * dx, py + t * dy, seen)) {
        memcpy(n, seen, sizeof(seen));
    }
    return true;
}
