/* SPDX-License-Identifier: MIT
 * Cell moments in blocks of 4 x 4 x 4 cells: a dense array of sums and a small block
 * table (see cell_blocks.h). */
#include "cell_blocks.h"

#include <stdlib.h>
#include <string.h>

#include "core/alloc.h"
#include "key_slots.h"

#define FIRST_CELLS   1024
#define FIRST_SLOTS   256
#define AXIS_MASK     (((uint64_t)1 << STA_MOMENTS_AXIS_BITS) - 1)
#define BLOCK_BITS    (STA_MOMENTS_AXIS_BITS - 2) /* block coordinates an axis */
#define BLOCK_MASK    (((uint64_t)1 << BLOCK_BITS) - 1)
/* Cells a parent of a surface's cells holds (2 x 2 of its 8), the coarser set's reserve. */
#define COARSER_CELLS 4
/* Points in `order` whose positions are asked for ahead of their sums. */
#define GATHER_AHEAD  32

// The key of the block holding the cell `local` (coordinates from m->base).
static uint64_t block_key(const int64_t local[3])
{
    return ((uint64_t)(local[0] >> 2) | (uint64_t)(local[1] >> 2) << BLOCK_BITS |
            (uint64_t)(local[2] >> 2) << (2 * BLOCK_BITS)) +
           1;
}

// The Morton index of x | y << 2 | z << 4 (two bits an axis): a table of 64, fewer
// instructions than the shifts and masks of every look-up.
#define PLACE(i)                                                                                   \
 (((i)&1u) | ((i) >> 2 & 1u) << 1 | ((i) >> 4 & 1u) << 2 | ((i) >> 1 & 1u) << 3 |                  \
  ((i) >> 3 & 1u) << 4 | ((i) >> 5 & 1u) << 5)
#define PLACE_4(i)  PLACE(i), PLACE((i) + 1), PLACE((i) + 2), PLACE((i) + 3)
#define PLACE_16(i) PLACE_4(i), PLACE_4((i) + 4), PLACE_4((i) + 8), PLACE_4((i) + 12)
static const uint8_t places[64] = { PLACE_16(0u), PLACE_16(16u), PLACE_16(32u), PLACE_16(48u) };

// The cell's place in its block: the Morton index of its two low bits an axis (x lowest),
// the order cell_order.h gives a block's cells.
static unsigned place(const int64_t local[3])
{
    return places[((unsigned)local[0] & 3) | ((unsigned)local[1] & 3) << 2 |
                  ((unsigned)local[2] & 3) << 4];
}

// The cell of block `key` at place p (coordinates from m->base).
static void cell_of(uint64_t key, unsigned p, int64_t local[3])
{
    uint64_t packed = key - 1;
    for (int a = 0; a < 3; a++) {
        uint64_t b = (packed >> (a * BLOCK_BITS)) & BLOCK_MASK;
        local[a] = (int64_t)(b << 2 | (p >> a & 1) | (p >> (a + 3) & 1) << 1);
    }
}

// The number of set bits (the baseline x86-64 has no popcount instruction: not a call).
static unsigned bit_count(uint64_t x)
{
    x = x - ((x >> 1) & 0x5555555555555555ull);
    x = (x & 0x3333333333333333ull) + ((x >> 2) & 0x3333333333333333ull);
    x = (x + (x >> 4)) & 0x0F0F0F0F0F0F0F0Full;
    return (unsigned)((x * 0x0101010101010101ull) >> 56);
}

// The index of the cell at place p among its block's cells.
static size_t cell_index(const sta_cell_block *b, unsigned p)
{
    return b->first + bit_count(b->mask & (((uint64_t)1 << p) - 1));
}

// The slot holding block `key`, or the empty one where it would go.
static size_t block_slot(const sta_cell_block *slots, size_t capacity, uint64_t key)
{
    size_t s = sta_key_home_slot(key, capacity);
    while (slots[s].key != 0 && slots[s].key != key) {
        s = (s + 1) & (capacity - 1);
    }
    return s;
}

static bool inside(const int64_t local[3])
{
    return local[0] >= 0 && local[1] >= 0 && local[2] >= 0 && local[0] <= (int64_t)AXIS_MASK &&
           local[1] <= (int64_t)AXIS_MASK && local[2] <= (int64_t)AXIS_MASK;
}

// Room for `cells` cells in the sums (and the loose keys while there are any).
static bool grow_cells(sta_cell_blocks *m, size_t cells)
{
    if (cells <= m->cell_capacity) {
        return true;
    }
    size_t capacity = m->cell_capacity ? m->cell_capacity : FIRST_CELLS;
    while (capacity < cells) {
        capacity *= 2;
    }
    sta_cell_sums *sums = sta_realloc_array(m->sums, capacity, sizeof(*sums));
    if (!sums) {
        return false;
    }
    m->sums = sums;
    if (m->higher) {
        sta_higher_sums *high = sta_realloc_array(m->high, capacity, sizeof(*high));
        if (!high) {
            return false;
        }
        m->high = high;
    }
    if (m->loose) {
        uint64_t *loose = sta_realloc_array(m->loose, capacity, sizeof(*loose));
        if (!loose) {
            return false;
        }
        m->loose = loose;
    }
    m->cell_capacity = capacity;
    return true;
}

// Room for `blocks` blocks in the table (at most half full); the slots move.
static bool grow_blocks(sta_cell_blocks *m, size_t blocks)
{
    if (2 * blocks <= m->capacity) {
        return true;
    }
    size_t capacity = m->capacity ? m->capacity : FIRST_SLOTS;
    while (2 * blocks > capacity) {
        capacity *= 2;
    }
    sta_cell_block *slots = sta_calloc(capacity, sizeof(*slots));
    uint32_t *order = sta_alloc_array(capacity / 2, sizeof(*order));
    if (!slots || !order || capacity > UINT32_MAX) {
        sta_free(slots);
        sta_free(order);
        return false;
    }
    for (size_t i = 0; i < m->blocks; i++) {
        const sta_cell_block *b = &m->slots[m->block_order[i]];
        size_t s = block_slot(slots, capacity, b->key);
        slots[s] = *b;
        order[i] = (uint32_t)s;
    }
    if (m->current != SIZE_MAX) { // (the block appended to is always the last one)
        m->current = order[m->blocks - 1];
    }
    sta_free(m->slots);
    sta_free(m->block_order);
    m->slots = slots;
    m->block_order = order;
    m->capacity = capacity;
    return true;
}

// A new cell at the end of the sums, zero (room for it made beforehand).
static size_t new_cell(sta_cell_blocks *m)
{
    memset(&m->sums[m->used], 0, sizeof(m->sums[0]));
    if (m->high) {
        memset(&m->high[m->used], 0, sizeof(m->high[0]));
    }
    return m->used++;
}

// The cells came out of block order: each cell's key kept beside its sums, to be sorted
// when the set is sealed.
static bool ungroup(sta_cell_blocks *m)
{
    m->loose = sta_alloc_array(m->cell_capacity, sizeof(*m->loose));
    if (!m->loose) {
        return false;
    }
    for (size_t i = 0; i < m->blocks; i++) {
        const sta_cell_block *b = &m->slots[m->block_order[i]];
        size_t c = b->first;
        for (uint64_t bits = b->mask; bits; bits &= bits - 1) {
            m->loose[c++] = b->key << 6 | (uint64_t)__builtin_ctzll(bits);
        }
    }
    m->current = SIZE_MAX;
    return true;
}

// The index of cell `local` to add to, made when new; SIZE_MAX when out of memory.
static size_t cell_for(sta_cell_blocks *m, const int64_t local[3])
{
    uint64_t key = block_key(local);
    unsigned p = place(local);
    if (!m->loose) {
        sta_cell_block *b = m->current != SIZE_MAX ? &m->slots[m->current] : NULL;
        if (b && b->key == key && (b->mask >> p) == 1) {
            return m->used - 1; // the last cell again
        }
        if (b && b->key == key && (b->mask >> p) == 0) { // the block's next cell
            if (!grow_cells(m, m->used + 1)) {
                return SIZE_MAX;
            }
            b->mask |= (uint64_t)1 << p;
            return new_cell(m);
        }
        size_t s = block_slot(m->slots, m->capacity, key);
        if (m->slots[s].key == 0) { // a new block
            if (!grow_blocks(m, m->blocks + 1) || !grow_cells(m, m->used + 1)) {
                return SIZE_MAX;
            }
            s = block_slot(m->slots, m->capacity, key);
            m->slots[s] = (sta_cell_block){ .key = key,
                                            .mask = (uint64_t)1 << p,
                                            .first = (uint32_t)m->used };
            m->block_order[m->blocks++] = (uint32_t)s;
            m->current = s;
            return new_cell(m);
        }
        if (!ungroup(m)) { // an earlier block again, or a cell before the last
            return SIZE_MAX;
        }
    }
    if (!grow_cells(m, m->used + 1)) {
        return SIZE_MAX;
    }
    m->loose[m->used] = key << 6 | p;
    return new_cell(m);
}

// Adds sums c (and the higher sums h, NULL: none) to cell `local`.
static bool add_cell(sta_cell_blocks *m, const int64_t local[3], const sta_cell_sums *c,
                     const sta_higher_sums *h)
{
    size_t i = cell_for(m, local);
    if (i == SIZE_MAX) {
        return false;
    }
    sta_cell_sums *s = &m->sums[i];
    s->n += c->n;
    for (int a = 0; a < 3; a++) {
        s->s1[a] += c->s1[a];
    }
    for (int t = 0; t < 6; t++) {
        s->s2[t] += c->s2[t];
    }
    if (m->high && h) {
        for (int a = 0; a < 3; a++) {
            m->high[i].s3[a] += h->s3[a];
        }
        m->high[i].s4 += h->s4;
    }
    return true;
}

typedef struct loose_cell {
    uint64_t key;  /* block key << 6 | place */
    uint32_t cell; /* index in the loose sums */
} loose_cell;

static int by_key(const void *a, const void *b)
{
    const loose_cell *x = a, *y = b;
    if (x->key != y->key) {
        return x->key < y->key ? -1 : 1;
    }
    return x->cell < y->cell ? -1 : x->cell > y->cell;
}

// Sorts loose cells into blocks (the same cell's entries added up); nothing when grouped.
static sta_status seal(sta_cell_blocks *m, sta_error *err)
{
    if (!m->loose) {
        return STA_OK;
    }
    size_t n = m->used;
    loose_cell *sorted = sta_alloc_array(n ? n : 1, sizeof(*sorted));
    sta_cell_sums *sums = sta_alloc_array(m->cell_capacity, sizeof(*sums));
    sta_higher_sums *high = m->high ? sta_alloc_array(m->cell_capacity, sizeof(*high)) : NULL;
    if (!sorted || !sums || (m->high && !high)) {
        sta_free(sorted);
        sta_free(sums);
        sta_free(high);
        return sta_fail(err, STA_ERR_NOMEM, "cell blocks: out of memory for %zu cells", n);
    }
    for (size_t i = 0; i < n; i++) {
        sorted[i] = (loose_cell){ .key = m->loose[i], .cell = (uint32_t)i };
    }
    qsort(sorted, n, sizeof(*sorted), by_key);
    sta_cell_sums *old = m->sums;
    sta_higher_sums *old_high = m->high;
    sta_free(m->loose);
    m->loose = NULL;
    m->sums = sums;
    m->high = high;
    m->used = 0;
    m->blocks = 0;
    m->current = SIZE_MAX;
    memset(m->slots, 0, m->capacity * sizeof(*m->slots));
    bool ok = true;
    for (size_t i = 0; i < n && ok; i++) { // (in block order now: no cell is loose again)
        int64_t local[3];
        cell_of(sorted[i].key >> 6, (unsigned)(sorted[i].key & 63), local);
        ok = add_cell(m, local, &old[sorted[i].cell], old_high ? &old_high[sorted[i].cell] : NULL);
    }
    sta_free(old);
    sta_free(old_high);
    sta_free(sorted);
    return ok ? STA_OK : sta_fail(err, STA_ERR_NOMEM, "cell blocks: out of memory");
}

sta_status sta_cell_blocks_init(sta_cell_blocks *m, int level, bool higher, const int64_t origin[3],
                                const int32_t lo[3], const int32_t hi[3], sta_error *err)
{
    memset(m, 0, sizeof(*m));
    m->current = SIZE_MAX;
    if (level < 0 || level > STA_MOMENTS_MAX_LEVEL) {
        return sta_fail(err, STA_ERR_ARG, "cell blocks: level %d out of range", level);
    }
    m->level = level;
    m->higher = higher;
    for (int a = 0; a < 3; a++) {
        m->origin[a] = origin[a];
        // One empty cell below and two above stay addressable (vertex boxes reach past the
        // set), the first block's corner a multiple of 4 cells from the scene corner.
        m->base[a] = (((((int64_t)lo[a] - origin[a]) >> level) - 1) >> 2) * 4; // (floored)
        int64_t top = ((int64_t)hi[a] - origin[a]) >> level;
        if (top - m->base[a] + 3 > (int64_t)AXIS_MASK) {
            return sta_fail(err, STA_ERR_ARG, "cell blocks: level %d spans too many cells", level);
        }
    }
    if (!grow_cells(m, FIRST_CELLS) || !grow_blocks(m, FIRST_SLOTS / 2)) {
        sta_cell_blocks_release(m);
        return sta_fail(err, STA_ERR_NOMEM, "cell blocks: out of memory");
    }
    return STA_OK;
}

bool sta_cell_blocks_reserve(sta_cell_blocks *m, size_t cells)
{
    return grow_cells(m, cells) && grow_blocks(m, cells);
}

sta_status sta_cell_blocks_add(sta_cell_blocks *m, const int32_t (*grid)[3], size_t n,
                               const uint32_t *order, sta_error *err)
{
    int level = m->level;
    // Consecutive points of one cell are summed first (a run: one look-up).
    int64_t run_cell[3] = { -1, -1, -1 };
    sta_moment_sums run = { 0 };
    for (size_t j = 0; j <= n; j++) {
        int64_t u[3], local[3] = { -1, -1, -1 }, d[3] = { 0, 0, 0 };
        size_t i = j < n ? (order ? order[j] : j) : 0;
        if (order && j + GATHER_AHEAD < n) { // (a random read each: asked for early)
            __builtin_prefetch(grid[order[j + GATHER_AHEAD]]);
        }
        if (j < n) {
            for (int a = 0; a < 3; a++) {
                u[a] = (int64_t)grid[i][a] - m->origin[a];
                local[a] = (u[a] >> level) - m->base[a];
                d[a] = u[a] & (((int64_t)1 << level) - 1);
            }
            if (!inside(local)) {
                return sta_fail(err, STA_ERR_ARG, "cell blocks: point %zu outside the set's box",
                                i);
            }
        }
        if (j == n || memcmp(local, run_cell, sizeof(local)) != 0) {
            if (run.n > 0) {
                const sta_cell_sums c = { .n = run.n,
                                          .s1 = { run.s1[0], run.s1[1], run.s1[2] },
                                          .s2 = { run.s2[0], run.s2[1], run.s2[2], run.s2[3],
                                                  run.s2[4], run.s2[5] } };
                const sta_higher_sums h = { .s3 = { run.s3[0], run.s3[1], run.s3[2] },
                                            .s4 = run.s4 };
                if (!add_cell(m, run_cell, &c, &h)) {
                    return sta_fail(err, STA_ERR_NOMEM, "cell blocks: out of memory");
                }
            }
            if (j == n) {
                break;
            }
            memcpy(run_cell, local, sizeof(local));
            memset(&run, 0, sizeof(run));
        }
        run.n++;
        run.s1[0] += d[0], run.s1[1] += d[1], run.s1[2] += d[2];
        run.s2[0] += d[0] * d[0], run.s2[1] += d[0] * d[1], run.s2[2] += d[0] * d[2];
        run.s2[3] += d[1] * d[1], run.s2[4] += d[1] * d[2], run.s2[5] += d[2] * d[2];
        if (m->higher) {
            uint64_t dd = (uint64_t)(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
            run.s3[0] += (uint64_t)d[0] * dd, run.s3[1] += (uint64_t)d[1] * dd;
            run.s3[2] += (uint64_t)d[2] * dd, run.s4 += dd * dd;
        }
    }
    return seal(m, err);
}

sta_status sta_cell_blocks_coarsen(const sta_cell_blocks *fine, sta_cell_blocks *coarse,
                                   sta_error *err)
{
    int level = fine->level;
    static const sta_higher_sums none = { { 0 }, 0 };
    // (a surface's cells have about a quarter as many parents; more grow the arrays)
    if (coarse->used == 0 && !sta_cell_blocks_reserve(coarse, fine->used / COARSER_CELLS)) {
        return sta_fail(err, STA_ERR_NOMEM, "cell blocks: out of memory");
    }
    for (size_t i = 0; i < fine->blocks; i++) {
        const sta_cell_block *b = &fine->slots[fine->block_order[i]];
        size_t index = b->first;
        for (uint64_t bits = b->mask; bits; bits &= bits - 1, index++) {
            int64_t cell[3], local[3], o[3];
            cell_of(b->key, (unsigned)__builtin_ctzll(bits), cell);
            for (int a = 0; a < 3; a++) {
                cell[a] += fine->base[a];
                // The parent's corner is 0 or one fine cell below the child's: sums move by o.
                o[a] = (cell[a] & 1) << level;
                local[a] = (cell[a] >> 1) - coarse->base[a];
            }
            if (!inside(local)) {
                continue; // (cannot happen for a set over the same box)
            }
            const sta_cell_sums *c = &fine->sums[index];
            sta_cell_sums moved = { .n = c->n };
            for (int r = 0, t = 0; r < 3; r++) {
                moved.s1[r] = c->s1[r] + c->n * o[r];
                for (int q = r; q < 3; q++, t++) {
                    moved.s2[t] = c->s2[t] + o[r] * c->s1[q] + o[q] * c->s1[r] + c->n * o[r] * o[q];
                }
            }
            sta_higher_sums high = { { 0 }, 0 };
            if (coarse->higher) { // (a finer set without them: its cells' sums moved, s3 s4 0)
                sta_higher_sums_add_moved(&high, c, fine->high ? &fine->high[index] : &none, o);
            }
            if (!add_cell(coarse, local, &moved, &high)) {
                return sta_fail(err, STA_ERR_NOMEM, "cell blocks: out of memory");
            }
        }
    }
    return seal(coarse, err);
}

// Whether cell a (coordinates >= 0) comes before cell b in Morton order: the axis whose
// coordinates differ in the highest bit decides, z before y before x on the same bit.
static bool morton_less(const int64_t a[3], const int64_t b[3])
{
    int axis = 2;
    uint64_t top = (uint64_t)(a[2] ^ b[2]);
    for (int k = 1; k >= 0; k--) {
        uint64_t x = (uint64_t)(a[k] ^ b[k]);
        if (top < x && top < (x ^ top)) { // (x's highest bit above top's)
            axis = k;
            top = x;
        }
    }
    return a[axis] < b[axis];
}

// Adds point p (offsets d in its cell) to the sums s.
static void add_point(sta_moment_sums *s, const int64_t d[3], bool higher)
{
    s->n++;
    s->s1[0] += d[0], s->s1[1] += d[1], s->s1[2] += d[2];
    s->s2[0] += d[0] * d[0], s->s2[1] += d[0] * d[1], s->s2[2] += d[0] * d[2];
    s->s2[3] += d[1] * d[1], s->s2[4] += d[1] * d[2], s->s2[5] += d[2] * d[2];
    if (higher) {
        uint64_t dd = (uint64_t)(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        s->s3[0] += (uint64_t)d[0] * dd, s->s3[1] += (uint64_t)d[1] * dd;
        s->s3[2] += (uint64_t)d[2] * dd, s->s4 += dd * dd;
    }
}

sta_status sta_cell_blocks_add_children(sta_cell_blocks *m, const int32_t (*a)[3], size_t na,
                                        const int32_t (*b)[3], size_t nb, const int32_t corner[3],
                                        const sta_cell_moments *wanted, sta_error *err)
{
    const int level = m->level, up = level + 1;
    const int32_t(*list[2])[3] = { a, b };
    const size_t count[2] = { na, nb };
    size_t at[2] = { 0, 0 };
    while (at[0] < na || at[1] < nb) {
        // The lists' next parents, from the corner (the Morton order's) and the scene's.
        int64_t from_corner[2][3], parent[2][3];
        for (int l = 0; l < 2; l++) {
            for (int a2 = 0; a2 < 3 && at[l] < count[l]; a2++) {
                int32_t c = list[l][at[l]][a2];
                from_corner[l][a2] = ((int64_t)c - corner[a2]) >> up;
                parent[l][a2] = ((int64_t)c - m->origin[a2]) >> up;
            }
        }
        int first = at[0] >= na ? 1 : at[1] >= nb ? 0 : morton_less(from_corner[1], from_corner[0]);
        const int64_t *p = parent[first];
        bool take = !wanted || sta_cell_moments_has(wanted, p);
        if (!take) { // (most parents: their runs passed over without the sums)
            for (int l = 0; l < 2; l++) {
                const int64_t edge = (int64_t)1 << up; // (p may be negative: no shift of it)
                const int64_t lo[3] = { p[0] * edge, p[1] * edge, p[2] * edge };
                const int64_t hi[3] = { lo[0] + edge, lo[1] + edge, lo[2] + edge };
                for (; at[l] < count[l]; at[l]++) {
                    const int32_t *q = list[l][at[l]];
                    int64_t u[3] = { (int64_t)q[0] - m->origin[0], (int64_t)q[1] - m->origin[1],
                                     (int64_t)q[2] - m->origin[2] };
                    if (u[0] < lo[0] || u[0] >= hi[0] || u[1] < lo[1] || u[1] >= hi[1] ||
                        u[2] < lo[2] || u[2] >= hi[2]) {
                        break;
                    }
                }
            }
            continue;
        }
        sta_moment_sums child[8];
        memset(child, 0, sizeof(child));
        for (int l = 0; l < 2; l++) { // (both lists may hold points of this parent)
            for (; at[l] < count[l]; at[l]++) {
                const int32_t *q = list[l][at[l]];
                int64_t u[3] = { (int64_t)q[0] - m->origin[0], (int64_t)q[1] - m->origin[1],
                                 (int64_t)q[2] - m->origin[2] };
                if ((u[0] >> up) != p[0] || (u[1] >> up) != p[1] || (u[2] >> up) != p[2]) {
                    break;
                }
                if (take) {
                    const int64_t d[3] = { u[0] & (((int64_t)1 << level) - 1),
                                           u[1] & (((int64_t)1 << level) - 1),
                                           u[2] & (((int64_t)1 << level) - 1) };
                    int k = (int)((u[0] >> level & 1) | (u[1] >> level & 1) << 1 |
                                  (u[2] >> level & 1) << 2);
                    add_point(&child[k], d, m->higher);
                }
            }
        }
        for (int k = 0; take && k < 8; k++) { // (in their place's order: k is its low bits)
            if (child[k].n == 0) {
                continue;
            }
            const int64_t local[3] = { 2 * p[0] + (k & 1) - m->base[0],
                                       2 * p[1] + (k >> 1 & 1) - m->base[1],
                                       2 * p[2] + (k >> 2) - m->base[2] };
            const sta_moment_sums *r = &child[k];
            const sta_cell_sums c = { .n = r->n,
                                      .s1 = { r->s1[0], r->s1[1], r->s1[2] },
                                      .s2 = { r->s2[0], r->s2[1], r->s2[2], r->s2[3], r->s2[4],
                                              r->s2[5] } };
            const sta_higher_sums h = { .s3 = { r->s3[0], r->s3[1], r->s3[2] }, .s4 = r->s4 };
            if (!inside(local)) {
                return sta_fail(err, STA_ERR_ARG, "cell blocks: a point outside the set's box");
            }
            if (!add_cell(m, local, &c, &h)) {
                return sta_fail(err, STA_ERR_NOMEM, "cell blocks: out of memory");
            }
        }
    }
    return seal(m, err);
}

sta_status sta_cell_blocks_add_moments(sta_cell_blocks *m, const sta_cell_moments *cells,
                                       sta_error *err)
{
    if (!m->loose && !ungroup(m)) { // (slots in hash order: sorted once at the end)
        return sta_fail(err, STA_ERR_NOMEM, "cell blocks: out of memory");
    }
    for (size_t s = 0; s < cells->capacity; s++) {
        if (cells->keys[s] == 0) {
            continue;
        }
        uint64_t packed = cells->keys[s] - 1;
        int64_t local[3];
        for (int a = 0; a < 3; a++) {
            int64_t cell =
                (int64_t)((packed >> (a * STA_MOMENTS_AXIS_BITS)) & AXIS_MASK) + cells->base[a];
            local[a] = cell - m->base[a];
        }
        if (!inside(local)) {
            return sta_fail(err, STA_ERR_ARG, "cell blocks: a cell outside the set's box");
        }
        if (!add_cell(m, local, &cells->sums[s], cells->high ? &cells->high[s] : NULL)) {
            return sta_fail(err, STA_ERR_NOMEM, "cell blocks: out of memory");
        }
    }
    return seal(m, err);
}

void sta_cell_blocks_release(sta_cell_blocks *m)
{
    sta_free(m->sums);
    sta_free(m->high);
    sta_free(m->slots);
    sta_free(m->block_order);
    sta_free(m->loose);
    memset(m, 0, sizeof(*m));
    m->current = SIZE_MAX;
}

// The block slot of cell `local` (coordinates from m->base, inside), NULL when the block
// does not exist.
static const sta_cell_block *block_of(const sta_cell_blocks *m, const int64_t local[3])
{
    const sta_cell_block *b = &m->slots[block_slot(m->slots, m->capacity, block_key(local))];
    return b->key != 0 ? b : NULL;
}

const sta_cell_sums *sta_cell_blocks_find(const sta_cell_blocks *m, const int64_t cell[3],
                                          size_t *index)
{
    int64_t local[3] = { cell[0] - m->base[0], cell[1] - m->base[1], cell[2] - m->base[2] };
    const sta_cell_block *b = inside(local) && m->capacity ? block_of(m, local) : NULL;
    unsigned p = place(local);
    if (!b || !((b->mask >> p) & 1)) {
        return NULL;
    }
    *index = cell_index(b, p);
    return &m->sums[*index];
}

int64_t sta_cell_blocks_count(const sta_cell_blocks *m, const int64_t cell[3])
{
    size_t index;
    const sta_cell_sums *c = sta_cell_blocks_find(m, cell, &index);
    return c ? c->n : 0;
}

// The cells of the 8 around `vertex` that exist: their indices and their offsets k (bit a:
// one cell up along axis a) from the lowest; returns how many. The 8 lie in 1, 2, 4 or 8
// blocks (an axis crosses into the next block where the lowest cell is a block's last):
// each block probed once.
static int vertex_cells(const sta_cell_blocks *m, const int64_t vertex[3], size_t index[8],
                        int offset[8])
{
    int64_t lo[3];
    unsigned cross = 0; // (bit a: axis a crosses)
    for (int a = 0; a < 3; a++) {
        lo[a] = vertex[a] - 1 - m->base[a];
        cross |= (unsigned)((lo[a] & 3) == 3) << a;
    }
    const sta_cell_block *blocks[8];
    unsigned probed = 0;
    int found = 0;
    for (int k = 0; k < 8; k++) {
        const int64_t c[3] = { lo[0] + (k & 1), lo[1] + (k >> 1 & 1), lo[2] + (k >> 2) };
        unsigned j = (unsigned)k & cross; // the cell's block among the 8's (blocks are
                                          // wholly inside or outside the set's range)
        if (!((probed >> j) & 1)) {
            blocks[j] = inside(c) && m->capacity ? block_of(m, c) : NULL;
            probed |= 1u << j;
        }
        const sta_cell_block *b = blocks[j];
        unsigned p = place(c);
        if (b && ((b->mask >> p) & 1)) {
            index[found] = cell_index(b, p);
            offset[found++] = k;
        }
    }
    return found;
}

void sta_cell_blocks_vertex_lower(const sta_cell_blocks *m, const int64_t vertex[3],
                                  sta_moment_sums *out)
{
    size_t index[8];
    int offset[8];
    int found = vertex_cells(m, vertex, index, offset);
    // Each cell's sums move to the box's corner by o (0 or one cell, w, an axis), in
    // integers: s1 + n o and s2 + o s1^T + s1 o^T + n o o^T. The moved parts are summed per
    // axis over the cells moved along it (their n, s1; and n over those moved along two
    // axes) and scaled by w once: the same integers, fewer products.
    int64_t n = 0, s1[3] = { 0, 0, 0 }, s2[6] = { 0, 0, 0, 0, 0, 0 };
    int64_t moved_n[3] = { 0, 0, 0 }, moved_s1[3][3] = { { 0 } }, both_n[3] = { 0, 0, 0 };
    for (int i = 0; i < found; i++) {
        int k = offset[i];
        const sta_cell_sums *c = &m->sums[index[i]];
        n += c->n;
        for (int t = 0; t < 3; t++) {
            s1[t] += c->s1[t];
        }
        for (int t = 0; t < 6; t++) {
            s2[t] += c->s2[t];
        }
        for (int r = 0; r < 3; r++) {
            if (k >> r & 1) {
                moved_n[r] += c->n;
                for (int q = 0; q < 3; q++) {
                    moved_s1[r][q] += c->s1[q];
                }
            }
        }
        both_n[0] += (k & 3) == 3 ? c->n : 0; // axes 0 and 1
        both_n[1] += (k & 5) == 5 ? c->n : 0; // 0 and 2
        both_n[2] += (k & 6) == 6 ? c->n : 0; // 1 and 2
    }
    const int64_t w = (int64_t)1 << m->level;
    for (int r = 0, t = 0; r < 3; r++) {
        for (int q = r; q < 3; q++, t++) {
            int64_t nn = r == q ? moved_n[r] : both_n[r + q - 1];
            s2[t] += w * (moved_s1[r][q] + moved_s1[q][r]) + w * w * nn;
        }
    }
    for (int r = 0; r < 3; r++) {
        s1[r] += w * moved_n[r];
    }
    memset(out, 0, sizeof(*out));
    out->n = n;
    memcpy(out->s1, s1, sizeof(s1));
    memcpy(out->s2, s2, sizeof(s2));
}

void sta_cell_blocks_vertex_higher(const sta_cell_blocks *m, const int64_t vertex[3],
                                   sta_moment_sums *out)
{
    sta_higher_sums h = { { 0 }, 0 };
    if (m->high) {
        size_t index[8];
        int offset[8];
        int found = vertex_cells(m, vertex, index, offset);
        for (int i = 0; i < found; i++) {
            int k = offset[i];
            const int64_t o[3] = { (int64_t)(k & 1) << m->level, (int64_t)(k >> 1 & 1) << m->level,
                                   (int64_t)(k >> 2) << m->level };
            sta_higher_sums_add_moved(&h, &m->sums[index[i]], &m->high[index[i]], o);
        }
    }
    memcpy(out->s3, h.s3, sizeof(h.s3));
    out->s4 = h.s4;
}
