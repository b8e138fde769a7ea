/* SPDX-License-Identifier: MIT
 * Eigenvalues and eigenvectors of real symmetric 3x3 matrices, in float (the CPU twin
 * of shaders/eigen3.glsl, used by the covariance normals) and in double.
 *
 * Based on: J. Kopp, "Efficient numerical diagonalization of hermitian 3x3 matrices",
 * Int. J. Mod. Phys. C 19 (2008) 523-548, arXiv:physics/0610206 — the hybrid method:
 * analytic (Cardano / trigonometric) eigenvalues, an eigenvector as the cross product
 * of two rows of A - lambda I, and Kopp's error estimate deciding when the analytic
 * result cannot be trusted, in which case an iterative method (here cyclic Jacobi)
 * takes over. docs/NORMALS.md describes the exact variant and its tolerances.
 */
#ifndef STA_CORE_EIGEN3_H
#define STA_CORE_EIGEN3_H

/* Which way a decomposition went. */
typedef enum sta_eigen3_path {
    STA_EIGEN3_ZERO = 0,     /* zero matrix: zero eigenvalues, identity basis */
    STA_EIGEN3_ANALYTIC = 1, /* Cardano + cross product + exact 2x2 rotation */
    STA_EIGEN3_FALLBACK = 2, /* Kopp's error estimate rejected the analytic vector: Jacobi */
    STA_EIGEN3_INVALID = 3   /* a NaN or infinite entry: zero eigenvalues, identity basis */
} sta_eigen3_path;

/* Decomposes the symmetric matrix `a`, row-major (a[3 * i + j] is row i, column j;
 * only the upper triangle j >= i is read). out_values: the eigenvalues in ascending order.
 * out_vectors[i]: a unit eigenvector for out_values[i]; the three are orthonormal (for a repeated
 * eigenvalue they are some orthonormal basis of its eigenspace). The matrix is first divided by its
 * largest absolute entry, so any finite scale (1e-30 .. 1e30 in float) works. Accuracy: eigenvalues
 * within a few ulps times the matrix norm; see docs/NORMALS.md. Pure function; thread-safe. Returns
 * which path it took. */
sta_eigen3_path sta_eigen3_sym_f(const float a[9], float out_values[3], float out_vectors[3][3]);
sta_eigen3_path sta_eigen3_sym_d(const double a[9], double out_values[3], double out_vectors[3][3]);

/* The fallback alone (scale normalisation, cyclic Jacobi, sorting), for tests. Returns
 * STA_EIGEN3_FALLBACK, or ZERO / INVALID as above. */
sta_eigen3_path sta_eigen3_sym_jacobi_f(const float a[9], float out_values[3],
                                        float out_vectors[3][3]);
sta_eigen3_path sta_eigen3_sym_jacobi_d(const double a[9], double out_values[3],
                                        double out_vectors[3][3]);

#endif
