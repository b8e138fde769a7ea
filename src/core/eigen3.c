/* SPDX-License-Identifier: MIT
 * Symmetric 3x3 eigen solver (Kopp's hybrid method), in float and double.
 *
 * Based on: J. Kopp, "Efficient numerical diagonalization of hermitian 3x3 matrices",
 * Int. J. Mod. Phys. C 19 (2008), arXiv:physics/0610206.
 *
 * Steps (the float version is repeated line by line in shaders/eigen3.glsl):
 * 1. Divide by the largest absolute entry (scale normalisation); a zero matrix gives
 *    zero eigenvalues and the identity.
 * 2. Eigenvalues from the characteristic cubic in trigonometric (Cardano) form, after
 *    removing the mean of the diagonal (fewer cancellations than the raw cubic).
 * 3. Of the two extreme eigenvalues take the one farther from the middle one; its
 *    eigenvector is the longest of the three cross products of rows of A - lambda I.
 * 4. Kopp's error estimate: if that cross product's squared length is at most
 *    256 eps u^2 (u = max|lambda|, or its square when >= 1), the analytic result is
 *    not trustworthy (near-degenerate eigenvalues, cancellation) and cyclic Jacobi
 *    decomposes the normalised matrix instead.
 * 5. Otherwise the other two eigenvectors come from the 2x2 matrix that A leaves in the
 *    plane orthogonal to the first one, diagonalised by one exact Jacobi rotation (Kopp
 *    takes a second cross product instead; the rotation keeps the basis orthonormal to
 *    rounding and handles the common covariance case of two equal large eigenvalues
 *    without the fallback). Eigenvalues are the Rayleigh quotients of the vectors.
 * 6. Sort ascending and undo the scale.
 *
 * The body below is written once for a generic REAL and compiled twice: this file
 * includes itself with EIGEN3_REAL set to float and then to double.
 */
#ifndef EIGEN3_REAL

# include "core/eigen3.h"

# include <float.h>
# include <math.h>

enum {
    JACOBI_MAX_SWEEPS = 20 /* 3x3 Jacobi converges quadratically: ~5 sweeps to rounding */
};

# define EIGEN3_REAL   float
# define EIGEN3_SUFFIX _f
# define EIGEN3_EPS    FLT_EPSILON
# define EIGEN3_MAX    FLT_MAX
# define SQRT          sqrtf
# define FABS          fabsf
# define ATAN2         atan2f
# define COS           cosf
# include "core/eigen3.c"
# undef EIGEN3_REAL
# undef EIGEN3_SUFFIX
# undef EIGEN3_EPS
# undef EIGEN3_MAX
# undef SQRT
# undef FABS
# undef ATAN2
# undef COS

# define EIGEN3_REAL   double
# define EIGEN3_SUFFIX _d
# define EIGEN3_EPS    DBL_EPSILON
# define EIGEN3_MAX    DBL_MAX
# define SQRT          sqrt
# define FABS          fabs
# define ATAN2         atan2
# define COS           cos
# include "core/eigen3.c"

#else /* the generic body */

# define T            EIGEN3_REAL
# define K(x)         ((T)(x))
# define PASTE_(a, b) a##b
# define PASTE(a, b)  PASTE_(a, b)
# define FN(name)     PASTE(name, EIGEN3_SUFFIX)

static void FN(set_identity)(T w[3], T v[3][3])
{
    for (int i = 0; i < 3; i++) {
        w[i] = 0;
        for (int k = 0; k < 3; k++) {
            v[i][k] = i == k ? K(1) : K(0);
        }
    }
}

static void FN(swap_if_greater)(T w[3], T v[3][3], int i, int j)
{
    if (w[i] > w[j]) {
        T t = w[i];
        w[i] = w[j];
        w[j] = t;
        for (int k = 0; k < 3; k++) {
            t = v[i][k];
            v[i][k] = v[j][k];
            v[j][k] = t;
        }
    }
}

// Ascending order by a fixed compare-swap network (the shader does the same).
static void FN(sort3)(T w[3], T v[3][3])
{
    FN(swap_if_greater)(w, v, 0, 1);
    FN(swap_if_greater)(w, v, 1, 2);
    FN(swap_if_greater)(w, v, 0, 1);
}

// Step 1: m = a / max|a_ij| from the upper triangle. Returns the scale, 0 for a zero
// matrix, or -1 when an entry is not finite.
static T FN(normalise)(const T a[9], T m[3][3])
{
    T s = 0;
    for (int i = 0; i < 3; i++) {
        for (int j = i; j < 3; j++) {
            T x = FABS(a[3 * i + j]);
            if (!(x <= EIGEN3_MAX)) {
                return K(-1);
            }
            s = x > s ? x : s;
        }
    }
    if (s == 0) {
        return 0;
    }
    for (int i = 0; i < 3; i++) {
        for (int j = i; j < 3; j++) {
            m[i][j] = a[3 * i + j] / s;
            m[j][i] = m[i][j];
        }
    }
    return s;
}

// Cyclic Jacobi on the normalised matrix m (overwritten). out_vectors[i] pairs with
// w[i]; unsorted.
static void FN(jacobi)(T m[3][3], T w[3], T out_vectors[3][3])
{
    T v[3][3] = { { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 } }; // columns are the vectors
    static const int pairs[3][3] = { { 0, 1, 2 }, { 0, 2, 1 }, { 1, 2, 0 } };
    for (int sweep = 0; sweep < JACOBI_MAX_SWEEPS; sweep++) {
        if (m[0][1] == 0 && m[0][2] == 0 && m[1][2] == 0) {
            break;
        }
        for (int e = 0; e < 3; e++) {
            int p = pairs[e][0], q = pairs[e][1], r = pairs[e][2];
            T apq = m[p][q];
            if (apq == 0) {
                continue;
            }
            T app = m[p][p], aqq = m[q][q];
            // Negligible against its diagonal, or against the (unit) matrix norm.
            if (FABS(apq) <= K(0.01) * EIGEN3_EPS * (FABS(app) + FABS(aqq)) ||
                FABS(apq) <= EIGEN3_EPS * EIGEN3_EPS) {
                m[p][q] = 0;
                m[q][p] = 0;
                continue;
            }
            T theta = (aqq - app) / (K(2) * apq);
            T t = K(1) / (FABS(theta) + SQRT(theta * theta + K(1)));
            if (theta < 0) {
                t = -t;
            }
            T c = K(1) / SQRT(t * t + K(1));
            T s = t * c;
            T tau = s / (K(1) + c);
            m[p][p] = app - t * apq;
            m[q][q] = aqq + t * apq;
            m[p][q] = 0;
            m[q][p] = 0;
            T arp = m[r][p], arq = m[r][q];
            m[r][p] = arp - s * (arq + tau * arp);
            m[p][r] = m[r][p];
            m[r][q] = arq + s * (arp - tau * arq);
            m[q][r] = m[r][q];
            for (int k = 0; k < 3; k++) {
                T vkp = v[k][p], vkq = v[k][q];
                v[k][p] = vkp - s * (vkq + tau * vkp);
                v[k][q] = vkq + s * (vkp - tau * vkq);
            }
        }
    }
    for (int i = 0; i < 3; i++) {
        w[i] = m[i][i];
        for (int k = 0; k < 3; k++) {
            out_vectors[i][k] = v[k][i];
        }
    }
}

static void FN(cross)(const T a[3], const T b[3], T out[3])
{
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

static T FN(dot)(const T a[3], const T b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void FN(mul)(T m[3][3], const T x[3], T out[3])
{
    for (int i = 0; i < 3; i++) {
        out[i] = m[i][0] * x[0] + m[i][1] * x[1] + m[i][2] * x[2];
    }
}

// Steps 2-5 on the normalised matrix m. Returns false when Kopp's estimate asks for
// the fallback; w and v are then unset.
static int FN(analytic)(T m[3][3], T w[3], T v[3][3])
{
    // 2. Trigonometric roots of det(B - x I) = 0 for B = m - mean I, B = 2 p C.
    T trace = m[0][0] + m[1][1] + m[2][2];
    T mean = trace / K(3);
    T b0 = m[0][0] - mean, b1 = m[1][1] - mean, b2 = m[2][2] - mean;
    T off = m[0][1] * m[0][1] + m[0][2] * m[0][2] + m[1][2] * m[1][2];
    T p2 = (b0 * b0 + b1 * b1 + b2 * b2 + K(2) * off) / K(6);
    if (!(p2 > 0)) {
        return 0; // a multiple of the identity: Jacobi returns it at once
    }
    T p = SQRT(p2);
    T c0 = b0 / p, c1 = b1 / p, c2 = b2 / p;
    T n01 = m[0][1] / p, n02 = m[0][2] / p, n12 = m[1][2] / p;
    T r =
        (c0 * (c1 * c2 - n12 * n12) - n01 * (n01 * c2 - n12 * n02) + n02 * (n01 * n12 - c1 * n02)) /
        K(2);
    r = r < K(-1) ? K(-1) : (r > K(1) ? K(1) : r);
    T disc = K(1) - r * r;
    T phi = ATAN2(SQRT(disc > 0 ? disc : K(0)), r) / K(3); // acos(r) / 3, in [0, pi/3]
    T lmax = mean + K(2) * p * COS(phi);
    T lmin = mean + K(2) * p * COS(phi + K(2.0943951023931954923)); // + 2 pi / 3
    T lmid = trace - lmax - lmin;

    // 3. The better isolated extreme eigenvalue, and the longest row cross product.
    T lambda = (lmid - lmin) >= (lmax - lmid) ? lmin : lmax;
    T rows[3][3];
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++) {
            rows[i][j] = i == j ? m[i][j] - lambda : m[i][j];
        }
    }
    T cr[3][3];
    FN(cross)(rows[0], rows[1], cr[0]);
    FN(cross)(rows[0], rows[2], cr[1]);
    FN(cross)(rows[1], rows[2], cr[2]);
    int best = 0;
    T best2 = FN(dot)(cr[0], cr[0]);
    for (int i = 1; i < 3; i++) {
        T n2 = FN(dot)(cr[i], cr[i]);
        if (n2 > best2) {
            best = i;
            best2 = n2;
        }
    }

    // 4. Kopp's error estimate.
    T t = FABS(lmax) > FABS(lmin) ? FABS(lmax) : FABS(lmin);
    T u = t < K(1) ? t : t * t;
    if (best2 <= K(256) * EIGEN3_EPS * u * u) {
        return 0;
    }
    T inv = K(1) / SQRT(best2);
    T x[3] = { cr[best][0] * inv, cr[best][1] * inv, cr[best][2] * inv };

    // 5. An orthonormal pair (e1, e2) spanning the plane orthogonal to x: e1 = x cross
    // the coordinate axis least aligned with x.
    int axis = 0;
    if (FABS(x[1]) < FABS(x[axis])) {
        axis = 1;
    }
    if (FABS(x[2]) < FABS(x[axis])) {
        axis = 2;
    }
    T unit[3] = { 0, 0, 0 };
    unit[axis] = 1;
    T e1[3], e2[3];
    FN(cross)(x, unit, e1);
    T inv1 = K(1) / SQRT(FN(dot)(e1, e1));
    e1[0] *= inv1;
    e1[1] *= inv1;
    e1[2] *= inv1;
    FN(cross)(x, e1, e2);
    T mx[3], me1[3], me2[3];
    FN(mul)(m, x, mx);
    FN(mul)(m, e1, me1);
    FN(mul)(m, e2, me2);
    T a11 = FN(dot)(e1, me1), a12 = FN(dot)(e1, me2), a22 = FN(dot)(e2, me2);
    T rt = 0; // tan of the rotation angle
    if (FABS(a12) > EIGEN3_EPS * EIGEN3_EPS * FABS(a22 - a11)) {
        T theta = (a22 - a11) / (K(2) * a12);
        rt = K(1) / (FABS(theta) + SQRT(theta * theta + K(1)));
        if (theta < 0) {
            rt = -rt;
        }
    }
    T rc = K(1) / SQRT(rt * rt + K(1));
    T rs = rt * rc;
    w[0] = FN(dot)(x, mx);
    w[1] = a11 - rt * a12;
    w[2] = a22 + rt * a12;
    for (int k = 0; k < 3; k++) {
        v[0][k] = x[k];
        v[1][k] = rc * e1[k] - rs * e2[k];
        v[2][k] = rs * e1[k] + rc * e2[k];
    }
    return 1;
}

static sta_eigen3_path FN(finish)(T s, T w[3], T v[3][3])
{
    FN(sort3)(w, v);
    for (int i = 0; i < 3; i++) {
        w[i] *= s;
    }
    return STA_EIGEN3_ANALYTIC;
}

sta_eigen3_path FN(sta_eigen3_sym)(const T a[9], T out_values[3], T out_vectors[3][3])
{
    T m[3][3];
    T s = FN(normalise)(a, m);
    if (s <= 0) {
        FN(set_identity)(out_values, out_vectors);
        return s == 0 ? STA_EIGEN3_ZERO : STA_EIGEN3_INVALID;
    }
    if (FN(analytic)(m, out_values, out_vectors)) {
        return FN(finish)(s, out_values, out_vectors);
    }
    FN(jacobi)(m, out_values, out_vectors);
    FN(finish)(s, out_values, out_vectors);
    return STA_EIGEN3_FALLBACK;
}

sta_eigen3_path FN(sta_eigen3_sym_jacobi)(const T a[9], T out_values[3], T out_vectors[3][3])
{
    T m[3][3];
    T s = FN(normalise)(a, m);
    if (s <= 0) {
        FN(set_identity)(out_values, out_vectors);
        return s == 0 ? STA_EIGEN3_ZERO : STA_EIGEN3_INVALID;
    }
    FN(jacobi)(m, out_values, out_vectors);
    FN(finish)(s, out_values, out_vectors);
    return STA_EIGEN3_FALLBACK;
}

# undef T
# undef K
# undef FN
# undef PASTE
# undef PASTE_

#endif
