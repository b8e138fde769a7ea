/* SPDX-License-Identifier: MIT
 * Tests for the cells' moment tensors (preprocess/cell_tensors.c): the 8 cells around a
 * vertex, each summed from its own corner and moved to the box's corner in 64-bit
 * integers, give exactly the sums of the box's points taken directly (every term, with
 * points in all 8 cells: a wrong binomial term of one axis or a mixed one shows); only
 * marked cells take points; the sums do not depend on the points' order; thousands of
 * cells, marked in a scattered order and twice, keep their own sums while the table and
 * the sums' array grow; the marked cells' runs of two cell-ordered sets give the sums of
 * all their points taken one by one. */
#include "test_support.h"

#include <string.h>

#include "cell_order.h"
#include "cell_tensors.h"

enum {
    POINTS = 3000
};

// The sums of points p (grid units) as offsets from `corner`.
static sta_tensor_sums direct(const int32_t (*p)[3], size_t n, const int64_t corner[3])
{
    sta_tensor_sums s = { { 0 } };
    for (size_t i = 0; i < n; i++) {
        for (int t = 0; t < STA_TENSOR_TERMS; t++) {
            const uint8_t *e = sta_tensor_exponent[t];
            uint64_t v = 1;
            for (int a = 0; a < 3; a++) {
                for (int k = 0; k < e[a]; k++) {
                    v *= (uint64_t)((int64_t)p[i][a] - corner[a]);
                }
            }
            s.s[t] += v;
        }
    }
    return s;
}

// Points scattered over the 2 x 2 x 2 cells of level 6 around vertex (16, 17, 18) of a
// scene whose corner is `origin`.
static size_t scatter(int32_t (*p)[3], const int64_t origin[3], uint32_t seed)
{
    const int64_t v[3] = { 16, 17, 18 };
    for (size_t i = 0; i < POINTS; i++) {
        for (int a = 0; a < 3; a++) {
            p[i][a] = (int32_t)(origin[a] + ((v[a] - 1) << 6) +
                                (int64_t)(sta_test_next_random(&seed) % 128u));
        }
    }
    return POINTS;
}

static void vertex_sums_equal_direct_sums(void **state)
{
    (void)state;
    static int32_t p[POINTS][3];
    const int64_t origin[3] = { -1000, 2000, 37 }, v[3] = { 16, 17, 18 };
    size_t n = scatter(p, origin, 7u);
    const int32_t lo[3] = { -1000, 2000, 37 }, hi[3] = { 3000, 6000, 4037 };
    sta_cell_tensors t;
    sta_error err = { 0 };
    assert_int_equal(sta_cell_tensors_init(&t, 6, origin, lo, hi, &err), STA_OK);
    for (int c = 0; c < 8; c++) {
        const int64_t cell[3] = { v[0] - 1 + (c & 1), v[1] - 1 + (c >> 1 & 1),
                                  v[2] - 1 + (c >> 2) };
        assert_true(sta_cell_tensors_mark(&t, cell));
    }
    sta_cell_tensors_add(&t, (const int32_t(*)[3])p, n);
    sta_tensor_sums box;
    sta_cell_tensors_vertex(&t, v, &box);
    int64_t corner[3];
    for (int a = 0; a < 3; a++) {
        corner[a] = origin[a] + ((v[a] - 1) << 6);
    }
    sta_tensor_sums want = direct((const int32_t(*)[3])p, n, corner);
    assert_int_equal(box.s[0], n);
    assert_memory_equal(&box, &want, sizeof(box));
    // In another order (reversed: each cell's points no longer together), the same bits.
    sta_cell_tensors r;
    assert_int_equal(sta_cell_tensors_init(&r, 6, origin, lo, hi, &err), STA_OK);
    for (int c = 7; c >= 0; c--) {
        const int64_t cell[3] = { v[0] - 1 + (c & 1), v[1] - 1 + (c >> 1 & 1),
                                  v[2] - 1 + (c >> 2) };
        assert_true(sta_cell_tensors_mark(&r, cell));
    }
    static int32_t q[POINTS][3];
    for (size_t i = 0; i < n; i++) {
        memcpy(q[i], p[n - 1 - i], sizeof(q[i]));
    }
    sta_cell_tensors_add(&r, (const int32_t(*)[3])q, n);
    sta_tensor_sums again;
    sta_cell_tensors_vertex(&r, v, &again);
    assert_memory_equal(&again, &box, sizeof(box));
    sta_cell_tensors_release(&r);
    sta_cell_tensors_release(&t);
}

// Only marked cells take points: with one of the 8 cells unmarked its points are left
// out, the box's sums are those of the other seven's points.
static void unmarked_cells_take_no_points(void **state)
{
    (void)state;
    static int32_t p[POINTS][3], kept[POINTS][3];
    const int64_t origin[3] = { 0, 0, 0 }, v[3] = { 16, 17, 18 };
    size_t n = scatter(p, origin, 11u), m = 0;
    const int32_t lo[3] = { 0, 0, 0 }, hi[3] = { 4000, 4000, 4000 };
    sta_cell_tensors t;
    sta_error err = { 0 };
    assert_int_equal(sta_cell_tensors_init(&t, 6, origin, lo, hi, &err), STA_OK);
    for (int c = 1; c < 8; c++) { // (not the lowest cell)
        const int64_t cell[3] = { v[0] - 1 + (c & 1), v[1] - 1 + (c >> 1 & 1),
                                  v[2] - 1 + (c >> 2) };
        assert_true(sta_cell_tensors_mark(&t, cell));
    }
    for (size_t i = 0; i < n; i++) {
        bool lowest = true;
        for (int a = 0; a < 3; a++) {
            lowest = lowest && (p[i][a] >> 6) == v[a] - 1;
        }
        if (!lowest) {
            memcpy(kept[m++], p[i], sizeof(p[i]));
        }
    }
    assert_true(m < n && m > n / 2);
    sta_cell_tensors_add(&t, (const int32_t(*)[3])p, n);
    sta_tensor_sums box;
    sta_cell_tensors_vertex(&t, v, &box);
    const int64_t corner[3] = { (v[0] - 1) << 6, (v[1] - 1) << 6, (v[2] - 1) << 6 };
    sta_tensor_sums want = direct((const int32_t(*)[3])kept, m, corner);
    assert_memory_equal(&box, &want, sizeof(box));
    // A vertex whose cells hold nothing: zero sums.
    const int64_t far[3] = { 40, 40, 40 };
    sta_cell_tensors_vertex(&t, far, &box);
    for (int k = 0; k < STA_TENSOR_TERMS; k++) {
        assert_int_equal(box.s[k], 0);
    }
    sta_cell_tensors_release(&t);
}

// 4000 cells of a 20^3 grid (every other one, marked in a scattered order, each twice)
// with one point in each of the 8000: every vertex's sums are those of the points of its
// marked cells, after the slots and the dense sums have grown several times.
static void many_cells_keep_their_sums_through_growth(void **state)
{
    (void)state;
    enum {
        SIDE = 20,
        CELLS = SIDE * SIDE * SIDE,
        LEVEL = 2
    };
    static int32_t p[CELLS][3];
    const int64_t origin[3] = { 0, 0, 0 };
    const int32_t lo[3] = { 0, 0, 0 }, hi[3] = { SIDE << LEVEL, SIDE << LEVEL, SIDE << LEVEL };
    sta_cell_tensors t;
    sta_error err = { 0 };
    assert_int_equal(sta_cell_tensors_init(&t, LEVEL, origin, lo, hi, &err), STA_OK);
    for (int pass = 0; pass < 2; pass++) {
        for (int i = 0; i < CELLS; i++) {
            int c = (i * 7919) % CELLS; // (7919 is prime to CELLS: every cell once)
            const int64_t cell[3] = { c % SIDE, c / SIDE % SIDE, c / (SIDE * SIDE) };
            if ((cell[0] + cell[1] + cell[2]) % 2 == 0) {
                assert_true(sta_cell_tensors_mark(&t, cell));
            }
        }
        assert_int_equal(t.used, CELLS / 2);
    }
    for (int c = 0; c < CELLS; c++) {
        const int32_t cell[3] = { c % SIDE, c / SIDE % SIDE, c / (SIDE * SIDE) };
        for (int a = 0; a < 3; a++) {
            p[c][a] = (cell[a] << LEVEL) + (cell[(a + 1) % 3] + 2 * a) % (1 << LEVEL);
        }
    }
    sta_cell_tensors_add(&t, (const int32_t(*)[3])p, CELLS);
    for (int64_t z = 1; z < SIDE; z += 3) {
        for (int64_t y = 1; y < SIDE; y += 2) {
            for (int64_t x = 1; x < SIDE; x++) {
                const int64_t v[3] = { x, y, z };
                int32_t in[8][3];
                size_t m = 0;
                for (int c = 0; c < 8; c++) {
                    const int64_t cell[3] = { x - 1 + (c & 1), y - 1 + (c >> 1 & 1),
                                              z - 1 + (c >> 2) };
                    if ((cell[0] + cell[1] + cell[2]) % 2 == 0) {
                        memcpy(in[m++], p[cell[0] + SIDE * (cell[1] + SIDE * cell[2])],
                               sizeof(in[0]));
                    }
                }
                const int64_t corner[3] = { (x - 1) << LEVEL, (y - 1) << LEVEL, (z - 1) << LEVEL };
                sta_tensor_sums box, want = direct((const int32_t(*)[3])in, m, corner);
                sta_cell_tensors_vertex(&t, v, &box);
                assert_int_equal(box.s[0], 4);
                assert_memory_equal(&box, &want, sizeof(box));
            }
        }
    }
    sta_cell_tensors_release(&t);
}

// sta_cell_tensors_add_sorted against sta_cell_tensors_add: points clustered over 16^3
// cells of level 3 above a corner aligned 11 levels up (not the scene's), dealt at random
// to two sets (a cell's points in both), each in cell order; a third of the cells marked,
// runs of neighbours among them (consecutive keys), and cells below the corner (no key).
// Every vertex's sums agree, so every marked cell's do; a set with no marked cell stays
// empty.
static void sorted_runs_equal_point_by_point_sums(void **state)
{
    (void)state;
    enum {
        SIDE = 16,
        LEVEL = 3,
        N = 6000
    };
    static int32_t p[N][3], sets[2][N][3];
    static uint32_t order[N];
    const int64_t origin[3] = { -1000, 2000, 37 };
    const int32_t corner[3] = { -1000, 2000 + (1 << 11), 37 + (2 << 11) };
    const int32_t lo[3] = { corner[0], corner[1], corner[2] };
    const int32_t hi[3] = { corner[0] + (SIDE << LEVEL), corner[1] + (SIDE << LEVEL),
                            corner[2] + (SIDE << LEVEL) };
    uint32_t seed = 11u;
    for (size_t i = 0; i < N; i++) {
        uint32_t r = sta_test_next_random(&seed);
        for (int a = 0; a < 3; a++) { // (half the points in the lowest quarter of each axis)
            uint32_t span =
                (r >> a & 1) ? (uint32_t)(SIDE << LEVEL) : (uint32_t)(SIDE << LEVEL) / 4;
            p[i][a] = corner[a] + (int32_t)(sta_test_next_random(&seed) % span);
        }
    }
    size_t counts[2] = { 0, 0 };
    for (size_t i = 0; i < N; i++) {
        int s = (int)(sta_test_next_random(&seed) & 1);
        memcpy(sets[s][counts[s]++], p[i], sizeof(p[0]));
    }
    sta_error err = { 0 };
    int32_t(*sorted[2])[3] = { NULL, NULL };
    for (int s = 0; s < 2; s++) {
        assert_int_equal(
            sta_cell_order((const int32_t(*)[3])sets[s], counts[s], corner, LEVEL, order, &err),
            STA_OK);
        sorted[s] = test_malloc((counts[s] + 1) * sizeof(*sorted[s]));
        for (size_t i = 0; i < counts[s]; i++) {
            memcpy(sorted[s][i], sets[s][order[i]], sizeof(sorted[s][0]));
        }
    }
    sta_cell_tensors want, got;
    assert_int_equal(sta_cell_tensors_init(&want, LEVEL, origin, lo, hi, &err), STA_OK);
    assert_int_equal(sta_cell_tensors_init(&got, LEVEL, origin, lo, hi, &err), STA_OK);
    int64_t first[3];
    for (int a = 0; a < 3; a++) {
        first[a] = ((int64_t)corner[a] - origin[a]) >> LEVEL;
    }
    for (int c = 0; c < SIDE * SIDE * SIDE; c++) {
        const int64_t cell[3] = { first[0] + c % SIDE, first[1] + c / SIDE % SIDE,
                                  first[2] + c / (SIDE * SIDE) };
        if ((c * 2654435761u) % 3 == 0 || c % SIDE < 3) {
            assert_true(sta_cell_tensors_mark(&want, cell));
            assert_true(sta_cell_tensors_mark(&got, cell));
        }
    }
    const int64_t below[3] = { first[0] - 1, first[1] - 1, first[2] };
    assert_true(sta_cell_tensors_mark(&want, below));
    assert_true(sta_cell_tensors_mark(&got, below));
    sta_cell_tensors_add(&want, (const int32_t(*)[3])p, N);
    const int32_t(*const in[2])[3] = { (const int32_t(*)[3])sorted[0],
                                       (const int32_t(*)[3])sorted[1] };
    assert_int_equal(sta_cell_tensors_add_sorted(&got, in, counts, 2, corner, &err), STA_OK);
    int64_t with_points = 0;
    for (int z = 0; z <= SIDE; z++) {
        for (int y = 0; y <= SIDE; y++) {
            for (int x = 0; x <= SIDE; x++) {
                const int64_t v[3] = { first[0] + x, first[1] + y, first[2] + z };
                sta_tensor_sums a, b;
                sta_cell_tensors_vertex(&want, v, &a);
                sta_cell_tensors_vertex(&got, v, &b);
                assert_memory_equal(&a, &b, sizeof(a));
                with_points += a.s[0] > 0;
            }
        }
    }
    assert_true(with_points > SIDE * SIDE * SIDE / 2);
    // No marked cell: nothing to add, nothing created.
    sta_cell_tensors none;
    assert_int_equal(sta_cell_tensors_init(&none, LEVEL, origin, lo, hi, &err), STA_OK);
    assert_int_equal(sta_cell_tensors_add_sorted(&none, in, counts, 2, corner, &err), STA_OK);
    assert_int_equal(none.used, 0);
    sta_cell_tensors_release(&none);
    sta_cell_tensors_release(&want);
    sta_cell_tensors_release(&got);
    test_free(sorted[0]);
    test_free(sorted[1]);
}

static const struct CMUnitTest tests[] = {
    cmocka_unit_test(vertex_sums_equal_direct_sums),
    cmocka_unit_test(unmarked_cells_take_no_points),
    cmocka_unit_test(many_cells_keep_their_sums_through_growth),
    cmocka_unit_test(sorted_runs_equal_point_by_point_sums),
};

STA_TEST_MAIN(tests)
