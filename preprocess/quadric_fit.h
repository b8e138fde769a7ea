/* SPDX-License-Identifier: MIT
 * The algebraic quadric of a set of points from its moment tensors (strata-convert
 * --normals, moments method: the rough boxes of the adaptive fine level; docs/CONVERTER.md
 * "The moments method").
 *
 * Design: Taubin's fit of q(x) = v . m(x), m the 10 monomials of degree <= 2 (1, x, y,
 * z, x^2, y^2, z^2, xy, xz, yz): minimise the mean of q^2 over the points subject to the
 * mean of |grad q|^2 being 1, a generalised eigenproblem of two 10 x 10 matrices whose
 * entries are moments of order <= 4 (tensor_sums.h sums them exactly). Coordinates are
 * centred on the points' mean and scaled by their spread; the constant term is
 * eliminated (a Schur complement), the rest is the smallest eigenvector of a symmetric
 * 9 x 9 matrix, found by inverse iteration. A quadric holds a plane, a sphere, a cylinder
 * (a pole, a trunk: its axis need not be known) and a pair of planes (a box's edge: the
 * product of the two faces' equations), so its gradient at a point is the point's face's
 * normal beside an edge, radial on a pole. The residual (the smallest eigenvalue) is near
 * the mean squared distance to the surface over the spread squared, comparable with a
 * plane's surface variation and sphere_fit.h's residual. Grid units: a quadric in metres
 * only where the grid's scale is the same on every axis.
 */
#ifndef STA_PREPROCESS_QUADRIC_FIT_H
#define STA_PREPROCESS_QUADRIC_FIT_H

#include <stdbool.h>

#include "tensor_sums.h"

/* A fitted quadric in coordinates x = (d - mean) / spread: q(x) = v . m(x). */
typedef struct sta_quadric {
    double mean[3];  /* grid units from the sums' corner */
    double spread;   /* root mean square distance to the mean, grid units */
    double v[10];    /* 1, x, y, z, x^2, y^2, z^2, xy, xz, yz */
    double residual; /* mean q^2 with mean |grad q|^2 = 1 */
} sta_quadric;

/* The moments of the sums centred on their mean (grid units from the sums' corner) and
 * scaled by their spread (root mean square distance to the mean), over the count: k[t]
 * for each term t of sta_tensor_exponent. False when there are no points or no spread. */
bool sta_tensor_moments_scaled(const sta_tensor_sums *sums, double mean[3], double *spread,
                               double k[STA_TENSOR_TERMS]);

/* Taubin's fit to the sums of points whose offsets lie in [0, extent) grid units an axis
 * from their corner; false when degenerate: fewer than 11 points, the sums may have
 * overflowed (n extent^4 reaches 2^62), no spread, points on a line, or no solution. */
bool sta_quadric_fit(const sta_tensor_sums *sums, double extent, sta_quadric *out);

/* The unit normal (gradient) of q at p (grid units from the sums' corner) and the
 * gradient's length there (its mean square over the points is 1); false when the gradient
 * vanishes (an edge's line, a sphere's centre). */
bool sta_quadric_normal(const sta_quadric *q, const double p[3], double n[3], double *length);

#endif
