/* SPDX-License-Identifier: MIT
 * The probe the converter's open-addressing tables share: a power-of-two capacity,
 * 64-bit keys, 0 marking an empty slot, a Fibonacci hash and linear probing. */
#ifndef STA_KEY_SLOTS_H
#define STA_KEY_SLOTS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

// The slot a key's probe starts at (capacity a power of two): the product's top bits, which
// depend on all of the key's (its bits from 17 up ignored the packed keys' third axis, so
// a wall's or a tree's cells of one column shared their home slots: long probes).
static inline size_t sta_key_home_slot(uint64_t key, size_t capacity)
{
    if (capacity < 2) {
        return 0;
    }
    return (size_t)((key * 0x9E3779B97F4A7C15ull) >> (64 - __builtin_ctzll((uint64_t)capacity)));
}

// The slot holding `key`, or the empty one where it would go.
static inline size_t sta_key_slot(const uint64_t *keys, size_t capacity, uint64_t key)
{
    size_t s = sta_key_home_slot(key, capacity);
    while (keys[s] != 0 && keys[s] != key) {
        s = (s + 1) & (capacity - 1);
    }
    return s;
}

/* Doubles a table: its keys (`*keys`, `*capacity` slots) and `count` value arrays beside
 * them (`values[i]`, `sizes[i]` bytes a slot; a NULL array stays NULL) move to new arrays
 * of twice the slots, each key and its values to the key's new slot. On success the old
 * arrays are freed, `grown[i]` holds the new value arrays, and the keys and capacity are
 * updated. Returns false, the table as it was, when out of memory. */
bool sta_key_slots_double(uint64_t **keys, size_t *capacity, void *const values[],
                          const size_t sizes[], void *grown[], int count);

#endif
