/* SPDX-License-Identifier: MIT
 * Morton order of points by their cells: keys and a stable radix sort. */
#include "cell_order.h"

#include <stdbool.h>
#include <string.h>

#include "core/alloc.h"

#define DIGIT_BITS 11
#define BUCKETS    (1u << DIGIT_BITS)
/* Digits of a key at most (3 axes of STA_CELL_ORDER_AXIS_BITS bits). */
#define DIGITS     ((3 * STA_CELL_ORDER_AXIS_BITS + DIGIT_BITS - 1) / DIGIT_BITS)

// The 21 low bits of v spread to every third bit.
static uint64_t spread(uint64_t v)
{
    v &= 0x1FFFFF;
    v = (v | v << 32) & 0x1F00000000FFFFull;
    v = (v | v << 16) & 0x1F0000FF0000FFull;
    v = (v | v << 8) & 0x100F00F00F00F00Full;
    v = (v | v << 4) & 0x10C30C30C30C30C3ull;
    v = (v | v << 2) & 0x1249249249249249ull;
    return v;
}

sta_status sta_cell_order(const int32_t (*grid)[3], size_t n, const int32_t lo[3], int level,
                          uint32_t *order, sta_error *err)
{
    if (n > UINT32_MAX) {
        return sta_fail(err, STA_ERR_ARG, "cell order: %zu points are too many", n);
    }
    uint64_t *key = sta_alloc_array(n ? n : 1, 2 * sizeof(*key));
    uint32_t *spare = sta_alloc_array(n ? n : 1, sizeof(*spare));
    // Every digit's histogram, counted as the keys are made (one pass, not one a digit).
    size_t *count = sta_calloc((size_t)DIGITS * BUCKETS, sizeof(*count));
    if (!key || !spare || !count) {
        sta_free(key);
        sta_free(spare);
        sta_free(count);
        return sta_fail(err, STA_ERR_NOMEM, "cell order: out of memory for %zu points", n);
    }
    uint64_t *key_spare = key + n, widest = 0;
    for (size_t i = 0; i < n; i++) {
        uint64_t k = 0;
        for (int a = 0; a < 3; a++) {
            uint64_t c = (uint64_t)(((int64_t)grid[i][a] - lo[a]) >> level);
            widest = c > widest ? c : widest;
            k |= spread(c) << a;
        }
        key[i] = k;
        order[i] = (uint32_t)i;
        for (int d = 0; d < DIGITS; d++) {
            count[(size_t)d * BUCKETS + ((k >> (d * DIGIT_BITS)) & (BUCKETS - 1))]++;
        }
    }
    if (widest >> STA_CELL_ORDER_AXIS_BITS) {
        sta_free(key);
        sta_free(spare);
        sta_free(count);
        return sta_fail(err, STA_ERR_ARG, "cell order: the points span too many cells");
    }
    int axis_bits = 0;
    while ((widest >> axis_bits) != 0) {
        axis_bits++;
    }
    uint64_t *from = key, *to_key = key_spare;
    uint32_t *from_order = order, *to_order = spare;
    for (int shift = 0, d = 0; shift < 3 * axis_bits; shift += DIGIT_BITS, d++) {
        size_t *digit = count + (size_t)d * BUCKETS, sum = 0;
        bool one_bucket = false; // all keys share this digit: the pass keeps the order
        for (size_t b = 0; b < BUCKETS; b++) {
            size_t c = digit[b];
            one_bucket = one_bucket || c == n;
            digit[b] = sum;
            sum += c;
        }
        if (one_bucket) {
            continue;
        }
        for (size_t i = 0; i < n; i++) {
            size_t to = digit[(from[i] >> shift) & (BUCKETS - 1)]++;
            to_key[to] = from[i];
            to_order[to] = from_order[i];
        }
        uint64_t *k = from;
        from = to_key;
        to_key = k;
        uint32_t *o = from_order;
        from_order = to_order;
        to_order = o;
    }
    if (from_order != order) {
        memcpy(order, from_order, n * sizeof(*order));
    }
    sta_free(key);
    sta_free(spare);
    sta_free(count);
    return STA_OK;
}

uint64_t sta_cell_order_key(const int64_t cell[3])
{
    uint64_t k = 0;
    for (int a = 0; a < 3; a++) {
        k |= spread((uint64_t)cell[a]) << a;
    }
    return k;
}

// The key of point i's cell.
static uint64_t key_at(const int32_t (*sorted)[3], const int32_t lo[3], int level, size_t i)
{
    int64_t cell[3];
    for (int a = 0; a < 3; a++) {
        cell[a] = ((int64_t)sorted[i][a] - lo[a]) >> level;
    }
    return sta_cell_order_key(cell);
}

size_t sta_cell_order_lower_near(const int32_t (*sorted)[3], size_t n, const int32_t lo[3],
                                 int level, uint64_t key, size_t hint)
{
    // Gallop from the hint to a bracket [from, to] of the answer, then bisect it.
    size_t from, to;
    hint = hint < n ? hint : n;
    if (hint < n && key_at(sorted, lo, level, hint) < key) {
        from = hint + 1;
        to = n;
        for (size_t step = 1; hint + step < n; step *= 2) {
            if (key_at(sorted, lo, level, hint + step) >= key) {
                to = hint + step;
                break;
            }
            from = hint + step + 1;
        }
    } else {
        from = 0;
        to = hint;
        for (size_t step = 1; step <= hint; step *= 2) {
            if (key_at(sorted, lo, level, hint - step) < key) {
                from = hint - step + 1;
                break;
            }
            to = hint - step;
        }
    }
    while (from < to) {
        size_t mid = from + (to - from) / 2;
        if (key_at(sorted, lo, level, mid) < key) {
            from = mid + 1;
        } else {
            to = mid;
        }
    }
    return from;
}
