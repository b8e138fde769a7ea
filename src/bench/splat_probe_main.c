/* SPDX-License-Identifier: MIT
 * strata-splat-probe: the splat pass's three ways of drawing (render/pass_splats.h),
 * instanced quads, a geometry shader and pulled quads, timed on the same synthetic
 * splats in memory, interleaved A B C A B C, headless (EGL). It needs no converted file: a wall of
 * splats facing the camera with jittered normals and a sphere in front, radius = the lattice
 * spacing (each pixel covered about pi times, as splats with the mean neighbour
 * distance as radius are), split into nodes of 8 m as the converter would.
 * bench/splat_methods.sh runs it; docs/BENCHMARKS.md has the figures.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/alloc.h"
#include "core/cli.h"
#include "core/clock.h"
#include "render/bindings.h"
#include "render/gl.h"
#include "render/gpu_cache.h"
#include "render/image_io.h"
#include "render/pass_splats.h"
#include "stream/gpu_points.h"
#include "stream/gpu_splats.h"

#define STEP_M          (1.0 / 1024.0)
#define WALL_DISTANCE_M 30.0
#define NODE_EDGE_M     8.0

enum {
    METHODS = 3 /* instanced, geometry, pulled */
};

static const char usage_text[] =
    "usage: strata-splat-probe [options]\n"
    "\n"
    "Times the splat pass's three methods (instanced, geometry shader, pulled) on the same\n"
    "synthetic splats in memory (a wall and a sphere), interleaved, headless; prints the\n"
    "median frame time of each and their ratios.\n";

typedef struct probe_args {
    uint64_t points;
    int width_px, height_px;
    int rounds, repeat;
    double scale;
    const char *out_png; /* the last instanced frame, or NULL */
} probe_args;

typedef struct probe_scene {
    uint32_t node_count;
    uint8_t **bytes; /* per node: points then splat records */
    uint32_t *counts;
    sta_gpu_node_frame *frames;
    uint32_t *draw;
} probe_scene;

static uint32_t rng_state = 12345;

static double uniform(void)
{
    rng_state = rng_state * 1664525u + 1013904223u;
    return (double)(rng_state >> 8) / 16777216.0;
}

// The wall (y, z within the view at x = WALL_DISTANCE_M) and a sphere of radius 5 m at
// 15 m, camera at the origin looking along +X: a fifth of the points on the sphere.
static void splat_at(uint64_t i, uint64_t count, const sta_camera *c, double p[3], double n[3],
                     double *radius)
{
    double half_h = WALL_DISTANCE_M * tan(0.5 * c->fov_y);
    double half_w = half_h * c->width_px / c->height_px;
    uint64_t sphere_count = count / 5, wall_count = count - sphere_count;
    if (i < wall_count) {
        // A jittered lattice, as a scan line pattern is: radius = the spacing.
        double spacing = sqrt(4.0 * half_w * half_h / (double)wall_count);
        uint64_t columns = (uint64_t)ceil(2.0 * half_w / spacing);
        *radius = spacing;
        p[0] = WALL_DISTANCE_M + 0.05 * uniform();
        p[1] = -half_w + spacing * ((double)(i % columns) + 0.3 * uniform());
        p[2] = -half_h + spacing * ((double)(i / columns) + 0.3 * uniform());
        double tilt = 0.2 * (uniform() - 0.5);
        n[0] = -cos(tilt), n[1] = sin(tilt), n[2] = 0.0;
        return;
    }
    double k = (double)(i - wall_count), sphere_n = (double)sphere_count;
    double z = 1.0 - (2.0 * k + 1.0) / sphere_n, r = sqrt(1.0 - z * z);
    double phi = k * M_PI * (3.0 - sqrt(5.0));
    n[0] = r * cos(phi), n[1] = r * sin(phi), n[2] = z;
    const double centre[3] = { 15.0, 0.0, 0.0 };
    for (int a = 0; a < 3; a++) {
        p[a] = centre[a] + 5.0 * n[a];
    }
    *radius = 5.0 * sqrt(4.0 * M_PI / sphere_n);
}

// Splits the splats into nodes of NODE_EDGE_M cubes (the grid from (0, -64, -64)).
static sta_status build(const probe_args *a, const sta_camera *camera, probe_scene *out,
                        sta_error *err)
{
    enum {
        GRID = 16
    }; // 16 x 16 x 16 cells of 8 m
    const double origin[3] = { 0.0, -64.0, -64.0 };
    uint32_t *cell_count = sta_calloc(GRID * GRID * GRID, sizeof(uint32_t));
    uint32_t *cell_of = sta_alloc_array(a->points, sizeof(uint32_t));
    double(*pos)[3] = sta_alloc_array(a->points, sizeof(*pos));
    float(*normal)[3] = sta_alloc_array(a->points, sizeof(*normal));
    float *radius = sta_alloc_array(a->points, sizeof(float));
    if (!cell_count || !cell_of || !pos || !normal || !radius) {
        return sta_fail(err, STA_ERR_NOMEM, "out of memory for %llu splats",
                        (unsigned long long)a->points);
    }
    for (uint64_t i = 0; i < a->points; i++) {
        double n[3], r;
        splat_at(i, a->points, camera, pos[i], n, &r);
        int cell[3];
        for (int k = 0; k < 3; k++) {
            normal[i][k] = (float)n[k];
            cell[k] = (int)floor((pos[i][k] - origin[k]) / NODE_EDGE_M);
            cell[k] = cell[k] < 0 ? 0 : cell[k] >= GRID ? GRID - 1 : cell[k];
        }
        radius[i] = (float)r;
        cell_of[i] = (uint32_t)((cell[2] * GRID + cell[1]) * GRID + cell[0]);
        cell_count[cell_of[i]]++;
    }
    memset(out, 0, sizeof(*out));
    out->bytes = sta_calloc(GRID * GRID * GRID, sizeof(uint8_t *));
    out->counts = sta_calloc(GRID * GRID * GRID, sizeof(uint32_t));
    out->frames = sta_calloc(GRID * GRID * GRID, sizeof(sta_gpu_node_frame));
    out->draw = sta_calloc(GRID * GRID * GRID, sizeof(uint32_t));
    uint32_t *node_of_cell = sta_calloc(GRID * GRID * GRID, sizeof(uint32_t));
    if (!out->bytes || !out->counts || !out->frames || !out->draw || !node_of_cell) {
        return sta_fail(err, STA_ERR_NOMEM, "out of memory for the nodes");
    }
    for (uint32_t c = 0; c < GRID * GRID * GRID; c++) {
        if (!cell_count[c]) {
            continue;
        }
        uint32_t node = out->node_count++;
        node_of_cell[c] = node;
        out->bytes[node] = sta_alloc_array(cell_count[c], STA_GPU_POINT_SIZE + STA_GPU_SPLAT_SIZE);
        if (!out->bytes[node]) {
            return sta_fail(err, STA_ERR_NOMEM, "out of memory for a node");
        }
        const uint32_t xyz[3] = { c % GRID, (c / GRID) % GRID, c / (GRID * GRID) };
        for (int k = 0; k < 3; k++) {
            out->frames[node].corner[k] = origin[k] + NODE_EDGE_M * xyz[k];
            out->frames[node].step[k] = STEP_M;
        }
        out->draw[node] = node;
    }
    for (uint64_t i = 0; i < a->points; i++) {
        uint32_t node = node_of_cell[cell_of[i]];
        uint32_t count = cell_count[cell_of[i]], k = out->counts[node]++;
        uint8_t *p = out->bytes[node] + (size_t)k * STA_GPU_POINT_SIZE;
        memset(p, 0, STA_GPU_POINT_SIZE);
        for (int d = 0; d < 3; d++) {
            long q = lround((pos[i][d] - out->frames[node].corner[d]) / STEP_M);
            q = q < 0 ? 0 : q > 65535 ? 65535 : q;
            p[2 * d] = (uint8_t)(q & 0xFF);
            p[2 * d + 1] = (uint8_t)(q >> 8);
        }
        p[8] = 200, p[9] = 180, p[10] = 150, p[12] = p[13] = 1;
        sta_gpu_splats_encode((const float(*)[3])normal[i], &radius[i], 1,
                              out->bytes[node] + (size_t)count * STA_GPU_POINT_SIZE +
                                  (size_t)k * STA_GPU_SPLAT_SIZE);
    }
    sta_free(cell_count);
    sta_free(cell_of);
    sta_free(pos);
    sta_free(normal);
    sta_free(radius);
    sta_free(node_of_cell);
    return STA_OK;
}

static int compare(const void *x, const void *y)
{
    double a = *(const double *)x, b = *(const double *)y;
    return a < b ? -1 : a > b;
}

static double median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof(*v), compare);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

static sta_status probe(const probe_args *a, sta_error *err)
{
    sta_camera camera = { .fov_y = 60.0 * M_PI / 180.0,
                          .near_m = 0.1,
                          .width_px = a->width_px,
                          .height_px = a->height_px };
    probe_scene scene;
    sta_status s = build(a, &camera, &scene, err);
    if (s != STA_OK) {
        return s;
    }
    sta_gpu_cache cache;
    s = sta_gpu_cache_init(&cache, scene.node_count, err);
    if (s != STA_OK) {
        return s;
    }
    sta_gpu_cache_enable_splats(&cache);
    for (uint32_t i = 0; i < scene.node_count && s == STA_OK; i++) {
        sta_stream_upload u = { i, scene.counts[i], scene.bytes[i] };
        sta_stream_frame frame = { .upload = &u, .upload_count = 1 };
        s = sta_gpu_cache_apply(&cache, &frame, err);
    }
    const int methods[METHODS] = { STA_SPLAT_INSTANCED, STA_SPLAT_GEOMETRY, STA_SPLAT_PULLED };
    sta_pass_splats passes[METHODS] = { 0 };
    for (int m = 0; m < METHODS && s == STA_OK; m++) {
        s = sta_pass_splats_init(&passes[m], methods[m], err);
    }
    sta_render_target target = { 0 };
    if (s == STA_OK) {
        s = sta_render_target_resize(&target, a->width_px, a->height_px, err);
    }
    double *times[METHODS];
    for (int m = 0; m < METHODS; m++) {
        times[m] = sta_alloc_array((size_t)(a->rounds * a->repeat), sizeof(double));
        if (s == STA_OK && !times[m]) {
            s = sta_fail(err, STA_ERR_NOMEM, "out of memory");
        }
    }
    sta_geometry_colours colours = { .mode = STA_COLOUR_RGB,
                                     .elevation_span = 1,
                                     .intensity_scale = 1.0f };
    sta_splat_options options = { .scale = (float)a->scale };
    char renderer[256];
    printf("renderer: %s\n", sta_gl_describe(renderer, sizeof(renderer)));
    printf("%llu splats in %u nodes, %dx%d\n", (unsigned long long)a->points, scene.node_count,
           a->width_px, a->height_px);
    // One warm-up frame each, then rounds of `repeat` frames, methods alternating.
    for (int r = -1; r < a->rounds && s == STA_OK; r++) {
        for (int m = 0; m < METHODS && s == STA_OK; m++) {
            options.method = methods[m];
            for (int k = 0; k < (r < 0 ? 1 : a->repeat) && s == STA_OK; k++) {
                sta_gl_finish();
                double t0 = sta_clock_ms();
                s = sta_pass_splats_draw(&passes[m], &options, &camera, &colours, &cache,
                                         scene.frames, scene.draw, scene.node_count, 0.0f, &target,
                                         err);
                sta_gl_finish();
                if (r >= 0) {
                    times[m][r * a->repeat + k] = sta_clock_ms() - t0;
                }
            }
        }
    }
    if (s == STA_OK && a->out_png) {
        options.method = STA_SPLAT_INSTANCED;
        s = sta_pass_splats_draw(&passes[0], &options, &camera, &colours, &cache, scene.frames,
                                 scene.draw, scene.node_count, 0.0f, &target, err);
        uint8_t *rgba = s == STA_OK ? sta_alloc_array((size_t)a->width_px * 4, a->height_px) : NULL;
        if (rgba) {
            sta_render_target_read_rgba(&target, rgba);
            s = sta_png_write_rgba(a->out_png, rgba, a->width_px, a->height_px, err);
            sta_free(rgba);
        }
    }
    if (s == STA_OK) {
        double ms[METHODS];
        for (int m = 0; m < METHODS; m++) {
            ms[m] = median(times[m], a->rounds * a->repeat);
        }
        printf("medians of %d frames each (%d rounds): instanced %.1f ms, geometry %.1f ms, "
               "pulled %.1f ms; instanced / geometry %.2f, pulled / geometry %.2f\n",
               a->rounds * a->repeat, a->rounds, ms[0], ms[1], ms[2], ms[0] / ms[1], ms[2] / ms[1]);
    }
    for (int m = 0; m < METHODS; m++) {
        sta_free(times[m]);
        sta_pass_splats_release(&passes[m]);
    }
    sta_render_target_release(&target);
    sta_gpu_cache_release(&cache);
    for (uint32_t i = 0; i < scene.node_count; i++) {
        sta_free(scene.bytes[i]);
    }
    sta_free(scene.bytes);
    sta_free(scene.counts);
    sta_free(scene.frames);
    sta_free(scene.draw);
    return s;
}

int main(int argc, char **argv)
{
    probe_args a = { .points = 1000000,
                     .width_px = 1920,
                     .height_px = 1080,
                     .rounds = 3,
                     .repeat = 3,
                     .scale = STA_SPLAT_DEFAULT_SCALE };
    const sta_cli_option options[] = {
        { .name = "points",
          .kind = STA_CLI_COUNT,
          .dest = &a.points,
          .metavar = "N",
          .count_min = 1000,
          .count_max = 200000000,
          .flags = STA_CLI_SUFFIX,
          .help = "splats drawn" },
        { .name = "width",
          .kind = STA_CLI_INT,
          .dest = &a.width_px,
          .int_min = 16,
          .int_max = 16384,
          .help = "viewport width, pixels" },
        { .name = "height",
          .kind = STA_CLI_INT,
          .dest = &a.height_px,
          .int_min = 16,
          .int_max = 16384,
          .help = "viewport height, pixels" },
        { .name = "rounds",
          .kind = STA_CLI_INT,
          .dest = &a.rounds,
          .int_min = 1,
          .int_max = 1000,
          .help = "rounds of the two methods, alternating" },
        { .name = "repeat",
          .kind = STA_CLI_INT,
          .dest = &a.repeat,
          .int_min = 1,
          .int_max = 1000,
          .help = "frames per method and round" },
        { .name = "out",
          .kind = STA_CLI_STRING,
          .dest = &a.out_png,
          .metavar = "FILE.png",
          .help = "write an instanced frame" },
        { .name = "splat-scale",
          .kind = STA_CLI_DOUBLE,
          .dest = &a.scale,
          .real_min = 0.0,
          .real_max = 1e3,
          .flags = STA_CLI_ABOVE_MIN,
          .help = "factor on the radii" },
        { 0 },
    };
    const sta_cli cli = { .program = "strata-splat-probe",
                          .usage = usage_text,
                          .options = options };
    sta_cli_result r;
    int rc = sta_cli_parse_main(&cli, argc, argv, &r);
    if (rc >= 0) {
        return rc;
    }
    if (r.positional_count > 0) {
        return sta_cli_usage_error(&cli, "unexpected argument '%s'", r.positional[0]);
    }
    sta_error err = { 0 };
    sta_gl_headless gl = { 0 };
    sta_status s = sta_gl_headless_create(&gl, &err);
    if (s == STA_OK) {
        s = probe(&a, &err);
        sta_gl_headless_destroy(&gl);
    }
    if (s != STA_OK) {
        fprintf(stderr, "strata-splat-probe: %s\n", err.message);
        return 1;
    }
    return 0;
}
