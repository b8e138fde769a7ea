/* SPDX-License-Identifier: MIT
 * Tests for the open-addressing probe the converter's tables share (preprocess/key_slots.h):
 * keys packed as cells (21 bits an axis, + 1) that differ along one axis only spread over
 * the home slots, whichever axis (the home slot once ignored the third: a column's cells
 * shared one and probed far), so a half-full table's probes stay short; after doubling,
 * every key and its value are found again. */
#include "test_support.h"

#include <stdlib.h>

#include "core/alloc.h"
#include "key_slots.h"

enum {
    AXIS_BITS = 21,
    CAPACITY = 4096,
    KEYS = CAPACITY / 2 /* the tables' largest load */
};

// The packed key of cell (x, y, z), as the cell and vertex tables make them.
static uint64_t pack(uint64_t x, uint64_t y, uint64_t z)
{
    return (x | y << AXIS_BITS | z << (2 * AXIS_BITS)) + 1;
}

// Cells along each axis in turn (a wall's or a tree's column along the third) fill half a
// table with short probes: every key found within a few slots of its home on average.
static void keys_along_any_axis_spread_over_the_slots(void **state)
{
    (void)state;
    for (int axis = 0; axis < 3; axis++) {
        uint64_t *keys = sta_calloc(CAPACITY, sizeof(*keys));
        assert_non_null(keys);
        size_t probes = 0;
        for (uint64_t i = 0; i < KEYS; i++) {
            uint64_t c[3] = { 1000, 2000, 3000 };
            c[axis] += i;
            uint64_t key = pack(c[0], c[1], c[2]);
            size_t home = sta_key_home_slot(key, CAPACITY);
            assert_true(home < CAPACITY);
            size_t s = sta_key_slot(keys, CAPACITY, key);
            assert_int_equal(keys[s], 0); // (new)
            keys[s] = key;
            probes += ((s - home) & (CAPACITY - 1)) + 1;
        }
        // (uniform hashing at half load: 1.5 slots a key on average; keys that share their
        // home slot: KEYS / 2)
        assert_true(probes < (size_t)4 * KEYS);
        sta_free(keys);
    }
}

// A table doubled by sta_key_slots_double finds every key at a slot holding its value.
static void doubled_table_finds_every_key(void **state)
{
    (void)state;
    size_t capacity = CAPACITY / 4;
    uint64_t *keys = sta_calloc(capacity, sizeof(*keys));
    uint32_t *values = sta_alloc_array(capacity, sizeof(*values));
    assert_non_null(keys);
    assert_non_null(values);
    for (uint32_t i = 0; i < capacity / 2; i++) {
        uint64_t key = pack(i % 7, i / 7 % 5, i / 35);
        size_t s = sta_key_slot(keys, capacity, key);
        keys[s] = key;
        values[s] = i;
    }
    void *const arrays[] = { values };
    const size_t sizes[] = { sizeof(*values) };
    void *grown[1];
    assert_true(sta_key_slots_double(&keys, &capacity, arrays, sizes, grown, 1));
    values = grown[0];
    assert_int_equal(capacity, CAPACITY / 2);
    for (uint32_t i = 0; i < CAPACITY / 8; i++) {
        uint64_t key = pack(i % 7, i / 7 % 5, i / 35);
        size_t s = sta_key_slot(keys, capacity, key);
        assert_true(keys[s] == key);
        assert_int_equal(values[s], i);
    }
    assert_int_equal(keys[sta_key_slot(keys, capacity, pack(9, 9, 9))], 0); // (absent)
    sta_free(keys);
    sta_free(values);
}

static const struct CMUnitTest tests[] = {
    cmocka_unit_test(keys_along_any_axis_spread_over_the_slots),
    cmocka_unit_test(doubled_table_finds_every_key),
};

STA_TEST_MAIN(tests)
