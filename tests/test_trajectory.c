/* SPDX-License-Identifier: MIT
 * Tests for the scanner path (preprocess/trajectory.c): a bin's centroid is the mean of
 * the points measured in it, times in no bin or not finite have none, and the memoised
 * look-up gives the same answers as the plain one in any order of times; points in runs of
 * one bin (the order sta_trajectory_add shortcuts), over enough bins to grow the table
 * within runs and coming back to earlier bins, are all counted in their bin, and so are
 * times on and beside the bins' edges (whose bins the look-ups remember by their times). */
#include "test_support.h"

#include <math.h>
#include <string.h>

#include "trajectory.h"

static void bins_hold_their_centroids(void **state)
{
    (void)state;
    sta_trajectory t = { 0 };
    sta_error err = { 0 };
    const int32_t a[3] = { 10, 20, 30 }, b[3] = { 14, 26, 40 }, c[3] = { -500, 0, 7 };
    assert_int_equal(sta_trajectory_add(&t, 1.001, a, &err), STA_OK);
    assert_int_equal(sta_trajectory_add(&t, 1.002, b, &err), STA_OK);
    assert_int_equal(sta_trajectory_add(&t, 3.0 + STA_TRAJECTORY_BIN_S / 2, c, &err), STA_OK);
    assert_int_equal(sta_trajectory_add(&t, NAN, c, &err), STA_OK); // ignored
    double at[3];
    assert_true(sta_trajectory_at(&t, 1.0 + STA_TRAJECTORY_BIN_S / 2, at));
    assert_true(at[0] == 12.0 && at[1] == 23.0 && at[2] == 35.0);
    assert_true(sta_trajectory_at(&t, 3.0 + STA_TRAJECTORY_BIN_S / 4, at));
    assert_true(at[0] == -500.0 && at[1] == 0.0 && at[2] == 7.0);
    assert_false(sta_trajectory_at(&t, 2.0, at));
    assert_false(sta_trajectory_at(&t, INFINITY, at));
    sta_trajectory_release(&t);
}

static void memoised_lookups_match(void **state)
{
    (void)state;
    sta_trajectory t = { 0 };
    sta_error err = { 0 };
    uint32_t s = 7;
    for (int i = 0; i < 2000; i++) {
        s = s * 1664525u + 1013904223u;
        const int32_t p[3] = { (int32_t)(s >> 20), -(int32_t)(s >> 22), (int32_t)(s >> 24) };
        // every other bin over 10 s holds points: the look-ups below hit and miss
        double time = (double)(i % 100) * 2.0 * STA_TRAJECTORY_BIN_S + (double)(s % 997) * 1e-5;
        assert_int_equal(sta_trajectory_add(&t, time, p, &err), STA_OK);
    }
    sta_trajectory_memo memo = { 0 };
    size_t hits = 0, misses = 0;
    for (int i = 0; i < 5000; i++) {
        s = s * 1664525u + 1013904223u;
        // runs of one time and jumps between bins, some outside any, some not finite
        double time =
            (i % 97 == 0) ? (double)NAN : (double)((s >> 8) % 230) * STA_TRAJECTORY_BIN_S * 0.5;
        double want[3] = { -1, -1, -1 }, got[3] = { -1, -1, -1 };
        bool w = sta_trajectory_at(&t, time, want);
        for (int k = 0; k < 3; k++) {
            bool g = sta_trajectory_at_memo(&t, &memo, time, got);
            assert_int_equal(g, w);
            assert_memory_equal(got, want, sizeof(want));
        }
        hits += w;
        misses += !w;
    }
    assert_true(hits > 100 && misses > 100);
    sta_trajectory_release(&t);
}

// Times on and a few doubles around bin edges (small times and GPS-week-sized ones), in
// runs that cross the edges both ways: every point lands in the bin of floor(time / BIN_S)
// (its x, y the key: a centroid off the key means a point in the wrong bin), and the
// memoised look-up of each time gives that bin's centroid, as the plain one does.
static void times_at_bin_edges_take_their_bins(void **state)
{
    (void)state;
    sta_trajectory t = { 0 };
    sta_error err = { 0 };
    enum {
        EDGES = 400,
        AROUND = 4
    };
    const double starts[2] = { 10.0, 6.1e8 };
    for (int pass = 0; pass < 2; pass++) { // (the second adds to the first's bins again)
        for (int e = 0; e < EDGES; e++) {
            double edge = starts[e % 2] + (double)(e / 2) * STA_TRAJECTORY_BIN_S;
            for (int i = 0; i <= 2 * AROUND; i++) { // (up across the edge, then down)
                int j = pass == 0 ? i - AROUND : AROUND - i;
                double time = edge;
                for (int u = 0; u < (j < 0 ? -j : j); u++) {
                    time = nextafter(time, j < 0 ? -HUGE_VAL : HUGE_VAL);
                }
                time = pass == 0 ? time : nextafter(time, HUGE_VAL); // (other doubles too)
                int64_t key = (int64_t)floor(time / STA_TRAJECTORY_BIN_S);
                const int32_t p[3] = { (int32_t)(key % 1000000), (int32_t)(key / 1000000), j };
                assert_int_equal(sta_trajectory_add(&t, time, p, &err), STA_OK);
            }
        }
    }
    sta_trajectory_memo memo = { 0 };
    for (int e = 0; e < 2 * EDGES; e++) {
        double edge = starts[e % 2] + (double)(e / 2 % (EDGES / 2)) * STA_TRAJECTORY_BIN_S;
        for (int i = 0; i <= 2 * AROUND; i++) {
            int j = e < EDGES ? i - AROUND : AROUND - i;
            double time = edge;
            for (int u = 0; u < (j < 0 ? -j : j); u++) {
                time = nextafter(time, j < 0 ? -HUGE_VAL : HUGE_VAL);
            }
            int64_t key = (int64_t)floor(time / STA_TRAJECTORY_BIN_S);
            double want[3], got[3];
            assert_true(sta_trajectory_at(&t, time, want));
            assert_true(want[0] == (double)(key % 1000000) && want[1] == (double)(key / 1000000));
            assert_true(sta_trajectory_at_memo(&t, &memo, time, got));
            assert_memory_equal(got, want, sizeof(want));
        }
    }
    sta_trajectory_release(&t);
}

static void runs_across_growth_keep_sums(void **state)
{
    (void)state;
    enum {
        BINS = 3000,
        RUN = 3
    };
    sta_trajectory t = { 0 };
    sta_error err = { 0 };
    // Bin b gets RUN points (x = b, y = 2b, z = k) in one run, then one more (x = b,
    // y = 2b, z = 4) after bin b + 1's run: its centroid is (b, 2b, (0+1+2+4)/4).
    for (int b = 0; b < BINS; b++) {
        double time = ((double)b + 0.5) * STA_TRAJECTORY_BIN_S;
        for (int k = 0; k < RUN; k++) {
            const int32_t p[3] = { b, 2 * b, k };
            assert_int_equal(sta_trajectory_add(&t, time, p, &err), STA_OK);
        }
        if (b > 0) {
            const int32_t p[3] = { b - 1, 2 * (b - 1), 4 };
            assert_int_equal(sta_trajectory_add(&t, time - STA_TRAJECTORY_BIN_S, p, &err), STA_OK);
        }
    }
    const int32_t p[3] = { BINS - 1, 2 * (BINS - 1), 4 };
    assert_int_equal(sta_trajectory_add(&t, ((double)BINS - 0.5) * STA_TRAJECTORY_BIN_S, p, &err),
                     STA_OK);
    assert_int_equal(t.count, BINS);
    for (int b = 0; b < BINS; b++) {
        double at[3];
        assert_true(sta_trajectory_at(&t, ((double)b + 0.5) * STA_TRAJECTORY_BIN_S, at));
        assert_true(at[0] == (double)b && at[1] == 2.0 * b && at[2] == 7.0 / 4.0);
    }
    sta_trajectory_release(&t);
}

static const struct CMUnitTest tests[] = {
    cmocka_unit_test(bins_hold_their_centroids),
    cmocka_unit_test(memoised_lookups_match),
    cmocka_unit_test(runs_across_growth_keep_sums),
    cmocka_unit_test(times_at_bin_edges_take_their_bins),
};

STA_TEST_MAIN(tests)
