/* SPDX-License-Identifier: MIT
 * Per-cell moment tensors up to the fourth order, and their exact sums around a vertex. */
#include "cell_tensors.h"

#include <string.h>

#include "cell_order.h"
#include "core/alloc.h"
#include "key_slots.h"

#define FIRST_CAPACITY 1024
#define AXIS_MASK      (((uint64_t)1 << STA_MOMENTS_AXIS_BITS) - 1)

// (by degree: 1; x, y, z; the 6 of degree 2; the 10 of degree 3; the 15 of degree 4)
const uint8_t sta_tensor_exponent[STA_TENSOR_TERMS][3] = {
    { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 }, { 2, 0, 0 }, { 1, 1, 0 }, { 1, 0, 1 },
    { 0, 2, 0 }, { 0, 1, 1 }, { 0, 0, 2 }, { 3, 0, 0 }, { 2, 1, 0 }, { 2, 0, 1 }, { 1, 2, 0 },
    { 1, 1, 1 }, { 1, 0, 2 }, { 0, 3, 0 }, { 0, 2, 1 }, { 0, 1, 2 }, { 0, 0, 3 }, { 4, 0, 0 },
    { 3, 1, 0 }, { 3, 0, 1 }, { 2, 2, 0 }, { 2, 1, 1 }, { 2, 0, 2 }, { 1, 3, 0 }, { 1, 2, 1 },
    { 1, 1, 2 }, { 1, 0, 3 }, { 0, 4, 0 }, { 0, 3, 1 }, { 0, 2, 2 }, { 0, 1, 3 }, { 0, 0, 4 },
};

static uint64_t pack(const int64_t local[3])
{
    return ((uint64_t)local[0] | (uint64_t)local[1] << STA_MOMENTS_AXIS_BITS |
            (uint64_t)local[2] << (2 * STA_MOMENTS_AXIS_BITS)) +
           1;
}

static bool local_of(const sta_cell_tensors *t, const int64_t cell[3], int64_t local[3])
{
    for (int a = 0; a < 3; a++) {
        local[a] = cell[a] - t->base[a];
        if (local[a] < 0 || local[a] > (int64_t)AXIS_MASK) {
            return false;
        }
    }
    return true;
}

sta_status sta_cell_tensors_init(sta_cell_tensors *t, int level, const int64_t origin[3],
                                 const int32_t lo[3], const int32_t hi[3], sta_error *err)
{
    memset(t, 0, sizeof(*t));
    if (level < 0 || level > STA_MOMENTS_MAX_LEVEL) {
        return sta_fail(err, STA_ERR_ARG, "cell tensors: level %d out of range", level);
    }
    t->level = level;
    for (int k = 0; k < STA_TENSOR_TERMS; k++) {
        const uint8_t *e = sta_tensor_exponent[k];
        t->index[e[0]][e[1]][e[2]] = (int8_t)k;
    }
    for (int a = 0; a < 3; a++) {
        t->origin[a] = origin[a];
        // One empty cell below and two above stay addressable (vertex boxes reach past).
        t->base[a] = (((int64_t)lo[a] - origin[a]) >> level) - 1;
        int64_t top = ((int64_t)hi[a] - origin[a]) >> level;
        if (top - t->base[a] + 3 > (int64_t)AXIS_MASK) {
            return sta_fail(err, STA_ERR_ARG, "cell tensors: level %d spans too many cells", level);
        }
    }
    t->capacity = FIRST_CAPACITY;
    t->sums_capacity = FIRST_CAPACITY / 2;
    t->keys = sta_calloc(t->capacity, sizeof(*t->keys));
    t->cell = sta_alloc_array(t->capacity, sizeof(*t->cell));
    t->sums = sta_alloc_array(t->sums_capacity, sizeof(*t->sums));
    if (!t->keys || !t->cell || !t->sums) {
        sta_cell_tensors_release(t);
        return sta_fail(err, STA_ERR_NOMEM, "cell tensors: out of memory");
    }
    return STA_OK;
}

void sta_cell_tensors_release(sta_cell_tensors *t)
{
    sta_free(t->keys);
    sta_free(t->cell);
    sta_free(t->sums);
    memset(t, 0, sizeof(*t));
}

// The slots double with only their keys and cell places (12 bytes a slot; the sums stay
// where they are): a marked cell costs its 280 bytes of sums and 24 of slots, where sums
// kept in the slots cost 576, and half as much again while the table doubled.
static bool grow(sta_cell_tensors *t)
{
    void *const values[] = { t->cell };
    const size_t sizes[] = { sizeof(*t->cell) };
    void *grown[1];
    if (!sta_key_slots_double(&t->keys, &t->capacity, values, sizes, grown, 1)) {
        return false;
    }
    t->cell = grown[0];
    return true;
}

static bool grow_sums(sta_cell_tensors *t)
{
    if (t->sums_capacity > UINT32_MAX / 2) {
        return false; // (the cell places are 32-bit)
    }
    size_t capacity = 2 * t->sums_capacity;
    sta_tensor_sums *sums = sta_realloc_array(t->sums, capacity, sizeof(*sums));
    if (!sums) {
        return false;
    }
    t->sums = sums;
    t->sums_capacity = capacity;
    return true;
}

// The sums of cell `local`, created empty when new; NULL when out of memory.
static sta_tensor_sums *cell_at(sta_cell_tensors *t, const int64_t local[3])
{
    uint64_t key = pack(local);
    size_t s = sta_key_slot(t->keys, t->capacity, key);
    if (t->keys[s] == 0) {
        if (2 * (t->used + 1) > t->capacity) {
            if (!grow(t)) {
                return NULL;
            }
            s = sta_key_slot(t->keys, t->capacity, key);
        }
        if (t->used == t->sums_capacity && !grow_sums(t)) {
            return NULL;
        }
        t->keys[s] = key;
        t->cell[s] = (uint32_t)t->used;
        memset(&t->sums[t->used], 0, sizeof(t->sums[t->used]));
        t->used++;
    }
    return &t->sums[t->cell[s]];
}

void sta_tensor_sums_add(sta_tensor_sums *sums, const uint64_t d[3])
{
    // Each monomial from one of degree one less (the terms of sta_tensor_exponent, written
    // out: a loop over the exponents took 470 instructions a point, this about 80).
    const uint64_t x = d[0], y = d[1], z = d[2];
    const uint64_t xx = x * x;
    const uint64_t xy = x * y;
    const uint64_t xz = x * z;
    const uint64_t yy = y * y;
    const uint64_t yz = y * z;
    const uint64_t zz = z * z;
    const uint64_t xxx = xx * x;
    const uint64_t xxy = xx * y;
    const uint64_t xxz = xx * z;
    const uint64_t xyy = xy * y;
    const uint64_t xyz = xy * z;
    const uint64_t xzz = xz * z;
    const uint64_t yyy = yy * y;
    const uint64_t yyz = yy * z;
    const uint64_t yzz = yz * z;
    const uint64_t zzz = zz * z;
    const uint64_t xxxx = xxx * x;
    const uint64_t xxxy = xxx * y;
    const uint64_t xxxz = xxx * z;
    const uint64_t xxyy = xxy * y;
    const uint64_t xxyz = xxy * z;
    const uint64_t xxzz = xxz * z;
    const uint64_t xyyy = xyy * y;
    const uint64_t xyyz = xyy * z;
    const uint64_t xyzz = xyz * z;
    const uint64_t xzzz = xzz * z;
    const uint64_t yyyy = yyy * y;
    const uint64_t yyyz = yyy * z;
    const uint64_t yyzz = yyz * z;
    const uint64_t yzzz = yzz * z;
    const uint64_t zzzz = zzz * z;
    const uint64_t term[STA_TENSOR_TERMS] = {
        1,    x,    y,    z,    xx,   xy,   xz,   yy,   yz,   zz,   xxx,  xxy,
        xxz,  xyy,  xyz,  xzz,  yyy,  yyz,  yzz,  zzz,  xxxx, xxxy, xxxz, xxyy,
        xxyz, xxzz, xyyy, xyyz, xyzz, xzzz, yyyy, yyyz, yyzz, yzzz, zzzz,
    };
    for (int k = 0; k < STA_TENSOR_TERMS; k++) {
        sums->s[k] += term[k];
    }
}

bool sta_cell_tensors_mark(sta_cell_tensors *t, const int64_t cell[3])
{
    int64_t local[3];
    return !local_of(t, cell, local) || cell_at(t, local) != NULL;
}

void sta_cell_tensors_add(sta_cell_tensors *t, const int32_t (*grid)[3], size_t n)
{
    int level = t->level;
    int64_t mask = ((int64_t)1 << level) - 1;
    // Points of one cell mostly come together (cell order): its look-up is kept.
    int64_t last[3] = { INT64_MIN, 0, 0 };
    sta_tensor_sums *sums = NULL;
    for (size_t j = 0; j < n; j++) {
        int64_t u[3], local[3];
        uint64_t d[3];
        for (int a = 0; a < 3; a++) {
            u[a] = (int64_t)grid[j][a] - t->origin[a];
            local[a] = (u[a] >> level) - t->base[a];
            d[a] = (uint64_t)(u[a] & mask);
        }
        if (memcmp(local, last, sizeof(local)) != 0) {
            memcpy(last, local, sizeof(local));
            sums = NULL;
            bool inside = true;
            for (int a = 0; a < 3; a++) {
                inside = inside && local[a] >= 0 && local[a] <= (int64_t)AXIS_MASK;
            }
            if (inside) {
                size_t s = sta_key_slot(t->keys, t->capacity, pack(local));
                sums = t->keys[s] != 0 ? &t->sums[t->cell[s]] : NULL;
            }
        }
        if (sums) {
            sta_tensor_sums_add(sums, d);
        }
    }
}

typedef struct keyed_cell {
    uint64_t key;  /* the cell order's key of the cell */
    uint32_t cell; /* its place in `sums` */
    int64_t at[3]; /* its coordinates from the scene corner */
} keyed_cell;

sta_status sta_cell_tensors_add_sorted(sta_cell_tensors *t, const int32_t (*const *sets)[3],
                                       const size_t *counts, int count, const int32_t corner[3],
                                       sta_error *err)
{
    keyed_cell *cells = sta_alloc_array(t->used + 1, sizeof(*cells));
    int32_t(*low)[3] = sta_alloc_array(t->used + 1, sizeof(*low));
    uint32_t *order = sta_alloc_array(t->used + 1, sizeof(*order));
    if (!cells || !low || !order) {
        sta_free(cells);
        sta_free(low);
        sta_free(order);
        return sta_fail(err, STA_ERR_NOMEM, "cell tensors: out of memory");
    }
    size_t found = 0;
    for (size_t s = 0; s < t->capacity; s++) {
        if (t->keys[s] == 0) {
            continue;
        }
        uint64_t packed = t->keys[s] - 1;
        int64_t first[3];
        bool inside = true;
        for (int a = 0; a < 3; a++) {
            int64_t local = (int64_t)(packed >> (a * STA_MOMENTS_AXIS_BITS) & AXIS_MASK);
            int64_t from = (local + t->base[a]) * ((int64_t)1 << t->level) + t->origin[a];
            cells[found].at[a] = local + t->base[a];
            // (a cell lies wholly above the aligned corner or below every point; one past
            // int32 holds none)
            first[a] = (from - corner[a]) >> t->level;
            inside = inside && first[a] >= 0 &&
                     first[a] < ((int64_t)1 << STA_CELL_ORDER_AXIS_BITS) && from <= INT32_MAX;
            low[found][a] = inside ? (int32_t)from : 0;
        }
        if (inside) {
            cells[found].key = sta_cell_order_key(first);
            cells[found++].cell = t->cell[s];
        }
    }
    // The cells in key order: the cell order of their lowest points.
    sta_status status =
        sta_cell_order((const int32_t(*)[3])low, found, corner, t->level, order, err);
    sta_free(low);
    if (status != STA_OK) {
        sta_free(cells);
        sta_free(order);
        return status;
    }
    int level = t->level;
    int64_t mask = ((int64_t)1 << level) - 1;
    for (int s = 0; s < count; s++) {
        size_t i = 0;
        for (size_t c = 0; c < found; c++) {
            const keyed_cell *k = &cells[order[c]];
            sta_tensor_sums *sums = &t->sums[k->cell];
            i = sta_cell_order_lower_near(sets[s], counts[s], corner, level, k->key, i);
            for (; i < counts[s]; i++) { // the cell's run
                int64_t u[3];
                uint64_t d[3];
                bool in = true;
                for (int a = 0; a < 3; a++) {
                    u[a] = (int64_t)sets[s][i][a] - t->origin[a];
                    in = in && u[a] >> level == k->at[a];
                    d[a] = (uint64_t)(u[a] & mask);
                }
                if (!in) {
                    break;
                }
                sta_tensor_sums_add(sums, d);
            }
        }
    }
    sta_free(cells);
    sta_free(order);
    return STA_OK;
}

// Moves the sums s in place by `by` along axis a (d_a + by): sum (x + o)^i y^j z^k = sum
// over i' <= i of C(i, i') o^(i - i') sum x^i' y^j z^k, modulo 2^64 like the sums.
static void move_along(const sta_cell_tensors *t, sta_tensor_sums *s, int a, uint64_t by)
{
    static const uint64_t binomial[5][5] = { { 1, 0, 0, 0, 0 },
                                             { 1, 1, 0, 0, 0 },
                                             { 1, 2, 1, 0, 0 },
                                             { 1, 3, 3, 1, 0 },
                                             { 1, 4, 6, 4, 1 } };
    const uint64_t p[5] = { 1, by, by * by, by * by * by, by * by * by * by };
    const sta_tensor_sums from = *s;
    for (int k = 0; k < STA_TENSOR_TERMS; k++) {
        const uint8_t *e = sta_tensor_exponent[k];
        uint64_t sum = 0;
        int f[3] = { e[0], e[1], e[2] };
        for (f[a] = 0; f[a] <= e[a]; f[a]++) {
            sum += binomial[e[a]][f[a]] * p[e[a] - f[a]] * from.s[t->index[f[0]][f[1]][f[2]]];
        }
        s->s[k] = sum;
    }
}

// dst += src.
static void add_sums(sta_tensor_sums *dst, const sta_tensor_sums *src)
{
    for (int k = 0; k < STA_TENSOR_TERMS; k++) {
        dst->s[k] += src->s[k];
    }
}

void sta_cell_tensors_vertex(const sta_cell_tensors *t, const int64_t vertex[3],
                             sta_tensor_sums *out)
{
    // The 8 cells' sums moved to the box's corner (one cell edge along each axis where the
    // cell is the upper one): the moves are linear and exact modulo 2^64, so the upper cell
    // of each pair along x is moved and added to the lower, then the upper pair sum of each
    // pair along y, then along z: 4 + 2 + 1 moves instead of one a cell and axis (12).
    uint64_t edge = (uint64_t)1 << t->level;
    sta_tensor_sums part[8];
    bool found[8];
    for (int c = 0; c < 8; c++) {
        const int64_t cell[3] = { vertex[0] - 1 + (c & 1), vertex[1] - 1 + (c >> 1 & 1),
                                  vertex[2] - 1 + (c >> 2) };
        int64_t local[3];
        size_t s = 0;
        found[c] = local_of(t, cell, local) &&
                   t->keys[s = sta_key_slot(t->keys, t->capacity, pack(local))] != 0;
        if (found[c]) {
            part[c] = t->sums[t->cell[s]];
        }
    }
    // Along axis a the cells (or partial sums) at index c and c + step pair up: the upper
    // one moves by an edge and joins the lower one.
    for (int a = 0, step = 1; a < 3; a++, step *= 2) {
        for (int c = 0; c < 8; c += 2 * step) {
            if (!found[c + step]) {
                continue;
            }
            move_along(t, &part[c + step], a, edge);
            if (found[c]) {
                add_sums(&part[c], &part[c + step]);
            } else {
                part[c] = part[c + step];
                found[c] = true;
            }
        }
    }
    if (found[0]) {
        *out = part[0];
    } else {
        memset(out, 0, sizeof(*out));
    }
}
