// SPDX-License-Identifier: MIT
// Symmetric 3x3 eigen solver: Kopp's hybrid method (Int. J. Mod. Phys. C 19, 2008,
// arXiv:physics/0610206). Line-by-line twin of the float path of
// src/render/ref/eigen3.c (read its header for the steps); docs/NORMALS.md has the
// tolerances. Include by naming "eigen3.glsl" before the stage in
// sta_gl_program_create.

#define EIG3_FLT_EPSILON 1.1920928955e-7
#define EIG3_FLT_MAX     3.4028234664e38

// A symmetric matrix as its six distinct entries.
struct eig3_sym_matrix {
    float a00, a11, a22, a01, a02, a12;
};

void eig3_swap_if_greater(inout float wi, inout float wj, inout vec3 vi, inout vec3 vj)
{
    if (wi > wj) {
        float t = wi;
        wi = wj;
        wj = t;
        vec3 tv = vi;
        vi = vj;
        vj = tv;
    }
}

// One Jacobi rotation annihilating apq; r is the third index. vp, vq: columns p, q of
// the accumulated rotation (the eigenvectors).
void eig3_rotate(inout float app, inout float aqq, inout float apq, inout float arp,
                 inout float arq, inout vec3 vp, inout vec3 vq)
{
    if (apq == 0.0) {
        return;
    }
    if (abs(apq) <= 0.01 * EIG3_FLT_EPSILON * (abs(app) + abs(aqq)) ||
        abs(apq) <= EIG3_FLT_EPSILON * EIG3_FLT_EPSILON) {
        apq = 0.0;
        return;
    }
    float theta = (aqq - app) / (2.0 * apq);
    float t = 1.0 / (abs(theta) + sqrt(theta * theta + 1.0));
    if (theta < 0.0) {
        t = -t;
    }
    float c = 1.0 / sqrt(t * t + 1.0);
    float s = t * c;
    float tau = s / (1.0 + c);
    float a_pp = app, a_qq = aqq, a_rp = arp, a_rq = arq;
    app = a_pp - t * apq;
    aqq = a_qq + t * apq;
    apq = 0.0;
    arp = a_rp - s * (a_rq + tau * a_rp);
    arq = a_rq + s * (a_rp - tau * a_rq);
    vec3 v_p = vp, v_q = vq;
    vp = v_p - s * (v_q + tau * v_p);
    vq = v_q + s * (v_p - tau * v_q);
}

// Cyclic Jacobi on the normalised matrix; unsorted.
void eig3_jacobi(eig3_sym_matrix m, out vec3 w, out vec3 v0, out vec3 v1, out vec3 v2)
{
    // Columns of the rotation: v0, v1, v2 (column k = eigenvector k).
    v0 = vec3(1.0, 0.0, 0.0);
    v1 = vec3(0.0, 1.0, 0.0);
    v2 = vec3(0.0, 0.0, 1.0);
    for (int sweep = 0; sweep < 20; sweep++) {
        if (m.a01 == 0.0 && m.a02 == 0.0 && m.a12 == 0.0) {
            break;
        }
        eig3_rotate(m.a00, m.a11, m.a01, m.a02, m.a12, v0, v1); // p=0 q=1 r=2
        eig3_rotate(m.a00, m.a22, m.a02, m.a01, m.a12, v0, v2); // p=0 q=2 r=1
        eig3_rotate(m.a11, m.a22, m.a12, m.a01, m.a02, v1, v2); // p=1 q=2 r=0
    }
    w = vec3(m.a00, m.a11, m.a22);
}

vec3 eig3_mul(eig3_sym_matrix m, vec3 x)
{
    return vec3(m.a00 * x.x + m.a01 * x.y + m.a02 * x.z, m.a01 * x.x + m.a11 * x.y + m.a12 * x.z,
                m.a02 * x.x + m.a12 * x.y + m.a22 * x.z);
}

vec3 eig3_cross(vec3 a, vec3 b)
{
    return vec3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}

float eig3_dot(vec3 a, vec3 b)
{
    return a.x * b.x + a.y * b.y + a.z * b.z;
}

// Analytic path; false when Kopp's error estimate asks for the fallback.
bool eig3_analytic(eig3_sym_matrix m, out vec3 w, out vec3 v0, out vec3 v1, out vec3 v2)
{
    w = vec3(0.0);
    v0 = vec3(1.0, 0.0, 0.0);
    v1 = vec3(0.0, 1.0, 0.0);
    v2 = vec3(0.0, 0.0, 1.0);
    float trace = m.a00 + m.a11 + m.a22;
    float mean = trace / 3.0;
    float b0 = m.a00 - mean, b1 = m.a11 - mean, b2 = m.a22 - mean;
    float off = m.a01 * m.a01 + m.a02 * m.a02 + m.a12 * m.a12;
    float p2 = (b0 * b0 + b1 * b1 + b2 * b2 + 2.0 * off) / 6.0;
    if (!(p2 > 0.0)) {
        return false;
    }
    float p = sqrt(p2);
    float c0 = b0 / p, c1 = b1 / p, c2 = b2 / p;
    float n01 = m.a01 / p, n02 = m.a02 / p, n12 = m.a12 / p;
    float r =
        (c0 * (c1 * c2 - n12 * n12) - n01 * (n01 * c2 - n12 * n02) + n02 * (n01 * n12 - c1 * n02)) /
        2.0;
    r = clamp(r, -1.0, 1.0);
    float disc = 1.0 - r * r;
    float phi = atan(sqrt(max(disc, 0.0)), r) / 3.0;
    float lmax = mean + 2.0 * p * cos(phi);
    float lmin = mean + 2.0 * p * cos(phi + 2.0943951023931954923);
    float lmid = trace - lmax - lmin;

    float lambda = (lmid - lmin) >= (lmax - lmid) ? lmin : lmax;
    vec3 r0 = vec3(m.a00 - lambda, m.a01, m.a02);
    vec3 r1 = vec3(m.a01, m.a11 - lambda, m.a12);
    vec3 r2 = vec3(m.a02, m.a12, m.a22 - lambda);
    vec3 best = eig3_cross(r0, r1);
    float best2 = eig3_dot(best, best);
    vec3 c = eig3_cross(r0, r2);
    float n2 = eig3_dot(c, c);
    if (n2 > best2) {
        best = c;
        best2 = n2;
    }
    c = eig3_cross(r1, r2);
    n2 = eig3_dot(c, c);
    if (n2 > best2) {
        best = c;
        best2 = n2;
    }

    float t = abs(lmax) > abs(lmin) ? abs(lmax) : abs(lmin);
    float u = t < 1.0 ? t : t * t;
    if (best2 <= 256.0 * EIG3_FLT_EPSILON * u * u) {
        return false;
    }
    vec3 x = best * (1.0 / sqrt(best2));

    int axis = 0;
    if (abs(x.y) < abs(x.x)) {
        axis = 1;
    }
    if (abs(x.z) < abs(axis == 0 ? x.x : x.y)) {
        axis = 2;
    }
    vec3 unit = vec3(axis == 0 ? 1.0 : 0.0, axis == 1 ? 1.0 : 0.0, axis == 2 ? 1.0 : 0.0);
    vec3 e1 = eig3_cross(x, unit);
    e1 = e1 * (1.0 / sqrt(eig3_dot(e1, e1)));
    vec3 e2 = eig3_cross(x, e1);
    vec3 mx = eig3_mul(m, x), me1 = eig3_mul(m, e1), me2 = eig3_mul(m, e2);
    float a11 = eig3_dot(e1, me1), a12 = eig3_dot(e1, me2), a22 = eig3_dot(e2, me2);
    float rt = 0.0;
    if (abs(a12) > EIG3_FLT_EPSILON * EIG3_FLT_EPSILON * abs(a22 - a11)) {
        float theta = (a22 - a11) / (2.0 * a12);
        rt = 1.0 / (abs(theta) + sqrt(theta * theta + 1.0));
        if (theta < 0.0) {
            rt = -rt;
        }
    }
    float rc = 1.0 / sqrt(rt * rt + 1.0);
    float rs = rt * rc;
    w = vec3(eig3_dot(x, mx), a11 - rt * a12, a22 + rt * a12);
    v0 = x;
    v1 = rc * e1 - rs * e2;
    v2 = rs * e1 + rc * e2;
    return true;
}

// Eigen decomposition of the symmetric matrix a (upper triangle read: a[j][i] for
// i <= j in GLSL's column-major indexing, the same entries for a symmetric a).
// values: ascending; vectors[i]: the unit eigenvector of values[i] (a column).
// Returns 0 zero matrix, 1 analytic, 2 fallback, 3 non-finite entry (as
// sta_eigen3_path); for 0 and 3 values are 0 and vectors the identity.
int eig3_sym(mat3 a, out vec3 values, out mat3 vectors)
{
    values = vec3(0.0);
    vectors = mat3(1.0);
    float s = 0.0;
    float e[6] = float[6](a[0][0], a[1][1], a[2][2], a[1][0], a[2][0], a[2][1]);
    for (int i = 0; i < 6; i++) {
        float x = abs(e[i]);
        if (!(x <= EIG3_FLT_MAX)) {
            return 3;
        }
        s = x > s ? x : s;
    }
    if (s == 0.0) {
        return 0;
    }
    eig3_sym_matrix m = eig3_sym_matrix(e[0] / s, e[1] / s, e[2] / s, e[3] / s, e[4] / s, e[5] / s);
    vec3 w, v0, v1, v2;
    int path = 1;
    if (!eig3_analytic(m, w, v0, v1, v2)) {
        eig3_jacobi(m, w, v0, v1, v2);
        path = 2;
    }
    eig3_swap_if_greater(w.x, w.y, v0, v1);
    eig3_swap_if_greater(w.y, w.z, v1, v2);
    eig3_swap_if_greater(w.x, w.y, v0, v1);
    values = w * s;
    vectors = mat3(v0, v1, v2);
    return path;
}
