/* SPDX-License-Identifier: MIT
 * The symmetric 3x3 eigen solver (src/core/eigen3.c, shaders/eigen3.glsl)
 * against LAPACK's dsyev on families of hard matrices.
 *
 * Tolerances (norm = spectral norm max|lambda| of the LAPACK result):
 * - eigenvalues: |lambda - lambda_ref| <= 1e-12 norm (double), 1e-5 norm (float);
 * - orthonormality: |v_i . v_j - delta_ij| <= 1e-12 (double), 1e-5 (float);
 * - residual: |A v_i - lambda_i v_i| <= 1e-12 norm (double), 1e-5 norm (float);
 * - eigenspaces: eigenvalues closer than 1000 eps norm form one cluster, compared as a
 *   projector: ||P - P_ref||_F <= 100 eps norm / gap (the Davis-Kahan bound for a
 *   backward error of 100 eps norm), gap = distance to the other eigenvalues. A
 *   cluster of all three eigenvalues is any basis and is not compared.
 * The float solver is checked against LAPACK on the float-rounded matrix.
 */
#include "test_support.h"

#include <float.h>
#include <lapacke.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "core/alloc.h"
#include "core/eigen3.h"
#include "render/gl.h"
#include "render/shader_source.h"

typedef struct rng {
    uint64_t state;
} rng;

static uint64_t rng_next(rng *r)
{
    uint64_t z = (r->state += 0x9e3779b97f4a7c15ull); // splitmix64
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

static double uniform(rng *r, double lo, double hi)
{
    return lo + (hi - lo) * (double)(rng_next(r) >> 11) * 0x1.0p-53;
}

static double gauss(rng *r)
{
    double u = uniform(r, 1e-12, 1.0), v = uniform(r, 0.0, 1.0);
    return sqrt(-2.0 * log(u)) * cos(6.283185307179586 * v);
}

static void random_rotation(rng *r, double q[3][3])
{
    double w = gauss(r), x = gauss(r), y = gauss(r), z = gauss(r);
    double n = sqrt(w * w + x * x + y * y + z * z);
    w /= n, x /= n, y /= n, z /= n;
    double m[3][3] = { { 1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y) },
                       { 2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x) },
                       { 2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y) } };
    memcpy(q, m, sizeof(m));
}

// a = Q diag(d) Q^T, exactly symmetric.
static void compose(rng *r, const double d[3], double a[3][3])
{
    double q[3][3];
    random_rotation(r, q);
    for (int i = 0; i < 3; i++) {
        for (int j = i; j < 3; j++) {
            double s = 0;
            for (int k = 0; k < 3; k++) {
                s += q[i][k] * d[k] * q[j][k];
            }
            a[i][j] = a[j][i] = s;
        }
    }
}

/* Matrix families. */

static void gen_random(rng *r, double a[3][3])
{
    for (int i = 0; i < 3; i++) {
        for (int j = i; j < 3; j++) {
            a[i][j] = a[j][i] = uniform(r, -1, 1);
        }
    }
}

static void gen_two_equal(rng *r, double a[3][3])
{
    double x = uniform(r, -1, 1), y = uniform(r, -1, 1);
    double d[3] = { x, x, y };
    compose(r, d, a);
}

static void gen_three_equal(rng *r, double a[3][3])
{
    double x = uniform(r, -1, 1);
    double d[3] = { x, x, x };
    compose(r, d, a);
}

static void gen_nearly_equal(rng *r, double a[3][3])
{
    double x = uniform(r, -1, 1), delta = pow(10.0, uniform(r, -12, -1));
    double d[3] = { x, x + delta, uniform(r, -1, 1) };
    compose(r, d, a);
}

static void gen_rank1(rng *r, double a[3][3])
{
    double v[3] = { gauss(r), gauss(r), gauss(r) };
    for (int i = 0; i < 3; i++) {
        for (int j = i; j < 3; j++) {
            a[i][j] = a[j][i] = v[i] * v[j];
        }
    }
}

static void gen_rank2(rng *r, double a[3][3])
{
    double u[3] = { gauss(r), gauss(r), gauss(r) }, v[3] = { gauss(r), gauss(r), gauss(r) };
    double sign = uniform(r, -1, 1) < 0 ? -1.0 : 1.0;
    for (int i = 0; i < 3; i++) {
        for (int j = i; j < 3; j++) {
            a[i][j] = a[j][i] = u[i] * u[j] + sign * v[i] * v[j];
        }
    }
}

static void gen_diagonal(rng *r, double a[3][3])
{
    memset(a, 0, 9 * sizeof(double));
    for (int i = 0; i < 3; i++) {
        a[i][i] = uniform(r, -1, 1) < -0.6 ? 0.0 : uniform(r, -1, 1);
    }
}

static void gen_mixed_magnitude(rng *r, double a[3][3])
{
    for (int i = 0; i < 3; i++) {
        for (int j = i; j < 3; j++) {
            double sign = uniform(r, -1, 1) < 0 ? -1.0 : 1.0;
            a[i][j] = a[j][i] =
                sign * pow(10.0, uniform(r, 0, 1) < 0.5 ? -8.0 : 8.0) * uniform(r, 0.5, 1.0);
        }
    }
}

static void gen_tiny(rng *r, double a[3][3])
{
    gen_random(r, a);
    for (int i = 0; i < 9; i++) {
        a[i / 3][i % 3] *= 1e-30;
    }
}

static void gen_huge(rng *r, double a[3][3])
{
    gen_random(r, a);
    for (int i = 0; i < 9; i++) {
        a[i / 3][i % 3] *= 1e30;
    }
}

// Centred covariance of 16 points on a plane (dims 2) or a line (dims 1) far from the
// origin, with noise 1e-6 of their spread.
static void covariance_of(rng *r, int dims, double a[3][3])
{
    double q[3][3];
    random_rotation(r, q);
    double origin[3] = { uniform(r, -100, 100), uniform(r, -100, 100), uniform(r, -100, 100) };
    double p[16][3], mean[3] = { 0, 0, 0 };
    for (int k = 0; k < 16; k++) {
        double s = uniform(r, -1, 1), t = dims == 2 ? uniform(r, -1, 1) : 0.0;
        for (int i = 0; i < 3; i++) {
            p[k][i] = origin[i] + s * q[i][0] + t * q[i][1] + 1e-6 * gauss(r);
            mean[i] += p[k][i] / 16;
        }
    }
    for (int i = 0; i < 3; i++) {
        for (int j = i; j < 3; j++) {
            double s = 0;
            for (int k = 0; k < 16; k++) {
                s += (p[k][i] - mean[i]) * (p[k][j] - mean[j]);
            }
            a[i][j] = a[j][i] = s / 16;
        }
    }
}

static void gen_plane_covariance(rng *r, double a[3][3])
{
    covariance_of(r, 2, a);
}

static void gen_line_covariance(rng *r, double a[3][3])
{
    covariance_of(r, 1, a);
}

typedef struct family {
    const char *name;
    void (*make)(rng *r, double a[3][3]);
} family;

static const family families[] = {
    { "random", gen_random },
    { "two equal", gen_two_equal },
    { "three equal", gen_three_equal },
    { "nearly equal", gen_nearly_equal },
    { "rank 1", gen_rank1 },
    { "rank 2", gen_rank2 },
    { "diagonal", gen_diagonal },
    { "1e-8 and 1e8 mixed", gen_mixed_magnitude },
    { "scale 1e-30", gen_tiny },
    { "scale 1e30", gen_huge },
    { "plane covariance", gen_plane_covariance },
    { "line covariance", gen_line_covariance },
};
enum {
    FAMILY_COUNT = sizeof(families) / sizeof(families[0]),
    PER_FAMILY = 4000
};

typedef struct tolerance {
    double eps, value, orth, resid;
} tolerance;

static const tolerance TOL_D = { DBL_EPSILON, 1e-12, 1e-12, 1e-12 };
static const tolerance TOL_F = { (double)FLT_EPSILON, 1e-5, 1e-5, 1e-5 };

// Worst errors seen, each divided by its tolerance (so <= 1 passes).
typedef struct worst {
    double value, orth, resid, space;
} worst;

static void reference(double a[3][3], double w[3], double v[3][3])
{
    double m[9];
    for (int i = 0; i < 9; i++) {
        m[i] = a[i / 3][i % 3];
    }
    lapack_int info = LAPACKE_dsyev(LAPACK_ROW_MAJOR, 'V', 'U', 3, m, 3, w);
    assert_int_equal(info, 0);
    for (int i = 0; i < 3; i++) {
        for (int k = 0; k < 3; k++) {
            v[i][k] = m[k * 3 + i]; // column i is eigenvector i
        }
    }
}

// Checks one decomposition (w, v) of a against LAPACK; updates `seen`.
static void check(double a[3][3], const double w[3], double v[3][3], const tolerance *tol,
                  const char *what, worst *seen)
{
    double wr[3], vr[3][3];
    reference(a, wr, vr);
    double norm = fmax(fabs(wr[0]), fabs(wr[2]));
    for (int i = 0; i < 3; i++) {
        assert_true(isfinite(w[i]));
        for (int k = 0; k < 3; k++) {
            assert_true(isfinite(v[i][k]));
        }
    }
    if (norm == 0) {
        for (int i = 0; i < 3; i++) {
            assert_true(w[i] == 0);
        }
        return;
    }
    worst here = { 0, 0, 0, 0 };
    for (int i = 0; i < 3; i++) {
        here.value = fmax(here.value, fabs(w[i] - wr[i]) / norm / tol->value);
        for (int j = 0; j < 3; j++) {
            double d = v[i][0] * v[j][0] + v[i][1] * v[j][1] + v[i][2] * v[j][2];
            here.orth = fmax(here.orth, fabs(d - (i == j ? 1.0 : 0.0)) / tol->orth);
        }
        double r2 = 0;
        for (int k = 0; k < 3; k++) {
            double av = a[k][0] * v[i][0] + a[k][1] * v[i][1] + a[k][2] * v[i][2];
            double e = (av - w[i] * v[i][k]) / norm; // scaled first: no overflow at 1e300
            r2 += e * e;
        }
        here.resid = fmax(here.resid, sqrt(r2) / tol->resid);
    }
    // Eigenspaces: clusters of reference eigenvalues closer than 1000 eps norm.
    for (int first = 0; first < 3;) {
        int last = first;
        while (last < 2 && wr[last + 1] - wr[last] <= 1000 * tol->eps * norm) {
            last++;
        }
        if (first == 0 && last == 2) {
            break;
        }
        double gap = HUGE_VAL;
        if (first > 0) {
            gap = fmin(gap, wr[first] - wr[first - 1]);
        }
        if (last < 2) {
            gap = fmin(gap, wr[last + 1] - wr[last]);
        }
        double diff2 = 0;
        for (int r = 0; r < 3; r++) {
            for (int c = 0; c < 3; c++) {
                double p = 0, pr = 0;
                for (int i = first; i <= last; i++) {
                    p += v[i][r] * v[i][c];
                    pr += vr[i][r] * vr[i][c];
                }
                diff2 += (p - pr) * (p - pr);
            }
        }
        here.space = fmax(here.space, sqrt(diff2) / (100 * tol->eps * norm / gap));
        first = last + 1;
    }
    if (here.value > 1 || here.orth > 1 || here.resid > 1 || here.space > 1) {
        print_error("%s: a = [%.17g %.17g %.17g; . %.17g %.17g; . . %.17g]\n"
                    "  values %.17g %.17g %.17g, reference %.17g %.17g %.17g\n"
                    "  error / tolerance: value %.3g orth %.3g resid %.3g space %.3g\n",
                    what, a[0][0], a[0][1], a[0][2], a[1][1], a[1][2], a[2][2], w[0], w[1], w[2],
                    wr[0], wr[1], wr[2], here.value, here.orth, here.resid, here.space);
        fail();
    }
    seen->value = fmax(seen->value, here.value);
    seen->orth = fmax(seen->orth, here.orth);
    seen->resid = fmax(seen->resid, here.resid);
    seen->space = fmax(seen->space, here.space);
}

// The solver takes row-major arrays of 9.
static sta_eigen3_path solve_d(double a[3][3], double w[3], double v[3][3])
{
    double flat[9];
    memcpy(flat, a, sizeof(flat));
    return sta_eigen3_sym_d(flat, w, v);
}

static sta_eigen3_path solve_f(float a[3][3], float w[3], float v[3][3])
{
    float flat[9];
    memcpy(flat, a, sizeof(flat));
    return sta_eigen3_sym_f(flat, w, v);
}

static void round_to_float(double a[3][3], float af[3][3], double back[3][3])
{
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++) {
            af[i][j] = (float)a[i][j];
            back[i][j] = (double)af[i][j];
        }
    }
}

static void to_double(const float w[3], float v[3][3], double wd[3], double vd[3][3])
{
    for (int i = 0; i < 3; i++) {
        wd[i] = (double)w[i];
        for (int k = 0; k < 3; k++) {
            vd[i][k] = (double)v[i][k];
        }
    }
}

static void print_worst(const char *solver, const char *name, const worst *s, int analytic,
                        int fallback)
{
    printf("%-7s %-20s worst/tol: value %.2e orth %.2e resid %.2e space %.2e  analytic %d "
           "fallback %d\n",
           solver, name, s->value, s->orth, s->resid, s->space, analytic, fallback);
}

static void double_solver_matches_lapack(void **state)
{
    (void)state;
    rng r = { 1 };
    int analytic_total = 0, fallback_total = 0;
    for (int f = 0; f < FAMILY_COUNT; f++) {
        worst seen = { 0, 0, 0, 0 };
        int counts[4] = { 0, 0, 0, 0 };
        for (int n = 0; n < PER_FAMILY; n++) {
            double a[3][3], w[3], v[3][3];
            families[f].make(&r, a);
            sta_eigen3_path path = solve_d(a, w, v);
            counts[path]++;
            check(a, w, v, &TOL_D, families[f].name, &seen);
        }
        print_worst("double", families[f].name, &seen, counts[1], counts[2]);
        analytic_total += counts[STA_EIGEN3_ANALYTIC];
        fallback_total += counts[STA_EIGEN3_FALLBACK];
        if (strcmp(families[f].name, "random") == 0) {
            assert_true(counts[STA_EIGEN3_ANALYTIC] > PER_FAMILY * 99 / 100);
        }
        if (strcmp(families[f].name, "three equal") == 0) {
            assert_int_equal(counts[STA_EIGEN3_FALLBACK], PER_FAMILY); // Kopp's estimate fires
        }
    }
    assert_true(analytic_total > 0 && fallback_total > 0);
}

static void float_solver_matches_lapack(void **state)
{
    (void)state;
    rng r = { 2 };
    for (int f = 0; f < FAMILY_COUNT; f++) {
        worst seen = { 0, 0, 0, 0 };
        int counts[4] = { 0, 0, 0, 0 };
        for (int n = 0; n < PER_FAMILY; n++) {
            double a[3][3], back[3][3], wd[3], vd[3][3];
            float af[3][3], w[3], v[3][3];
            families[f].make(&r, a);
            round_to_float(a, af, back);
            counts[solve_f(af, w, v)]++;
            to_double(w, v, wd, vd);
            check(back, wd, vd, &TOL_F, families[f].name, &seen);
        }
        print_worst("float", families[f].name, &seen, counts[1], counts[2]);
    }
}

static void jacobi_fallback_matches_lapack(void **state)
{
    (void)state;
    rng r = { 3 };
    for (int f = 0; f < FAMILY_COUNT; f++) {
        worst seen_d = { 0, 0, 0, 0 }, seen_f = { 0, 0, 0, 0 };
        for (int n = 0; n < PER_FAMILY / 4; n++) {
            double a[3][3], back[3][3], w[3], v[3][3];
            float af[3][3], wf[3], vf[3][3];
            families[f].make(&r, a);
            double flat[9];
            float flatf[9];
            memcpy(flat, a, sizeof(flat));
            sta_eigen3_sym_jacobi_d(flat, w, v);
            check(a, w, v, &TOL_D, families[f].name, &seen_d);
            round_to_float(a, af, back);
            memcpy(flatf, af, sizeof(flatf));
            sta_eigen3_sym_jacobi_f(flatf, wf, vf);
            to_double(wf, vf, w, v);
            check(back, w, v, &TOL_F, families[f].name, &seen_f);
        }
        print_worst("jacobi", families[f].name, &seen_d, 0, PER_FAMILY / 4);
        print_worst("jacobif", families[f].name, &seen_f, 0, PER_FAMILY / 4);
    }
}

static void extreme_scales_in_double(void **state)
{
    (void)state;
    rng r = { 4 };
    worst seen = { 0, 0, 0, 0 };
    const double scales[] = { 1e-300, 1e-150, 1e150, 1e300 };
    for (int s = 0; s < 4; s++) {
        for (int n = 0; n < 500; n++) {
            double a[3][3], w[3], v[3][3];
            gen_random(&r, a);
            for (int i = 0; i < 9; i++) {
                a[i / 3][i % 3] *= scales[s];
            }
            solve_d(a, w, v);
            check(a, w, v, &TOL_D, "extreme scale", &seen);
        }
    }
}

static void zero_and_non_finite_matrices(void **state)
{
    (void)state;
    double zero[9] = { 0 }, w[3], v[3][3];
    assert_int_equal(sta_eigen3_sym_d(zero, w, v), STA_EIGEN3_ZERO);
    float zf[9] = { 0 }, wf[3], vf[3][3];
    assert_int_equal(sta_eigen3_sym_f(zf, wf, vf), STA_EIGEN3_ZERO);
    for (int i = 0; i < 3; i++) {
        assert_true(w[i] == 0 && wf[i] == 0);
        for (int k = 0; k < 3; k++) {
            assert_true(v[i][k] == (i == k ? 1.0 : 0.0));
            assert_true(vf[i][k] == (i == k ? 1.0f : 0.0f));
        }
    }
    const double nan = (double)NAN;
    double bad[9] = { 1, nan, 0, nan, 1, 0, 0, 0, 1 };
    assert_int_equal(sta_eigen3_sym_d(bad, w, v), STA_EIGEN3_INVALID);
    bad[1] = bad[3] = 0;
    bad[8] = HUGE_VAL;
    assert_int_equal(sta_eigen3_sym_d(bad, w, v), STA_EIGEN3_INVALID);
    for (int i = 0; i < 3; i++) {
        assert_true(w[i] == 0);
    }
    // Only the upper triangle is read: garbage below the diagonal changes nothing.
    double upper[9] = { 2, 1, 0, nan, 3, 1, nan, nan, 4 };
    double full[9] = { 2, 1, 0, 1, 3, 1, 0, 1, 4 };
    double w2[3], v2[3][3];
    assert_int_equal(sta_eigen3_sym_d(upper, w, v), STA_EIGEN3_ANALYTIC);
    sta_eigen3_sym_d(full, w2, v2);
    assert_memory_equal(w, w2, sizeof(w));
    assert_memory_equal(v, v2, sizeof(v));
}

/* The GLSL twin on llvmpipe. */

static const char *const kernel_source =
    "layout(local_size_x = 64) in;\n"
    "layout(std430, binding = 0) readonly buffer Matrices { float a[]; };\n"
    "layout(std430, binding = 1) writeonly buffer Results { float o[]; };\n"
    "uniform uint u_count;\n"
    "void main()\n"
    "{\n"
    "    uint i = gl_GlobalInvocationID.x;\n"
    "    if (i >= u_count) {\n"
    "        return;\n"
    "    }\n"
    "    uint b = 6u * i;\n"
    "    mat3 m = mat3(a[b], a[b + 1u], a[b + 2u], a[b + 1u], a[b + 3u], a[b + 4u], a[b + 2u],\n"
    "                  a[b + 4u], a[b + 5u]);\n"
    "    vec3 w;\n"
    "    mat3 v;\n"
    "    int path = eig3_sym(m, w, v);\n"
    "    uint c = 16u * i;\n"
    "    o[c] = w.x; o[c + 1u] = w.y; o[c + 2u] = w.z; o[c + 3u] = float(path);\n"
    "    for (int k = 0; k < 3; k++) {\n"
    "        for (int j = 0; j < 3; j++) {\n"
    "            o[c + 4u + 4u * uint(k) + uint(j)] = v[k][j];\n"
    "        }\n"
    "    }\n"
    "}\n";

static const char *find_embedded(const char *name)
{
    for (const sta_shader_source *s = sta_shader_sources; s->name; s++) {
        if (strcmp(s->name, name) == 0) {
            return s->text;
        }
    }
    return NULL;
}

static GLuint build_kernel(void)
{
    const char *library = find_embedded("eigen3.glsl");
    assert_non_null(library);
    const char *parts[] = { "#version 450 core\n", library, kernel_source };
    GLuint shader = glCreateShader(GL_COMPUTE_SHADER);
    glShaderSource(shader, 3, parts, NULL);
    glCompileShader(shader);
    GLint ok = 0;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[2048];
        glGetShaderInfoLog(shader, sizeof(log), NULL, log);
        print_error("eigen3.glsl test kernel: %s\n", log);
        fail();
    }
    GLuint program = glCreateProgram();
    glAttachShader(program, shader);
    glLinkProgram(program);
    glDeleteShader(shader);
    glGetProgramiv(program, GL_LINK_STATUS, &ok);
    assert_true(ok);
    return program;
}

static void glsl_matches_c_float(void **state)
{
    (void)state;
    sta_gl_headless gl = { 0 };
    sta_error err = { 0 };
    assert_int_equal(sta_gl_headless_create(&gl, &err), STA_OK);
    enum {
        PER = 256,
        COUNT = PER * FAMILY_COUNT + 2
    };
    float *in = sta_alloc_array(COUNT * 6, sizeof(float));
    float *out = sta_alloc_array(COUNT * 16, sizeof(float));
    double(*mats)[3][3] = sta_alloc_array(COUNT, sizeof(*mats));
    assert_non_null(in);
    assert_non_null(out);
    assert_non_null(mats);
    rng r = { 5 };
    for (int n = 0; n < COUNT; n++) {
        double a[3][3] = { { 0 } };
        if (n < PER * FAMILY_COUNT) {
            families[n / PER].make(&r, a);
        } else if (n == COUNT - 1) {
            a[0][0] = a[1][1] = a[2][2] = 1; // exactly the identity: no off-diagonal
        }
        float af[3][3];
        round_to_float(a, af, mats[n]);
        const float e[6] = { af[0][0], af[0][1], af[0][2], af[1][1], af[1][2], af[2][2] };
        memcpy(in + 6 * n, e, sizeof(e));
    }
    GLuint buffers[2];
    glCreateBuffers(2, buffers);
    glNamedBufferData(buffers[0], (GLsizeiptr)(COUNT * 6 * sizeof(float)), in, GL_STATIC_DRAW);
    glNamedBufferData(buffers[1], (GLsizeiptr)(COUNT * 16 * sizeof(float)), NULL, GL_STATIC_READ);
    GLuint program = build_kernel();
    glUseProgram(program);
    glUniform1ui(glGetUniformLocation(program, "u_count"), COUNT);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, buffers[0]);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, buffers[1]);
    glDispatchCompute((COUNT + 63) / 64, 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    glGetNamedBufferSubData(buffers[1], 0, (GLsizeiptr)(COUNT * 16 * sizeof(float)), out);
    assert_int_equal(sta_gl_check("eigen3.glsl kernel", &err), STA_OK);

    // Tolerance GLSL vs C float: eigenvalues within 1e-5 norm; eigenvectors of
    // eigenvalues separated by gap agree as projectors within 100 eps norm / gap (the
    // two differ in rounding and in llvmpipe's atan/cos). Both also pass the LAPACK
    // check with the float tolerances.
    worst seen_gl = { 0, 0, 0, 0 };
    double worst_value = 0, worst_space = 0;
    int same_path = 0;
    for (int n = 0; n < COUNT; n++) {
        const float *o = out + 16 * n;
        float af[3][3], wc[3], vc[3][3];
        for (int i = 0; i < 9; i++) {
            af[i / 3][i % 3] = (float)mats[n][i / 3][i % 3];
        }
        int path = (int)solve_f(af, wc, vc);
        same_path += path == (int)o[3];
        double wg[3], vg[3][3], wcd[3], vcd[3][3];
        for (int i = 0; i < 3; i++) {
            wg[i] = (double)o[i];
            for (int k = 0; k < 3; k++) {
                vg[i][k] = (double)o[4 + 4 * i + k];
            }
        }
        check(mats[n], wg, vg, &TOL_F, "glsl", &seen_gl);
        to_double(wc, vc, wcd, vcd);
        double norm = fmax(fabs(wcd[0]), fabs(wcd[2]));
        if (norm == 0) {
            for (int i = 0; i < 3; i++) {
                assert_true(wg[i] == 0);
            }
            continue;
        }
        for (int i = 0; i < 3; i++) {
            double e = fabs(wg[i] - wcd[i]) / norm / 1e-5;
            worst_value = fmax(worst_value, e);
            assert_true(e <= 1.0);
            // A simple eigenvalue (clear of the others by > 1e-3 norm): compare vectors.
            double gap = HUGE_VAL;
            for (int j = 0; j < 3; j++) {
                if (j != i) {
                    gap = fmin(gap, fabs(wcd[j] - wcd[i]));
                }
            }
            if (gap > 1e-3 * norm) {
                double minus = 0, plus = 0; // the sign of an eigenvector is arbitrary
                for (int k = 0; k < 3; k++) {
                    minus += (vg[i][k] - vcd[i][k]) * (vg[i][k] - vcd[i][k]);
                    plus += (vg[i][k] + vcd[i][k]) * (vg[i][k] + vcd[i][k]);
                }
                double diff = sqrt(fmin(minus, plus));
                double s = diff / (100 * (double)FLT_EPSILON * norm / gap);
                worst_space = fmax(worst_space, s);
                if (s > 1.0) {
                    print_error("matrix %d vector %d: gl %g %g %g (path %g) c %g %g %g (path %d) "
                                "values %g %g %g\n",
                                n, i, vg[i][0], vg[i][1], vg[i][2], (double)o[3], vcd[i][0],
                                vcd[i][1], vcd[i][2], path, wcd[0], wcd[1], wcd[2]);
                }
            }
        }
    }
    printf("glsl vs C float over %d matrices: worst value diff/tol %.2e, vector diff/tol %.2e, "
           "same path %d; glsl vs LAPACK worst/tol value %.2e orth %.2e resid %.2e space %.2e\n",
           COUNT, worst_value, worst_space, same_path, seen_gl.value, seen_gl.orth, seen_gl.resid,
           seen_gl.space);
    glDeleteProgram(program);
    glDeleteBuffers(2, buffers);
    sta_free(in);
    sta_free(out);
    sta_free(mats);
    sta_gl_headless_destroy(&gl);
}

static const struct CMUnitTest tests[] = {
    cmocka_unit_test(double_solver_matches_lapack),   cmocka_unit_test(float_solver_matches_lapack),
    cmocka_unit_test(jacobi_fallback_matches_lapack), cmocka_unit_test(extreme_scales_in_double),
    cmocka_unit_test(zero_and_non_finite_matrices),   cmocka_unit_test(glsl_matches_c_float),
};

STA_TEST_MAIN(tests)
