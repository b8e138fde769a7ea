/* SPDX-License-Identifier: MIT
 * Dense Cholesky factors of small symmetric matrices and their triangular solves: the
 * inverse iterations of the algebraic fits (sphere_fit.c, quadric_fit.c). */
#ifndef STA_CHOLESKY_H
#define STA_CHOLESKY_H

#include <stdbool.h>

/* The lower factor l of a + shift I = l l^T (a symmetric, both n x n row-major; l's upper
 * triangle is zeroed); false when that matrix is not positive definite. */
bool sta_cholesky(const double *a, int n, double shift, double *l);

/* Solves l y = x in place (l from sta_cholesky). */
void sta_cholesky_solve_lower(const double *l, int n, double *x);

/* Solves l^T y = x in place (l from sta_cholesky). */
void sta_cholesky_solve_upper(const double *l, int n, double *x);

#endif
