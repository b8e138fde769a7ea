/* SPDX-License-Identifier: MIT
 * Tests for the exact kNN search (preprocess/knn_grid.c) and its selection
 * (knn_select.c): every neighbourhood, narrow and widened, is the set a brute-force
 * search gives under the same order (squared float distance, then integer
 * coordinates), on random volumes, lattices full of distance ties, dense scan lines,
 * duplicates and a set whose last points are only searched (a halo). */
#include "test_support.h"

#include <stdlib.h>
#include <string.h>

#include "core/alloc.h"
#include "knn_grid.h"
#include "knn_select.h"

typedef struct entry {
    float d2;
    int32_t grid[3];
} entry;

static int compare_entry(const void *pa, const void *pb)
{
    const entry *a = pa, *b = pb;
    if (a->d2 != b->d2) {
        return a->d2 < b->d2 ? -1 : 1;
    }
    for (int i = 0; i < 3; i++) {
        if (a->grid[i] != b->grid[i]) {
            return a->grid[i] < b->grid[i] ? -1 : 1;
        }
    }
    return 0;
}

typedef struct check {
    const float (*xyz)[3];
    const int32_t (*grid)[3];
    size_t n, queries;
    int k, widen_every; /* every widen_every-th point asks for `wide` (0: none) */
    int wide;
    int *visits;       /* per point: visits seen */
    size_t mismatches; /* neighbourhoods unlike brute force */
    entry *scratch;    /* n */
} check;

// Brute force: all n points under the same order, the first want + 1.
static size_t brute(const check *c, size_t i, int want, entry *out)
{
    const float *q = c->xyz[i];
    for (size_t j = 0; j < c->n; j++) {
        float dx = c->xyz[j][0] - q[0], dy = c->xyz[j][1] - q[1], dz = c->xyz[j][2] - q[2];
        c->scratch[j].d2 = dx * dx + dy * dy + dz * dz;
        memcpy(c->scratch[j].grid, c->grid[j], sizeof(c->grid[j]));
    }
    qsort(c->scratch, c->n, sizeof(entry), compare_entry);
    size_t size = c->n < (size_t)want + 1 ? c->n : (size_t)want + 1;
    memcpy(out, c->scratch, size * sizeof(entry));
    return size;
}

static int visit(void *user, size_t i, const sta_knn *nb)
{
    check *c = user;
    assert_true(i < c->queries);
    c->visits[i]++;
    int want = nb->capacity - 1;
    entry expected[STA_KNN_MAX + 1], got[STA_KNN_MAX + 1];
    size_t size = brute(c, i, want, expected);
    bool same = (size_t)nb->size == size;
    for (int j = 0; j < nb->size && same; j++) {
        got[j].d2 = nb->d2[j];
        memcpy(got[j].grid, nb->grid[j], sizeof(got[j].grid));
    }
    if (same) {
        qsort(got, size, sizeof(entry), compare_entry);
        same = memcmp(got, expected, size * sizeof(entry)) == 0;
    }
    c->mismatches += !same;
    bool widen = c->widen_every > 0 && i % (size_t)c->widen_every == 0 && want < c->wide;
    return widen ? c->wide : 0;
}

// Runs the search over grid points (metres = grid / 1000) and checks every visit.
static void run_check(const int32_t (*grid)[3], size_t n, size_t queries, int k, int widen_every,
                      int wide)
{
    float(*xyz)[3] = sta_alloc_array(n, sizeof(*xyz));
    int *visits = sta_calloc(n, sizeof(int));
    entry *scratch = sta_alloc_array(n, sizeof(entry));
    assert_non_null(xyz);
    assert_non_null(visits);
    assert_non_null(scratch);
    for (size_t i = 0; i < n; i++) {
        for (int a = 0; a < 3; a++) {
            xyz[i][a] = (float)((double)grid[i][a] * 0.001);
        }
    }
    check c = {
        (const float(*)[3])xyz, grid, n, queries, k, widen_every, wide, visits, 0, scratch
    };
    sta_error err = { 0 };
    assert_int_equal(sta_knn_each(c.xyz, grid, n, queries, k, visit, &c, &err), STA_OK);
    assert_int_equal(c.mismatches, 0);
    for (size_t i = 0; i < n; i++) {
        bool widened =
            widen_every > 0 && i % (size_t)widen_every == 0 && k < wide && (size_t)k + 1 < n;
        assert_int_equal(visits[i], i < queries ? (widened ? 2 : 1) : 0);
    }
    sta_free(xyz);
    sta_free(visits);
    sta_free(scratch);
}

static int32_t (*alloc_grid(size_t n))[3]
{
    int32_t(*grid)[3] = sta_alloc_array(n, sizeof(*grid));
    assert_non_null(grid);
    return grid;
}

static void random_volume_matches_brute_force(void **state)
{
    (void)state;
    const size_t n = 3000;
    int32_t(*grid)[3] = alloc_grid(n);
    srand(3);
    for (size_t i = 0; i < n; i++) {
        for (int a = 0; a < 3; a++) {
            grid[i][a] = rand() % 20000;
        }
    }
    run_check((const int32_t(*)[3])grid, n, n, 10, 0, 0);
    run_check((const int32_t(*)[3])grid, n, n, 10, 3, 60); // a third widened
    run_check((const int32_t(*)[3])grid, n, n, 40, 0, 0);
    run_check((const int32_t(*)[3])grid, n, n, 3, 1, 64); // all widened, the largest K
    sta_free(grid);
}

// A lattice: every neighbourhood cuts through a shell of equidistant points, which the
// coordinate order must choose between as brute force does.
static void lattice_ties_match_brute_force(void **state)
{
    (void)state;
    const int side = 14;
    const size_t n = (size_t)side * side * side;
    int32_t(*grid)[3] = alloc_grid(n);
    for (size_t i = 0; i < n; i++) {
        grid[i][0] = (int32_t)(i % side) * 50;
        grid[i][1] = (int32_t)(i / side % side) * 50;
        grid[i][2] = (int32_t)(i / side / side) * 50;
    }
    run_check((const int32_t(*)[3])grid, n, n, 10, 0, 0);
    run_check((const int32_t(*)[3])grid, n, n, 10, 2, 60);
    run_check((const int32_t(*)[3])grid, n, n, 26, 0, 0);
    sta_free(grid);
}

// Dense scan lines (2 mm along, 60 mm across, a little noise) and a sparser surface
// patch: the density the grid is tuned to fits neither, and searches leave the block.
// (A point farther than 12 cells from its neighbours gets what those hold: not tested.)
static void scan_lines_and_duplicates_match_brute_force(void **state)
{
    (void)state;
    const size_t n = 4000;
    int32_t(*grid)[3] = alloc_grid(n);
    srand(5);
    for (size_t i = 0; i < n; i++) {
        if (i < 3000) {
            grid[i][0] = (int32_t)(i % 500) * 2;
            grid[i][1] = (int32_t)(i / 500) * 60 + rand() % 3;
            grid[i][2] = rand() % 5;
        } else if (i < 3900) { // a sparser patch beside them (within the 12 shells searched)
            grid[i][0] = 1500 + rand() % 2000;
            grid[i][1] = rand() % 2000;
            grid[i][2] = 100;
        } else { // duplicates of a few points
            memcpy(grid[i], grid[(i % 7) * 100], sizeof(grid[i]));
        }
    }
    run_check((const int32_t(*)[3])grid, n, n, 10, 0, 0);
    run_check((const int32_t(*)[3])grid, n, n, 10, 1, 60);
    sta_free(grid);
}

// Only the first points are queried; the rest (a halo) are candidates only.
static void halo_points_are_candidates_not_queries(void **state)
{
    (void)state;
    const size_t n = 2000;
    int32_t(*grid)[3] = alloc_grid(n);
    srand(9);
    for (size_t i = 0; i < n; i++) {
        grid[i][0] = rand() % 4000;
        grid[i][1] = rand() % 4000;
        grid[i][2] = (grid[i][0] + grid[i][1]) / 3 + rand() % 4;
    }
    run_check((const int32_t(*)[3])grid, n, 700, 10, 4, 60);
    run_check((const int32_t(*)[3])grid, 8, 8, 10, 0, 0); // fewer points than K + 1
    sta_free(grid);
}

static void select_kth_matches_sorting(void **state)
{
    (void)state;
    srand(11);
    for (int round = 0; round < 600; round++) {
        // Half the rounds short (up to 40: both sides of the rank selection's limit).
        size_t n = 1 + (size_t)(rand() % (round < 300 ? 400 : 40));
        float v[400], sorted[400];
        int distinct = 1 + rand() % 20; // few distinct values: many ties
        for (size_t i = 0; i < n; i++) {
            v[i] = (float)(rand() % (round % 2 ? distinct : 100000));
        }
        memcpy(sorted, v, n * sizeof(float));
        for (size_t i = 1; i < n; i++) { // insertion sort, the definition
            float x = sorted[i];
            size_t j = i;
            while (j > 0 && sorted[j - 1] > x) {
                sorted[j] = sorted[j - 1];
                j--;
            }
            sorted[j] = x;
        }
        size_t k = (size_t)rand() % n;
        assert_true(sta_knn_select_kth(v, n, k) == sorted[k]);
    }
}

static const struct CMUnitTest tests[] = {
    cmocka_unit_test(random_volume_matches_brute_force),
    cmocka_unit_test(lattice_ties_match_brute_force),
    cmocka_unit_test(scan_lines_and_duplicates_match_brute_force),
    cmocka_unit_test(halo_points_are_candidates_not_queries),
    cmocka_unit_test(select_kth_matches_sorting),
};

STA_TEST_MAIN(tests)
