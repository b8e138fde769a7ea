/* SPDX-License-Identifier: MIT
 * Ground model for height-above-ground colouring. */
#include "stream/ground.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/alloc.h"

enum {
    MAX_CELLS_PER_AXIS = 1024,
    POINTS_PER_CELL = 8,
    CLASS_GROUND = 2,
    RELAX_ITERATIONS = 100 /* enough for holes of about 100 cells */
};

static size_t cell_index(const sta_ground *g, double x, double y)
{
    long cx = (long)floor((x - g->min[0]) / g->cell_m);
    long cy = (long)floor((y - g->min[1]) / g->cell_m);
    cx = cx < 0 ? 0 : (cx >= g->width ? g->width - 1 : cx);
    cy = cy < 0 ? 0 : (cy >= g->height ? g->height - 1 : cy);
    return (size_t)cy * (size_t)g->width + (size_t)cx;
}

// Lowest (erode) or highest (dilate) value within `radius` cells of each cell, square
// window, separable: rows then columns; empty cells (NaN) are skipped.
static sta_status morph(sta_ground *g, int radius, bool lowest_wins, sta_error *err)
{
    size_t n = (size_t)g->width * (size_t)g->height;
    float *tmp = sta_alloc_array(n, sizeof(float));
    if (!tmp) {
        return sta_fail(err, STA_ERR_NOMEM, "out of memory for the ground model");
    }
    for (int pass = 0; pass < 2; pass++) {
        const float *src = pass == 0 ? g->z : tmp;
        float *dst = pass == 0 ? tmp : g->z;
        for (int y = 0; y < g->height; y++) {
            for (int x = 0; x < g->width; x++) {
                float best = NAN;
                for (int d = -radius; d <= radius; d++) {
                    int sx = pass == 0 ? x + d : x, sy = pass == 0 ? y : y + d;
                    if (sx < 0 || sy < 0 || sx >= g->width || sy >= g->height) {
                        continue;
                    }
                    float v = src[(size_t)sy * (size_t)g->width + (size_t)sx];
                    if (!isnan(v) && (isnan(best) || (lowest_wins ? v < best : v > best))) {
                        best = v;
                    }
                }
                dst[(size_t)y * (size_t)g->width + (size_t)x] = best;
            }
        }
    }
    sta_free(tmp);
    return STA_OK;
}

// Smooths the filled cells (mask) towards the mean of their 4-neighbours by successive
// over-relaxation: the harmonic fill, which reproduces a planar slope exactly.
static void relax(sta_ground *g, const uint8_t *was_empty)
{
    const double omega = 1.8;
    for (int iteration = 0; iteration < RELAX_ITERATIONS; iteration++) {
        for (int y = 0; y < g->height; y++) {
            for (int x = 0; x < g->width; x++) {
                size_t i = (size_t)y * (size_t)g->width + (size_t)x;
                if (!was_empty[i]) {
                    continue;
                }
                double sum = 0.0;
                int count = 0;
                if (x > 0) {
                    sum += (double)g->z[i - 1], count++;
                }
                if (x + 1 < g->width) {
                    sum += (double)g->z[i + 1], count++;
                }
                if (y > 0) {
                    sum += (double)g->z[i - (size_t)g->width], count++;
                }
                if (y + 1 < g->height) {
                    sum += (double)g->z[i + (size_t)g->width], count++;
                }
                if (count > 0) {
                    double z = (double)g->z[i];
                    g->z[i] = (float)(z + omega * (sum / count - z));
                }
            }
        }
    }
}

// Empty cells (NaN) take the mean of their filled 8-neighbours, ring by ring, then are
// relaxed towards the harmonic fill.
static sta_status fill_empty(sta_ground *g, sta_error *err)
{
    size_t n = (size_t)g->width * (size_t)g->height;
    float *next = sta_alloc_array(n, sizeof(float));
    uint8_t *was_empty = sta_alloc_array(n, 1);
    if (!next || !was_empty) {
        sta_free(next);
        sta_free(was_empty);
        return sta_fail(err, STA_ERR_NOMEM, "out of memory for the ground model");
    }
    for (size_t i = 0; i < n; i++) {
        was_empty[i] = isnan(g->z[i]);
    }
    bool any_empty = true;
    while (any_empty) {
        any_empty = false;
        bool filled_some = false;
        memcpy(next, g->z, n * sizeof(float));
        for (int y = 0; y < g->height; y++) {
            for (int x = 0; x < g->width; x++) {
                size_t i = (size_t)y * (size_t)g->width + (size_t)x;
                if (!isnan(g->z[i])) {
                    continue;
                }
                double sum = 0.0;
                int count = 0;
                for (int dy = -1; dy <= 1; dy++) {
                    for (int dx = -1; dx <= 1; dx++) {
                        int sx = x + dx, sy = y + dy;
                        if (sx < 0 || sy < 0 || sx >= g->width || sy >= g->height) {
                            continue;
                        }
                        float v = g->z[(size_t)sy * (size_t)g->width + (size_t)sx];
                        if (!isnan(v)) {
                            sum += (double)v;
                            count++;
                        }
                    }
                }
                if (count > 0) {
                    next[i] = (float)(sum / count);
                    filled_some = true;
                } else {
                    any_empty = true;
                }
            }
        }
        memcpy(g->z, next, n * sizeof(float));
        if (any_empty && !filled_some) {
            break; // cannot happen with at least one filled cell; guards the loop
        }
    }
    relax(g, was_empty);
    sta_free(next);
    sta_free(was_empty);
    return STA_OK;
}

static int compare_floats(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return x < y ? -1 : (x > y ? 1 : 0);
}

// The ramp's top: the 98th percentile of the heights above the model, within 2..100 m.
static sta_status height_span(sta_ground *g, const sta_ground_sample *s, size_t count,
                              sta_error *err)
{
    float *heights = sta_alloc_array(count, sizeof(float));
    if (!heights) {
        return sta_fail(err, STA_ERR_NOMEM, "out of memory for the ground model");
    }
    for (size_t i = 0; i < count; i++) {
        heights[i] = (float)(s[i].xyz[2] - sta_ground_at(g, s[i].xyz[0], s[i].xyz[1]));
    }
    qsort(heights, count, sizeof(float), compare_floats);
    double p98 = (double)heights[(size_t)((double)(count - 1) * 0.98)];
    g->height_span_m = fmax(2.0, fmin(100.0, p98));
    sta_free(heights);
    return STA_OK;
}

sta_status sta_ground_from_samples(const sta_ground_sample *s, size_t count, sta_ground *g,
                                   sta_error *err)
{
    memset(g, 0, sizeof(*g));
    if (count == 0) {
        return sta_fail(err, STA_ERR_ARG, "no points to find the ground from");
    }
    double lo[3] = { INFINITY, INFINITY, INFINITY }, hi[3] = { -INFINITY, -INFINITY, -INFINITY };
    size_t ground = 0;
    for (size_t i = 0; i < count; i++) {
        for (int a = 0; a < 3; a++) {
            lo[a] = fmin(lo[a], s[i].xyz[a]);
            hi[a] = fmax(hi[a], s[i].xyz[a]);
        }
        ground += s[i].classification == CLASS_GROUND;
    }
    g->from_class = ground * 100 >= count;
    g->sampled = count;
    g->z_origin = lo[2];
    g->min[0] = lo[0];
    g->min[1] = lo[1];
    double area = fmax(hi[0] - lo[0], 1e-3) * fmax(hi[1] - lo[1], 1e-3);
    double used = (double)(g->from_class ? ground : count);
    g->cell_m = sqrt(area * POINTS_PER_CELL / used);
    double longest = fmax(hi[0] - lo[0], hi[1] - lo[1]);
    g->cell_m = fmax(g->cell_m, longest / MAX_CELLS_PER_AXIS);
    g->cell_m = fmax(g->cell_m, 1e-3);
    g->width = (int)fmin(MAX_CELLS_PER_AXIS, floor((hi[0] - lo[0]) / g->cell_m) + 1);
    g->height = (int)fmin(MAX_CELLS_PER_AXIS, floor((hi[1] - lo[1]) / g->cell_m) + 1);
    size_t cells = (size_t)g->width * (size_t)g->height;
    g->z = sta_alloc_array(cells, sizeof(float));
    if (!g->z) {
        return sta_fail(err, STA_ERR_NOMEM, "out of memory for %zu ground cells", cells);
    }
    for (size_t i = 0; i < cells; i++) {
        g->z[i] = NAN;
    }
    for (size_t i = 0; i < count; i++) {
        if (g->from_class && s[i].classification != CLASS_GROUND) {
            continue;
        }
        size_t c = cell_index(g, s[i].xyz[0], s[i].xyz[1]);
        float z = (float)(s[i].xyz[2] - g->z_origin);
        g->z[c] = isnan(g->z[c]) || z < g->z[c] ? z : g->z[c];
    }
    sta_status status = STA_OK;
    if (!g->from_class) {
        // A morphological opening: erosion removes what is narrower than the window,
        // dilation then restores the terrain's slopes.
        int radius = (int)ceil(0.5 * STA_GROUND_OPENING_M / g->cell_m);
        radius = radius < 1 ? 1 : radius;
        status = morph(g, radius, true, err);
        if (status == STA_OK) {
            status = morph(g, radius, false, err);
        }
    }
    if (status == STA_OK) {
        status = fill_empty(g, err);
    }
    if (status == STA_OK) {
        status = height_span(g, s, count, err);
    }
    if (status != STA_OK) {
        sta_ground_release(g);
    }
    return status;
}

sta_status sta_ground_build(const sta_strata_reader *reader, const sta_lod_tree *tree,
                            sta_ground *out, sta_error *err)
{
    memset(out, 0, sizeof(*out));
    const sta_strata_info *info = sta_strata_reader_info(reader);
    // Nodes level by level from the root: the top of the tree is a uniform subsample.
    uint64_t total = 0;
    uint8_t max_level = 0;
    for (uint32_t i = 0; i < tree->count; i++) {
        max_level = tree->nodes[i].level > max_level ? tree->nodes[i].level : max_level;
    }
    int last_level = 0;
    for (int level = 0; level <= max_level; level++) {
        uint64_t at_level = 0;
        for (uint32_t i = 0; i < tree->count; i++) {
            at_level += tree->nodes[i].level == level ? tree->nodes[i].point_count : 0;
        }
        if (level > 0 && total + at_level > STA_GROUND_SAMPLE_POINTS) {
            break;
        }
        total += at_level;
        last_level = level;
    }
    sta_ground_sample *samples = sta_alloc_array(total ? total : 1, sizeof(*samples));
    sta_strata_decoder *decoder = NULL;
    sta_status status = samples ? sta_strata_decoder_create(&decoder, err)
                                : sta_fail(err, STA_ERR_NOMEM,
                                           "%s: out of memory for the "
                                           "ground model",
                                           info->path);
    size_t n = 0;
    const sta_grid *grid = &info->geometry.grid;
    for (uint32_t i = 0; i < tree->count && status == STA_OK; i++) {
        if (tree->nodes[i].level > last_level) {
            continue;
        }
        sta_strata_points points;
        status = sta_strata_decode_node(reader, i, decoder, &points, err);
        for (size_t k = 0; status == STA_OK && k < points.count && n < total; k++) {
            const sta_point *p = &points.points[k];
            samples[n].xyz[0] = sta_grid_apply(grid, 0, p->X);
            samples[n].xyz[1] = sta_grid_apply(grid, 1, p->Y);
            samples[n].xyz[2] = sta_grid_apply(grid, 2, p->Z);
            samples[n].classification = p->classification;
            n++;
        }
    }
    if (status == STA_OK) {
        status = sta_ground_from_samples(samples, n, out, err);
    }
    sta_strata_decoder_destroy(decoder);
    sta_free(samples);
    return status;
}

double sta_ground_at(const sta_ground *g, double x, double y)
{
    // Cell centres are at min + (i + 0.5) cell.
    double fx = (x - g->min[0]) / g->cell_m - 0.5, fy = (y - g->min[1]) / g->cell_m - 0.5;
    fx = fmax(0.0, fmin(g->width - 1.0, fx));
    fy = fmax(0.0, fmin(g->height - 1.0, fy));
    int x0 = (int)floor(fx), y0 = (int)floor(fy);
    int x1 = x0 + 1 < g->width ? x0 + 1 : x0, y1 = y0 + 1 < g->height ? y0 + 1 : y0;
    double tx = fx - x0, ty = fy - y0;
    size_t w = (size_t)g->width;
    double z00 = (double)g->z[(size_t)y0 * w + (size_t)x0];
    double z10 = (double)g->z[(size_t)y0 * w + (size_t)x1];
    double z01 = (double)g->z[(size_t)y1 * w + (size_t)x0];
    double z11 = (double)g->z[(size_t)y1 * w + (size_t)x1];
    double top = z00 * (1 - tx) + z10 * tx, bottom = z01 * (1 - tx) + z11 * tx;
    return g->z_origin + top * (1 - ty) + bottom * ty;
}

void sta_ground_release(sta_ground *g)
{
    sta_free(g->z);
    memset(g, 0, sizeof(*g));
}
