/* SPDX-License-Identifier: MIT
 * A box's plane by Newton's method on its characteristic polynomial (box_plane.h): the
 * moments normals fit one plane a vertex box, about one a point of the chunk, and Kopp's
 * analytic eigenvalues (an atan2, a cos and a sqrt each, all three eigenvectors) were 7 %
 * of a 4 M street conversion (fifteenth round, third part, docs/BENCHMARKS.md).
 */
#include "box_plane.h"

#include <math.h>

/* Newton steps at most; it stops earlier when a step is below NEWTON_TOLERANCE of the
 * trace (from 0 it converges from below, quadratically once near the root). */
#define NEWTON_STEPS     40
#define NEWTON_TOLERANCE 1e-15
/* The chosen cross product's squared length must exceed this times l2^4 (two rows of
 * C - l0 I that span the plane have a product of about l1 l2). */
#define CROSS_LEAST      1e-20

bool sta_box_plane(const double scale[3], const double m2[6], double n[3], double w[3])
{
    const double *s = scale;
    double a = m2[0] * s[0] * s[0], b = m2[1] * s[0] * s[1], c = m2[2] * s[0] * s[2];
    double d = m2[3] * s[1] * s[1], e = m2[4] * s[1] * s[2], f = m2[5] * s[2] * s[2];
    // det(C - x I) = -x^3 + c2 x^2 - c1 x + c0
    double c2 = a + d + f, c1 = a * d + a * f + d * f - b * b - c * c - e * e;
    double c0 = a * (d * f - e * e) - b * (b * f - c * e) + c * (b * e - c * d);
    if (!(c2 > 0.0) || !(c1 >= 0.0) || !(c0 >= 0.0) || !isfinite(c2 + c1 + c0)) {
        return false;
    }
    double x = 0.0;
    for (int i = 0; i < NEWTON_STEPS && c0 > 0.0; i++) {
        double p = ((-x + c2) * x - c1) * x + c0, dp = (-3.0 * x + 2.0 * c2) * x - c1;
        if (!(dp < 0.0)) {
            return false; // (a double smallest root: no gap anyway)
        }
        double step = p / dp;
        x -= step;
        if (fabs(step) <= NEWTON_TOLERANCE * c2) {
            break;
        }
    }
    // The other two: their sum is c2 - x, their product c1 - x (c2 - x).
    double sum = c2 - x, product = c1 - x * sum, disc = sum * sum - 4.0 * product;
    disc = disc > 0.0 ? sqrt(disc) : 0.0;
    double l1 = 0.5 * (sum - disc), l2 = 0.5 * (sum + disc);
    if (!(l2 > 0.0) || !(l1 - x > STA_BOX_PLANE_GAP * l2)) {
        return false;
    }
    const double r[3][3] = { { a - x, b, c }, { b, d - x, e }, { c, e, f - x } };
    double best = 0.0, v[3] = { 0, 0, 0 };
    for (int i = 0; i < 3; i++) {
        const double *p = r[i], *q = r[(i + 1) % 3];
        double t[3] = { p[1] * q[2] - p[2] * q[1], p[2] * q[0] - p[0] * q[2],
                        p[0] * q[1] - p[1] * q[0] };
        double len = t[0] * t[0] + t[1] * t[1] + t[2] * t[2];
        if (len > best) {
            best = len;
            v[0] = t[0], v[1] = t[1], v[2] = t[2];
        }
    }
    if (!(best > CROSS_LEAST * l2 * l2 * l2 * l2) || !isfinite(best)) {
        return false;
    }
    double inv = 1.0 / sqrt(best);
    for (int k = 0; k < 3; k++) {
        n[k] = v[k] * inv;
    }
    w[0] = x > 0.0 ? x : 0.0;
    w[1] = l1;
    w[2] = l2;
    return true;
}
