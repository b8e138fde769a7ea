/* SPDX-License-Identifier: MIT
 * Exact kNN of every point of a set: a tuned, hashed uniform grid, blocks of 27 (or 125)
 * cells searched by bounded quickselect, shell search beyond them. */
#include "knn_grid.h"

#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "core/alloc.h"
#include "knn_select.h"

/* Points in a point's cell the grid edge is tuned to: TARGET_PER_K x K, at least
 * TARGET_MIN. Measured on a 1 M street at K = 10 and 40: 1.2-1.6 x K was the fastest
 * (fewer cells to probe against fewer points to compare). */
#define TARGET_PER_K 1.5

/* The first bound tried for a point's K-th squared distance: the previous point's,
 * times this (on the 4 M street: about 1.3 x K candidates, under 10 % retried). */
#define HINT_WIDEN 1.25f

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
    const float (*xyz)[3];     /* all points */
    const int32_t (*grid)[3];  /* their integer positions */
    float (*sorted)[3];        /* the points in cell order */
    int32_t (*sorted_grid)[3]; /* their integer positions */
    uint32_t *cell_of;         /* slot of each point */
    uint32_t *order;           /* point index of each sorted position */
    uint32_t *cells;           /* occupied slots in key order */
    uint64_t *bloom;           /* occupied-cell filter, 2^bloom_log2 bits (NULL while tuning) */
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
    return points * (3 * sizeof(float) + 3 * sizeof(int32_t) + 3 * sizeof(uint32_t)) +
           slots * sizeof(grid_slot);
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
    // stay in cache where the full size would not. (The tuning's last fill was at this
    // edge with the full table: `occupied` is its count.)
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
        memcpy(g->sorted_grid[slot->start + slot->count], g->grid[i], sizeof(g->grid[i]));
        memcpy(g->sorted[slot->start + slot->count++], g->xyz[i], sizeof(g->xyz[i]));
    }
}

// Distance first, then the integer coordinates: the same neighbourhood whatever order
// the cells are visited in (chunkings differ in their grids).
static inline bool before(const knn_grid *g, float d2, uint32_t p, float e2, uint32_t e)
{
    if (d2 != e2) {
        return d2 < e2;
    }
    for (int a = 0; a < 3; a++) {
        if (g->sorted_grid[p][a] != g->sorted_grid[e][a]) {
            return g->sorted_grid[p][a] < g->sorted_grid[e][a];
        }
    }
    return false;
}

// A neighbourhood being found: squared distances, sorted positions and integer
// positions. Sorted ascending only while the shell search (nearest_from) inserts into it.
typedef struct knn_list {
    int size, capacity;
    float d2[STA_KNN_MAX + 1];
    uint32_t pos[STA_KNN_MAX + 1];
    int32_t grid[STA_KNN_MAX + 1][3];
} knn_list;

static inline void list_set(knn_list *nb, int i, float d2, uint32_t pos, const int32_t grid[3])
{
    nb->d2[i] = d2;
    nb->pos[i] = pos;
    memcpy(nb->grid[i], grid, sizeof(nb->grid[i]));
}

static inline void list_swap(knn_list *nb, int i, int j)
{
    float d = nb->d2[i];
    uint32_t p = nb->pos[i];
    int32_t gr[3];
    memcpy(gr, nb->grid[i], sizeof(gr));
    list_set(nb, i, nb->d2[j], nb->pos[j], nb->grid[j]);
    list_set(nb, j, d, p, gr);
}

static inline void offer(const knn_grid *g, knn_list *nb, float d2, uint32_t p,
                         const int32_t grid[3])
{
    if (nb->size == nb->capacity &&
        !before(g, d2, p, nb->d2[nb->size - 1], nb->pos[nb->size - 1])) {
        return;
    }
    int i = nb->size < nb->capacity ? nb->size++ : nb->size - 1;
    while (i > 0 && before(g, d2, p, nb->d2[i - 1], nb->pos[i - 1])) {
        list_set(nb, i, nb->d2[i - 1], nb->pos[i - 1], nb->grid[i - 1]);
        i--;
    }
    list_set(nb, i, d2, p, grid);
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

static void scan_cell(const knn_grid *g, const int64_t c[3], const float q[3], knn_list *nb)
{
    const grid_slot *slot = cell_slot(g, c);
    if (!slot) {
        return;
    }
    for (uint32_t j = slot->start; j < slot->start + slot->count; j++) {
        const float *p = g->sorted[j];
        float dx = p[0] - q[0], dy = p[1] - q[1], dz = p[2] - q[2];
        offer(g, nb, dx * dx + dy * dy + dz * dz, j, g->sorted_grid[j]);
    }
}

// Completes the k + 1 nearest points of q (q itself among them) in `nb` (sorted), which
// holds the best of the cells within Chebyshev distance `done` of q's cell `c`: shells
// of cells further out are added until the K-th distance is within the scanned block
// (exact), or MAX_SHELLS stops the search. `face`: q's distance to its own cell's
// nearest face.
static void nearest_from(const knn_grid *g, const float q[3], const int64_t c[3], float face,
                         int done, knn_list *nb)
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

// The 27 cells of a block, the own cell first, then by distance (faces, edges, corners);
// the 98 of the second ring follow them (block_offsets_init).
enum {
    FILTER_GROUP = 16, /* block distances tested at once against a bound */
    INNER_CELLS = 27,
    WIDE_CELLS = 125
};
static const int8_t inner_offsets[INNER_CELLS][3] = {
    { 0, 0, 0 },  { -1, 0, 0 },   { 1, 0, 0 },   { 0, -1, 0 },  { 0, 1, 0 },  { 0, 0, -1 },
    { 0, 0, 1 },  { -1, -1, 0 },  { 1, -1, 0 },  { -1, 1, 0 },  { 1, 1, 0 },  { -1, 0, -1 },
    { 1, 0, -1 }, { -1, 0, 1 },   { 1, 0, 1 },   { 0, -1, -1 }, { 0, 1, -1 }, { 0, -1, 1 },
    { 0, 1, 1 },  { -1, -1, -1 }, { 1, -1, -1 }, { -1, 1, -1 }, { 1, 1, -1 }, { -1, -1, 1 },
    { 1, -1, 1 }, { -1, 1, 1 },   { 1, 1, 1 },
};

static void block_offsets_init(int8_t out[WIDE_CELLS][3])
{
    memcpy(out, inner_offsets, sizeof(inner_offsets));
    int n = INNER_CELLS;
    for (int dz = -2; dz <= 2; dz++) {
        for (int dy = -2; dy <= 2; dy++) {
            for (int dx = -2; dx <= 2; dx++) {
                if (abs(dx) == 2 || abs(dy) == 2 || abs(dz) == 2) {
                    out[n][0] = (int8_t)dx, out[n][1] = (int8_t)dy, out[n][2] = (int8_t)dz;
                    n++;
                }
            }
        }
    }
}

// The points of the cells around one cell, as structure of arrays (`cap` each): the
// inner ring's `inner` points first, then (once gathered) the second ring's up to `wide`
// (0 until then).
typedef struct knn_block {
    size_t cap, inner, wide;
    const int8_t (*offsets)[3];   /* WIDE_CELLS, inner ring first */
    float *x, *y, *z, *d2, *vals; /* vals: quickselect scratch */
    uint32_t *pos, *cand;         /* sorted positions; candidate scratch */
    int32_t (*grid)[3];           /* integer positions */
} knn_block;

static void block_free(knn_block *b)
{
    sta_free(b->x);
    sta_free(b->y);
    sta_free(b->z);
    sta_free(b->d2);
    sta_free(b->vals);
    sta_free(b->pos);
    sta_free(b->cand);
    sta_free(b->grid);
}

static bool block_reserve(knn_block *b, size_t need)
{
    if (need <= b->cap) {
        return true;
    }
    size_t cap = 2 * need;
    float **f[] = { &b->x, &b->y, &b->z, &b->d2, &b->vals };
    for (size_t i = 0; i < sizeof(f) / sizeof(f[0]); i++) {
        float *grown = sta_realloc_array(*f[i], cap, sizeof(float));
        if (!grown) {
            return false;
        }
        *f[i] = grown;
    }
    uint32_t **u[] = { &b->pos, &b->cand };
    for (size_t i = 0; i < sizeof(u) / sizeof(u[0]); i++) {
        uint32_t *grown = sta_realloc_array(*u[i], cap, sizeof(uint32_t));
        if (!grown) {
            return false;
        }
        *u[i] = grown;
    }
    int32_t(*grid)[3] = sta_realloc_array(b->grid, cap, sizeof(*b->grid));
    if (!grid) {
        return false;
    }
    b->grid = grid;
    b->cap = cap;
    return true;
}

// Appends the points of cells offsets[from .. to) around c; false when out of memory.
static bool block_gather(const knn_grid *g, knn_block *b, size_t *count, const int64_t c[3],
                         int from, int to)
{
    for (int o_i = from; o_i < to; o_i++) {
        const int64_t cell[3] = { c[0] + b->offsets[o_i][0], c[1] + b->offsets[o_i][1],
                                  c[2] + b->offsets[o_i][2] };
        const grid_slot *o = cell_slot(g, cell);
        if (!o) {
            continue;
        }
        if (!block_reserve(b, *count + o->count)) {
            return false;
        }
        memcpy(b->grid + *count, g->sorted_grid + o->start, o->count * sizeof(*b->grid));
        for (uint32_t j = 0; j < o->count; j++) {
            const float *p = g->sorted[o->start + j];
            b->x[*count] = p[0], b->y[*count] = p[1], b->z[*count] = p[2];
            b->pos[(*count)++] = o->start + j;
        }
    }
    return true;
}

// Squared distances from q to block points [from, to), in a loop the compiler vectorises.
static void block_distances(knn_block *b, size_t from, size_t to, const float q[3])
{
    const float *restrict bx = b->x, *restrict by = b->y, *restrict bz = b->z;
    float *restrict d2 = b->d2;
    const float qx = q[0], qy = q[1], qz = q[2];
    for (size_t i = from; i < to; i++) {
        float ex = bx[i] - qx, ey = by[i] - qy, ez = bz[i] - qz;
        d2[i] = ex * ex + ey * ey + ez * ez;
    }
}

// The indices of d2[0 .. count) <= bound into cand; their number. Few pass (about
// 1.3 K of the block's hundreds): groups of FILTER_GROUP are first tested at once (a
// loop the compiler vectorises) and skipped when none passes.
static size_t filter_under(const float *restrict d2, size_t count, float bound,
                           uint32_t *restrict cand)
{
    size_t m = 0, i = 0;
    for (; i + FILTER_GROUP <= count; i += FILTER_GROUP) {
        int any = 0;
        for (size_t j = 0; j < FILTER_GROUP; j++) {
            any |= d2[i + j] <= bound;
        }
        if (!any) {
            continue;
        }
        for (size_t j = i; j < i + FILTER_GROUP; j++) {
            cand[m] = (uint32_t)j;
            m += d2[j] <= bound;
        }
    }
    for (; i < count; i++) {
        cand[m] = (uint32_t)i;
        m += d2[i] <= bound;
    }
    return m;
}

// The previous search's point and K-th distance at each width: they bound the next
// point's K-th distance.
typedef struct knn_hint {
    float q[3];
    float kth2; /* INFINITY: none */
} knn_hint;

// The `need` nearest of q among the block's first `count` points (their distances
// computed) into nb, as a set, by a bounded quickselect; true when they are provably the
// nearest of all points (the K-th within `inside` of q, inside the block).
static bool nearest_in_block(const knn_grid *g, knn_block *b, size_t count, float inside,
                             const float q[3], int need, knn_hint *hint, knn_list *nb)
{
    const float *d2 = b->d2;
    nb->size = 0;
    nb->capacity = need;
    // Candidates under a bound; any bound that keeps `need` of them gives the exact set
    // (all that it drops are farther than those), one too tight keeps fewer and the next
    // is tried: the previous K-th distance a little widened (density changes slowly: few
    // more than `need`), the triangle inequality's (holds unless the previous
    // neighbourhood left the block), then none.
    float bounds[3] = { INFINITY, INFINITY, INFINITY };
    if (hint->kth2 < INFINITY) {
        float dx = q[0] - hint->q[0], dy = q[1] - hint->q[1], dz = q[2] - hint->q[2];
        double reach = sqrt((double)hint->kth2) + sqrt((double)(dx * dx + dy * dy + dz * dz));
        bounds[0] = hint->kth2 * HINT_WIDEN;
        bounds[1] = (float)(reach * reach * (1.0 + 1e-5));
        bounds[2] = 4.0f * bounds[1];
    }
    size_t m = 0;
    float tried = 0.0f;
    for (int t = 0; t < 3 && m < (size_t)need; t++) {
        const float bound = bounds[t];
        if (!(bound < INFINITY) || !(bound > tried)) {
            continue;
        }
        tried = bound;
        m = filter_under(d2, count, bound, b->cand);
    }
    if (m < (size_t)need) { // the whole block
        m = count;
        for (size_t i = 0; i < count; i++) {
            b->cand[i] = (uint32_t)i;
        }
    }
    float kth2 = INFINITY;
    if (m > 0) {
        size_t take = m < (size_t)need ? m : (size_t)need;
        for (size_t j = 0; j < m; j++) {
            b->vals[j] = d2[b->cand[j]];
        }
        kth2 = sta_knn_select_kth(b->vals, m, take - 1);
        // Those nearer than the K-th, and of the ties at it the first by coordinates (a
        // lattice has many).
        knn_list ties;
        ties.size = 0, ties.capacity = (int)take;
        for (size_t j = 0; j < m; j++) {
            uint32_t i = b->cand[j];
            if (d2[i] < kth2) {
                list_set(nb, nb->size++, d2[i], b->pos[i], b->grid[i]);
            } else if (d2[i] == kth2) {
                offer(g, &ties, d2[i], b->pos[i], b->grid[i]);
            }
        }
        ties.size = ties.size < (int)take - nb->size ? ties.size : (int)take - nb->size;
        for (int j = 0; j < ties.size; j++) {
            list_set(nb, nb->size++, ties.d2[j], ties.pos[j], ties.grid[j]);
        }
    }
    memcpy(hint->q, q, sizeof(hint->q));
    hint->kth2 = nb->size == need ? kth2 : INFINITY;
    return nb->size == need && kth2 <= inside * inside;
}

// Distance from q to the nearest face of its cell c.
static float face_distance(const knn_grid *g, const float q[3], const int64_t c[3])
{
    float face = g->edge;
    for (int a = 0; a < 3; a++) {
        float lo = g->min[a] + (float)c[a] * g->edge;
        float below = q[a] - lo, above = lo + g->edge - q[a], d = below < above ? below : above;
        d = d > 0.0f ? d : 0.0f; // ternaries, not libm's fminf / fmaxf calls (no NaN here)
        face = d < face ? d : face;
    }
    return face;
}

// The search of one cell's points: its block and where the distances stand.
typedef struct knn_cell {
    int64_t c[3];
    knn_block *block;
    knn_hint hints[2]; /* narrow, wider (carried from cell to cell) */
} knn_cell;

// The `need` nearest of q (of cell c) into nb: from the 27 cells' block, the 125 cells'
// when that is not provably enough (or `wide`), shells beyond them when that is not
// either. `done`: the block points whose distances to q are computed. False when out of
// memory.
static bool nearest(const knn_grid *g, knn_cell *cell, const float q[3], int need, bool wide,
                    size_t *done, knn_list *nb)
{
    knn_block *b = cell->block;
    float face = face_distance(g, q, cell->c);
    for (int ring = 1; ring <= 2; ring++) {
        if (ring == 2 && b->wide == 0) {
            b->wide = b->inner;
            if (!block_gather(g, b, &b->wide, cell->c, INNER_CELLS, WIDE_CELLS)) {
                return false;
            }
        }
        size_t count = ring == 2 ? b->wide : b->inner;
        if (*done < count) {
            block_distances(b, *done, count, q);
            *done = count;
        }
        if (ring == 1 && wide) {
            continue;
        }
        if (nearest_in_block(g, b, count, (float)ring * g->edge + face, q, need, &cell->hints[wide],
                             nb)) {
            return true;
        }
    }
    // Rare (sparse points, the edge of a dense patch): sorted, then shells.
    knn_list sorted;
    sorted.size = 0, sorted.capacity = need;
    for (int j = 0; j < nb->size; j++) {
        offer(g, &sorted, nb->d2[j], nb->pos[j], nb->grid[j]);
    }
    nearest_from(g, q, cell->c, face, 2, &sorted);
    memcpy(nb, &sorted, sizeof(*nb));
    return true;
}

sta_status sta_knn_each(const float (*xyz)[3], const int32_t (*grid)[3], size_t n, size_t queries,
                        int k, sta_knn_visit visit, void *user, sta_error *err)
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
    g.grid = grid;
    g.sorted = sta_alloc_array(n, sizeof(*g.sorted));
    g.sorted_grid = sta_alloc_array(n, sizeof(*g.sorted_grid));
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
    int8_t offsets[WIDE_CELLS][3];
    block_offsets_init(offsets);
    knn_block block = { 0 };
    block.offsets = (const int8_t(*)[3])offsets;
    knn_cell cell = { .block = &block };
    for (int w = 0; w < 2; w++) {
        cell.hints[w].kth2 = INFINITY;
    }
    if (!g.sorted || !g.sorted_grid || !g.cell_of || !g.order || !g.cells || !g.slots || !bloom) {
        status = sta_fail(err, STA_ERR_NOMEM, "kNN: out of memory for %zu points", n);
        goto out;
    }
    g.bloom = NULL; // off while the grid is tuned (fill_cells probes with keys directly)
    build_grid(&g, n, k, bloom);
    // Cell by cell: the points of the 27 cells around are gathered once and searched for
    // each of the cell's own points (the 125 cells for a wider neighbourhood); one that
    // may reach beyond those cells (its K-th distance beyond the block's nearest face) is
    // searched again in shells.
    for (size_t cell_index = 0; cell_index < g.cell_count && status == STA_OK; cell_index++) {
        const grid_slot *slot = &g.slots[g.cells[cell_index]];
        bool has_own = false;
        for (uint32_t j = slot->start; j < slot->start + slot->count && !has_own; j++) {
            has_own = g.order[j] < queries;
        }
        if (!has_own) {
            continue; // halo only
        }
        for (int a = 0; a < 3; a++) {
            cell.c[a] = (int64_t)((slot->key >> (CELL_BITS * a)) & ((1u << CELL_BITS) - 1));
        }
        block.inner = block.wide = 0;
        if (!block_gather(&g, &block, &block.inner, cell.c, 0, INNER_CELLS)) {
            status = sta_fail(err, STA_ERR_NOMEM, "kNN: out of memory");
            break;
        }
        for (uint32_t j = slot->start; j < slot->start + slot->count && status == STA_OK; j++) {
            size_t i = g.order[j];
            if (i >= queries) {
                continue;
            }
            const float *q = g.sorted[j];
            knn_list found;
            sta_knn nb;
            size_t done = 0;
            int want = k;
            for (;;) {
                if (!nearest(&g, &cell, q, want + 1, want > k, &done, &found)) {
                    status = sta_fail(err, STA_ERR_NOMEM, "kNN: out of memory");
                    break;
                }
                nb.capacity = want + 1;
                nb.size = found.size;
                memcpy(nb.d2, found.d2, (size_t)found.size * sizeof(float));
                memcpy(nb.grid, found.grid, (size_t)found.size * sizeof(nb.grid[0]));
                int next = visit(user, i, &nb);
                next = next < STA_KNN_MAX ? next : STA_KNN_MAX;
                if (next <= want || (size_t)want + 1 >= n) {
                    break;
                }
                want = next;
            }
        }
    }
out:
    sta_free(g.sorted);
    sta_free(g.sorted_grid);
    sta_free(g.cell_of);
    sta_free(g.order);
    sta_free(g.cells);
    sta_free(bloom);
    sta_free(g.slots);
    block_free(&block);
    return status;
}
