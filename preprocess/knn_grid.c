/* SPDX-License-Identifier: MIT
 * Exact kNN of every point of a set: a tuned, hashed uniform grid, blocks of 27 cells,
 * shell search beyond them. */
#include "knn_grid.h"

#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "core/alloc.h"

/* Points in a point's cell the grid edge is tuned to: TARGET_PER_K x K, at least
 * TARGET_MIN. Measured on a 1 M street at K = 10 and 40: 1.2-1.6 x K was the fastest
 * (fewer cells to probe against fewer points to compare). */
#define TARGET_PER_K 1.5

enum {
    TARGET_MIN = 8,
    MAX_SHELLS = 12, /* a neighbourhood searched no wider gets what it found */
    TUNE_ROUNDS = 4
};
#define CELL_BITS 21 /* per axis in a cell key */
#define EMPTY_KEY UINT64_MAX

typedef struct grid_slot {
    uint64_t key;
    uint32_t start, count;
} grid_slot;

typedef struct knn_grid {
    const float (*xyz)[3]; /* all points */
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

size_t sta_knn_memory_bytes(size_t points)
{
    size_t slots = 1;
    while (slots < 2 * points + 2) {
        slots <<= 1;
    }
    return points * (3 * sizeof(float) + 3 * sizeof(uint32_t)) + slots * sizeof(grid_slot);
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
    // Cells in key order (z, then y, then x): consecutive cells are sta_knn in space,
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

static inline void offer(sta_knn *nb, float d2, const float *p)
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

static void scan_cell(const knn_grid *g, const int64_t c[3], const float q[3], sta_knn *nb)
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
                         int done, sta_knn *nb)
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

// The k + 1 nearest of q (in cell c) from the gathered block (also as structure of
// arrays, `cap` each, the fourth array scratch for distances), then in shells beyond it.
static void nearest_in_block(const knn_grid *g, const float (*block)[3], float *block_soa,
                             size_t cap, size_t block_n, const float q[3], const int64_t c[3],
                             int k, sta_knn *nb)
{
    nb->size = 0;
    nb->capacity = k + 1;
    // Distances first, in a loop the compiler vectorises; then the few nearer than the
    // current K-th go into the sorted list.
    const float *bx = block_soa, *by = bx + cap, *bz = by + cap;
    float *d2 = block_soa + 3 * cap;
    for (size_t b = 0; b < block_n; b++) {
        float ex = bx[b] - q[0], ey = by[b] - q[1], ez = bz[b] - q[2];
        d2[b] = ex * ex + ey * ey + ez * ez;
    }
    for (size_t b = 0; b < block_n; b++) {
        if (nb->size < nb->capacity || d2[b] <= nb->d2[nb->size - 1]) { // most are farther
            offer(nb, d2[b], block[b]);
        }
    }
    float face = g->edge; // distance from q to its cell's nearest face
    for (int a = 0; a < 3; a++) {
        float lo = g->min[a] + (float)c[a] * g->edge;
        face = fminf(face, fmaxf(0.0f, fminf(q[a] - lo, lo + g->edge - q[a])));
    }
    float inside = g->edge + face; // to the outside of the 27 cells
    if (nb->size < nb->capacity || !(nb->d2[nb->size - 1] <= inside * inside)) {
        nearest_from(g, q, c, face, 1, nb);
    }
}

sta_status sta_knn_each(const float (*xyz)[3], size_t n, size_t queries, int k, sta_knn_visit visit,
                        void *user, sta_error *err)
{
    if (k < 1 || k > STA_KNN_MAX) {
        return sta_fail(err, STA_ERR_ARG, "kNN: K = %d outside 1..%d", k, STA_KNN_MAX);
    }
    if (queries == 0) {
        return STA_OK;
    }
    if (n > UINT32_MAX) {
        return sta_fail(err, STA_ERR_ARG, "kNN: %zu points in one set", n);
    }
    knn_grid g = { 0 };
    g.slot_mask = 1;
    while (g.slot_mask < 2 * n + 2) {
        g.slot_mask <<= 1;
    }
    g.xyz = xyz;
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
    if (!g.sorted || !g.cell_of || !g.order || !g.cells || !g.slots || !bloom) {
        status = sta_fail(err, STA_ERR_NOMEM, "kNN: out of memory for %zu points", n);
        goto out;
    }
    g.bloom = NULL; // off while the grid is tuned (fill_cells probes with keys directly)
    build_grid(&g, n, k, bloom);
    // Cell by cell: the points of the 27 cells around are gathered once and searched for
    // each of the cell's own points; a neighbourhood that may reach beyond those cells
    // (its K-th distance beyond the block's nearest face) is searched again in shells.
    for (size_t cell_index = 0; cell_index < g.cell_count && status == STA_OK; cell_index++) {
        const grid_slot *slot = &g.slots[g.cells[cell_index]];
        bool has_own = false;
        for (uint32_t j = slot->start; j < slot->start + slot->count && !has_own; j++) {
            has_own = g.order[j] < queries;
        }
        if (!has_own) {
            continue; // halo only
        }
        int64_t c[3];
        for (int a = 0; a < 3; a++) {
            c[a] = (int64_t)((slot->key >> (CELL_BITS * a)) & ((1u << CELL_BITS) - 1));
        }
        size_t block_n = 0;
        // Neighbourhoods a point widened to, searched at once for the next point of the
        // cell: widening is local (a road's cells), and a wide search serves the narrow
        // visit too.
        int guess = k;
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
                    status = sta_fail(err, STA_ERR_NOMEM, "kNN: out of memory");
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
            if (i >= queries) {
                continue;
            }
            const float *q = g.sorted[j];
            sta_knn nb;
            int want = k, searched = 0, found = 0;
            for (;;) {
                if (want > searched) {
                    searched = want > guess ? want : guess;
                    nearest_in_block(&g, (const float(*)[3])block, block_soa, block_capacity,
                                     block_n, q, c, searched, &nb);
                    found = nb.size;
                }
                // The K + 1 nearest are the first K + 1 of a wider search (a total order).
                nb.capacity = want + 1;
                nb.size = found < want + 1 ? found : want + 1;
                int next = visit(user, i, &nb);
                next = next < STA_KNN_MAX ? next : STA_KNN_MAX;
                if (next <= want || (size_t)want + 1 >= n) {
                    break;
                }
                want = next;
            }
            guess = want;
        }
    }
out:
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
