/* SPDX-License-Identifier: MIT
 * Pratt's algebraic sphere from exact moments, and its normal at a point. */
#include "sphere_fit.h"

#include <math.h>
#include <string.h>

#include "cholesky.h"

/* Inverse iterations for the smallest eigenvector: each shrinks the others by the ratio of
 * the eigenvalues; where the sphere is used it fits twice better than the plane. */
#define SPHERE_ITERATIONS 8
/* The shift of the inverse iteration, times the trace: an exact sphere's zero eigenvalue
 * stays factorable. */
#define SPHERE_SHIFT      1e-12
/* The scaled second moments' (trace 1) 2 x 2 principal minors summed below this: the points
 * lie on a line (or are one point), the spheres through them are many. */
#define SPHERE_LINE       1e-9
/* Fewer points cannot decide a sphere (4 unknowns) with one to spare. */
#define SPHERE_POINTS     5.0
/* n (3 extent^2)^2 below this: sum |d|^4 fits an int64 (2^62: with a margin). */
#define SPHERE_EXACT      4.611686018427387904e18

bool sta_sphere_isotropic(const double scale[3])
{
    return scale[0] > 0.0 && scale[0] == scale[1] && scale[0] == scale[2];
}

bool sta_sphere_moments_higher(const sta_moment_sums *sums, double extent, double n,
                               const double mean[3], const double c[6], sta_sphere_moments *out)
{
    double far = 3.0 * extent * extent;
    if (!(n > 0.0) || !(n * far * far < SPHERE_EXACT)) {
        return false;
    }
    out->n = n;
    memcpy(out->mean, mean, sizeof(out->mean));
    memcpy(out->c, c, sizeof(out->c));
    // The raw sums t3 = sum d |d|^2, t4 = sum |d|^4 moved to the mean m, with the centred
    // second moments C (sum d d^T = C + n m m^T): t = t3 - 2 C m - m tr C - n m |m|^2,
    // q = t4 + 4 m.C m - 4 m.t3 + 2 |m|^2 tr C + 3 n |m|^4.
    const double *m = mean;
    const double cm[3] = { c[0] * m[0] + c[1] * m[1] + c[2] * m[2],
                           c[1] * m[0] + c[3] * m[1] + c[4] * m[2],
                           c[2] * m[0] + c[4] * m[1] + c[5] * m[2] };
    double trace = c[0] + c[3] + c[5], mm = m[0] * m[0] + m[1] * m[1] + m[2] * m[2];
    double t3[3], mt3 = 0.0, mcm = 0.0;
    for (int a = 0; a < 3; a++) {
        t3[a] = (double)(int64_t)sums->s3[a];
        mt3 += m[a] * t3[a];
        mcm += m[a] * cm[a];
    }
    for (int a = 0; a < 3; a++) {
        out->t[a] = t3[a] - 2.0 * cm[a] - m[a] * trace - n * m[a] * mm;
    }
    out->q =
        (double)(int64_t)sums->s4 + 4.0 * mcm - 4.0 * mt3 + 2.0 * mm * trace + 3.0 * n * mm * mm;
    return true;
}

bool sta_sphere_moments_of(const sta_moment_sums *sums, double extent, sta_sphere_moments *out)
{
    double n = (double)sums->n, mean[3], c[6];
    if (!(n > 0.0)) {
        return false;
    }
    for (int a = 0; a < 3; a++) {
        mean[a] = (double)sums->s1[a] / n;
    }
    for (int r = 0, t = 0; r < 3; r++) {
        for (int q = r; q < 3; q++, t++) {
            c[t] = (double)sums->s2[t] - (double)sums->s1[r] * (double)sums->s1[q] / n;
        }
    }
    return sta_sphere_moments_higher(sums, extent, n, mean, c, out);
}

// The unit eigenvector x of the smallest eigenvalue of the symmetric positive semi-definite
// a (left as it is), by inverse iteration (Cholesky of a shifted by a trace's 1e-12), and its
// eigenvalue (the Rayleigh quotient); false when a is not positive semi-definite.
static bool smallest_eigen4(double a[4][4], double x[4], double *value)
{
    double trace = a[0][0] + a[1][1] + a[2][2] + a[3][3], l[4][4], inv[4];
    if (!(trace > 0.0) || !sta_cholesky(&a[0][0], 4, SPHERE_SHIFT * trace, &l[0][0], inv)) {
        return false;
    }
    for (int i = 0; i < 4; i++) {
        x[i] = 0.5;
    }
    for (int it = 0; it < SPHERE_ITERATIONS; it++) {
        sta_cholesky_solve_lower(&l[0][0], inv, 4, x);
        sta_cholesky_solve_upper(&l[0][0], inv, 4, x);
        double len = 0.0;
        for (int i = 3; i >= 0; i--) {
            len += x[i] * x[i];
        }
        double shrink = 1.0 / sqrt(len); // (one division, not four)
        for (int i = 0; i < 4; i++) {
            x[i] *= shrink;
        }
    }
    *value = 0.0;
    for (int i = 0; i < 4; i++) {
        for (int j = 0; j < 4; j++) {
            *value += x[i] * a[i][j] * x[j];
        }
    }
    return true;
}

bool sta_sphere_fit(const sta_sphere_moments *m, sta_sphere *out)
{
    double n = m->n, trace = m->c[0] + m->c[3] + m->c[5];
    if (!(n >= SPHERE_POINTS) || !(trace > 0.0)) {
        return false;
    }
    // x = (d - mean) / spread, spread^2 = tr C / n: the mean of |x|^2 is 1, and with u0 = -u4
    // the constraint |u|^2 + 4 u4^2 = 1 makes y = (u, 2 u4) a unit vector minimising
    // y^T A y: A = [C / (n s^2), t / (2 n s^3); ., (q / (n s^4) - 1) / 4].
    double s2 = trace / n, s = sqrt(s2);
    double a[4][4];
    const int idx[3][3] = { { 0, 1, 2 }, { 1, 3, 4 }, { 2, 4, 5 } };
    for (int r = 0; r < 3; r++) {
        for (int q = 0; q < 3; q++) {
            a[r][q] = m->c[idx[r][q]] / (n * s2);
        }
        a[r][3] = a[3][r] = m->t[r] / (2.0 * n * s2 * s);
    }
    a[3][3] = (m->q / (n * s2 * s2) - 1.0) / 4.0;
    // Points on a line (the second moments of rank 1): the spheres through it are many.
    double minors = a[0][0] * a[1][1] - a[0][1] * a[0][1] + a[0][0] * a[2][2] - a[0][2] * a[0][2] +
                    a[1][1] * a[2][2] - a[1][2] * a[1][2];
    double x[4], value;
    if (!(minors > SPHERE_LINE) || !smallest_eigen4(a, x, &value)) {
        return false;
    }
    memcpy(out->mean, m->mean, sizeof(out->mean));
    out->spread = s;
    for (int r = 0; r < 3; r++) {
        out->u[r] = x[r];
    }
    out->u4 = 0.5 * x[3];
    out->residual = value > 0.0 ? value : 0.0;
    return isfinite(out->u[0]) && isfinite(out->u[1]) && isfinite(out->u[2]) && isfinite(out->u4);
}

double sta_sphere_radius(const sta_sphere *s)
{
    if (s->u4 == 0.0) {
        return INFINITY;
    }
    double uu = s->u[0] * s->u[0] + s->u[1] * s->u[1] + s->u[2] * s->u[2];
    return sqrt(uu / (4.0 * s->u4 * s->u4) + 1.0);
}

bool sta_sphere_normal(const sta_sphere *s, const double p[3], double n[3])
{
    double g[3], len2 = 0.0;
    for (int a = 0; a < 3; a++) {
        g[a] = s->u[a] + 2.0 * s->u4 * (p[a] - s->mean[a]) / s->spread;
        len2 += g[a] * g[a];
    }
    if (!(len2 > 1e-18)) {
        return false;
    }
    double len = sqrt(len2);
    for (int a = 0; a < 3; a++) {
        n[a] = g[a] / len;
    }
    return true;
}
