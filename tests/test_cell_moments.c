/* SPDX-License-Identifier: MIT
 * Tests for the per-cell exact moments (preprocess/cell_moments.c): every cell of a
 * block holds the sums a brute-force pass over the points gives (offsets from the
 * block's corner), at fine and coarse levels and for blocks reaching past the set, and
 * so do the summed 2 x 2 x 2 blocks around grid vertices;
 * adding only the points of wanted coarser cells keeps those cells whole; a set of marks
 * keeps thousands of cells through its growth and refuses points; a set too
 * wide for the cell coordinates is refused; a level coarsened from a finer one and the
 * points added in cell order (cell_order.c) give the same sums as adding the points
 * directly; the cell order keeps every cell's points together, and is the stable sort by
 * the cells' Morton keys also when whole digits of the keys are the same for all points. */
#include "test_support.h"

#include <stdlib.h>
#include <string.h>

#include "cell_moments.h"
#include "cell_order.h"
#include "core/alloc.h"

enum {
    POINTS = 4000
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

// `m` initialised at `level` and holding all POINTS points of `grid` (in `order` when
// not NULL).
static void moments_of_all(sta_cell_moments *m, int level, const int64_t origin[3],
                           const int32_t lo[3], const int32_t hi[3], const int32_t (*grid)[3],
                           const uint32_t *order)
{
    sta_error err = { 0 };
    assert_int_equal(sta_cell_moments_init(m, level, origin, lo, hi, &err), STA_OK);
    m->higher = true;
    assert_int_equal(sta_cell_moments_add(m, grid, POINTS, order, NULL, &err), STA_OK);
}

// The sums of the points in cell (anchor + xyz) of `level`, offsets from the block corner.
static sta_moment_sums brute(const int32_t (*grid)[3], size_t n, const int64_t origin[3], int level,
                             const int64_t anchor[3], const int xyz[3])
{
    sta_moment_sums m = { 0 };
    for (size_t i = 0; i < n; i++) {
        int64_t d[3];
        bool inside = true;
        for (int a = 0; a < 3; a++) {
            int64_t u = (int64_t)grid[i][a] - origin[a];
            inside = inside && (u >> level) == anchor[a] + xyz[a];
            d[a] = u - anchor[a] * ((int64_t)1 << level);
        }
        if (!inside) {
            continue;
        }
        m.n++;
        for (int a = 0; a < 3; a++) {
            m.s1[a] += d[a];
        }
        for (int r = 0, t = 0; r < 3; r++) {
            for (int c = r; c < 3; c++, t++) {
                m.s2[t] += d[r] * d[c];
            }
        }
        // the sphere fit's sums, modulo 2^64 as the cells keep them
        uint64_t dd = (uint64_t)(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        for (int a = 0; a < 3; a++) {
            m.s3[a] += (uint64_t)d[a] * dd;
        }
        m.s4 += dd * dd;
    }
    return m;
}

// Every block of `cells` cells an axis from each point's cell (moved by -1 and -2, so
// blocks reach past the set's lowest cells) against brute force. Returns the cells
// checked that held points.
static size_t check_blocks(const sta_cell_moments *m, const int32_t (*grid)[3], size_t n,
                           const int64_t origin[3], int cells, size_t every)
{
    sta_moment_sums out[64];
    size_t full = 0;
    for (size_t i = 0; i < n; i += every) {
        int64_t anchor[3];
        for (int a = 0; a < 3; a++) {
            anchor[a] = (((int64_t)grid[i][a] - origin[a]) >> m->level) - 1 - (int64_t)(i % 2);
        }
        sta_cell_moments_block(m, anchor, cells, out);
        for (int z = 0, j = 0; z < cells; z++) {
            for (int y = 0; y < cells; y++) {
                for (int x = 0; x < cells; x++, j++) {
                    const int xyz[3] = { x, y, z };
                    sta_moment_sums b = brute(grid, n, origin, m->level, anchor, xyz);
                    assert_memory_equal(&out[j], &b, sizeof(b));
                    full += b.n > 0;
                }
            }
        }
    }
    return full;
}

static void block_sums_match_brute_force(void **state)
{
    (void)state;
    int32_t(*grid)[3] = sta_alloc_array(POINTS, sizeof(*grid));
    assert_non_null(grid);
    const int32_t corner[3] = { 1000000, -2000000, 37 };
    sta_test_random_grid(grid, POINTS, corner, 5000, 11, false);
    const int64_t origin[3] = { 999000, -2000500, 0 }; // the scene's corner: below every point
    int32_t lo[3], hi[3];
    bounds((const int32_t(*)[3])grid, POINTS, lo, hi);
    const int levels[] = { 0, 4, 8, 11 };
    for (size_t l = 0; l < sizeof(levels) / sizeof(levels[0]); l++) {
        sta_cell_moments m;
        moments_of_all(&m, levels[l], origin, lo, hi, (const int32_t(*)[3])grid, NULL);
        size_t full = 0;
        for (int cells = 3; cells <= 4; cells++) {
            full += check_blocks(&m, (const int32_t(*)[3])grid, POINTS, origin, cells, 97);
        }
        assert_true(full > 0);
        sta_cell_moments_release(&m);
    }
    sta_free(grid);
}

// The summed 2 x 2 x 2 blocks around grid vertices (sta_cell_moments_vertex, the vertex
// boxes of the moments normals) against brute force: vertices of the points' cells and
// beside them, and ones at and beyond the set's lowest cells (the general path).
static void vertex_sums_match_brute_force(void **state)
{
    (void)state;
    int32_t(*grid)[3] = sta_alloc_array(POINTS, sizeof(*grid));
    assert_non_null(grid);
    const int32_t corner[3] = { -300000, 7000, 123456 };
    sta_test_random_grid(grid, POINTS, corner, 3000, 5, false);
    const int64_t origin[3] = { -300100, 6000, 100000 };
    int32_t lo[3], hi[3];
    bounds((const int32_t(*)[3])grid, POINTS, lo, hi);
    const int levels[] = { 0, 5, 9 };
    for (size_t l = 0; l < sizeof(levels) / sizeof(levels[0]); l++) {
        sta_cell_moments m;
        moments_of_all(&m, levels[l], origin, lo, hi, (const int32_t(*)[3])grid, NULL);
        size_t full = 0, outside = 0;
        for (size_t s = 0; s < POINTS / 41 + 8; s++) {
            size_t i = s < POINTS / 41 ? s * 41 : POINTS + s - POINTS / 41;
            int64_t v[3];
            for (int a = 0; a < 3; a++) {
                if (i >= POINTS) { // at and below the set's lowest cell
                    v[a] = m.base[a] + 1 - (int64_t)((i >> a) & 1);
                } else {
                    v[a] = (((int64_t)grid[i][a] - origin[a]) >> m.level) + (int64_t)(i % 3) - 1;
                }
            }
            outside += i >= POINTS;
            sta_moment_sums got, want = { 0 };
            sta_cell_moments_vertex(&m, v, &got);
            const int64_t anchor[3] = { v[0] - 1, v[1] - 1, v[2] - 1 };
            for (int k = 0; k < 8; k++) {
                const int xyz[3] = { k & 1, k >> 1 & 1, k >> 2 };
                sta_moment_sums b =
                    brute((const int32_t(*)[3])grid, POINTS, origin, m.level, anchor, xyz);
                want.n += b.n;
                for (int a = 0; a < 3; a++) {
                    want.s1[a] += b.s1[a];
                }
                for (int t = 0; t < 6; t++) {
                    want.s2[t] += b.s2[t];
                }
                for (int a = 0; a < 3; a++) {
                    want.s3[a] += b.s3[a];
                }
                want.s4 += b.s4;
            }
            assert_memory_equal(&got, &want, sizeof(want));
            full += want.n > 0;
        }
        assert_true(full > 0 && outside > 0);
        sta_cell_moments_release(&m);
    }
    sta_free(grid);
}

static void wanted_cells_hold_all_their_points(void **state)
{
    (void)state;
    int32_t(*grid)[3] = sta_alloc_array(POINTS, sizeof(*grid));
    assert_non_null(grid);
    const int32_t corner[3] = { 0, 0, 0 };
    sta_test_random_grid(grid, POINTS, corner, 3000, 5, false);
    const int64_t origin[3] = { 0, 0, 0 };
    int32_t lo[3], hi[3];
    bounds((const int32_t(*)[3])grid, POINTS, lo, hi);
    sta_error err = { 0 };
    sta_cell_moments wanted, all, some;
    assert_int_equal(sta_cell_moments_init_marks(&wanted, 9, origin, lo, hi, &err), STA_OK);
    const int64_t mark[2][3] = { { 1, 2, 0 }, { 4, 4, 5 } };
    for (int i = 0; i < 2; i++) {
        assert_true(sta_cell_moments_mark(&wanted, mark[i]));
        assert_true(sta_cell_moments_has(&wanted, mark[i]));
    }
    assert_false(sta_cell_moments_has(&wanted, (const int64_t[3]){ 1, 2, 1 }));
    moments_of_all(&all, 6, origin, lo, hi, (const int32_t(*)[3])grid, NULL);
    assert_int_equal(sta_cell_moments_init(&some, 6, origin, lo, hi, &err), STA_OK);
    some.higher = true;
    assert_int_equal(
        sta_cell_moments_add(&some, (const int32_t(*)[3])grid, POINTS, NULL, &wanted, &err),
        STA_OK);
    // Inside a wanted cell (8 cells of level 6 an axis) every cell equals the full set's;
    // the cells next to it are empty.
    sta_moment_sums a[64], b[64];
    size_t full = 0;
    for (int i = 0; i < 2; i++) {
        for (int dz = -1; dz <= 8; dz += 3) {
            for (int dy = -1; dy <= 8; dy += 3) {
                for (int dx = -1; dx <= 8; dx += 3) {
                    const int64_t anchor[3] = { mark[i][0] * 8 + dx, mark[i][1] * 8 + dy,
                                                mark[i][2] * 8 + dz };
                    sta_cell_moments_block(&all, anchor, 3, a);
                    sta_cell_moments_block(&some, anchor, 3, b);
                    for (int j = 0; j < 27; j++) {
                        int64_t c[3] = { anchor[0] + j % 3, anchor[1] + j / 3 % 3,
                                         anchor[2] + j / 9 };
                        bool in = true;
                        for (int k = 0; k < 3; k++) {
                            in = in && (c[k] >> 3) == mark[i][k];
                        }
                        if (in) {
                            assert_memory_equal(&a[j], &b[j], sizeof(a[j]));
                            full += a[j].n > 0;
                        } else {
                            assert_int_equal(b[j].n, 0);
                        }
                    }
                }
            }
        }
    }
    assert_true(full > 10);
    assert_true(some.used < all.used);
    sta_cell_moments_release(&wanted);
    sta_cell_moments_release(&all);
    sta_cell_moments_release(&some);
    sta_free(grid);
}

// A set of marks (no sums): 4000 cells marked in a scattered order, twice, through
// several doublings of its table; exactly those exist; it refuses points.
static void a_set_of_marks_grows_and_takes_no_points(void **state)
{
    (void)state;
    enum {
        SIDE = 20,
        CELLS = SIDE * SIDE * SIDE
    };
    const int64_t origin[3] = { 0, 0, 0 };
    const int32_t lo[3] = { 0, 0, 0 }, hi[3] = { SIDE << 4, SIDE << 4, SIDE << 4 };
    sta_cell_moments marks;
    sta_error err = { 0 };
    assert_int_equal(sta_cell_moments_init_marks(&marks, 4, origin, lo, hi, &err), STA_OK);
    assert_null(marks.sums);
    for (int pass = 0; pass < 2; pass++) {
        for (int i = 0; i < CELLS; i++) {
            int c = (i * 7919) % CELLS; // (7919 is prime to CELLS: every cell once)
            const int64_t cell[3] = { c % SIDE, c / SIDE % SIDE, c / (SIDE * SIDE) };
            if ((cell[0] + cell[1] + cell[2]) % 2 == 0) {
                assert_true(sta_cell_moments_mark(&marks, cell));
            }
        }
        assert_int_equal(marks.used, CELLS / 2);
    }
    for (int c = 0; c < CELLS; c++) {
        const int64_t cell[3] = { c % SIDE, c / SIDE % SIDE, c / (SIDE * SIDE) };
        assert_int_equal(sta_cell_moments_has(&marks, cell),
                         (cell[0] + cell[1] + cell[2]) % 2 == 0);
    }
    const int32_t point[1][3] = { { 1, 1, 1 } };
    assert_int_equal(sta_cell_moments_add(&marks, point, 1, NULL, NULL, &err), STA_ERR_ARG);
    assert_non_null(strstr(err.message, "marks"));
    sta_cell_moments_release(&marks);
}

static void too_wide_a_set_is_refused(void **state)
{
    (void)state;
    const int64_t origin[3] = { 0, 0, 0 };
    const int32_t lo[3] = { 0, 0, 0 }, hi[3] = { 1 << 22, 5, 5 };
    sta_cell_moments m;
    sta_error err = { 0 };
    assert_int_equal(sta_cell_moments_init(&m, 0, origin, lo, hi, &err), STA_ERR_ARG);
    assert_non_null(strstr(err.message, "spans too many cells"));
    assert_int_equal(sta_cell_moments_init(&m, STA_MOMENTS_MAX_LEVEL + 1, origin, lo, hi, &err),
                     STA_ERR_ARG);
    assert_int_equal(sta_cell_moments_init(&m, 2, origin, lo, hi, &err), STA_OK);
    sta_cell_moments_release(&m);
}

// Levels 3 to 9: built from the points directly (input order), and each from the level
// below by coarsening, starting from level 2 built in cell order: every block of both
// holds the brute-force sums (exact integers: the same whatever the order).
static void coarsened_levels_match_brute_force(void **state)
{
    (void)state;
    int32_t(*grid)[3] = sta_alloc_array(POINTS, sizeof(*grid));
    uint32_t *order = sta_alloc_array(POINTS, sizeof(*order));
    assert_non_null(grid);
    assert_non_null(order);
    const int32_t corner[3] = { -300000, 4000, 1000000 };
    sta_test_random_grid(grid, POINTS, corner, 3000, 23, false);
    const int64_t origin[3] = { -300100, 3000, 999999 };
    int32_t lo[3], hi[3];
    bounds((const int32_t(*)[3])grid, POINTS, lo, hi);
    sta_error err = { 0 };
    assert_int_equal(sta_cell_order((const int32_t(*)[3])grid, POINTS, lo, 2, order, &err), STA_OK);
    sta_cell_moments fine;
    moments_of_all(&fine, 2, origin, lo, hi, (const int32_t(*)[3])grid, order);
    for (int level = 3; level <= 9; level++) {
        sta_cell_moments coarse, direct;
        assert_int_equal(sta_cell_moments_init(&coarse, level, origin, lo, hi, &err), STA_OK);
        coarse.higher = true;
        assert_int_equal(sta_cell_moments_coarsen(&fine, &coarse, &err), STA_OK);
        moments_of_all(&direct, level, origin, lo, hi, (const int32_t(*)[3])grid, NULL);
        assert_int_equal(coarse.used, direct.used);
        assert_true(check_blocks(&coarse, (const int32_t(*)[3])grid, POINTS, origin, 3, 31) > 0);
        assert_true(check_blocks(&direct, (const int32_t(*)[3])grid, POINTS, origin, 3, 31) > 0);
        sta_cell_moments_release(&direct);
        sta_cell_moments_release(&fine);
        fine = coarse;
    }
    sta_cell_moments_release(&fine);
    sta_free(order);
    sta_free(grid);
}

// The order is a permutation in which the points of each cell (of the sorted level and
// of coarser ones, aligned to `lo`) come together, in input order within a cell.
static void cell_order_keeps_cells_together(void **state)
{
    (void)state;
    int32_t(*grid)[3] = sta_alloc_array(POINTS, sizeof(*grid));
    uint32_t *order = sta_alloc_array(POINTS, sizeof(*order));
    uint8_t *seen = sta_calloc(POINTS, 1);
    assert_non_null(grid);
    assert_non_null(order);
    assert_non_null(seen);
    const int32_t corner[3] = { 5, -77, 123456 };
    sta_test_random_grid(grid, POINTS, corner, 20000, 5, false);
    int32_t lo[3], hi[3];
    bounds((const int32_t(*)[3])grid, POINTS, lo, hi);
    sta_error err = { 0 };
    assert_int_equal(sta_cell_order((const int32_t(*)[3])grid, POINTS, lo, 6, order, &err), STA_OK);
    for (size_t j = 0; j < POINTS; j++) {
        assert_true(order[j] < POINTS && !seen[order[j]]);
        seen[order[j]] = 1;
    }
    for (int level = 6; level <= 10; level += 2) {
        // A cell's run, once left, never comes back.
        size_t runs = 0;
        for (size_t j = 0; j < POINTS; j++) {
            int64_t c[3], p[3];
            for (int a = 0; a < 3; a++) {
                c[a] = ((int64_t)grid[order[j]][a] - lo[a]) >> level;
                p[a] = j > 0 ? ((int64_t)grid[order[j - 1]][a] - lo[a]) >> level : -1;
            }
            if (memcmp(c, p, sizeof(c)) != 0) {
                runs++;
                for (size_t k = j + 1; k < POINTS; k++) { // (4000^2 / runs: small)
                    int64_t d[3];
                    for (int a = 0; a < 3; a++) {
                        d[a] = ((int64_t)grid[order[k]][a] - lo[a]) >> level;
                    }
                    bool same = memcmp(c, d, sizeof(c)) == 0;
                    bool prev_same = true;
                    for (int a = 0; a < 3; a++) {
                        prev_same = prev_same &&
                                    (((int64_t)grid[order[k - 1]][a] - lo[a]) >> level) == c[a];
                    }
                    assert_false(same && !prev_same);
                }
            } else if (level == 6) {
                assert_true(order[j] > order[j - 1]); // stable: input order within a cell
            }
        }
        assert_true(runs > 1);
    }
    sta_free(seen);
    sta_free(order);
    sta_free(grid);
}

// Morton key of a cell (x in bit 0, y in 1, z in 2, then the next bit of each).
static uint64_t morton(const int64_t c[3])
{
    uint64_t k = 0;
    for (int b = 0; b < 21; b++) {
        for (int a = 0; a < 3; a++) {
            k |= (uint64_t)((c[a] >> b) & 1) << (3 * b + a);
        }
    }
    return k;
}

typedef struct keyed {
    uint64_t key;
    uint32_t index;
} keyed;

static int compare_keyed(const void *a, const void *b)
{
    const keyed *x = a, *y = b;
    if (x->key != y->key) {
        return x->key < y->key ? -1 : 1;
    }
    return x->index < y->index ? -1 : x->index > y->index;
}

static void cell_order_is_stable_morton_sort(void **state)
{
    (void)state;
    int32_t(*grid)[3] = sta_alloc_array(POINTS, sizeof(*grid));
    uint32_t *order = sta_alloc_array(POINTS, sizeof(*order));
    keyed *want = sta_alloc_array(POINTS, sizeof(*want));
    assert_non_null(grid);
    assert_non_null(order);
    assert_non_null(want);
    const int32_t corner[3] = { -3000, 17, 99 };
    sta_error err = { 0 };
    // Random cells, then cells on a lattice 16 apart (the keys' low 12 bits, the first
    // digit of the sort, are 0 for every point), then on a 2-cell lattice spanning many
    // digits, then on one spanning all 21 bits an axis (63-bit keys), then 27 cells for
    // 4 000 points (ties everywhere: the input order keeps them), then the 63-bit lattice
    // for every tenth point and the rest in 40 cells an axis near the corner (one large
    // bucket of the first pass, sorted by its 52 bits below): each the stable sort of the
    // indices by key.
    for (int round = 0; round < 6; round++) {
        uint32_t s = 11u + (uint32_t)round;
        const int32_t strides[6] = { 1, 16, 2, 2, 1, 2 },
                      counts[6] = { 300, 300, 60000, 1000000, 3, 1000000 };
        int32_t stride = strides[round], cells = counts[round];
        for (size_t i = 0; i < POINTS; i++) {
            bool near = round == 5 && i % 10 != 0;
            for (int a = 0; a < 3; a++) {
                uint32_t r = sta_test_next_random(&s);
                grid[i][a] = corner[a] +
                             (near ? (int32_t)(r % 40u) : stride * (int32_t)(r % (uint32_t)cells));
            }
        }
        assert_int_equal(sta_cell_order((const int32_t(*)[3])grid, POINTS, corner, 0, order, &err),
                         STA_OK);
        for (size_t i = 0; i < POINTS; i++) {
            int64_t c[3];
            for (int a = 0; a < 3; a++) {
                c[a] = (int64_t)grid[i][a] - corner[a];
            }
            want[i] = (keyed){ morton(c), (uint32_t)i };
        }
        qsort(want, POINTS, sizeof(*want), compare_keyed);
        for (size_t j = 0; j < POINTS; j++) {
            assert_int_equal(order[j], want[j].index);
        }
    }
    sta_free(grid);
    sta_free(order);
    sta_free(want);
}

// A set without the higher sums (moments-fine, kNN) keeps no array for them and returns
// them as zero; its other sums equal those of a set with them. A reserved set (room made
// before adding) holds the same cells and sums as one that grew, and so does a coarser set
// built from it.
static void lower_only_and_reserved_sets_hold_the_same_sums(void **state)
{
    (void)state;
    int32_t(*grid)[3] = sta_alloc_array(POINTS, sizeof(*grid));
    assert_non_null(grid);
    const int32_t corner[3] = { 2000, 3000, -4000 };
    sta_test_random_grid(grid, POINTS, corner, 2500, 31, false);
    const int64_t origin[3] = { 0, 0, -5000 };
    int32_t lo[3], hi[3];
    bounds((const int32_t(*)[3])grid, POINTS, lo, hi);
    sta_error err = { 0 };
    sta_cell_moments with, without, reserved, coarse, coarse_reserved;
    moments_of_all(&with, 5, origin, lo, hi, (const int32_t(*)[3])grid, NULL);
    assert_int_equal(sta_cell_moments_init(&without, 5, origin, lo, hi, &err), STA_OK);
    assert_int_equal(
        sta_cell_moments_add(&without, (const int32_t(*)[3])grid, POINTS, NULL, NULL, &err),
        STA_OK);
    assert_null(without.high);
    assert_non_null(with.high);
    assert_int_equal(sta_cell_moments_init(&reserved, 5, origin, lo, hi, &err), STA_OK);
    reserved.higher = true;
    assert_true(sta_cell_moments_reserve(&reserved, 2 * (size_t)POINTS));
    assert_true(reserved.capacity >= 4 * (size_t)POINTS && reserved.used == 0);
    assert_int_equal(
        sta_cell_moments_add(&reserved, (const int32_t(*)[3])grid, POINTS, NULL, NULL, &err),
        STA_OK);
    assert_int_equal(reserved.used, with.used);
    assert_true(with.capacity < reserved.capacity); // (it grew to less)
    assert_int_equal(sta_cell_moments_init(&coarse, 6, origin, lo, hi, &err), STA_OK);
    assert_int_equal(sta_cell_moments_init(&coarse_reserved, 6, origin, lo, hi, &err), STA_OK);
    coarse.higher = coarse_reserved.higher = true;
    assert_int_equal(sta_cell_moments_coarsen(&with, &coarse, &err), STA_OK);
    assert_true(sta_cell_moments_reserve(&coarse_reserved, with.used));
    assert_int_equal(sta_cell_moments_coarsen(&reserved, &coarse_reserved, &err), STA_OK);
    size_t full = 0;
    for (size_t i = 0; i < POINTS; i += 17) {
        int64_t v[3];
        for (int a = 0; a < 3; a++) {
            v[a] = (((int64_t)grid[i][a] - origin[a]) >> with.level) + (int64_t)(i % 2);
        }
        sta_moment_sums a, b, c;
        sta_cell_moments_vertex(&with, v, &a);
        sta_cell_moments_vertex(&without, v, &b);
        sta_cell_moments_vertex(&reserved, v, &c);
        assert_memory_equal(&a, &c, sizeof(a));
        assert_true(b.s4 == 0 && b.s3[0] == 0 && b.s3[1] == 0 && b.s3[2] == 0);
        memcpy(b.s3, a.s3, sizeof(b.s3));
        b.s4 = a.s4;
        assert_memory_equal(&a, &b, sizeof(a));
        full += a.n > 0 && a.s4 != 0;
        for (int k = 0; k < 3; k++) {
            v[k] >>= 1;
        }
        sta_cell_moments_vertex(&coarse, v, &a);
        sta_cell_moments_vertex(&coarse_reserved, v, &c);
        assert_memory_equal(&a, &c, sizeof(a));
    }
    assert_true(full > 0);
    assert_int_equal(coarse.used, coarse_reserved.used);
    sta_cell_moments_release(&coarse_reserved);
    sta_cell_moments_release(&coarse);
    sta_cell_moments_release(&reserved);
    sta_cell_moments_release(&without);
    sta_cell_moments_release(&with);
    sta_free(grid);
}

// The points of a cell of a coarser level (aligned to `lo`) are one run of consecutive keys
// of the order's level, and sta_cell_order_lower_near finds the run's ends from any hint.
static void cell_order_finds_a_cells_run(void **state)
{
    (void)state;
    int32_t(*grid)[3] = sta_alloc_array(POINTS, sizeof(*grid));
    int32_t(*sorted)[3] = sta_alloc_array(POINTS, sizeof(*sorted));
    uint32_t *order = sta_alloc_array(POINTS, sizeof(*order));
    assert_non_null(grid);
    assert_non_null(sorted);
    assert_non_null(order);
    const int32_t corner[3] = { -40, 7, 90000 };
    sta_test_random_grid(grid, POINTS, corner, 5000, 31, false);
    int32_t lo[3], hi[3];
    bounds((const int32_t(*)[3])grid, POINTS, lo, hi);
    sta_error err = { 0 };
    const int level = 5, up = 2;
    assert_int_equal(sta_cell_order((const int32_t(*)[3])grid, POINTS, lo, level, order, &err),
                     STA_OK);
    for (size_t j = 0; j < POINTS; j++) {
        memcpy(sorted[j], grid[order[j]], sizeof(sorted[j]));
    }
    uint32_t s = 77;
    for (int probe = 0; probe < 300; probe++) {
        // A coarse cell of a random point (and every 10th an empty one beside the set).
        const int32_t *p = grid[sta_test_next_random(&s) % POINTS];
        int64_t coarse[3], first[3];
        for (int a = 0; a < 3; a++) {
            coarse[a] = (((int64_t)p[a] - lo[a]) >> (level + up)) + (probe % 10 == 9 ? 200 : 0);
            first[a] = coarse[a] << up;
        }
        uint64_t from_key = sta_cell_order_key(first), to_key = from_key + (1u << (3 * up));
        size_t from = 0, to = 0; // (the points whose keys are below each)
        for (size_t j = 0; j < POINTS; j++) {
            int64_t c[3];
            for (int a = 0; a < 3; a++) {
                c[a] = ((int64_t)sorted[j][a] - lo[a]) >> level;
            }
            from += sta_cell_order_key(c) < from_key;
            to += sta_cell_order_key(c) < to_key;
        }
        size_t inside = 0;
        for (size_t j = 0; j < POINTS; j++) {
            bool in = true;
            for (int a = 0; a < 3; a++) {
                in = in && (((int64_t)sorted[j][a] - lo[a]) >> (level + up)) == coarse[a];
            }
            inside += in;
            assert_true(in == (j >= from && j < to));
        }
        assert_int_equal(to - from, inside);
        assert_true(probe % 10 != 9 || inside == 0);
        const size_t hints[] = {
            0, POINTS, from, to, sta_test_next_random(&s) % POINTS, POINTS + 5
        };
        for (size_t h = 0; h < sizeof(hints) / sizeof(hints[0]); h++) {
            assert_int_equal(sta_cell_order_lower_near((const int32_t(*)[3])sorted, POINTS, lo,
                                                       level, from_key, hints[h]),
                             from);
            assert_int_equal(sta_cell_order_lower_near((const int32_t(*)[3])sorted, POINTS, lo,
                                                       level, to_key, hints[h]),
                             to);
        }
    }
    sta_free(order);
    sta_free(sorted);
    sta_free(grid);
}

static const struct CMUnitTest tests[] = {
    cmocka_unit_test(block_sums_match_brute_force),
    cmocka_unit_test(vertex_sums_match_brute_force),
    cmocka_unit_test(lower_only_and_reserved_sets_hold_the_same_sums),
    cmocka_unit_test(a_set_of_marks_grows_and_takes_no_points),
    cmocka_unit_test(wanted_cells_hold_all_their_points),
    cmocka_unit_test(too_wide_a_set_is_refused),
    cmocka_unit_test(coarsened_levels_match_brute_force),
    cmocka_unit_test(cell_order_keeps_cells_together),
    cmocka_unit_test(cell_order_is_stable_morton_sort),
    cmocka_unit_test(cell_order_finds_a_cells_run),
};

STA_TEST_MAIN(tests)
