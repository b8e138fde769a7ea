/* SPDX-License-Identifier: MIT
 * Taubin's algebraic quadric from exact moment tensors, and its normal at a point. */
#include "quadric_fit.h"

#include <math.h>
#include <string.h>

#include "cholesky.h"

/* Unknowns once the constant term is eliminated. */
#define UNKNOWNS       9
/* Fewer points cannot decide a quadric (9 unknowns) with one to spare. */
#define QUADRIC_POINTS 11.0
/* n extent^4 below this: every sum fits an int64 (2^62: with a margin). */
#define QUADRIC_EXACT  4.611686018427387904e18
/* The gradients' matrix is singular for points on a plane (the square of the plane's
 * coordinate has no gradient there): a ridge of this times its trace keeps it factorable
 * without moving the fit of any surface that is not flat. */
#define QUADRIC_RIDGE  1e-9
/* The shift of the inverse iteration, times the trace (an exact fit's zero eigenvalue). */
#define QUADRIC_SHIFT  1e-12
/* Inverse iterations: each shrinks the other eigenvectors by the ratio of the eigenvalues;
 * where the quadric is used it fits several times better than the plane and the sphere. */
#define QUADRIC_STEPS  10
/* The scaled covariance's 2 x 2 principal minors summed below this: points on a line. */
#define QUADRIC_LINE   1e-9

/* The 10 monomials' exponents. */
static const int monomial[10][3] = { { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 },
                                     { 2, 0, 0 }, { 0, 2, 0 }, { 0, 0, 2 }, { 1, 1, 0 },
                                     { 1, 0, 1 }, { 0, 1, 1 } };

// The terms' places by exponents (i + j + k <= 4).
typedef struct term_index {
    int8_t of[5][5][5];
} term_index;

// The centred moments of the sums over n, scaled by the spread: k[t] for each term t of
// sta_tensor_exponent (moved to the mean one axis at a time); false when there is no
// spread.
static bool scaled_moments(const sta_tensor_sums *sums, const term_index *ti, double n,
                           double mean[3], double *spread, double k[STA_TENSOR_TERMS])
{
    static const double binomial[5][5] = { { 1, 0, 0, 0, 0 },
                                           { 1, 1, 0, 0, 0 },
                                           { 1, 2, 1, 0, 0 },
                                           { 1, 3, 3, 1, 0 },
                                           { 1, 4, 6, 4, 1 } };
    for (int t = 0; t < STA_TENSOR_TERMS; t++) {
        k[t] = (double)sums->s[t] / n;
    }
    for (int a = 0; a < 3; a++) {
        mean[a] = k[1 + a];
    }
    for (int a = 0; a < 3; a++) {
        double p[5] = { 1.0, -mean[a], mean[a] * mean[a], -mean[a] * mean[a] * mean[a],
                        mean[a] * mean[a] * mean[a] * mean[a] };
        double from[STA_TENSOR_TERMS];
        memcpy(from, k, sizeof(from));
        for (int t = 0; t < STA_TENSOR_TERMS; t++) {
            const uint8_t *e = sta_tensor_exponent[t];
            int f[3] = { e[0], e[1], e[2] };
            double c = 0.0;
            for (f[a] = 0; f[a] <= e[a]; f[a]++) {
                c += binomial[e[a]][f[a]] * p[e[a] - f[a]] * from[ti->of[f[0]][f[1]][f[2]]];
            }
            k[t] = c;
        }
    }
    double s2 = k[ti->of[2][0][0]] + k[ti->of[0][2][0]] + k[ti->of[0][0][2]];
    if (!(s2 > 0.0)) {
        return false;
    }
    double s = sqrt(s2), scale[5] = { 1.0, 1.0 / s, 1.0 / s2, 1.0 / (s2 * s), 1.0 / (s2 * s2) };
    for (int t = 0; t < STA_TENSOR_TERMS; t++) {
        const uint8_t *e = sta_tensor_exponent[t];
        k[t] *= scale[e[0] + e[1] + e[2]];
    }
    *spread = s;
    return true;
}

bool sta_tensor_moments_scaled(const sta_tensor_sums *sums, double mean[3], double *spread,
                               double k[STA_TENSOR_TERMS])
{
    term_index ti;
    for (int t = 0; t < STA_TENSOR_TERMS; t++) {
        const uint8_t *e = sta_tensor_exponent[t];
        ti.of[e[0]][e[1]][e[2]] = (int8_t)t;
    }
    double n = (double)sums->s[0];
    return n > 0.0 && scaled_moments(sums, &ti, n, mean, spread, k);
}

// The scaled moment of exponents e (each >= 0, sum <= 4).
static double moment(const double k[STA_TENSOR_TERMS], const term_index *ti, const int e[3])
{
    return k[ti->of[e[0]][e[1]][e[2]]];
}

bool sta_quadric_fit(const sta_tensor_sums *sums, double extent, sta_quadric *out)
{
    double n = (double)sums->s[0], e2 = extent * extent;
    if (!(n >= QUADRIC_POINTS) || !(n * e2 * e2 < QUADRIC_EXACT)) {
        return false;
    }
    term_index ti;
    for (int t = 0; t < STA_TENSOR_TERMS; t++) {
        const uint8_t *e = sta_tensor_exponent[t];
        ti.of[e[0]][e[1]][e[2]] = (int8_t)t;
    }
    double k[STA_TENSOR_TERMS], mean[3], spread;
    if (!scaled_moments(sums, &ti, n, mean, &spread, k)) {
        return false;
    }
    double xx = k[ti.of[2][0][0]], yy = k[ti.of[0][2][0]], zz = k[ti.of[0][0][2]];
    double xy = k[ti.of[1][1][0]], xz = k[ti.of[1][0][1]], yz = k[ti.of[0][1][1]];
    double minors = xx * yy - xy * xy + xx * zz - xz * xz + yy * zz - yz * yz;
    if (!(minors > QUADRIC_LINE)) {
        return false; // (on a line: the quadrics through it are many)
    }
    // M = mean m m^T, N = mean sum_a (d m / d x_a)(d m / d x_a)^T; the constant term v0 =
    // -M[0][1..] v (M[0][0] = 1) leaves A = M[1..][1..] - M[1..][0] M[0][1..] and B = N[1..][1..].
    double m0[10], a[UNKNOWNS][UNKNOWNS], b[UNKNOWNS][UNKNOWNS];
    for (int i = 0; i < 10; i++) {
        const int e[3] = { monomial[i][0], monomial[i][1], monomial[i][2] };
        m0[i] = moment(k, &ti, e);
    }
    double trace = 0.0;
    for (int i = 1; i < 10; i++) {
        for (int j = 1; j < 10; j++) {
            const int e[3] = { monomial[i][0] + monomial[j][0], monomial[i][1] + monomial[j][1],
                               monomial[i][2] + monomial[j][2] };
            a[i - 1][j - 1] = moment(k, &ti, e) - m0[i] * m0[j];
            double g = 0.0;
            for (int ax = 0; ax < 3; ax++) {
                if (monomial[i][ax] > 0 && monomial[j][ax] > 0) {
                    int f[3] = { e[0], e[1], e[2] };
                    f[ax] -= 2;
                    g += monomial[i][ax] * monomial[j][ax] * moment(k, &ti, f);
                }
            }
            b[i - 1][j - 1] = g;
        }
        trace += b[i - 1][i - 1];
    }
    for (int i = 0; i < UNKNOWNS; i++) {
        b[i][i] += QUADRIC_RIDGE * trace;
    }
    // C = L^-1 A L^-T with B = L L^T: the smallest eigenvector w of C gives v = L^-T w.
    double l[UNKNOWNS][UNKNOWNS], c[UNKNOWNS][UNKNOWNS], x[UNKNOWNS][UNKNOWNS], inv[UNKNOWNS];
    if (!sta_cholesky(&b[0][0], UNKNOWNS, 0.0, &l[0][0], inv)) {
        return false;
    }
    for (int j = 0; j < UNKNOWNS; j++) { // x = L^-1 A, column by column (A symmetric: rows)
        sta_cholesky_solve_lower(&l[0][0], inv, UNKNOWNS, memcpy(x[j], a[j], sizeof(x[j])));
    }
    double ctrace = 0.0;
    for (int j = 0; j < UNKNOWNS; j++) { // c = L^-1 x^T: x[j] is column j of L^-1 A
        double col[UNKNOWNS];
        for (int i = 0; i < UNKNOWNS; i++) {
            col[i] = x[i][j];
        }
        sta_cholesky_solve_lower(&l[0][0], inv, UNKNOWNS, col);
        for (int i = 0; i < UNKNOWNS; i++) {
            c[i][j] = col[i];
        }
    }
    for (int i = 0; i < UNKNOWNS; i++) {
        for (int j = 0; j < i; j++) {
            c[i][j] = c[j][i] = 0.5 * (c[i][j] + c[j][i]);
        }
        ctrace += c[i][i];
    }
    if (!(ctrace > 0.0)) {
        return false;
    }
    double shifted[UNKNOWNS][UNKNOWNS], lc[UNKNOWNS][UNKNOWNS], w[UNKNOWNS], inv_c[UNKNOWNS];
    memcpy(shifted, c, sizeof(shifted));
    for (int i = 0; i < UNKNOWNS; i++) {
        shifted[i][i] += QUADRIC_SHIFT * ctrace;
        w[i] = 1.0 - 0.07 * i; // (no special direction)
    }
    if (!sta_cholesky(&shifted[0][0], UNKNOWNS, 0.0, &lc[0][0], inv_c)) {
        return false;
    }
    for (int it = 0; it < QUADRIC_STEPS; it++) {
        sta_cholesky_solve_lower(&lc[0][0], inv_c, UNKNOWNS, w);
        sta_cholesky_solve_upper(&lc[0][0], inv_c, UNKNOWNS, w);
        double len = 0.0;
        for (int i = 0; i < UNKNOWNS; i++) {
            len += w[i] * w[i];
        }
        len = sqrt(len);
        if (!(len > 0.0) || !isfinite(len)) {
            return false;
        }
        double shrink = 1.0 / len; // (one division, not UNKNOWNS)
        for (int i = 0; i < UNKNOWNS; i++) {
            w[i] *= shrink;
        }
    }
    double value = 0.0;
    for (int i = 0; i < UNKNOWNS; i++) {
        for (int j = 0; j < UNKNOWNS; j++) {
            value += w[i] * c[i][j] * w[j];
        }
    }
    sta_cholesky_solve_upper(&l[0][0], inv, UNKNOWNS, w);
    double v0 = 0.0;
    for (int i = 0; i < UNKNOWNS; i++) {
        out->v[i + 1] = w[i];
        v0 -= m0[i + 1] * w[i];
    }
    out->v[0] = v0;
    memcpy(out->mean, mean, sizeof(out->mean));
    out->spread = spread;
    out->residual = value > 0.0 ? value : 0.0;
    for (int i = 0; i < 10; i++) {
        if (!isfinite(out->v[i])) {
            return false;
        }
    }
    return true;
}

bool sta_quadric_normal(const sta_quadric *q, const double p[3], double n[3], double *length)
{
    double x[3];
    for (int a = 0; a < 3; a++) {
        x[a] = (p[a] - q->mean[a]) / q->spread;
    }
    const double *v = q->v;
    double g[3] = { v[1] + 2.0 * v[4] * x[0] + v[7] * x[1] + v[8] * x[2],
                    v[2] + 2.0 * v[5] * x[1] + v[7] * x[0] + v[9] * x[2],
                    v[3] + 2.0 * v[6] * x[2] + v[8] * x[0] + v[9] * x[1] };
    double len = sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
    *length = len;
    if (!(len > 1e-12) || !isfinite(len)) {
        return false;
    }
    for (int a = 0; a < 3; a++) {
        n[a] = g[a] / len;
    }
    return true;
}
