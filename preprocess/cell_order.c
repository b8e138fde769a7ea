/* SPDX-License-Identifier: MIT
 * Morton order of points by their cells: keys and a stable radix sort. */
#include "cell_order.h"

#include <string.h>

#include "core/alloc.h"

#define DIGIT_BITS   11
#define BUCKETS      (1u << DIGIT_BITS)
/* The first pass's digit (the keys' top bits), and the passes' within its buckets. */
#define SUB_BITS     8
#define SUB_BUCKETS  (1u << SUB_BITS)
/* Buckets of fewer keys than this are sorted by insertion. */
#define SMALL_BUCKET 32

// A byte's 8 bits spread to every third bit (the table below: three look-ups a coordinate
// take fewer instructions than the shifts and masks, and the 1 KiB stay in cache).
#define SPREAD_BYTE(b)                                                                             \
 (((b)&1u) | ((b)&2u) << 2 | ((b)&4u) << 4 | ((b)&8u) << 6 | ((b)&16u) << 8 | ((b)&32u) << 10 |    \
  ((b)&64u) << 12 | ((b)&128u) << 14)
#define SPREAD_2(b)   SPREAD_BYTE(b), SPREAD_BYTE((b) + 1)
#define SPREAD_8(b)   SPREAD_2(b), SPREAD_2((b) + 2), SPREAD_2((b) + 4), SPREAD_2((b) + 6)
#define SPREAD_32(b)  SPREAD_8(b), SPREAD_8((b) + 8), SPREAD_8((b) + 16), SPREAD_8((b) + 24)
#define SPREAD_128(b) SPREAD_32(b), SPREAD_32((b) + 32), SPREAD_32((b) + 64), SPREAD_32((b) + 96)
static const uint32_t spread_byte[256] = { SPREAD_128(0u), SPREAD_128(128u) };

// The 21 low bits of v spread to every third bit.
static uint64_t spread(uint64_t v)
{
    return (uint64_t)spread_byte[v & 0xFF] | (uint64_t)spread_byte[v >> 8 & 0xFF] << 24 |
           (uint64_t)spread_byte[v >> 16 & 0x1F] << 48;
}

// Sorts the n keys `key` (with the indices `index` beside them) by their low `bits` bits,
// stably, by SUB_BITS a pass through `key_spare` and `spare` (the result back in key and
// index); count: SUB_BUCKETS counters. The buckets of the first pass are small: in cache.
static void sort_low(uint64_t *key, uint32_t *index, uint64_t *key_spare, uint32_t *spare, size_t n,
                     int bits, size_t *count)
{
    if (n < SMALL_BUCKET) { // insertion sort: stable, and cheaper for a few
        for (size_t i = 1; i < n; i++) {
            uint64_t k = key[i];
            uint32_t x = index[i];
            size_t j = i;
            for (; j > 0 && key[j - 1] > k; j--) {
                key[j] = key[j - 1];
                index[j] = index[j - 1];
            }
            key[j] = k;
            index[j] = x;
        }
        return;
    }
    uint64_t *from = key, *to = key_spare;
    uint32_t *from_index = index, *to_index = spare;
    for (int shift = 0; shift < bits; shift += SUB_BITS) {
        memset(count, 0, SUB_BUCKETS * sizeof(*count));
        for (size_t i = 0; i < n; i++) {
            count[(from[i] >> shift) & (SUB_BUCKETS - 1)]++;
        }
        size_t sum = 0;
        for (size_t b = 0; b < SUB_BUCKETS; b++) {
            size_t c = count[b];
            count[b] = sum;
            sum += c;
        }
        for (size_t i = 0; i < n; i++) {
            size_t at = count[(from[i] >> shift) & (SUB_BUCKETS - 1)]++;
            to[at] = from[i];
            to_index[at] = from_index[i];
        }
        uint64_t *k = from;
        from = to;
        to = k;
        uint32_t *o = from_index;
        from_index = to_index;
        to_index = o;
    }
    if (from != key) {
        memcpy(key, from, n * sizeof(*key));
        memcpy(index, from_index, n * sizeof(*index));
    }
}

sta_status sta_cell_order(const int32_t (*grid)[3], size_t n, const int32_t lo[3], int level,
                          uint32_t *order, sta_error *err)
{
    if (n > UINT32_MAX) {
        return sta_fail(err, STA_ERR_ARG, "cell order: %zu points are too many", n);
    }
    uint64_t *key = sta_alloc_array(n ? n : 1, 2 * sizeof(*key));
    uint32_t *spare = sta_alloc_array(n ? n : 1, sizeof(*spare));
    size_t *count = sta_calloc(BUCKETS + 1, sizeof(*count));
    size_t sub_count[SUB_BUCKETS];
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
        key_spare[i] = k;
    }
    if (widest >> STA_CELL_ORDER_AXIS_BITS) {
        sta_free(key);
        sta_free(spare);
        sta_free(count);
        return sta_fail(err, STA_ERR_ARG, "cell order: the points span too many cells");
    }
    int key_bits = 0;
    while ((widest >> key_bits) != 0) {
        key_bits++;
    }
    key_bits *= 3;
    // The first pass by the keys' top DIGIT_BITS bits (most significant first: the one
    // pass over all points that misses the caches), stable, into key and order; then each
    // of its buckets by the bits below, stably, in cache.
    int top = key_bits > DIGIT_BITS ? key_bits - DIGIT_BITS : 0;
    for (size_t i = 0; i < n; i++) {
        count[(key_spare[i] >> top) + 1]++;
    }
    for (size_t b = 0; b < BUCKETS; b++) {
        count[b + 1] += count[b]; // count[b]: bucket b's start
    }
    for (size_t i = 0; i < n; i++) {
        size_t at = count[key_spare[i] >> top]++;
        key[at] = key_spare[i];
        order[at] = (uint32_t)i;
    }
    // (count[b] is now bucket b's end, the next one's start)
    for (size_t b = 0, from = 0; b < BUCKETS && top > 0; b++) {
        size_t to = count[b];
        if (to - from > 1) {
            sort_low(key + from, order + from, key_spare, spare, to - from, top, sub_count);
        }
        from = to;
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
