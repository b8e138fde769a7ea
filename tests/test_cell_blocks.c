/* SPDX-License-Identifier: MIT
 * Tests for the cell moments in blocks of 4 x 4 x 4 cells (preprocess/cell_blocks.c)
 * against the hashed cells (cell_moments.c, itself checked against brute force): the
 * points added in Morton order, in input order and from a hashed set give the same cells,
 * counts and vertex sums (lower and higher halves) at fine and coarse levels, at and below
 * the set's lowest cells; levels coarsened from a finer one equal levels added directly;
 * the children of wanted cells summed from two sorted lists equal the hashed set of them;
 * a set too wide for the cell coordinates and a point outside the box are refused. */
#include "test_support.h"

#include <stdlib.h>
#include <string.h>

#include "cell_blocks.h"
#include "cell_moments.h"
#include "cell_order.h"
#include "core/alloc.h"

enum {
    POINTS = 5000
};

static void bounds(const int32_t (*grid)[3], size_t n, int32_t lo[3], int32_t hi[3])
{
    for (int a = 0; a < 3; a++) {
        lo[a] = hi[a] = grid[0][a];
        for (size_t i = 1; i < n; i++) {
            lo[a] = grid[i][a] < lo[a] ? grid[i][a] : lo[a];
            hi[a] = grid[i][a] > hi[a] ? grid[i][a] : hi[a];
        }
    }
}

// The points' Morton order of cells of `level` from a corner 256 cells aligned (as the
// moments normals sort them).
static void morton_order(const int32_t (*grid)[3], const int64_t origin[3], const int32_t lo[3],
                         int level, uint32_t *order)
{
    int32_t corner[3];
    int align = level + 8;
    for (int a = 0; a < 3; a++) {
        corner[a] = (int32_t)(origin[a] + ((((int64_t)lo[a] - origin[a]) >> align) << align));
    }
    sta_error err = { 0 };
    assert_int_equal(sta_cell_order(grid, POINTS, corner, level, order, &err), STA_OK);
}

// Every cell and vertex sum of `b` equals `h`'s: the cells of the points and beside them,
// and the vertices at and beyond the set's lowest cells. Returns the vertices with points.
static size_t check_same(const sta_cell_blocks *b, const sta_cell_moments *h,
                         const int32_t (*grid)[3], const int64_t origin[3])
{
    assert_int_equal(b->used, h->used);
    assert_null(b->loose);
    size_t full = 0;
    for (size_t s = 0; s < POINTS / 7 + 8; s++) {
        size_t i = s < POINTS / 7 ? s * 7 : POINTS + s - POINTS / 7;
        int64_t v[3];
        for (int a = 0; a < 3; a++) {
            if (i >= POINTS) { // at and below the set's lowest cell
                v[a] = h->base[a] + 1 - (int64_t)((i >> a) & 1);
            } else {
                v[a] = (((int64_t)grid[i][a] - origin[a]) >> h->level) + (int64_t)(i % 3) - 1;
            }
        }
        assert_int_equal(sta_cell_blocks_count(b, v), sta_cell_moments_count(h, v));
        sta_moment_sums want, lower, higher;
        sta_cell_moments_vertex(h, v, &want);
        memset(&higher, 0x5a, sizeof(higher));
        sta_cell_blocks_vertex_lower(b, v, &lower);
        sta_cell_blocks_vertex_higher(b, v, &higher);
        assert_true(lower.s4 == 0 && lower.s3[0] == 0 && lower.s3[1] == 0 && lower.s3[2] == 0);
        assert_true(higher.n == 0x5a5a5a5a5a5a5a5a); // (left as it was)
        memcpy(lower.s3, higher.s3, sizeof(lower.s3));
        lower.s4 = higher.s4;
        assert_memory_equal(&lower, &want, sizeof(want));
        full += want.n > 0;
    }
    return full;
}

static void hashed(sta_cell_moments *h, int level, const int64_t origin[3], const int32_t lo[3],
                   const int32_t hi[3], const int32_t (*grid)[3])
{
    sta_error err = { 0 };
    assert_int_equal(sta_cell_moments_init(h, level, origin, lo, hi, &err), STA_OK);
    h->higher = true;
    assert_int_equal(sta_cell_moments_add(h, grid, POINTS, NULL, NULL, &err), STA_OK);
}

// The same cells from the points in Morton order (appended block by block), in input order
// (sorted when sealed) and from the hashed set, at fine and coarse levels.
static void every_order_holds_the_hashed_sums(void **state)
{
    (void)state;
    int32_t(*grid)[3] = sta_alloc_array(POINTS, sizeof(*grid));
    uint32_t *order = sta_alloc_array(POINTS, sizeof(*order));
    assert_non_null(grid);
    assert_non_null(order);
    const int32_t corner[3] = { -300000, 7000, 123456 };
    sta_test_random_grid(grid, POINTS, corner, 3000, 5, true);
    const int64_t origin[3] = { -300101, 6003, 100000 };
    int32_t lo[3], hi[3];
    bounds((const int32_t(*)[3])grid, POINTS, lo, hi);
    const int levels[] = { 0, 3, 5, 9 };
    sta_error err = { 0 };
    for (size_t l = 0; l < sizeof(levels) / sizeof(levels[0]); l++) {
        int level = levels[l];
        sta_cell_moments h;
        hashed(&h, level, origin, lo, hi, (const int32_t(*)[3])grid);
        morton_order((const int32_t(*)[3])grid, origin, lo, level, order);
        sta_cell_blocks sorted, input, from;
        assert_int_equal(sta_cell_blocks_init(&sorted, level, true, origin, lo, hi, &err), STA_OK);
        assert_int_equal(sta_cell_blocks_init(&input, level, true, origin, lo, hi, &err), STA_OK);
        assert_int_equal(sta_cell_blocks_init(&from, level, true, origin, lo, hi, &err), STA_OK);
        assert_int_equal(
            sta_cell_blocks_add(&sorted, (const int32_t(*)[3])grid, POINTS, order, &err), STA_OK);
        // (half the points first, the rest later: blocks met again)
        assert_int_equal(
            sta_cell_blocks_add(&input, (const int32_t(*)[3])grid, POINTS / 2, NULL, &err), STA_OK);
        assert_int_equal(sta_cell_blocks_add(&input, (const int32_t(*)[3])grid + POINTS / 2,
                                             POINTS - POINTS / 2, NULL, &err),
                         STA_OK);
        assert_int_equal(sta_cell_blocks_add_moments(&from, &h, &err), STA_OK);
        assert_true(check_same(&sorted, &h, (const int32_t(*)[3])grid, origin) > 0);
        assert_true(check_same(&input, &h, (const int32_t(*)[3])grid, origin) > 0);
        assert_true(check_same(&from, &h, (const int32_t(*)[3])grid, origin) > 0);
        sta_cell_blocks_release(&sorted);
        sta_cell_blocks_release(&input);
        sta_cell_blocks_release(&from);
        sta_cell_moments_release(&h);
    }
    sta_free(order);
    sta_free(grid);
}

// Levels 3..9 coarsened one from the next finer, from level 2 added in Morton order and
// from level 2 added in input order: the same cells as each level added directly.
static void coarsened_levels_match_direct(void **state)
{
    (void)state;
    int32_t(*grid)[3] = sta_alloc_array(POINTS, sizeof(*grid));
    uint32_t *order = sta_alloc_array(POINTS, sizeof(*order));
    assert_non_null(grid);
    assert_non_null(order);
    const int32_t corner[3] = { 1000000, -2000000, 37 };
    sta_test_random_grid(grid, POINTS, corner, 5000, 11, true);
    const int64_t origin[3] = { 999000, -2000500, 0 };
    int32_t lo[3], hi[3];
    bounds((const int32_t(*)[3])grid, POINTS, lo, hi);
    morton_order((const int32_t(*)[3])grid, origin, lo, 2, order);
    sta_error err = { 0 };
    for (int ordered = 0; ordered < 2; ordered++) {
        sta_cell_blocks fine;
        assert_int_equal(sta_cell_blocks_init(&fine, 2, true, origin, lo, hi, &err), STA_OK);
        assert_int_equal(sta_cell_blocks_add(&fine, (const int32_t(*)[3])grid, POINTS,
                                             ordered ? order : NULL, &err),
                         STA_OK);
        for (int level = 3; level <= 9; level++) {
            sta_cell_blocks coarse;
            sta_cell_moments direct;
            assert_int_equal(sta_cell_blocks_init(&coarse, level, true, origin, lo, hi, &err),
                             STA_OK);
            assert_int_equal(sta_cell_blocks_coarsen(&fine, &coarse, &err), STA_OK);
            hashed(&direct, level, origin, lo, hi, (const int32_t(*)[3])grid);
            assert_true(check_same(&coarse, &direct, (const int32_t(*)[3])grid, origin) > 0);
            sta_cell_moments_release(&direct);
            sta_cell_blocks_release(&fine);
            fine = coarse;
        }
        sta_cell_blocks_release(&fine);
    }
    sta_free(order);
    sta_free(grid);
}

// The children of the wanted cells one level up from two lists in Morton order of those
// cells (points of one parent in both lists), and from the lists in input order: the
// same cells as the hashed set of the wanted cells' points; NULL wanted: all points.
static void children_of_wanted_cells_from_two_lists(void **state)
{
    (void)state;
    int32_t(*grid)[3] = sta_alloc_array(POINTS, sizeof(*grid));
    int32_t(*lists)[3] = sta_alloc_array(POINTS, sizeof(*lists));
    uint32_t *order = sta_alloc_array(POINTS, sizeof(*order));
    assert_non_null(grid);
    assert_non_null(lists);
    assert_non_null(order);
    const int32_t corner[3] = { 40000, -9000, 77 };
    sta_test_random_grid(grid, POINTS, corner, 4000, 17, true);
    const int64_t origin[3] = { 39001, -9500, -3 };
    int32_t lo[3], hi[3], from[3];
    bounds((const int32_t(*)[3])grid, POINTS, lo, hi);
    sta_error err = { 0 };
    for (int level = 2; level <= 6; level += 4) {
        int align = level + 1 + 8;
        for (int a = 0; a < 3; a++) {
            from[a] = (int32_t)(origin[a] + ((((int64_t)lo[a] - origin[a]) >> align) << align));
        }
        sta_cell_moments wanted, want, all;
        assert_int_equal(sta_cell_moments_init(&wanted, level + 1, origin, lo, hi, &err), STA_OK);
        for (size_t i = 0; i < POINTS; i += 3) { // (about a third of the parents)
            const int64_t cell[3] = { ((int64_t)grid[i][0] - origin[0]) >> (level + 1),
                                      ((int64_t)grid[i][1] - origin[1]) >> (level + 1),
                                      ((int64_t)grid[i][2] - origin[2]) >> (level + 1) };
            assert_true(sta_cell_moments_mark(&wanted, cell));
        }
        assert_int_equal(sta_cell_moments_init(&want, level, origin, lo, hi, &err), STA_OK);
        want.higher = true;
        assert_int_equal(
            sta_cell_moments_add(&want, (const int32_t(*)[3])grid, POINTS, NULL, &wanted, &err),
            STA_OK);
        assert_true(want.used > 0 && want.used < POINTS);
        hashed(&all, level, origin, lo, hi, (const int32_t(*)[3])grid);
        assert_int_equal(
            sta_cell_order((const int32_t(*)[3])grid, POINTS, from, level + 1, order, &err),
            STA_OK);
        for (int sorted = 0; sorted < 2; sorted++) {
            // Every third point to the second list, the rest to the first (each in order).
            size_t na = 0, nb = 0, second = POINTS - POINTS / 3;
            for (size_t j = 0; j < POINTS; j++) {
                size_t i = sorted ? order[j] : j;
                memcpy(lists[j % 3 == 2 ? second + nb++ : na++], grid[i], sizeof(lists[0]));
            }
            assert_int_equal(na, second);
            for (int every = 0; every < 2; every++) {
                sta_cell_blocks m;
                assert_int_equal(sta_cell_blocks_init(&m, level, true, origin, lo, hi, &err),
                                 STA_OK);
                assert_int_equal(sta_cell_blocks_add_children(&m, (const int32_t(*)[3])lists, na,
                                                              (const int32_t(*)[3])lists + second,
                                                              nb, from, every ? NULL : &wanted,
                                                              &err),
                                 STA_OK);
                assert_true(
                    check_same(&m, every ? &all : &want, (const int32_t(*)[3])grid, origin) > 0);
                sta_cell_blocks_release(&m);
            }
        }
        sta_cell_moments_release(&all);
        sta_cell_moments_release(&want);
        sta_cell_moments_release(&wanted);
    }
    sta_free(order);
    sta_free(lists);
    sta_free(grid);
}

static void bad_boxes_are_refused(void **state)
{
    (void)state;
    const int64_t origin[3] = { 0, 0, 0 };
    const int32_t lo[3] = { 0, 0, 0 }, hi[3] = { 1 << 22, 5, 5 };
    sta_error err = { 0 };
    sta_cell_blocks m;
    assert_int_equal(sta_cell_blocks_init(&m, 0, false, origin, lo, hi, &err), STA_ERR_ARG);
    assert_int_equal(
        sta_cell_blocks_init(&m, STA_MOMENTS_MAX_LEVEL + 1, false, origin, lo, hi, &err),
        STA_ERR_ARG);
    assert_int_equal(sta_cell_blocks_init(&m, 2, false, origin, lo, hi, &err), STA_OK);
    // A point below the box's lowest cell's block: refused with a message, nothing added.
    const int32_t far[2][3] = { { 100, 1, 1 }, { -100, 2, 2 } };
    assert_int_equal(sta_cell_blocks_add(&m, far, 2, NULL, &err), STA_ERR_ARG);
    assert_non_null(strstr(err.message, "outside"));
    sta_cell_blocks_release(&m);
}

static const struct CMUnitTest tests[] = {
    cmocka_unit_test(every_order_holds_the_hashed_sums),
    cmocka_unit_test(coarsened_levels_match_direct),
    cmocka_unit_test(children_of_wanted_cells_from_two_lists),
    cmocka_unit_test(bad_boxes_are_refused),
};

STA_TEST_MAIN(tests)
