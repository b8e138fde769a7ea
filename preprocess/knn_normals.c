/* SPDX-License-Identifier: MIT
 * Per-chunk kNN normals: a hashed uniform grid, shell search, covariance, eigenvector. */
#include "knn_normals.h"

#include <math.h>
#include <string.h>

#include "core/alloc.h"
#include "core/eigen3.h"
#include "core/octahedral.h"

enum {
    TARGET_PER_CELL = 4, /* points per occupied cell the grid edge is tuned to */
    MAX_SHELLS = 12,     /* a neighbourhood searched no wider gets what it found */
    TUNE_ROUNDS = 4
};
#define CELL_BITS    21 /* per axis in a cell key */
#define EMPTY_KEY    UINT64_MAX
/* l1 <= COLLINEAR * l2: the neighbours lie on a line, no plane to fit. */
#define COLLINEAR    1e-6
/* |n . up| below this: a vertical surface, oriented towards the scene's up-axis line. */
#define VERTICAL_DOT 0.2

typedef struct grid_slot {
    uint64_t key;
    uint32_t start, count;
} grid_slot;

typedef struct knn_grid {
    float (*xyz)[3]; /* all points, metres from the scene's corner */
    float (*sorted)[3];
    uint32_t *cell_of; /* slot of each point */
    grid_slot *slots;
    size_t slot_mask;
    float min[3];
    float edge;
} knn_grid;

size_t sta_normals_memory_bytes(size_t points)
{
    size_t slots = 1;
    while (slots < 2 * points + 2) {
        slots <<= 1;
    }
    return points * (2 * 3 * sizeof(float) + sizeof(uint32_t)) + slots * sizeof(grid_slot);
}

static uint64_t cell_key(const knn_grid *g, const float p[3], int64_t out[3])
{
    uint64_t key = 0;
    for (int a = 0; a < 3; a++) {
        int64_t c = (int64_t)floorf((p[a] - g->min[a]) / g->edge);
        c = c < 0 ? 0 : c >= (1 << CELL_BITS) ? (1 << CELL_BITS) - 1 : c;
        out[a] = c;
        key |= (uint64_t)c << (CELL_BITS * a);
    }
    return key;
}

static size_t hash_key(uint64_t key, size_t mask)
{
    key ^= key >> 33;
    key *= 0xff51afd7ed558ccdull;
    key ^= key >> 33;
    return (size_t)key & mask;
}

static grid_slot *find_slot(const knn_grid *g, uint64_t key)
{
    size_t s = hash_key(key, g->slot_mask);
    while (g->slots[s].key != EMPTY_KEY) {
        if (g->slots[s].key == key) {
            return &g->slots[s];
        }
        s = (s + 1) & g->slot_mask;
    }
    return NULL;
}

// Hashes every point into cells of the current edge; returns the occupied cells.
static size_t fill_cells(knn_grid *g, size_t n)
{
    for (size_t s = 0; s <= g->slot_mask; s++) {
        g->slots[s] = (grid_slot){ EMPTY_KEY, 0, 0 };
    }
    size_t occupied = 0;
    for (size_t i = 0; i < n; i++) {
        int64_t c[3];
        uint64_t key = cell_key(g, g->xyz[i], c);
        size_t s = hash_key(key, g->slot_mask);
        while (g->slots[s].key != EMPTY_KEY && g->slots[s].key != key) {
            s = (s + 1) & g->slot_mask;
        }
        if (g->slots[s].key == EMPTY_KEY) {
            g->slots[s].key = key;
            occupied++;
        }
        g->slots[s].count++;
        g->cell_of[i] = (uint32_t)s;
    }
    return occupied;
}

// Chooses the cell edge (about TARGET_PER_CELL points per occupied cell, whatever the
// points' dimension: the correction assumes surfaces, the common case) and sorts the
// points by cell.
static void build_grid(knn_grid *g, size_t n)
{
    float max[3];
    for (int a = 0; a < 3; a++) {
        g->min[a] = max[a] = g->xyz[0][a];
    }
    for (size_t i = 1; i < n; i++) {
        for (int a = 0; a < 3; a++) {
            g->min[a] = fminf(g->min[a], g->xyz[i][a]);
            max[a] = fmaxf(max[a], g->xyz[i][a]);
        }
    }
    float extent = fmaxf(fmaxf(max[0] - g->min[0], max[1] - g->min[1]), max[2] - g->min[2]);
    float floor_edge = extent / (float)((1 << CELL_BITS) - 2); // keys must not overflow
    g->edge = fmaxf(extent / cbrtf((float)n / TARGET_PER_CELL), floor_edge);
    if (!(g->edge > 0.0f)) {
        g->edge = 1.0f; // all points identical
    }
    for (int round = 0; round < TUNE_ROUNDS; round++) {
        size_t occupied = fill_cells(g, n);
        double per_cell = (double)n / (double)occupied;
        if (per_cell > 0.5 * TARGET_PER_CELL && per_cell < 2.0 * TARGET_PER_CELL) {
            break;
        }
        float next = g->edge * (float)sqrt(TARGET_PER_CELL / per_cell);
        next = fmaxf(next, floor_edge);
        if (next == g->edge || round == TUNE_ROUNDS - 1) {
            break;
        }
        g->edge = next;
    }
    fill_cells(g, n);
    uint32_t start = 0;
    for (size_t s = 0; s <= g->slot_mask; s++) {
        if (g->slots[s].key != EMPTY_KEY) {
            g->slots[s].start = start;
            start += g->slots[s].count;
            g->slots[s].count = 0;
        }
    }
    for (size_t i = 0; i < n; i++) {
        grid_slot *slot = &g->slots[g->cell_of[i]];
        memcpy(g->sorted[slot->start + slot->count++], g->xyz[i], sizeof(g->xyz[i]));
    }
}

typedef struct neighbours {
    int size, capacity;
    float d2[STA_NORMALS_MAX_K + 1];
    const float *p[STA_NORMALS_MAX_K + 1];
} neighbours;

// Distance first, then the coordinates: the same neighbourhood whatever order the
// cells are visited in (chunkings differ in their grids).
static bool before(float d2, const float *p, float e2, const float *e)
{
    if (d2 != e2) {
        return d2 < e2;
    }
    for (int a = 0; a < 3; a++) {
        if (p[a] != e[a]) {
            return p[a] < e[a];
        }
    }
    return false;
}

static void offer(neighbours *nb, float d2, const float *p)
{
    if (nb->size == nb->capacity && !before(d2, p, nb->d2[nb->size - 1], nb->p[nb->size - 1])) {
        return;
    }
    int i = nb->size < nb->capacity ? nb->size++ : nb->size - 1;
    while (i > 0 && before(d2, p, nb->d2[i - 1], nb->p[i - 1])) {
        nb->d2[i] = nb->d2[i - 1];
        nb->p[i] = nb->p[i - 1];
        i--;
    }
    nb->d2[i] = d2;
    nb->p[i] = p;
}

static void scan_cell(const knn_grid *g, const int64_t c[3], const float q[3], neighbours *nb)
{
    for (int a = 0; a < 3; a++) {
        if (c[a] < 0 || c[a] >= (1 << CELL_BITS)) {
            return;
        }
    }
    uint64_t key = (uint64_t)c[0] | (uint64_t)c[1] << CELL_BITS | (uint64_t)c[2] << (2 * CELL_BITS);
    const grid_slot *slot = find_slot(g, key);
    if (!slot) {
        return;
    }
    for (uint32_t j = slot->start; j < slot->start + slot->count; j++) {
        const float *p = g->sorted[j];
        float dx = p[0] - q[0], dy = p[1] - q[1], dz = p[2] - q[2];
        offer(nb, dx * dx + dy * dy + dz * dz, p);
    }
}

// The k + 1 nearest points of q (q itself among them), exact unless MAX_SHELLS stopped
// the search.
static void nearest(const knn_grid *g, const float q[3], int k, neighbours *nb)
{
    nb->size = 0;
    nb->capacity = k + 1;
    int64_t c[3];
    cell_key(g, q, c);
    for (int r = 0; r <= MAX_SHELLS; r++) {
        for (int64_t dz = -r; dz <= r; dz++) {
            for (int64_t dy = -r; dy <= r; dy++) {
                bool face = dz == -r || dz == r || dy == -r || dy == r;
                for (int64_t dx = -r; dx <= r; dx += face ? 1 : 2 * r) {
                    const int64_t cell[3] = { c[0] + dx, c[1] + dy, c[2] + dz };
                    scan_cell(g, cell, q, nb);
                    if (r == 0) {
                        break;
                    }
                }
            }
        }
        // Every unscanned point is at least r cell edges away.
        float reach = (float)r * g->edge;
        if (nb->size == nb->capacity && nb->d2[nb->size - 1] <= reach * reach) {
            return;
        }
    }
}

static void orient(const sta_normals_chunk *chunk, const double p[3], double n[3])
{
    int up = chunk->up_axis == 1 ? 1 : 2;
    double sign = n[up];
    if (fabs(n[up]) < VERTICAL_DOT) { // a wall: face the scene's up-axis line
        sign = 0.0;
        for (int a = 0; a < 3; a++) {
            if (a != up) {
                sign += n[a] * (chunk->scene_centre[a] - p[a]) * chunk->scale[a];
            }
        }
    }
    if (sign < 0.0) {
        for (int a = 0; a < 3; a++) {
            n[a] = -n[a];
        }
    }
}

// The plane normal of a neighbourhood; false when it is degenerate.
static bool fit_normal(const neighbours *nb, double n[3])
{
    double mean[3] = { 0, 0, 0 };
    for (int i = 0; i < nb->size; i++) {
        for (int a = 0; a < 3; a++) {
            mean[a] += (double)nb->p[i][a];
        }
    }
    for (int a = 0; a < 3; a++) {
        mean[a] /= nb->size;
    }
    double cov[9] = { 0 };
    for (int i = 0; i < nb->size; i++) {
        double d[3] = { (double)nb->p[i][0] - mean[0], (double)nb->p[i][1] - mean[1],
                        (double)nb->p[i][2] - mean[2] };
        for (int r = 0; r < 3; r++) {
            for (int c = r; c < 3; c++) {
                cov[3 * r + c] += d[r] * d[c];
            }
        }
    }
    double w[3], v[3][3];
    sta_eigen3_path path = sta_eigen3_sym_d(cov, w, v);
    if (path == STA_EIGEN3_ZERO || path == STA_EIGEN3_INVALID || !(w[2] > 0.0) ||
        w[1] <= COLLINEAR * w[2]) {
        return false; // duplicates, one point, a line
    }
    memcpy(n, v[0], sizeof(v[0]));
    return isfinite(n[0]) && isfinite(n[1]) && isfinite(n[2]);
}

// Distance in metres from grid point p to the outside of the halo (the box grown by the
// margin, clipped to the scene bounds beyond which no point lies).
static double halo_reach(const sta_normals_chunk *chunk, const int32_t p[3])
{
    double reach = INFINITY;
    for (int a = 0; a < 3; a++) {
        double lo = (double)(p[a] - chunk->box_min[a]) * chunk->scale[a] + chunk->margin;
        double hi = (double)(chunk->box_max[a] - p[a]) * chunk->scale[a] + chunk->margin;
        if (chunk->box_min[a] > chunk->scene_min[a]) {
            reach = fmin(reach, lo);
        }
        if (chunk->box_max[a] <= chunk->scene_max[a]) {
            reach = fmin(reach, hi);
        }
    }
    return reach;
}

sta_status sta_normals_compute(const sta_normals_chunk *chunk, const sta_record_layout *layout,
                               uint8_t *records, size_t count, const int32_t *halo,
                               size_t halo_count, sta_normals_stats *stats, sta_error *err)
{
    if (!(layout->attributes & STA_ATTR_SPLAT) || chunk->k < 3 || chunk->k > STA_NORMALS_MAX_K) {
        return sta_fail(err, STA_ERR_ARG, "normals: no SPLAT attribute or K outside 3..%d",
                        STA_NORMALS_MAX_K);
    }
    size_t n = count + halo_count;
    if (count == 0) {
        return STA_OK;
    }
    if (n > UINT32_MAX) {
        return sta_fail(err, STA_ERR_ARG, "normals: %zu points in one chunk and halo", n);
    }
    knn_grid g = { 0 };
    g.slot_mask = 1;
    while (g.slot_mask < 2 * n + 2) {
        g.slot_mask <<= 1;
    }
    g.xyz = sta_alloc_array(n, sizeof(*g.xyz));
    g.sorted = sta_alloc_array(n, sizeof(*g.sorted));
    g.cell_of = sta_alloc_array(n, sizeof(*g.cell_of));
    g.slots = sta_alloc_array(g.slot_mask, sizeof(*g.slots));
    g.slot_mask--;
    sta_status status = STA_OK;
    if (!g.xyz || !g.sorted || !g.cell_of || !g.slots) {
        status = sta_fail(err, STA_ERR_NOMEM, "normals: out of memory for %zu points", n);
        goto out;
    }
    for (size_t i = 0; i < n; i++) {
        int32_t p[3];
        if (i < count) {
            sta_record_position(records + i * layout->size, p);
        } else {
            memcpy(p, halo + 3 * (i - count), sizeof(p));
        }
        for (int a = 0; a < 3; a++) {
            // From the scene's corner, not the chunk's: the same floats in every chunking.
            g.xyz[i][a] = (float)((double)(p[a] - chunk->scene_min[a]) * chunk->scale[a]);
        }
    }
    build_grid(&g, n);
    neighbours nb;
    for (size_t i = 0; i < count; i++) {
        nearest(&g, g.xyz[i], chunk->k, &nb);
        double normal[3] = { 0, 0, 0 };
        normal[chunk->up_axis == 1 ? 1 : 2] = 1.0; // the fallback: up
        bool ok = nb.size >= 3 && fit_normal(&nb, normal);
        int32_t p[3];
        sta_record_position(records + i * layout->size, p);
        double pd[3] = { p[0], p[1], p[2] };
        if (ok) {
            orient(chunk, pd, normal);
        } else {
            stats->degenerate++;
        }
        double sum = 0.0;
        for (int j = 0; j < nb.size; j++) {
            sum += sqrt(nb.d2[j]);
        }
        double radius = nb.size > 1 ? sum / (nb.size - 1) : 0.0; // q itself adds 0
        if (nb.size > 0 && sqrt(nb.d2[nb.size - 1]) > halo_reach(chunk, p)) {
            stats->beyond_halo++;
        }
        const float nf[3] = { (float)normal[0], (float)normal[1], (float)normal[2] };
        uint16_t packed[3];
        sta_splat_pack(nf, (float)radius, packed);
        memcpy(records + i * layout->size + layout->splat_offset, packed, sizeof(packed));
    }
    stats->points += count;
out:
    sta_free(g.xyz);
    sta_free(g.sorted);
    sta_free(g.cell_of);
    sta_free(g.slots);
    return status;
}
