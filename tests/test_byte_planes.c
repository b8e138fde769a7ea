/* SPDX-License-Identifier: MIT
 * Tests for the byte planes of the temporary runs (preprocess/byte_planes.c): the
 * 8x8 register transpose gives exactly the plain definition's layout, for every
 * record size and count around its 8-byte and 8-record groups, and joins back. */
#include "test_support.h"

#include <stdlib.h>
#include <string.h>

#include "core/alloc.h"
#include "core/byte_planes.h"

static void planes_match_the_definition_and_join_back(void **state)
{
    (void)state;
    const size_t max_rec = 41, max_count = 75;
    size_t bytes = max_rec * max_count;
    uint8_t *in = sta_malloc(bytes + 1), *planes = sta_malloc(bytes + 1);
    uint8_t *back = sta_malloc(bytes + 1);
    assert_non_null(in);
    assert_non_null(planes);
    assert_non_null(back);
    srand(17);
    for (size_t i = 0; i < bytes; i++) {
        in[i] = (uint8_t)rand();
    }
    for (size_t rec = 1; rec <= max_rec; rec++) {
        for (size_t count = 0; count <= max_count; count++) {
            size_t n = rec * count;
            // A guard byte after the planes catches writes past the end.
            memset(planes, 0xA5, n + 1);
            sta_byte_planes_split(in, count, rec, planes);
            for (size_t k = 0; k < rec; k++) {
                for (size_t i = 0; i < count; i++) {
                    if (planes[k * count + i] != in[i * rec + k]) {
                        fail_msg("rec %zu count %zu: plane %zu record %zu", rec, count, k, i);
                    }
                }
            }
            assert_int_equal(planes[n], 0xA5);
            memset(back, 0x5A, n + 1);
            sta_byte_planes_join(planes, count, rec, back);
            assert_memory_equal(back, in, n);
            assert_int_equal(back[n], 0x5A);
        }
    }
    sta_free(in);
    sta_free(planes);
    sta_free(back);
}

static const struct CMUnitTest tests[] = {
    cmocka_unit_test(planes_match_the_definition_and_join_back),
};

STA_TEST_MAIN(tests)
