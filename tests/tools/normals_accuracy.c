/* SPDX-License-Identifier: MIT
 * normals_accuracy: the normals of a `strata-convert --normals` scene against the truth
 * of the strata-synth scene it came from (issue 12, bench/normals.sh). Test and bench
 * tooling only: built with the tests, never installed.
 *
 *   normals_accuracy FILE.strata SCENE POINTS [SEED] [ORIGIN] [--border-level L]
 *   normals_accuracy --peer NORMALS.txt SCENE.las SCENE POINTS [SEED] [ORIGIN]
 *
 * The second form scores another tool's normals: NORMALS.txt holds "nx ny nz" per line
 * in the order of the points of SCENE.las (CloudCompare, PCL; bench/normals.sh).
 *
 * --by-material (street): groups by the truth surface's material (synth.h's
 * sta_synth_material: a tree's trunk and its leaf clusters apart) instead of the class.
 *
 * SCENE, POINTS, SEED (default 1) and ORIGIN (default utm) as given to strata-synth,
 * with its default noise. Truth: sphere radial; planes +z; nested the box face or inner
 * sphere of the point's user_data (primitive id); street the surface the scanner's ray
 * meets near the point (scanner at the point's GPS time, raycast within 0.1 m of the
 * point's range; points with no such surface, e.g. on glass, are left out), per class.
 *
 * Prints per group: points, median and p95 of the unoriented angle error (degrees), the
 * share oriented like the truth (analytic: outward; street: towards the scanner), the
 * same two angles for points near octree node borders (within 3 radii of a node face of
 * levels 1 to --border-level L, default 3: chunk borders when the chunks are nodes of
 * level L or above, as in a 20 M street's 8 chunks) and away from them, and the median
 * radius over the expected mean distance to the K = 10 nearest neighbours of uniform
 * points at the scene's density (analytic scenes).
 */
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/alloc.h"
#include "format/strata_reader.h"
#include "io/cloud.h"
#include "synth/synth.h"

#define DEG             (180.0 / 3.14159265358979323846)
#define BORDER_RADII    3.0 /* a point within this many of its radii of a face is "border" */
#define STREET_WINDOW_M 0.1
#define MAX_GROUPS      256

typedef struct group {
    float *err, *err_border, *err_inner, *radius;
    size_t n, n_border, n_inner, cap, oriented;
} group;

static int grow(group *g)
{
    if (g->n < g->cap) {
        return 1;
    }
    size_t cap = g->cap ? 2 * g->cap : 4096;
    float **arrays[] = { &g->err, &g->err_border, &g->err_inner, &g->radius };
    for (int i = 0; i < 4; i++) {
        float *p = realloc(*arrays[i], cap * sizeof(float));
        if (!p) {
            return 0;
        }
        *arrays[i] = p;
    }
    g->cap = cap;
    return 1;
}

static int compare_float(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return x < y ? -1 : x > y;
}

static double quantile(float *v, size_t n, double q)
{
    if (n == 0) {
        return NAN;
    }
    qsort(v, n, sizeof(float), compare_float);
    return v[(size_t)(q * (double)(n - 1))];
}

// Expected mean distance to the k nearest of uniform points at density rho (per m^2):
// E r_j = Gamma(j + 1/2) / (Gamma(j) sqrt(pi rho)).
static double expected_radius(int k, double rho)
{
    double sum = 0.0;
    for (int j = 1; j <= k; j++) {
        sum += exp(lgamma(j + 0.5) - lgamma(j)) / sqrt(3.14159265358979323846 * rho);
    }
    return sum / k;
}

static double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

// Distance (m) to the nearest node face of levels 1..levels along any axis.
static double border_distance(const sta_strata_info *info, const sta_point *p, int levels)
{
    double best = INFINITY;
    const int32_t xyz[3] = { p->X, p->Y, p->Z };
    for (int a = 0; a < 3; a++) {
        int64_t rel = (int64_t)xyz[a] - info->geometry.root_corner[a];
        int log2 = info->geometry.root_size_log2[a];
        int64_t cell = (int64_t)1 << (log2 > levels ? log2 - levels : 0);
        int64_t below = rel % cell, above = cell - below;
        double d = (double)(below < above ? below : above) * info->geometry.grid.scale[a];
        best = d < best ? d : best;
    }
    return best;
}

static group groups[MAX_GROUPS];
static bool by_material; /* --by-material: street groups by the truth's material */

// Adds one point's error to its group; false when the truth has no surface for it.
static bool account(const sta_synth_params *params, sta_synth_scene *scene,
                    const sta_synth_georef *georef, const sta_strata_info *info, int border_level,
                    const sta_point *p, const float normal[3], float radius)
{
    sta_error err = { 0 };
    double local[3] = {
        (double)(p->X - georef->origin_steps[0]) * georef->grid.scale[0],
        (double)(p->Y - georef->origin_steps[1]) * georef->grid.scale[1],
        (double)(p->Z - georef->origin_steps[2]) * georef->grid.scale[2],
    };
    double truth[3] = { 0, 0, 1 }, seen_from[3] = { 0, 0, 0 };
    int g = 0;
    if (params->kind == STA_SYNTH_SPHERE) {
        double l = sqrt(dot3(local, local));
        for (int a = 0; a < 3; a++) {
            truth[a] = local[a] / l;
        }
    } else if (params->kind == STA_SYNTH_NESTED) {
        unsigned id = p->user_data;
        if (id < 6) {
            truth[2] = 0.0;
            truth[id / 2] = id % 2 ? 1.0 : -1.0;
        } else {
            double l = sqrt(dot3(local, local));
            for (int a = 0; a < 3; a++) {
                truth[a] = local[a] / l;
            }
        }
        g = id < 6 ? 0 : 1;
    } else if (params->kind == STA_SYNTH_STREET) {
        double s[3];
        if (sta_synth_scene_scanner_position(scene, p->gps_time, s, &err) != STA_OK) {
            return false;
        }
        double d[3] = { local[0] - s[0], local[1] - s[1], local[2] - s[2] };
        double range = sqrt(dot3(d, d));
        for (int a = 0; a < 3; a++) {
            d[a] /= range;
        }
        sta_synth_hit hit;
        if (!sta_synth_scene_raycast_ex(scene, s, d, fmax(0.0, range - STREET_WINDOW_M),
                                        range + STREET_WINDOW_M, 0, &hit)) {
            return false;
        }
        double flip = dot3(hit.normal, d) > 0.0 ? -1.0 : 1.0; // towards the scanner
        for (int a = 0; a < 3; a++) {
            truth[a] = flip * hit.normal[a];
            seen_from[a] = -d[a];
        }
        g = by_material ? hit.material : p->classification;
    }
    (void)seen_from;
    group *gr = &groups[g];
    if (!grow(gr)) {
        fprintf(stderr, "normals_accuracy: out of memory\n");
        exit(1);
    }
    const double n[3] = { normal[0], normal[1], normal[2] };
    double c = dot3(n, truth);
    // atan2 of cross and dot: acos near 1 would floor the error at ~0.03 degrees.
    double x[3] = { n[1] * truth[2] - n[2] * truth[1], n[2] * truth[0] - n[0] * truth[2],
                    n[0] * truth[1] - n[1] * truth[0] };
    double e = atan2(sqrt(dot3(x, x)), fabs(c)) * DEG;
    gr->err[gr->n] = (float)e;
    gr->radius[gr->n] = radius;
    gr->n++;
    gr->oriented += c > 0.0;
    if (info && border_distance(info, p, border_level) < BORDER_RADII * (double)radius) {
        gr->err_border[gr->n_border++] = (float)e;
    } else {
        gr->err_inner[gr->n_inner++] = (float)e;
    }
    return true;
}

int main(int argc, char **argv)
{
    int border_level = 3;
    const char *peer = NULL, *peer_las = NULL; // --peer NORMALS.txt LAS: another tool's normals
    if (argc >= 4 && strcmp(argv[1], "--peer") == 0) {
        peer = argv[2];
        peer_las = argv[3];
        argv += 2;
        argc -= 2;
    }
    if (argc >= 2 && strcmp(argv[argc - 1], "--by-material") == 0) {
        by_material = true;
        argc--;
    }
    if (argc >= 3 && strcmp(argv[argc - 2], "--border-level") == 0) {
        border_level = atoi(argv[argc - 1]);
        argc -= 2;
    }
    if (argc < 4 || strcmp(argv[1], "--help") == 0) {
        fprintf(stderr, "usage: normals_accuracy [--peer NORMALS.txt SCENE.las] FILE.strata SCENE "
                        "POINTS [SEED] [ORIGIN] [--border-level L] [--by-material]\n");
        return argc >= 2 && strcmp(argv[1], "--help") == 0 ? 0 : 2;
    }
    sta_synth_params params = { .seed = argc > 4 ? strtoull(argv[4], NULL, 10) : 1,
                                .point_count = strtoull(argv[3], NULL, 10),
                                .origin = STA_SYNTH_ORIGIN_UTM };
    if (!sta_synth_kind_from_name(argv[2], &params.kind) || params.kind == STA_SYNTH_MESH) {
        fprintf(stderr, "normals_accuracy: scene '%s' is not sphere, planes, nested or street\n",
                argv[2]);
        return 2;
    }
    if (argc > 5) {
        params.origin = strcmp(argv[5], "zero")
                            ? strcmp(argv[5], "ecef") ? STA_SYNTH_ORIGIN_UTM : STA_SYNTH_ORIGIN_ECEF
                            : STA_SYNTH_ORIGIN_ZERO;
    }
    sta_synth_georef georef;
    sta_synth_georef_init(params.origin, &georef);
    sta_error err = { 0 };
    sta_synth_scene *scene = NULL;
    if (params.kind == STA_SYNTH_STREET &&
        sta_synth_scene_create(&params, &scene, &err) != STA_OK) {
        fprintf(stderr, "normals_accuracy: %s\n", err.message);
        return 1;
    }
    sta_strata_reader *reader = NULL;
    sta_strata_decoder *decoder = NULL;
    const sta_strata_info *info = NULL;
    if (!peer && (sta_strata_open(argv[1], NULL, &reader, &err) != STA_OK ||
                  sta_strata_decoder_create(&decoder, &err) != STA_OK)) {
        fprintf(stderr, "normals_accuracy: %s\n", err.message);
        return 1;
    }
    info = reader ? sta_strata_reader_info(reader) : NULL;
    if (info && !(info->layout.attributes & STA_STRATA_ATTR_SPLAT)) {
        fprintf(stderr, "normals_accuracy: %s has no normals (convert with --normals)\n", argv[1]);
        return 1;
    }
    uint64_t missed = 0;
    if (peer) { // points from the LAS, normals from the peer's text file, in the same order
        sta_cloud_reader *las = NULL;
        if (sta_cloud_open(peer_las, NULL, &las, &err) != STA_OK) {
            fprintf(stderr, "normals_accuracy: %s\n", err.message);
            return 1;
        }
        FILE *f = fopen(peer, "r");
        if (!f) {
            fprintf(stderr, "normals_accuracy: %s: cannot open\n", peer);
            return 1;
        }
        sta_point_batch batch = { 0 };
        sta_point_batch_init(&batch, 65536, sta_cloud_reader_info(las)->extra_size, &err);
        while (sta_cloud_read(las, &batch, &err) == STA_OK && batch.count > 0) {
            for (size_t i = 0; i < batch.count; i++) {
                float n[3];
                if (fscanf(f, "%f %f %f", &n[0], &n[1], &n[2]) != 3) {
                    fprintf(stderr, "normals_accuracy: %s: fewer normals than points\n", peer);
                    return 1;
                }
                missed += !account(&params, scene, &georef, NULL, 0, &batch.points[i], n, 0.0f);
            }
        }
        sta_point_batch_release(&batch);
        fclose(f);
        sta_cloud_close(las);
    } else {
        for (uint32_t node = 0; node < info->node_count; node++) {
            sta_strata_points pts;
            if (sta_strata_decode_node(reader, node, decoder, &pts, &err) != STA_OK) {
                fprintf(stderr, "normals_accuracy: %s\n", err.message);
                return 1;
            }
            for (size_t i = 0; i < pts.count; i++) {
                const sta_point *p = &pts.points[i];
                missed +=
                    !account(&params, scene, &georef, info, border_level, p, p->normal, p->radius);
            }
        }
    }
    // Density for the radius check (analytic scenes, m^2 of surface per point).
    double area = params.kind == STA_SYNTH_SPHERE   ? 4.0 * 3.14159265358979 * 100.0
                  : params.kind == STA_SYNTH_PLANES ? 500.0
                  : params.kind == STA_SYNTH_NESTED ? 600.0 + 4.0 * 3.14159265358979 * 9.0
                                                    : 0.0;
    double expect = area > 0 ? expected_radius(10, (double)params.point_count / area) : (double)NAN;
    printf("| scene | group | points | median deg | p95 deg | oriented | border median / p95 | "
           "inside median / p95 | radius / expected |\n|---|---|---|---|---|---|---|---|---|\n");
    for (int g = 0; g < MAX_GROUPS; g++) {
        group *gr = &groups[g];
        if (gr->n == 0) {
            continue;
        }
        char name[32];
        if (params.kind == STA_SYNTH_STREET) {
            snprintf(name, sizeof(name), by_material ? "material %d" : "class %d", g);
        } else if (params.kind == STA_SYNTH_NESTED) {
            snprintf(name, sizeof(name), "%s", g ? "inner sphere" : "box");
        } else {
            snprintf(name, sizeof(name), "all");
        }
        size_t n = gr->n;
        double rmed = peer ? (double)NAN : quantile(gr->radius, n, 0.5);
        printf(
            "| %s | %s | %zu | %.3f | %.3f | %.1f %% | %.3f / %.3f | %.3f / %.3f | %.2f |\n",
            argv[2], name, n, quantile(gr->err, n, 0.5), quantile(gr->err, n, 0.95),
            100.0 * (double)gr->oriented / (double)n, quantile(gr->err_border, gr->n_border, 0.5),
            quantile(gr->err_border, gr->n_border, 0.95), quantile(gr->err_inner, gr->n_inner, 0.5),
            quantile(gr->err_inner, gr->n_inner, 0.95), rmed / expect);
        free(gr->err);
        free(gr->err_border);
        free(gr->err_inner);
        free(gr->radius);
    }
    if (missed) {
        printf("(%" PRIu64
               " points without a truth surface within %.1f m of their range: left out)\n",
               missed, STREET_WINDOW_M);
    }
    if (reader) {
        sta_strata_decoder_destroy(decoder);
        sta_strata_close(reader);
    }
    sta_synth_scene_destroy(scene);
    return 0;
}
