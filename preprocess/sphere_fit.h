/* SPDX-License-Identifier: MIT
 * The algebraic sphere of a set of points from its moments (strata-convert --normals,
 * moments method: boxes that are not flat; docs/CONVERTER.md "The moments method").
 *
 * Design: Pratt's fit of the algebraic sphere s(x) = u0 + u.x + u4 |x|^2 (Guennebaud and
 * Gross's "algebraic point set surfaces" without normals): minimise sum s(p)^2 subject to
 * |u|^2 - 4 u0 u4 = 1. It needs the sums of 1, p, p p^T, p |p|^2 and |p|^4 (cell_moments.h
 * keeps them exactly, additive over cells); centred on the points' mean and scaled by
 * their spread, u0 drops out and the rest is the smallest eigenvector of a symmetric
 * 4 x 4 matrix. The normal at a point is the gradient u + 2 u4 x there: radial on a
 * sphere, the plane's normal where u4 = 0 (flat points), and a circle's radius across a
 * cylinder seen from one side. Coordinates are grid units: the fit is a sphere in metres
 * only where the grid's scale is the same on every axis (sta_sphere_isotropic).
 */
#ifndef STA_PREPROCESS_SPHERE_FIT_H
#define STA_PREPROCESS_SPHERE_FIT_H

#include <stdbool.h>

#include "cell_moments.h"

/* The centred moments of a set of points for the sphere fit (grid units). */
typedef struct sta_sphere_moments {
    double n;
    double mean[3]; /* from the sums' corner */
    double c[6];    /* sum (d - mean)(d - mean)^T: xx xy xz yy yz zz */
    double t[3];    /* sum (d - mean) |d - mean|^2 */
    double q;       /* sum |d - mean|^4 */
} sta_sphere_moments;

/* A fitted sphere in coordinates x = (d - mean) / spread: u0 + u.x + u4 |x|^2 = 0 with
 * u0 = -u4 (the mean of |x|^2 is 1); u4 = 0 is a plane. */
typedef struct sta_sphere {
    double mean[3]; /* grid units from the sums' corner */
    double spread;  /* root mean square distance to the mean, grid units */
    double u[3], u4;
    double residual; /* mean squared algebraic distance over spread^2: near the sphere the
                        mean squared distance over spread^2, as a plane's surface
                        variation */
} sta_sphere;

/* Whether the grid's metres per unit are the same on the three axes (a sphere in grid
 * units is one in metres). */
bool sta_sphere_isotropic(const double scale[3]);

/* The centred moments of sums whose offsets lie in [0, extent) grid units an axis from
 * their corner; false when the higher sums may have overflowed (n (3 extent^2)^2 reaches
 * 2^62) or there are no points. */
bool sta_sphere_moments_of(const sta_moment_sums *sums, double extent, sta_sphere_moments *out);

/* As sta_sphere_moments_of, for sums whose n, mean and centred second moments (`c`) are
 * known already: only t and q from the higher sums. */
bool sta_sphere_moments_higher(const sta_moment_sums *sums, double extent, double n,
                               const double mean[3], const double c[6], sta_sphere_moments *out);

/* Pratt's fit; false when degenerate (fewer than 5 points, no spread, points on a line:
 * the smallest eigenvalue not alone, or no solution). */
bool sta_sphere_fit(const sta_sphere_moments *m, sta_sphere *out);

/* The sphere's radius over the points' spread (INFINITY for a plane). */
double sta_sphere_radius(const sta_sphere *s);

/* The unit normal (gradient) of the sphere at p (grid units from the sums' corner); false
 * when the gradient vanishes there (p at the sphere's centre). */
bool sta_sphere_normal(const sta_sphere *s, const double p[3], double n[3]);

#endif
