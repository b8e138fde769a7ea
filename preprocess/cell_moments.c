/* SPDX-License-Identifier: MIT
 * Per-cell exact moments of one grid level and their sums over blocks of cells. */
#include "cell_moments.h"

#include <string.h>

#include "core/alloc.h"
#include "key_slots.h"

#define FIRST_CAPACITY 1024
/* Cells a parent of a surface's cells holds (2 x 2 of its 8), the coarser set's reserve. */
#define COARSER_CELLS  4
/* Points in `order` whose positions are asked for ahead of their sums. */
#define GATHER_AHEAD   32
#define AXIS_MASK      (((uint64_t)1 << STA_MOMENTS_AXIS_BITS) - 1)

static uint64_t pack(const int64_t local[3])
{
    return ((uint64_t)local[0] | (uint64_t)local[1] << STA_MOMENTS_AXIS_BITS |
            (uint64_t)local[2] << (2 * STA_MOMENTS_AXIS_BITS)) +
           1;
}

static bool grow(sta_cell_moments *m)
{
    void *const values[] = { m->sums, m->high };
    const size_t sizes[] = { sizeof(*m->sums), sizeof(*m->high) };
    void *grown[2];
    if (!sta_key_slots_double(&m->keys, &m->capacity, values, sizes, grown, 2)) {
        return false;
    }
    m->sums = grown[0];
    m->high = grown[1];
    return true;
}

// The slot of cell `local`, created empty when new; SIZE_MAX when out of memory. The
// higher sums' array comes with the first cell of a set that keeps them.
static size_t cell_at(sta_cell_moments *m, const int64_t local[3])
{
    if (m->higher && !m->high && !(m->high = sta_calloc(m->capacity, sizeof(*m->high)))) {
        return SIZE_MAX;
    }
    uint64_t key = pack(local);
    size_t s = sta_key_slot(m->keys, m->capacity, key);
    if (m->keys[s] == 0) {
        if (2 * (m->used + 1) > m->capacity) {
            if (!grow(m)) {
                return SIZE_MAX;
            }
            s = sta_key_slot(m->keys, m->capacity, key);
        }
        m->keys[s] = key;
        if (m->sums) {
            memset(&m->sums[s], 0, sizeof(m->sums[s]));
        }
        if (m->high) {
            memset(&m->high[s], 0, sizeof(m->high[s]));
        }
        m->used++;
    }
    return s;
}

// Cell coordinates (from the scene corner) relative to the set's lowest cell; false when
// they lie outside what the set addresses.
static bool local_of(const sta_cell_moments *m, const int64_t cell[3], int64_t local[3])
{
    for (int a = 0; a < 3; a++) {
        local[a] = cell[a] - m->base[a];
        if (local[a] < 0 || local[a] > (int64_t)AXIS_MASK) {
            return false;
        }
    }
    return true;
}

void sta_higher_sums_add_moved(sta_higher_sums *dst, const sta_cell_sums *c,
                               const sta_higher_sums *h, const int64_t o[3])
{
    const uint64_t n = (uint64_t)c->n, q[3] = { (uint64_t)o[0], (uint64_t)o[1], (uint64_t)o[2] };
    const uint64_t s1[3] = { (uint64_t)c->s1[0], (uint64_t)c->s1[1], (uint64_t)c->s1[2] };
    const uint64_t s2[3][3] = { { (uint64_t)c->s2[0], (uint64_t)c->s2[1], (uint64_t)c->s2[2] },
                                { (uint64_t)c->s2[1], (uint64_t)c->s2[3], (uint64_t)c->s2[4] },
                                { (uint64_t)c->s2[2], (uint64_t)c->s2[4], (uint64_t)c->s2[5] } };
    uint64_t trace = s2[0][0] + s2[1][1] + s2[2][2], qq = 0, qs1 = 0, qs2q = 0, qs3 = 0;
    uint64_t s2q[3];
    for (int r = 0; r < 3; r++) {
        s2q[r] = s2[r][0] * q[0] + s2[r][1] * q[1] + s2[r][2] * q[2];
        qq += q[r] * q[r];
        qs1 += q[r] * s1[r];
        qs3 += q[r] * h->s3[r];
    }
    for (int r = 0; r < 3; r++) {
        qs2q += q[r] * s2q[r];
        // sum (d + o) |d + o|^2, with |d + o|^2 = |d|^2 + 2 d.o + |o|^2
        dst->s3[r] +=
            h->s3[r] + 2 * s2q[r] + qq * s1[r] + q[r] * trace + 2 * q[r] * qs1 + n * q[r] * qq;
    }
    dst->s4 += h->s4 + 4 * qs2q + n * qq * qq + 4 * qs3 + 2 * qq * trace + 4 * qq * qs1;
}

static sta_status init_set(sta_cell_moments *m, int level, const int64_t origin[3],
                           const int32_t lo[3], const int32_t hi[3], bool sums, sta_error *err)
{
    memset(m, 0, sizeof(*m));
    if (level < 0 || level > STA_MOMENTS_MAX_LEVEL) {
        return sta_fail(err, STA_ERR_ARG, "cell moments: level %d out of range", level);
    }
    m->level = level;
    for (int a = 0; a < 3; a++) {
        m->origin[a] = origin[a];
        // One empty cell below and two above stay addressable (blocks reach past the set).
        m->base[a] = (((int64_t)lo[a] - origin[a]) >> level) - 1;
        int64_t top = ((int64_t)hi[a] - origin[a]) >> level;
        if (top - m->base[a] + 3 > (int64_t)AXIS_MASK) {
            return sta_fail(err, STA_ERR_ARG, "cell moments: level %d spans too many cells", level);
        }
    }
    m->capacity = FIRST_CAPACITY;
    m->keys = sta_calloc(m->capacity, sizeof(*m->keys));
    m->sums = sums ? sta_alloc_array(m->capacity, sizeof(*m->sums)) : NULL;
    if (!m->keys || (sums && !m->sums)) {
        sta_cell_moments_release(m);
        return sta_fail(err, STA_ERR_NOMEM, "cell moments: out of memory");
    }
    return STA_OK;
}

sta_status sta_cell_moments_init(sta_cell_moments *m, int level, const int64_t origin[3],
                                 const int32_t lo[3], const int32_t hi[3], sta_error *err)
{
    return init_set(m, level, origin, lo, hi, true, err);
}

sta_status sta_cell_moments_init_marks(sta_cell_moments *m, int level, const int64_t origin[3],
                                       const int32_t lo[3], const int32_t hi[3], sta_error *err)
{
    return init_set(m, level, origin, lo, hi, false, err);
}

bool sta_cell_moments_reserve(sta_cell_moments *m, size_t cells)
{
    while (2 * cells > m->capacity) {
        if (!grow(m)) {
            return false;
        }
    }
    return true;
}

bool sta_cell_moments_mark(sta_cell_moments *m, const int64_t cell[3])
{
    int64_t local[3];
    return !local_of(m, cell, local) || cell_at(m, local) != SIZE_MAX;
}

bool sta_cell_moments_has(const sta_cell_moments *m, const int64_t cell[3])
{
    int64_t local[3];
    return local_of(m, cell, local) &&
           m->keys[sta_key_slot(m->keys, m->capacity, pack(local))] != 0;
}

int64_t sta_cell_moments_count(const sta_cell_moments *m, const int64_t cell[3])
{
    int64_t local[3];
    if (!local_of(m, cell, local)) {
        return 0;
    }
    size_t s = sta_key_slot(m->keys, m->capacity, pack(local));
    return m->keys[s] != 0 ? m->sums[s].n : 0;
}

// Adds the sums of a run of points of one cell to it.
static bool add_run(sta_cell_moments *m, const int64_t local[3], const sta_moment_sums *run)
{
    size_t s = cell_at(m, local);
    if (s == SIZE_MAX) {
        return false;
    }
    sta_cell_sums *c = &m->sums[s];
    c->n += run->n;
    for (int a = 0; a < 3; a++) {
        c->s1[a] += run->s1[a];
    }
    for (int t = 0; t < 6; t++) {
        c->s2[t] += run->s2[t];
    }
    if (m->high) {
        for (int a = 0; a < 3; a++) {
            m->high[s].s3[a] += run->s3[a];
        }
        m->high[s].s4 += run->s4;
    }
    return true;
}

sta_status sta_cell_moments_add(sta_cell_moments *m, const int32_t (*grid)[3], size_t n,
                                const uint32_t *order, const sta_cell_moments *only, sta_error *err)
{
    if (!m->sums) {
        return sta_fail(err, STA_ERR_ARG, "cell moments: a set of marks takes no points");
    }
    int level = m->level;
    // Consecutive points of one cell are summed first (a run: one look-up).
    int64_t run_cell[3] = { -1, -1, -1 }, only_cell[3] = { -1, -1, -1 };
    bool only_has = false;
    sta_moment_sums run = { 0 };
    for (size_t j = 0; j < n; j++) {
        size_t i = order ? order[j] : j;
        if (order && j + GATHER_AHEAD < n) { // (a random read each: asked for early)
            __builtin_prefetch(grid[order[j + GATHER_AHEAD]]);
        }
        int64_t u[3], local[3], d[3];
        for (int a = 0; a < 3; a++) {
            u[a] = (int64_t)grid[i][a] - m->origin[a];
        }
        if (only) {
            int64_t cell[3] = { u[0] >> only->level, u[1] >> only->level, u[2] >> only->level };
            if (memcmp(cell, only_cell, sizeof(cell)) != 0) { // (points come in runs of a cell)
                memcpy(only_cell, cell, sizeof(cell));
                only_has = sta_cell_moments_has(only, cell);
            }
            if (!only_has) {
                continue;
            }
        }
        for (int a = 0; a < 3; a++) {
            local[a] = (u[a] >> level) - m->base[a];
            d[a] = u[a] & (((int64_t)1 << level) - 1);
        }
        if (memcmp(local, run_cell, sizeof(local)) != 0) {
            if (run.n > 0 && !add_run(m, run_cell, &run)) {
                return sta_fail(err, STA_ERR_NOMEM, "cell moments: out of memory");
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
    if (run.n > 0 && !add_run(m, run_cell, &run)) {
        return sta_fail(err, STA_ERR_NOMEM, "cell moments: out of memory");
    }
    return STA_OK;
}

void sta_cell_moments_release(sta_cell_moments *m)
{
    sta_free(m->keys);
    sta_free(m->sums);
    sta_free(m->high);
    memset(m, 0, sizeof(*m));
}

void sta_cell_moments_block(const sta_cell_moments *m, const int64_t anchor[3], int cells,
                            sta_moment_sums *out)
{
    for (int z = 0, i = 0; z < cells; z++) {
        for (int y = 0; y < cells; y++) {
            for (int x = 0; x < cells; x++, i++) {
                memset(&out[i], 0, sizeof(out[i]));
                int64_t local[3] = { anchor[0] - m->base[0] + x, anchor[1] - m->base[1] + y,
                                     anchor[2] - m->base[2] + z };
                if (local[0] < 0 || local[1] < 0 || local[2] < 0 || local[0] > (int64_t)AXIS_MASK ||
                    local[1] > (int64_t)AXIS_MASK || local[2] > (int64_t)AXIS_MASK) {
                    continue; // beyond the set: empty
                }
                size_t s = sta_key_slot(m->keys, m->capacity, pack(local));
                if (m->keys[s] == 0) {
                    continue;
                }
                // The cell's sums move from its corner to the block's by o (exact).
                const sta_cell_sums *c = &m->sums[s];
                int64_t o[3] = { (int64_t)x << m->level, (int64_t)y << m->level,
                                 (int64_t)z << m->level };
                out[i].n = c->n;
                for (int a = 0; a < 3; a++) {
                    out[i].s1[a] = c->s1[a] + c->n * o[a];
                }
                for (int r = 0, t = 0; r < 3; r++) {
                    for (int q = r; q < 3; q++, t++) {
                        out[i].s2[t] =
                            c->s2[t] + o[r] * c->s1[q] + o[q] * c->s1[r] + c->n * o[r] * o[q];
                    }
                }
                if (m->high) {
                    sta_higher_sums h = { { 0 }, 0 };
                    sta_higher_sums_add_moved(&h, c, &m->high[s], o);
                    memcpy(out[i].s3, h.s3, sizeof(h.s3));
                    out[i].s4 = h.s4;
                }
            }
        }
    }
}

// The packed key of the lowest of vertex's 8 cells; false when they reach beyond the set's
// addressable cells (then the general block, which skips what lies outside).
static bool vertex_key(const sta_cell_moments *m, const int64_t vertex[3], uint64_t *key)
{
    int64_t local[3];
    for (int a = 0; a < 3; a++) {
        local[a] = vertex[a] - 1 - m->base[a];
        if (local[a] < 0 || local[a] + 1 > (int64_t)AXIS_MASK) {
            return false;
        }
    }
    *key = pack(local);
    return true;
}

// The key of the cell d (0 or 1 an axis) above the lowest of a vertex's 8 (packed
// coordinates add), and its slot; SIZE_MAX when the cell does not exist.
static inline size_t corner_slot(const sta_cell_moments *m, uint64_t key, const int64_t d[3])
{
    uint64_t cell = key + ((uint64_t)d[0] | (uint64_t)d[1] << STA_MOMENTS_AXIS_BITS |
                           (uint64_t)d[2] << (2 * STA_MOMENTS_AXIS_BITS));
    size_t s = sta_key_slot(m->keys, m->capacity, cell);
    return m->keys[s] != 0 ? s : SIZE_MAX;
}

// n, s1 and s2 of sta_cell_moments_vertex (s3, s4 zero).
static void vertex_lower(const sta_cell_moments *m, const int64_t vertex[3], sta_moment_sums *out)
{
    uint64_t key;
    memset(out, 0, sizeof(*out));
    if (!vertex_key(m, vertex, &key)) {
        sta_moment_sums block[8];
        const int64_t anchor[3] = { vertex[0] - 1, vertex[1] - 1, vertex[2] - 1 };
        sta_cell_moments_block(m, anchor, 2, block);
        for (int c = 0; c < 8; c++) {
            out->n += block[c].n;
            for (int b = 0; b < 3; b++) {
                out->s1[b] += block[c].s1[b];
            }
            for (int t = 0; t < 6; t++) {
                out->s2[t] += block[c].s2[t];
            }
        }
        return;
    }
    // Each cell's sums move to the block's corner by o (0 or one cell an axis), all in
    // integers: the same sums as sta_cell_moments_block's cells added up, in fewer steps.
    int64_t n = 0, s1[3] = { 0, 0, 0 }, s2[6] = { 0, 0, 0, 0, 0, 0 };
    for (int k = 0; k < 8; k++) {
        const int64_t d[3] = { k & 1, k >> 1 & 1, k >> 2 };
        size_t s = corner_slot(m, key, d);
        if (s == SIZE_MAX) {
            continue;
        }
        const sta_cell_sums *c = &m->sums[s];
        const int64_t o[3] = { d[0] << m->level, d[1] << m->level, d[2] << m->level };
        n += c->n;
        for (int r = 0, t = 0; r < 3; r++) {
            s1[r] += c->s1[r] + c->n * o[r];
            for (int q = r; q < 3; q++, t++) {
                s2[t] += c->s2[t] + o[r] * c->s1[q] + o[q] * c->s1[r] + c->n * o[r] * o[q];
            }
        }
    }
    out->n = n;
    memcpy(out->s1, s1, sizeof(s1));
    memcpy(out->s2, s2, sizeof(s2));
}

// s3 and s4 of sta_cell_moments_vertex (the rest left as it is).
static void vertex_higher(const sta_cell_moments *m, const int64_t vertex[3], sta_moment_sums *out)
{
    sta_higher_sums h = { { 0 }, 0 };
    uint64_t key;
    if (!m->high) {
        // (no higher sums kept: zero)
    } else if (!vertex_key(m, vertex, &key)) {
        sta_moment_sums block[8];
        const int64_t anchor[3] = { vertex[0] - 1, vertex[1] - 1, vertex[2] - 1 };
        sta_cell_moments_block(m, anchor, 2, block);
        for (int c = 0; c < 8; c++) {
            for (int b = 0; b < 3; b++) {
                h.s3[b] += block[c].s3[b];
            }
            h.s4 += block[c].s4;
        }
    } else {
        for (int k = 0; k < 8; k++) {
            const int64_t d[3] = { k & 1, k >> 1 & 1, k >> 2 };
            size_t s = corner_slot(m, key, d);
            if (s != SIZE_MAX) {
                const int64_t o[3] = { d[0] << m->level, d[1] << m->level, d[2] << m->level };
                sta_higher_sums_add_moved(&h, &m->sums[s], &m->high[s], o);
            }
        }
    }
    memcpy(out->s3, h.s3, sizeof(h.s3));
    out->s4 = h.s4;
}

void sta_cell_moments_vertex(const sta_cell_moments *m, const int64_t vertex[3],
                             sta_moment_sums *out)
{
    vertex_lower(m, vertex, out);
    vertex_higher(m, vertex, out);
}

sta_status sta_cell_moments_coarsen(const sta_cell_moments *fine, sta_cell_moments *coarse,
                                    sta_error *err)
{
    int level = fine->level;
    // (a surface's cells have about a quarter as many parents; more grow the table)
    if (coarse->used == 0 && !sta_cell_moments_reserve(coarse, fine->used / COARSER_CELLS)) {
        return sta_fail(err, STA_ERR_NOMEM, "cell moments: out of memory");
    }
    for (size_t s = 0; s < fine->capacity; s++) {
        if (fine->keys[s] == 0) {
            continue;
        }
        uint64_t packed = fine->keys[s] - 1;
        int64_t cell[3], local[3], o[3];
        for (int a = 0; a < 3; a++) {
            cell[a] =
                (int64_t)((packed >> (a * STA_MOMENTS_AXIS_BITS)) & AXIS_MASK) + fine->base[a];
            // The parent's corner is 0 or one fine cell below the child's: sums move by o.
            o[a] = (cell[a] & 1) << level;
            local[a] = (cell[a] >> 1) - coarse->base[a];
        }
        if (local[0] < 0 || local[1] < 0 || local[2] < 0 || local[0] > (int64_t)AXIS_MASK ||
            local[1] > (int64_t)AXIS_MASK || local[2] > (int64_t)AXIS_MASK) {
            continue; // (cannot happen for a set over the same box: its cells stay inside)
        }
        size_t sp = cell_at(coarse, local);
        if (sp == SIZE_MAX) {
            return sta_fail(err, STA_ERR_NOMEM, "cell moments: out of memory");
        }
        sta_cell_sums *p = &coarse->sums[sp];
        const sta_cell_sums *c = &fine->sums[s];
        p->n += c->n;
        for (int r = 0, t = 0; r < 3; r++) {
            for (int q = r; q < 3; q++, t++) {
                p->s2[t] += c->s2[t] + o[r] * c->s1[q] + o[q] * c->s1[r] + c->n * o[r] * o[q];
            }
        }
        if (coarse->high) { // (a finer set without them: its cells' sums moved, s3 s4 0)
            static const sta_higher_sums none = { { 0 }, 0 };
            sta_higher_sums_add_moved(&coarse->high[sp], c, fine->high ? &fine->high[s] : &none, o);
        }
        for (int a = 0; a < 3; a++) {
            p->s1[a] += c->s1[a] + c->n * o[a];
        }
    }
    return STA_OK;
}
