/* SPDX-License-Identifier: MIT
 * Per-chunk kNN normals: a hashed uniform grid, shell search, covariance, eigenvector. */
#include "knn_normals.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/alloc.h"
#include "core/eigen3.h"
#include "core/octahedral.h"

/* Points in a point's cell the grid edge is tuned to: TARGET_PER_K x K, at least
 * TARGET_MIN. Measured on a 1 M street at K = 10 and 40: 1.2-1.6 x K was the fastest
 * (fewer cells to probe against fewer points to compare). */
#define TARGET_PER_K 1.5

enum {
    TARGET_MIN = 8,
    MAX_SHELLS = 12, /* a neighbourhood searched no wider gets what it found */
    TUNE_ROUNDS = 4
};
#define CELL_BITS    21 /* per axis in a cell key */
#define EMPTY_KEY    UINT64_MAX
/* l1 <= COLLINEAR * l2: the neighbours lie on a line, no plane to fit. */
#define COLLINEAR    1e-6
/* |n . up| below this: a vertical surface (a wall), oriented by the trajectory or the
 * scene's up-axis line. */
#define VERTICAL_DOT 0.2

typedef struct grid_slot {
    uint64_t key;
    uint32_t start, count;
} grid_slot;

typedef struct knn_grid {
    float (*xyz)[3]; /* all points, metres from the scene's corner */
    float (*sorted)[3];
    uint32_t *cell_of; /* slot of each point */
    uint32_t *order;   /* point index of each sorted position */
    uint32_t *cells;   /* occupied slots in key order */
    uint64_t *bloom;   /* occupied-cell filter, 2^bloom_log2 bits (NULL while tuning) */
    int bloom_log2, bloom_max_log2;
    size_t cell_count;
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
    return points * (2 * 3 * sizeof(float) + 3 * sizeof(uint32_t)) + slots * sizeof(grid_slot);
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

// A bit per hashed cell key (16 bits a cell): most cells around a surface are empty,
// and a probe of the table for an empty cell is a cache miss the filter saves.
static uint64_t bloom_bit(const knn_grid *g, uint64_t key)
{
    return (key * 0x9e3779b97f4a7c15ull) >> (64 - g->bloom_log2);
}

static grid_slot *find_slot(const knn_grid *g, uint64_t key)
{
    if (g->bloom) {
        uint64_t bit = bloom_bit(g, key);
        if (!(g->bloom[bit >> 6] & (1ull << (bit & 63)))) {
            return NULL;
        }
    }
    size_t s = hash_key(key, g->slot_mask);
    while (g->slots[s].key != EMPTY_KEY) {
        if (g->slots[s].key == key) {
            return &g->slots[s];
        }
        s = (s + 1) & g->slot_mask;
    }
    return NULL;
}

// Hashes every point into cells of the current edge; returns the mean number of points
// in a point's cell (what a search costs, whatever the density varies).
static double fill_cells(knn_grid *g, size_t n, size_t *out_occupied)
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
    double squares = 0.0;
    for (size_t s = 0; s <= g->slot_mask; s++) {
        squares += (double)g->slots[s].count * (double)g->slots[s].count;
    }
    *out_occupied = occupied;
    return squares / (double)n;
}

// qsort has no context argument: the slots whose indices are being sorted (one sort at
// a time per thread).
static _Thread_local const grid_slot *sort_slots;

static int compare_slot_key(const void *a, const void *b)
{
    uint64_t x = sort_slots[*(const uint32_t *)a].key, y = sort_slots[*(const uint32_t *)b].key;
    return x < y ? -1 : x > y;
}

// Chooses the cell edge (about `target` points in a point's cell, whatever the
// points' dimension: the correction assumes surfaces, the common case) and sorts the
// points by cell.
static void build_grid(knn_grid *g, size_t n, int k, uint64_t *bloom)
{
    const double target = fmax(TARGET_MIN, TARGET_PER_K * k);
    float max[3];
    const size_t full_mask = g->slot_mask;
    size_t occupied = 0;
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
    g->edge = fmaxf(extent / cbrtf((float)((double)n / target)), floor_edge);
    if (!(g->edge > 0.0f)) {
        g->edge = 1.0f; // all points identical
    }
    for (int round = 0; round < TUNE_ROUNDS; round++) {
        double per_cell = fill_cells(g, n, &occupied);
        if (per_cell > 0.5 * target && per_cell < 2.0 * target) {
            break;
        }
        float next = g->edge * (float)sqrt(target / per_cell);
        next = fmaxf(next, floor_edge);
        if (next == g->edge || round == TUNE_ROUNDS - 1) {
            break;
        }
        g->edge = next;
    }
    // The final table sized to the cells, not the points: a few MiB probed at random
    // stay in cache where the full size would not.
    g->slot_mask = full_mask;
    fill_cells(g, n, &occupied);
    size_t small = 1;
    while (small < 2 * occupied + 2) {
        small <<= 1;
    }
    g->slot_mask = small - 1 < full_mask ? small - 1 : full_mask;
    fill_cells(g, n, &occupied);
    g->bloom_log2 = 6;
    while (((size_t)1 << g->bloom_log2) < 16 * occupied && g->bloom_log2 < g->bloom_max_log2) {
        g->bloom_log2++;
    }
    g->bloom = bloom;
    memset(g->bloom, 0, ((size_t)1 << g->bloom_log2) / 8);
    for (size_t s = 0; s <= g->slot_mask; s++) {
        if (g->slots[s].key != EMPTY_KEY) {
            uint64_t bit = bloom_bit(g, g->slots[s].key);
            g->bloom[bit >> 6] |= 1ull << (bit & 63);
        }
    }
    // Cells in key order (z, then y, then x): consecutive cells are neighbours in space,
    // so their points lie together and the hash slots they probe were probed recently.
    g->cell_count = 0;
    for (size_t s = 0; s <= g->slot_mask; s++) {
        if (g->slots[s].key != EMPTY_KEY) {
            g->cells[g->cell_count++] = (uint32_t)s;
        }
    }
    sort_slots = g->slots;
    qsort(g->cells, g->cell_count, sizeof(uint32_t), compare_slot_key);
    uint32_t start = 0;
    for (size_t c = 0; c < g->cell_count; c++) {
        grid_slot *slot = &g->slots[g->cells[c]];
        slot->start = start;
        start += slot->count;
        slot->count = 0;
    }
    for (size_t i = 0; i < n; i++) {
        grid_slot *slot = &g->slots[g->cell_of[i]];
        g->order[slot->start + slot->count] = (uint32_t)i;
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
static inline bool before(float d2, const float *p, float e2, const float *e)
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

static inline void offer(neighbours *nb, float d2, const float *p)
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

// The slot of cell c, NULL when empty or outside the key range.
static const grid_slot *cell_slot(const knn_grid *g, const int64_t c[3])
{
    for (int a = 0; a < 3; a++) {
        if (c[a] < 0 || c[a] >= (1 << CELL_BITS)) {
            return NULL;
        }
    }
    uint64_t key = (uint64_t)c[0] | (uint64_t)c[1] << CELL_BITS | (uint64_t)c[2] << (2 * CELL_BITS);
    return find_slot(g, key);
}

static void scan_cell(const knn_grid *g, const int64_t c[3], const float q[3], neighbours *nb)
{
    const grid_slot *slot = cell_slot(g, c);
    if (!slot) {
        return;
    }
    for (uint32_t j = slot->start; j < slot->start + slot->count; j++) {
        const float *p = g->sorted[j];
        float dx = p[0] - q[0], dy = p[1] - q[1], dz = p[2] - q[2];
        offer(nb, dx * dx + dy * dy + dz * dz, p);
    }
}

// Completes the k + 1 nearest points of q (q itself among them) in `nb`, which holds
// the best of the cells within Chebyshev distance `done` of q's cell `c`: shells of
// cells further out are added until the K-th distance is within the scanned block
// (exact), or MAX_SHELLS stops the search. `face`: q's distance to its own cell's
// nearest face.
static void nearest_from(const knn_grid *g, const float q[3], const int64_t c[3], float face,
                         int done, neighbours *nb)
{
    float lo[3]; // q's cell's lower corner
    for (int a = 0; a < 3; a++) {
        lo[a] = g->min[a] + (float)c[a] * g->edge;
    }
    for (int r = done + 1; r <= MAX_SHELLS; r++) {
        bool full = nb->size == nb->capacity;
        float worst = full ? nb->d2[nb->size - 1] : INFINITY;
        for (int64_t dz = -r; dz <= r; dz++) {
            for (int64_t dy = -r; dy <= r; dy++) {
                bool side = dz == -r || dz == r || dy == -r || dy == r;
                for (int64_t dx = -r; dx <= r; dx += side ? 1 : 2 * r) {
                    const int64_t d[3] = { dx, dy, dz };
                    float gap2 = 0.0f; // q's squared distance to the cell: skip far ones unprobed
                    for (int a = 0; a < 3; a++) {
                        float gap = d[a] > 0   ? lo[a] + (float)d[a] * g->edge - q[a]
                                    : d[a] < 0 ? q[a] - (lo[a] + (float)(d[a] + 1) * g->edge)
                                               : 0.0f;
                        gap2 += gap > 0.0f ? gap * gap : 0.0f;
                    }
                    if (gap2 > worst) {
                        continue;
                    }
                    const int64_t cell[3] = { c[0] + dx, c[1] + dy, c[2] + dz };
                    scan_cell(g, cell, q, nb);
                    if (nb->size == nb->capacity) {
                        worst = nb->d2[nb->size - 1];
                    }
                }
            }
        }
        // Every unscanned point is further than r cell edges plus q's own face distance.
        float reach = (float)r * g->edge + face;
        if (nb->size == nb->capacity && nb->d2[nb->size - 1] <= reach * reach) {
            return;
        }
    }
}

// The rule of docs/CONVERTER.md: up for surfaces that face up or down; a wall faces the
// scanner's position when the trajectory knows it, else away from the scene's up-axis
// line (an object scanned from around it).
static void orient(const sta_normals_chunk *chunk, const double p[3], const double *gps_time,
                   double n[3])
{
    int up = chunk->up_axis == 1 ? 1 : 2;
    double sign = n[up];
    if (fabs(n[up]) < VERTICAL_DOT) {
        double target[3];
        bool seen = chunk->trajectory && gps_time &&
                    sta_trajectory_at(chunk->trajectory, *gps_time, target);
        sign = 0.0;
        for (int a = 0; a < 3; a++) {
            if (seen) {
                sign += n[a] * (target[a] - p[a]) * chunk->scale[a];
            } else if (a != up) {
                sign += n[a] * (p[a] - chunk->scene_centre[a]) * chunk->scale[a];
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

// The 27 cells of a block, the own cell first, then by distance (faces, edges, corners):
// the first K + 1 candidates, taken unconditionally, are then near ones, and fewer of
// the rest pass the K-th distance.
static const int8_t block_offsets[27][3] = {
    { 0, 0, 0 },  { -1, 0, 0 },   { 1, 0, 0 },   { 0, -1, 0 },  { 0, 1, 0 },  { 0, 0, -1 },
    { 0, 0, 1 },  { -1, -1, 0 },  { 1, -1, 0 },  { -1, 1, 0 },  { 1, 1, 0 },  { -1, 0, -1 },
    { 1, 0, -1 }, { -1, 0, 1 },   { 1, 0, 1 },   { 0, -1, -1 }, { 0, 1, -1 }, { 0, -1, 1 },
    { 0, 1, 1 },  { -1, -1, -1 }, { 1, -1, -1 }, { -1, 1, -1 }, { 1, 1, -1 }, { -1, -1, 1 },
    { 1, -1, 1 }, { -1, 1, 1 },   { 1, 1, 1 },
};

// Normal, orientation and radius of record i from its neighbourhood, into its SPLAT bytes.
static void finish_point(const sta_normals_chunk *chunk, const sta_record_layout *layout,
                         uint8_t *records, size_t i, const neighbours *nb, sta_normals_stats *stats)
{
    double normal[3] = { 0, 0, 0 };
    normal[chunk->up_axis == 1 ? 1 : 2] = 1.0; // the fallback: up
    bool ok = nb->size >= 3 && fit_normal(nb, normal);
    int32_t p[3];
    sta_record_position(records + i * layout->size, p);
    double pd[3] = { p[0], p[1], p[2] };
    double gps_time;
    bool timed = (layout->attributes & STA_ATTR_GPS_TIME) != 0;
    if (timed) {
        memcpy(&gps_time, records + i * layout->size + layout->gps_offset, sizeof(gps_time));
    }
    if (ok) {
        orient(chunk, pd, timed ? &gps_time : NULL, normal);
    } else {
        stats->degenerate++;
    }
    // Radius: the mean distance to the nearest STA_NORMALS_RADIUS_K (or K) neighbours,
    // whatever K the normal used; nb->p[0] is q itself (distance 0).
    int m = nb->size - 1 < STA_NORMALS_RADIUS_K ? nb->size - 1 : STA_NORMALS_RADIUS_K;
    double sum = 0.0;
    for (int j = 1; j <= m; j++) {
        sum += sqrt((double)nb->d2[j]);
    }
    double radius = m > 0 ? sum / m : 0.0;
    if (nb->size > 0 && sqrt((double)nb->d2[nb->size - 1]) > halo_reach(chunk, p)) {
        stats->beyond_halo++;
    }
    const float nf[3] = { (float)normal[0], (float)normal[1], (float)normal[2] };
    uint16_t packed[3];
    sta_splat_pack(nf, (float)radius, packed);
    memcpy(records + i * layout->size + layout->splat_offset, packed, sizeof(packed));
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
    g.order = sta_alloc_array(n, sizeof(*g.order));
    g.cells = sta_alloc_array(n, sizeof(*g.cells));
    g.bloom_max_log2 = 6;
    while (((size_t)1 << g.bloom_max_log2) < 16 * n) {
        g.bloom_max_log2++;
    }
    uint64_t *bloom = sta_alloc_array(((size_t)1 << g.bloom_max_log2) / 64, sizeof(uint64_t));
    g.slots = sta_alloc_array(g.slot_mask, sizeof(*g.slots));
    g.slot_mask--;
    sta_status status = STA_OK;
    float(*block)[3] = NULL;
    float *block_soa = NULL; /* x, y, z and squared distance, block_capacity each */
    size_t block_capacity = 0;
    if (!g.xyz || !g.sorted || !g.cell_of || !g.order || !g.cells || !g.slots || !bloom) {
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
    g.bloom = NULL; // off while the grid is tuned (fill_cells probes with keys directly)
    build_grid(&g, n, chunk->k, bloom);
    // Cell by cell: the points of the 27 cells around are gathered once and searched for
    // each of the cell's own points; a neighbourhood that may reach beyond those cells
    // (its K-th distance beyond the block's nearest face) is searched again in shells.
    for (size_t cell_index = 0; cell_index < g.cell_count && status == STA_OK; cell_index++) {
        const grid_slot *slot = &g.slots[g.cells[cell_index]];
        bool has_own = false;
        for (uint32_t j = slot->start; j < slot->start + slot->count && !has_own; j++) {
            has_own = g.order[j] < count;
        }
        if (!has_own) {
            continue; // halo only
        }
        int64_t c[3];
        for (int a = 0; a < 3; a++) {
            c[a] = (int64_t)((slot->key >> (CELL_BITS * a)) & ((1u << CELL_BITS) - 1));
        }
        size_t block_n = 0;
        for (int o_i = 0; o_i < 27 && status == STA_OK; o_i++) {
            const int64_t cell[3] = { c[0] + block_offsets[o_i][0], c[1] + block_offsets[o_i][1],
                                      c[2] + block_offsets[o_i][2] };
            const grid_slot *o = cell_slot(&g, cell);
            if (!o) {
                continue;
            }
            if (block_n + o->count > block_capacity) {
                size_t cap = 2 * (block_n + o->count);
                float(*grown)[3] = sta_realloc_array(block, cap, sizeof(*block));
                float *soa = grown ? sta_realloc_array(block_soa, 4 * cap, sizeof(float)) : NULL;
                block = grown ? grown : block;
                block_soa = soa ? soa : block_soa;
                if (!grown || !soa) {
                    status = sta_fail(err, STA_ERR_NOMEM, "normals: out of memory");
                    break;
                }
                block_capacity = cap;
            }
            memcpy(block + block_n, g.sorted + o->start, o->count * sizeof(*block));
            block_n += o->count;
        }
        if (status == STA_OK) { // the block as structure of arrays too, for the distances
            float *bx = block_soa, *by = bx + block_capacity, *bz = by + block_capacity;
            for (size_t b = 0; b < block_n; b++) {
                bx[b] = block[b][0], by[b] = block[b][1], bz[b] = block[b][2];
            }
        }
        for (uint32_t j = slot->start; j < slot->start + slot->count && status == STA_OK; j++) {
            size_t i = g.order[j];
            if (i >= count) {
                continue;
            }
            const float *q = g.sorted[j];
            neighbours nb;
            nb.size = 0;
            nb.capacity = chunk->k + 1;
            // Distances first, in a loop the compiler vectorises; then the few nearer
            // than the current K-th go into the sorted list.
            float *bx = block_soa, *by = bx + block_capacity, *bz = by + block_capacity;
            float *d2 = bz + block_capacity;
            for (size_t b = 0; b < block_n; b++) {
                float ex = bx[b] - q[0], ey = by[b] - q[1], ez = bz[b] - q[2];
                d2[b] = ex * ex + ey * ey + ez * ez;
            }
            for (size_t b = 0; b < block_n; b++) {
                if (nb.size < nb.capacity || d2[b] <= nb.d2[nb.size - 1]) { // most are farther
                    offer(&nb, d2[b], block[b]);
                }
            }
            float face = g.edge; // distance from q to its cell's nearest face
            for (int a = 0; a < 3; a++) {
                float lo = g.min[a] + (float)c[a] * g.edge;
                face = fminf(face, fmaxf(0.0f, fminf(q[a] - lo, lo + g.edge - q[a])));
            }
            float inside = g.edge + face; // to the outside of the 27 cells
            if (nb.size < nb.capacity || !(nb.d2[nb.size - 1] <= inside * inside)) {
                nearest_from(&g, q, c, face, 1, &nb);
            }
            finish_point(chunk, layout, records, i, &nb, stats);
        }
    }
    stats->points += count;
out:
    sta_free(g.xyz);
    sta_free(g.sorted);
    sta_free(g.cell_of);
    sta_free(g.order);
    sta_free(g.cells);
    sta_free(bloom);
    sta_free(g.slots);
    sta_free(block);
    sta_free(block_soa);
    return status;
}
