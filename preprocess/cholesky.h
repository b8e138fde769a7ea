/* SPDX-License-Identifier: MIT
 * Dense Cholesky factors of small symmetric matrices and their triangular solves: the
 * inverse iterations of the algebraic fits (sphere_fit.c, quadric_fit.c).
 *
 * Design: the factor keeps the reciprocals of its diagonal beside it, so a solve
 * multiplies where it would divide (the fits' iterations were bound by the latency of
 * their divisions, docs/BENCHMARKS.md, sixteenth round); the results differ from
 * dividing by at most a rounding a step.
 */
#ifndef STA_CHOLESKY_H
#define STA_CHOLESKY_H

#include <stdbool.h>

/* The lower factor l of a + shift I = l l^T (a symmetric, both n x n row-major; l's upper
 * triangle is zeroed) and inv[i] = 1 / l[i][i]; false when that matrix is not positive
 * definite. */
bool sta_cholesky(const double *a, int n, double shift, double *l, double *inv);

/* Solves l y = x in place (l and inv from sta_cholesky). Inline: a call with a constant n
 * is unrolled (the fits' n are 4 and 9). */
static inline void sta_cholesky_solve_lower(const double *l, const double *inv, int n, double *x)
{
    for (int i = 0; i < n; i++) {
        double sum = x[i];
        for (int k = 0; k < i; k++) {
            sum -= l[i * n + k] * x[k];
        }
        x[i] = sum * inv[i];
    }
}

/* Solves l^T y = x in place (l and inv from sta_cholesky). */
static inline void sta_cholesky_solve_upper(const double *l, const double *inv, int n, double *x)
{
    for (int i = n - 1; i >= 0; i--) {
        double sum = x[i];
        for (int k = i + 1; k < n; k++) {
            sum -= l[k * n + i] * x[k];
        }
        x[i] = sum * inv[i];
    }
}

#endif
