/* SPDX-License-Identifier: MIT
 * Tests for the exact moment sums up to the fourth order (preprocess/tensor_sums.c): the
 * exponent table lists every monomial of degree at most 4 once, by degree; the written-out
 * sums equal the table's monomials taken one by one, for small offsets and for offsets
 * whose powers wrap modulo 2^64, in either order of the points. */
#include "test_support.h"

#include <string.h>

#include "tensor_sums.h"

enum {
    POINTS = 2000
};

// The sums of offsets d taken term by term from sta_tensor_exponent.
static sta_tensor_sums by_table(const uint64_t (*d)[3], size_t n)
{
    sta_tensor_sums s = { { 0 } };
    for (size_t i = 0; i < n; i++) {
        for (int t = 0; t < STA_TENSOR_TERMS; t++) {
            const uint8_t *e = sta_tensor_exponent[t];
            uint64_t v = 1;
            for (int a = 0; a < 3; a++) {
                for (int k = 0; k < e[a]; k++) {
                    v *= d[i][a];
                }
            }
            s.s[t] += v;
        }
    }
    return s;
}

static void exponents_list_each_monomial_once_by_degree(void **state)
{
    (void)state;
    int seen[5][5][5] = { { { 0 } } };
    int last_degree = 0;
    for (int t = 0; t < STA_TENSOR_TERMS; t++) {
        const uint8_t *e = sta_tensor_exponent[t];
        int degree = e[0] + e[1] + e[2];
        assert_true(degree <= 4);
        assert_true(degree >= last_degree); // by degree
        last_degree = degree;
        seen[e[0]][e[1]][e[2]]++;
    }
    for (int i = 0; i <= 4; i++) {
        for (int j = 0; i + j <= 4; j++) {
            for (int k = 0; i + j + k <= 4; k++) {
                assert_int_equal(seen[i][j][k], 1);
            }
        }
    }
}

static void sums_equal_the_tables_monomials_in_any_order(void **state)
{
    (void)state;
    static uint64_t d[POINTS][3];
    uint32_t seed = 31u;
    for (size_t i = 0; i < POINTS; i++) {
        for (int a = 0; a < 3; a++) {
            uint64_t r = sta_test_next_random(&seed);
            // Half small (a box's offsets), half up to 2^38: their fourth powers wrap.
            d[i][a] = i % 2 ? r % 4096u : r << (a * 3);
        }
    }
    sta_tensor_sums forward = { { 0 } }, backward = { { 0 } };
    for (size_t i = 0; i < POINTS; i++) {
        sta_tensor_sums_add(&forward, d[i]);
        sta_tensor_sums_add(&backward, d[POINTS - 1 - i]);
    }
    sta_tensor_sums expected = by_table((const uint64_t(*)[3])d, POINTS);
    for (int t = 0; t < STA_TENSOR_TERMS; t++) {
        assert_true(forward.s[t] == expected.s[t]);
        assert_true(backward.s[t] == expected.s[t]);
    }
    assert_int_equal(forward.s[0], POINTS); // (the count)
}

static const struct CMUnitTest tests[] = {
    cmocka_unit_test(exponents_list_each_monomial_once_by_degree),
    cmocka_unit_test(sums_equal_the_tables_monomials_in_any_order),
};

STA_TEST_MAIN(tests)
