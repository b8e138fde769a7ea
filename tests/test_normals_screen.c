/* SPDX-License-Identifier: MIT
 * Screen-space normals (LD, PD, PC, TI and smoothing) on llvmpipe against their CPU
 * twin, and both against analytic truth: planes, spheres, silhouettes, hard cases.
 *
 * Tolerances: shader vs twin: identical validity masks and at most 0.05 degree between
 * normals. Truth: a noise-free plane within 0.5 degree mean for every method and
 * scheme; with depth noise TI-25 beats LD (mean error) on the plane and the sphere.
 */
#include "test_support.h"

#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/alloc.h"
#include "render/gl.h"
#include "render/gl_image.h"
#include "render/pass_normals_screen.h"
#include "render/ref/normals_screen_ref.h"

/* Every configuration: LD once, then PD, PC, TI with each scheme. */
typedef struct config {
    int method, samples;
} config;

static const config configs[] = {
    { STA_NORMALS_SCREEN_LD, 9 },  { STA_NORMALS_SCREEN_PD, 5 },  { STA_NORMALS_SCREEN_PD, 9 },
    { STA_NORMALS_SCREEN_PD, 17 }, { STA_NORMALS_SCREEN_PD, 25 }, { STA_NORMALS_SCREEN_PC, 5 },
    { STA_NORMALS_SCREEN_PC, 9 },  { STA_NORMALS_SCREEN_PC, 17 }, { STA_NORMALS_SCREEN_PC, 25 },
    { STA_NORMALS_SCREEN_TI, 5 },  { STA_NORMALS_SCREEN_TI, 9 },  { STA_NORMALS_SCREEN_TI, 17 },
    { STA_NORMALS_SCREEN_TI, 25 },
};
enum {
    CONFIG_COUNT = sizeof(configs) / sizeof(configs[0])
};

/* Random numbers (splitmix64). */
static uint64_t rng_state = 1;

static double uniform01(void)
{
    uint64_t z = (rng_state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return (double)((z ^ (z >> 31)) >> 11) * 0x1.0p-53;
}

static double gauss(void)
{
    double u = fmax(uniform01(), 1e-12), v = uniform01();
    return sqrt(-2.0 * log(u)) * cos(6.283185307179586 * v);
}

/* Scenes: analytic surfaces unprojected at pixel centres (as the unproject pass does),
 * with the true normal per pixel. */

typedef enum surface_kind {
    SURFACE_NONE,
    SURFACE_PLANE,
    SURFACE_SPHERE
} surface_kind;

typedef struct surface {
    surface_kind kind;
    double normal[3];   /* plane: normal facing the camera (any length) */
    double point[3];    /* plane: a point on it; sphere: the centre */
    double radius;      /* sphere */
    int x0, y0, x1, y1; /* only pixels in [x0, x1) x [y0, y1) see it (x1 = 0: all) */
} surface;

typedef struct scene {
    sta_view_params view;
    sta_image position; /* 4 channels */
    sta_image truth;    /* 4 channels: true normal, w = 1 where a surface was hit */
} scene;

static void normalise3(double v[3])
{
    double n = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    v[0] /= n, v[1] /= n, v[2] /= n;
}

static double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

// Distance along the ray (depth, since dir.z = -1) to the surface, or INFINITY.
static double hit(const surface *s, const double dir[3], int x, int y, double normal[3])
{
    if (s->x1 > 0 && (x < s->x0 || x >= s->x1 || y < s->y0 || y >= s->y1)) {
        return HUGE_VAL;
    }
    if (s->kind == SURFACE_PLANE) {
        memcpy(normal, s->normal, sizeof(s->normal));
        normalise3(normal);
        double t = dot3(normal, s->point) / dot3(normal, dir);
        return t > 0 ? t : HUGE_VAL;
    }
    if (s->kind == SURFACE_SPHERE) {
        double a = dot3(dir, dir), b = dot3(dir, s->point);
        double c = dot3(s->point, s->point) - s->radius * s->radius;
        double disc = b * b - a * c;
        if (disc < 0) {
            return HUGE_VAL;
        }
        double t = (b - sqrt(disc)) / a;
        for (int i = 0; i < 3; i++) {
            normal[i] = (t * dir[i] - s->point[i]) / s->radius;
        }
        return t > 0 ? t : HUGE_VAL;
    }
    return HUGE_VAL;
}

// Renders the nearest of `count` surfaces; depth noise: t *= 1 + noise * gauss.
static void render(scene *sc, int w, int h, const surface *surfaces, int count, double noise)
{
    sc->view = (sta_view_params){ w, h, 0.9f, 0.05f, 0.1f }; // s0: default limit 0.5 m
    assert_int_equal(sta_image_init(&sc->position, w, h, 4, NULL), STA_OK);
    assert_int_equal(sta_image_init(&sc->truth, w, h, 4, NULL), STA_OK);
    double tan_y = tan(0.45), tan_x = tan_y * w / h;
    for (int y = 0; y < h; y++) {
        for (int x = 0; x < w; x++) {
            double dir[3] = { ((x + 0.5) / w * 2 - 1) * tan_x, ((y + 0.5) / h * 2 - 1) * tan_y,
                              -1 };
            double best = HUGE_VAL, normal[3] = { 0, 0, 0 };
            for (int i = 0; i < count; i++) {
                double n[3];
                double t = hit(&surfaces[i], dir, x, y, n);
                if (t < best) {
                    best = t;
                    memcpy(normal, n, sizeof(n));
                }
            }
            if (!isfinite(best)) {
                continue;
            }
            double t = best * (1 + noise * gauss());
            float *p = sta_image_at(&sc->position, x, y);
            float *n = sta_image_at(&sc->truth, x, y);
            for (int i = 0; i < 3; i++) {
                p[i] = (float)(t * dir[i]);
                n[i] = (float)normal[i];
            }
            p[3] = n[3] = 1.0f;
        }
    }
}

static void scene_release(scene *sc)
{
    sta_image_release(&sc->position);
    sta_image_release(&sc->truth);
}

static const surface tilted_plane = {
    SURFACE_PLANE, { 0.3, 0.5, 1.0 }, { 0, 0, -6 }, 0, 0, 0, 0, 0
};
static const surface sphere = { SURFACE_SPHERE, { 0, 0, 0 }, { 0.2, -0.1, -3.5 }, 1.5, 0, 0, 0, 0 };

/* Running the shader. */

typedef struct gl_fixture {
    sta_gl_headless gl;
    sta_normals_screen_pass pass;
} gl_fixture;

static void gl_start(gl_fixture *f)
{
    memset(f, 0, sizeof(*f));
    sta_error err = { 0 };
    assert_int_equal(sta_gl_headless_create(&f->gl, &err), STA_OK);
    if (sta_normals_screen_pass_init(&f->pass, &err) != STA_OK) {
        print_error("%s\n", err.message);
        fail();
    }
}

static void gl_stop(gl_fixture *f)
{
    sta_normals_screen_pass_release(&f->pass);
    sta_gl_headless_destroy(&f->gl);
}

// Estimates normals on the GPU (and smooths them when `smooth`) into `out`.
static void run_gl(gl_fixture *f, const sta_view_params *view,
                   const sta_normals_screen_params *params, const sta_image *position, int smooth,
                   sta_image *out)
{
    sta_error err = { 0 };
    GLuint pos_tex, normal_tex, smooth_tex;
    int w = position->width, h = position->height;
    assert_int_equal(sta_gl_texture_from_image(position, &pos_tex, &err), STA_OK);
    assert_int_equal(sta_gl_texture_create(w, h, 4, 1, &normal_tex, &err), STA_OK);
    assert_int_equal(sta_gl_texture_create(w, h, 4, 1, &smooth_tex, &err), STA_OK);
    assert_int_equal(sta_normals_screen_pass_run(&f->pass, view, params, pos_tex, normal_tex, &err),
                     STA_OK);
    if (smooth) {
        assert_int_equal(sta_normals_smooth_pass_run(&f->pass, view, params, pos_tex, normal_tex,
                                                     smooth_tex, &err),
                         STA_OK);
    }
    assert_int_equal(sta_gl_texture_to_image(smooth ? smooth_tex : normal_tex, 0, 4, out, &err),
                     STA_OK);
    assert_int_equal(sta_gl_check("normals", &err), STA_OK);
    GLuint textures[3] = { pos_tex, normal_tex, smooth_tex };
    glDeleteTextures(3, textures);
}

static void run_ref(const sta_view_params *view, const sta_normals_screen_params *params,
                    const sta_image *position, int smooth, sta_image *out)
{
    sta_error err = { 0 };
    assert_int_equal(sta_image_init(out, position->width, position->height, 4, &err), STA_OK);
    assert_int_equal(sta_normals_screen_ref(view, params, position, out, &err), STA_OK);
    if (smooth) {
        sta_image smoothed;
        assert_int_equal(sta_image_init(&smoothed, position->width, position->height, 4, &err),
                         STA_OK);
        assert_int_equal(sta_normals_smooth_ref(view, params, position, out, &smoothed, &err),
                         STA_OK);
        sta_image_release(out);
        *out = smoothed;
    }
}

/* Angles. */

// Degrees between two vectors, robust near 0 (atan2 of |a x b| and a . b).
static double angle_deg(const float *a, const float *b)
{
    double ad[3] = { (double)a[0], (double)a[1], (double)a[2] };
    double bd[3] = { (double)b[0], (double)b[1], (double)b[2] };
    double c[3] = { ad[1] * bd[2] - ad[2] * bd[1], ad[2] * bd[0] - ad[0] * bd[2],
                    ad[0] * bd[1] - ad[1] * bd[0] };
    return atan2(sqrt(dot3(c, c)), dot3(ad, bd)) * 57.29577951308232;
}

// Every output pixel is finite, either all zero (w = 0) or a unit normal facing the
// camera (w = 1).
static void assert_well_formed(const sta_image *normals, const sta_image *position)
{
    for (int y = 0; y < normals->height; y++) {
        for (int x = 0; x < normals->width; x++) {
            const float *n = sta_image_at(normals, x, y);
            const float *p = sta_image_at(position, x, y);
            for (int i = 0; i < 4; i++) {
                assert_true(isfinite(n[i]));
            }
            if (n[3] == 0.0f) {
                assert_true(n[0] == 0.0f && n[1] == 0.0f && n[2] == 0.0f);
                continue;
            }
            assert_true(n[3] == 1.0f);
            assert_true(p[3] > 0.0f);
            double nd[3] = { (double)n[0], (double)n[1], (double)n[2] };
            double pd[3] = { (double)p[0], (double)p[1], (double)p[2] };
            assert_true(fabs(sqrt(dot3(nd, nd)) - 1.0) < 1e-5);
            assert_true(dot3(nd, pd) <= 0.0);
        }
    }
}

typedef struct stats {
    double mean, median, p95, max, coverage;
} stats;

static int compare_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

// Angle error statistics over pixels where truth exists (and `mask`, if given, is set);
// coverage = fraction of those with an estimate.
static stats error_stats(const sta_image *est, const sta_image *truth, const unsigned char *mask)
{
    int n = truth->width * truth->height, total = 0, count = 0;
    double *errors = sta_alloc_array((size_t)n, sizeof(double));
    assert_non_null(errors);
    double sum = 0;
    for (int i = 0; i < n; i++) {
        const float *t = truth->data + 4 * i, *e = est->data + 4 * i;
        if (t[3] == 0.0f || (mask && !mask[i])) {
            continue;
        }
        total++;
        if (e[3] > 0.0f) {
            errors[count] = angle_deg(e, t);
            sum += errors[count++];
        }
    }
    stats s = { 0, 0, 0, 0, total ? (double)count / total : 0 };
    if (count > 0) {
        qsort(errors, (size_t)count, sizeof(double), compare_double);
        s.mean = sum / count;
        s.median = errors[count / 2];
        s.p95 = errors[(int)(0.95 * (count - 1))];
        s.max = errors[count - 1];
    }
    sta_free(errors);
    return s;
}

/* Tests. */

// Shader and twin agree: same validity, normals within 0.05 degree.
static void compare_gl_and_twin(gl_fixture *f, const scene *sc,
                                const sta_normals_screen_params *params, int smooth,
                                const char *what, double *worst)
{
    sta_image got, expected;
    run_gl(f, &sc->view, params, &sc->position, smooth, &got);
    run_ref(&sc->view, params, &sc->position, smooth, &expected);
    assert_well_formed(&expected, &sc->position);
    assert_well_formed(&got, &sc->position);
    int valid = 0;
    for (int i = 0; i < got.width * got.height; i++) {
        const float *g = got.data + 4 * i, *e = expected.data + 4 * i;
        if (g[3] != e[3]) {
            print_error("%s %s-%d smooth %d: pixel (%d, %d) valid %g in the shader, %g in the "
                        "twin\n",
                        what, sta_normals_screen_method_name(params->method), params->samples,
                        smooth, i % got.width, i / got.width, (double)g[3], (double)e[3]);
            fail();
        }
        if (e[3] > 0.0f) {
            double a = angle_deg(g, e);
            valid++;
            *worst = fmax(*worst, a);
            if (a > 0.05) {
                print_error("%s %s-%d: pixel (%d, %d) differs by %g degree\n", what,
                            sta_normals_screen_method_name(params->method), params->samples,
                            i % got.width, i / got.width, a);
                fail();
            }
        }
    }
    if (valid == 0) {
        print_error("%s %s-%d: no normal at all\n", what,
                    sta_normals_screen_method_name(params->method), params->samples);
        fail();
    }
    sta_image_release(&got);
    sta_image_release(&expected);
}

static void shader_matches_twin(void **state)
{
    (void)state;
    gl_fixture f;
    gl_start(&f);
    rng_state = 7;
    // Scenes: a noisy plane and sphere (odd sizes: partial workgroups), a near patch in
    // front of a wall, and random holes (w = 0) punched into a noisy sphere.
    scene scenes[4];
    const char *names[4] = { "noisy plane", "noisy sphere", "silhouette", "holes" };
    render(&scenes[0], 37, 23, &tilted_plane, 1, 0.002);
    render(&scenes[1], 61, 47, &sphere, 1, 0.002);
    surface near_far[2] = { { SURFACE_PLANE, { 0.4, -0.2, 1.0 }, { 0, 0, -3 }, 0, 20, 12, 44, 36 },
                            { SURFACE_PLANE, { 0, 0, 1 }, { 0, 0, -20 }, 0, 0, 0, 0, 0 } };
    render(&scenes[2], 64, 48, near_far, 2, 0.0);
    render(&scenes[3], 45, 33, &sphere, 1, 0.001);
    for (int i = 0; i < 45 * 33; i++) {
        if (uniform01() < 0.3) {
            scenes[3].position.data[4 * i + 3] = 0.0f;
        }
    }
    double worst = 0;
    for (int s = 0; s < 4; s++) {
        for (int c = 0; c < CONFIG_COUNT; c++) {
            for (int smooth = 0; smooth < 2; smooth++) {
                sta_normals_screen_params params = { configs[c].method, configs[c].samples, 0.5f };
                compare_gl_and_twin(&f, &scenes[s], &params, smooth, names[s], &worst);
            }
        }
    }
    // Default parameters (TI-9, 5 * s0) and no distance limit.
    sta_normals_screen_params defaults = { 0, 0, 0.0f }, unlimited = { 0, 25, -1.0f };
    compare_gl_and_twin(&f, &scenes[2], &defaults, 0, "silhouette default", &worst);
    compare_gl_and_twin(&f, &scenes[2], &unlimited, 1, "silhouette unlimited", &worst);
    printf("shader vs twin: worst angle difference %.2e degree\n", worst);
    for (int s = 0; s < 4; s++) {
        scene_release(&scenes[s]);
    }
    gl_stop(&f);
}

static void error_tables_plane_and_sphere(void **state)
{
    (void)state;
    gl_fixture f;
    gl_start(&f);
    rng_state = 11;
    // Depth noise 0.2 % (about a quarter of a pixel footprint at these depths).
    scene scenes[4];
    render(&scenes[0], 160, 120, &tilted_plane, 1, 0.0);
    render(&scenes[1], 160, 120, &tilted_plane, 1, 0.002);
    render(&scenes[2], 160, 120, &sphere, 1, 0.0);
    render(&scenes[3], 160, 120, &sphere, 1, 0.002);
    const char *names[4] = { "plane", "plane+noise", "sphere", "sphere+noise" };
    stats table[CONFIG_COUNT][4], smoothed[CONFIG_COUNT][4];
    printf("angle error in degrees (mean / median / p95, coverage %%), 160x120, shader on "
           "llvmpipe, max distance 0.5 m\n%-6s",
           "method");
    for (int s = 0; s < 4; s++) {
        printf(" | %-28s", names[s]);
    }
    printf("\n");
    for (int c = 0; c < CONFIG_COUNT; c++) {
        sta_normals_screen_params params = { configs[c].method, configs[c].samples, 0.5f };
        for (int smooth = 0; smooth < 2; smooth++) {
            printf("%s-%-2d%s", sta_normals_screen_method_name(params.method), params.samples,
                   smooth ? "+s" : "  ");
            for (int s = 0; s < 4; s++) {
                sta_image est;
                run_gl(&f, &scenes[s].view, &params, &scenes[s].position, smooth, &est);
                assert_well_formed(&est, &scenes[s].position);
                stats st = error_stats(&est, &scenes[s].truth, NULL);
                (smooth ? smoothed : table)[c][s] = st;
                printf(" | %6.3f %6.3f %6.3f %5.1f%%", st.mean, st.median, st.p95,
                       100 * st.coverage);
                sta_image_release(&est);
            }
            printf("\n");
        }
    }
    int ld = 0, ti25 = CONFIG_COUNT - 1;
    for (int c = 0; c < CONFIG_COUNT; c++) {
        assert_true(table[c][0].mean < 0.5);      // exact plane: every method
        assert_true(table[c][0].coverage > 0.99); // and everywhere
        assert_true(smoothed[c][0].mean < 0.5);
        assert_true(table[c][2].median < 1.0); // sphere: curvature only
    }
    assert_true(table[ti25][1].mean < table[ld][1].mean); // noise: TI-25 beats LD
    assert_true(table[ti25][3].mean < table[ld][3].mean);
    assert_true(smoothed[ld][1].mean < table[ld][1].mean); // smoothing helps noisy LD
    for (int s = 0; s < 4; s++) {
        scene_release(&scenes[s]);
    }
    gl_stop(&f);
}

// A tilted patch 17 m in front of a wall: with the distance limit, the patch's pixels
// next to the silhouette keep their normals; without it the wall drags them away.
static void max_distance_keeps_silhouettes(void **state)
{
    (void)state;
    gl_fixture f;
    gl_start(&f);
    surface near_far[2] = { { SURFACE_PLANE, { 0.4, -0.2, 1.0 }, { 0, 0, -3 }, 0, 30, 20, 66, 52 },
                            { SURFACE_PLANE, { 0, 0, 1 }, { 0, 0, -20 }, 0, 0, 0, 0, 0 } };
    scene sc;
    render(&sc, 96, 72, near_far, 2, 0.0);
    // Edge pixels: on the patch, within 3 pixels (Chebyshev) of the wall.
    unsigned char *edge = sta_calloc(96 * 72, 1);
    assert_non_null(edge);
    int edge_count = 0;
    for (int y = 20; y < 52; y++) {
        for (int x = 30; x < 66; x++) {
            edge[y * 96 + x] = x < 33 || x >= 63 || y < 23 || y >= 49;
            edge_count += edge[y * 96 + x];
        }
    }
    printf("silhouette pixels (%d): max error in degrees, coverage\n", edge_count);
    for (int c = 0; c < CONFIG_COUNT; c++) {
        sta_normals_screen_params limited = { configs[c].method, configs[c].samples, 0.5f };
        sta_normals_screen_params unlimited = { configs[c].method, configs[c].samples, -1.0f };
        sta_image a, b;
        run_gl(&f, &sc.view, &limited, &sc.position, 0, &a);
        run_gl(&f, &sc.view, &unlimited, &sc.position, 0, &b);
        stats with = error_stats(&a, &sc.truth, edge), without = error_stats(&b, &sc.truth, edge);
        printf("%s-%-2d limit 0.5 m: max %7.3f cover %5.1f%% | no limit: max %7.3f mean %7.3f\n",
               sta_normals_screen_method_name(limited.method), limited.samples, with.max,
               100 * with.coverage, without.max, without.mean);
        assert_true(with.max < 2.0);
        assert_true(without.max > 10.0);
        // Everywhere, except that the 5-sample schemes (diagonals only) see a single
        // patch sample at the patch's 4 corners: too few for a normal.
        double expected = limited.samples == 5 ? (edge_count - 4.0) / edge_count : 1.0;
        assert_true(fabs(with.coverage - expected) < 1e-9);
        sta_image_release(&a);
        sta_image_release(&b);
    }
    sta_free(edge);
    scene_release(&sc);
    gl_stop(&f);
}

// Runs every configuration (and smoothing) through the shader and the twin on
// `position`, checks that both are well formed and agree, and returns the number of
// valid normals the twin found summed over configurations.
static int run_all(gl_fixture *f, const sta_view_params *view, const sta_image *position,
                   float max_distance_m)
{
    int valid = 0;
    for (int c = 0; c < CONFIG_COUNT; c++) {
        sta_normals_screen_params params = { configs[c].method, configs[c].samples,
                                             max_distance_m };
        for (int smooth = 0; smooth < 2; smooth++) {
            sta_image got, expected;
            run_gl(f, view, &params, position, smooth, &got);
            run_ref(view, &params, position, smooth, &expected);
            assert_well_formed(&got, position);
            assert_well_formed(&expected, position);
            for (int i = 0; i < got.width * got.height; i++) {
                assert_true(got.data[4 * i + 3] == expected.data[4 * i + 3]);
                valid += expected.data[4 * i + 3] > 0.0f;
            }
            sta_image_release(&got);
            sta_image_release(&expected);
        }
    }
    return valid;
}

static void hard_cases(void **state)
{
    (void)state;
    gl_fixture f;
    gl_start(&f);
    sta_image img;
    // Empty frames, including 1x1 and 2x1.
    const int sizes[3][2] = { { 1, 1 }, { 2, 1 }, { 29, 17 } };
    for (int s = 0; s < 3; s++) {
        sta_view_params view = { sizes[s][0], sizes[s][1], 0.9f, 0.05f, 0.01f };
        assert_int_equal(sta_image_init(&img, sizes[s][0], sizes[s][1], 4, NULL), STA_OK);
        assert_int_equal(run_all(&f, &view, &img, 0.5f), 0);
        // One isolated point (in the middle, or the only pixel): no normal.
        float *p = sta_image_at(&img, sizes[s][0] / 2, sizes[s][1] / 2);
        p[0] = 0.01f, p[1] = 0.02f, p[2] = -4.0f, p[3] = 1.0f;
        assert_int_equal(run_all(&f, &view, &img, 0.5f), 0);
        assert_int_equal(run_all(&f, &view, &img, -1.0f), 0);
        sta_image_release(&img);
    }
    // One row of points (collinear neighbourhoods in screen and in 3D): no normal
    // anywhere, TI's rank-1 covariance included.
    sta_view_params view = { 20, 9, 0.9f, 0.05f, 0.01f };
    assert_int_equal(sta_image_init(&img, 20, 9, 4, NULL), STA_OK);
    for (int x = 0; x < 20; x++) {
        float *p = sta_image_at(&img, x, 4);
        p[0] = 0.1f * (float)x, p[1] = 0.0f, p[2] = -5.0f, p[3] = 1.0f;
    }
    assert_int_equal(run_all(&f, &view, &img, -1.0f), 0);
    // Every pixel valid but all positions on one 3D line: no normal anywhere.
    for (int y = 0; y < 9; y++) {
        for (int x = 0; x < 20; x++) {
            float *p = sta_image_at(&img, x, y);
            float t = 1.0f + 0.05f * (float)x + 0.013f * (float)y;
            p[0] = 0.2f * t, p[1] = -0.1f * t, p[2] = -3.0f * t, p[3] = 1.0f;
        }
    }
    assert_int_equal(run_all(&f, &view, &img, -1.0f), 0);
    // NaN and infinite positions marked valid are never used as neighbours.
    float *bad = sta_image_at(&img, 5, 5);
    bad[0] = NAN;
    bad = sta_image_at(&img, 9, 3);
    bad[2] = -INFINITY;
    run_all(&f, &view, &img, -1.0f);
    sta_image_release(&img);

    // Very far (1e5 m, no limit) and at the near plane (0.05 m): still accurate.
    const double depths[2] = { 1e5, 0.05 };
    for (int d = 0; d < 2; d++) {
        surface plane = tilted_plane;
        plane.point[2] = -depths[d];
        scene sc;
        render(&sc, 33, 21, &plane, 1, 0.0);
        assert_true(run_all(&f, &sc.view, &sc.position, -1.0f) > 0);
        for (int c = 0; c < CONFIG_COUNT; c++) {
            sta_normals_screen_params params = { configs[c].method, configs[c].samples, -1.0f };
            sta_image est;
            run_ref(&sc.view, &params, &sc.position, 0, &est);
            stats st = error_stats(&est, &sc.truth, NULL);
            assert_true(st.coverage > 0.99 && st.max < 0.5);
            sta_image_release(&est);
        }
        scene_release(&sc);
    }
    gl_stop(&f);
}

static void parameters_resolve_and_reject(void **state)
{
    (void)state;
    sta_view_params view = { 10, 10, 0.9f, 0.05f, 0.02f };
    sta_normals_screen_params p = { 0, 0, 0.0f };
    sta_error err = { 0 };
    assert_int_equal(sta_normals_screen_params_check(&p, &err), STA_OK);
    sta_normals_screen_params_defaults(&p);
    assert_int_equal(p.method, STA_NORMALS_SCREEN_TI);
    assert_int_equal(p.samples, 9);
    assert_true(p.max_distance_m == 0.0f); // derived from the view where used
    assert_true(sta_normals_screen_max_distance2(&view, &p) == (5.0f * 0.02f) * (5.0f * 0.02f));
    view.s0 = 0.0f;
    assert_true(sta_normals_screen_max_distance2(&view, &p) == FLT_MAX);
    p.max_distance_m = -1.0f;
    view.s0 = 0.02f;
    assert_true(sta_normals_screen_max_distance2(&view, &p) == FLT_MAX);
    // Set fields stay as they are.
    sta_normals_screen_params set = { STA_NORMALS_SCREEN_PD, 17, 0.5f };
    sta_normals_screen_params_defaults(&set);
    assert_true(set.method == STA_NORMALS_SCREEN_PD && set.samples == 17 &&
                set.max_distance_m == 0.5f);
    p.samples = 7;
    assert_int_equal(sta_normals_screen_params_check(&p, &err), STA_ERR_ARG);
    assert_non_null(strstr(err.message, "samples 7"));
    p.samples = 25;
    p.method = 9;
    assert_int_equal(sta_normals_screen_params_check(&p, &err), STA_ERR_ARG);
    p.method = STA_NORMALS_SCREEN_PD;
    p.max_distance_m = NAN;
    assert_int_equal(sta_normals_screen_params_check(&p, &err), STA_ERR_ARG);
    // The twin rejects mismatched images.
    sta_image position, normal;
    assert_int_equal(sta_image_init(&position, 4, 3, 4, NULL), STA_OK);
    assert_int_equal(sta_image_init(&normal, 3, 4, 4, NULL), STA_OK);
    p.max_distance_m = 1.0f;
    assert_int_equal(sta_normals_screen_ref(&view, &p, &position, &normal, &err), STA_ERR_ARG);
    assert_int_equal(sta_normals_smooth_ref(&view, &p, &position, &position, &position, &err),
                     STA_ERR_ARG);
    sta_image_release(&position);
    sta_image_release(&normal);
}

static const struct CMUnitTest tests[] = {
    cmocka_unit_test(shader_matches_twin),
    cmocka_unit_test(error_tables_plane_and_sphere),
    cmocka_unit_test(max_distance_keeps_silhouettes),
    cmocka_unit_test(hard_cases),
    cmocka_unit_test(parameters_resolve_and_reject),
};

STA_TEST_MAIN(tests)
