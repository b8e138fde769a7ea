/* SPDX-License-Identifier: MIT
 * The plane of a moments box without the trigonometry of Kopp's analytic eigenvalues: the
 * smallest root of the covariance's characteristic polynomial by Newton's method, the normal
 * as the largest cross product of two rows of C - l0 I (the eigenvector step of Kopp's hybrid
 * method), the other two eigenvalues from the deflated quadratic. It answers only where that
 * is well conditioned (the two smallest eigenvalues apart: a plane, not a line or a blob);
 * elsewhere the caller takes Kopp's solver (normal_fit.h).
 */
#ifndef STA_PREPROCESS_BOX_PLANE_H
#define STA_PREPROCESS_BOX_PLANE_H

#include <stdbool.h>

/* The two smallest eigenvalues must differ by more than this share of the largest: below it
 * the cross products lose digits and Kopp's solver decides. */
#define STA_BOX_PLANE_GAP 0.05

/* The covariance m2 (upper triangle xx, xy, xz, yy, yz, zz, in grid units^2 times the count)
 * scaled by scale[a] scale[b] (metres a grid unit): its unit normal n (the eigenvector of the
 * smallest eigenvalue, some sign) and eigenvalues w, ascending, as sta_normal_fit_moments
 * gives them. False (n and w untouched) where the gap is too small, the matrix is not
 * positive semi-definite or not finite: then ask Kopp's solver. */
bool sta_box_plane(const double scale[3], const double m2[6], double n[3], double w[3]);

#endif
