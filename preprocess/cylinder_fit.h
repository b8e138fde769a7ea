/* SPDX-License-Identifier: MIT
 * The circular cylinder of an elongated set of points from its moment tensors
 * (strata-convert --normals, moments method: the boxes along a pole or a trunk;
 * docs/CONVERTER.md "The moments method").
 *
 * Design: the axis is the covariance's widest direction; the cross-section is Taubin's
 * algebraic circle in the plane across it: minimise the mean of q^2, q = A rho^2 + B.X + C
 * over the points projected into that plane (X, rho = |X|), subject to the mean of
 * |grad q|^2 being 1. Centred, C = -A mean(rho^2) drops out and the rest is the smallest
 * eigenvector of a symmetric 3 x 3 matrix of the projected moments up to the fourth order.
 * (Kasa's circle, a linear solve from the third order, underestimated the radius of the
 * street's half-seen poles and turned their normals by 5 degrees more: docs/BENCHMARKS.md,
 * fifteenth round.) Along a straight cylinder the cross-section does not change, so a set
 * much taller than the cylinder is wide (a 0.5 m box along an 0.22 m pole) fits the
 * circle from many points, where a sphere fitted to a box of the pole tilts with the box's
 * height and a plane fits across it. The moments come from tensor_sums.h's exact sums: the
 * fit is the same bits in any order of the points. Coordinates are grid units: a cylinder
 * in metres only where the grid's scale is the same on every axis (sta_sphere_isotropic).
 */
#ifndef STA_PREPROCESS_CYLINDER_FIT_H
#define STA_PREPROCESS_CYLINDER_FIT_H

#include <stdbool.h>

#include "tensor_sums.h"

/* A fitted cylinder, in coordinates x = (d - mean) / spread. */
typedef struct sta_cylinder {
    double mean[3];    /* grid units from the sums' corner */
    double spread;     /* root mean square distance to the mean, grid units */
    double axis[3];    /* unit: the covariance's widest direction */
    double e[2][3];    /* unit, across the axis: the cross-section's plane */
    double elongation; /* the covariance's largest eigenvalue over its second */
    double centre[2];  /* the circle's centre in the cross-section (along e[0], e[1]) */
    double radius;
    double residual; /* Taubin's: near the mean squared distance to the cylinder (over
                        spread^2, as the radius) */
} sta_cylinder;

/* The fit to the sums of points whose offsets lie in [0, extent) grid units an axis from
 * their corner; false when degenerate: fewer than 10 points, the sums may have overflowed
 * (n extent^4 reaches 2^62), no spread, no second direction, a cross-section on a line or
 * no circle (a plane across the axis). */
bool sta_cylinder_fit(const sta_tensor_sums *sums, double extent, sta_cylinder *out);

/* The unit normal of the cylinder at p (grid units from the sums' corner): radial from its
 * axis, across it; *off: p's distance from the cylinder over its radius. False when p is
 * on the axis. */
bool sta_cylinder_normal(const sta_cylinder *c, const double p[3], double n[3], double *off);

/* As sta_cylinder_normal (the same *off), but the normal where the ray from `from` (the
 * scanner, grid units from the sums' corner) through p enters the cylinder: a point's
 * range noise moves it along its ray, and the radial normal at p turns with it (4 M
 * street: poles 3.12 / 18.54 degrees radial, 2.25 / 15.09 at the ray's entry). A ray
 * that misses the cylinder or runs along its axis keeps the radial normal. */
bool sta_cylinder_normal_seen(const sta_cylinder *c, const double p[3], const double from[3],
                              double n[3], double *off);

#endif
