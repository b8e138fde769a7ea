/* SPDX-License-Identifier: MIT
 * The live Katz mode's screen cells (visibility/katz_cells.h): each kept point is the
 * nearest of its cell and every occupied cell keeps one, the count stays within the cap
 * and near it, points outside the view are dropped, tags travel with their points; and
 * through the worker (sta_katz_worker_submit_view) a dense sphere comes back as its
 * front hemisphere, with bad views refused.
 */
#include "test_support.h"

#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "core/alloc.h"
#include "visibility/katz_cells.h"
#include "visibility/katz_worker.h"

#define PI 3.14159265358979323846

// At the origin looking along +X (yaw 0), Z up, 64 x 48 pixels.
static sta_camera test_camera(void)
{
    return (
        sta_camera){ .fov_y = 60.0 * PI / 180.0, .near_m = 0.1, .width_px = 64, .height_px = 48 };
}

static uint64_t next_random(uint64_t *state)
{
    *state = *state * 6364136223846793005ull + 1442695040888963407ull;
    return *state >> 11;
}

static double uniform(uint64_t *state, double lo, double hi)
{
    return lo + (hi - lo) * (double)next_random(state) / (double)(1ull << 53);
}

// Points filling the view at depths 5..20 m (plus some behind the eye and beside the view).
static size_t fill(float (*points)[3], uint64_t *tags, size_t count)
{
    uint64_t seed = 7;
    for (size_t i = 0; i < count; i++) {
        double x = uniform(&seed, 5.0, 20.0);
        points[i][0] = (float)x;
        points[i][1] = (float)uniform(&seed, -0.8 * x, 0.8 * x); // ~10 % beside the view
        points[i][2] = (float)uniform(&seed, -0.6 * x, 0.6 * x);
        if (i % 50 == 0) {
            points[i][0] = -points[i][0]; // behind the eye
        }
        tags[i] = 1000000 + i;
    }
    return count;
}

static void nearest_point_of_each_cell(void **state)
{
    (void)state;
    enum {
        COUNT = 20000,
        CAP = 700
    };
    float(*points)[3] = sta_alloc_array(COUNT, sizeof(*points));
    float(*original)[3] = sta_alloc_array(COUNT, sizeof(*points));
    uint64_t *tags = sta_alloc_array(COUNT, sizeof(*tags));
    assert_true(points && original && tags);
    fill(points, tags, COUNT);
    memcpy(original, points, COUNT * sizeof(*points));
    const sta_camera camera = test_camera();
    const double origin[3] = { 0.0, 0.0, 0.0 };
    sta_katz_cells cells = { 0 };
    size_t n = COUNT;
    assert_int_equal(sta_katz_cells_select(&cells, &camera, origin, CAP, points, tags, &n, NULL),
                     STA_OK);
    const double side = cells.cell_px;
    printf("kept %zu of %zu (in view %zu), cells of %.3f px\n", n, (size_t)COUNT, cells.in_view,
           side);
    assert_true(n <= CAP && n >= (size_t)(0.85 * CAP));
    assert_true(side > 1.0);
    assert_true(cells.in_view > COUNT / 2 && cells.in_view < COUNT);
    // The test's own binning, in double; points within 1e-3 px of a cell border are left
    // out of the comparison (float and double may bin them apart).
    const int cx = (int)ceil(camera.width_px / side), cy = (int)ceil(camera.height_px / side);
    double *nearest = sta_alloc_array((size_t)(cx * cy), sizeof(double));
    assert_non_null(nearest);
    for (int c = 0; c < cx * cy; c++) {
        nearest[c] = INFINITY;
    }
    for (size_t i = 0; i < COUNT; i++) {
        const double w[3] = { original[i][0], original[i][1], original[i][2] };
        double x, y, depth;
        if (!sta_camera_project(&camera, w, &x, &y, &depth) || x < 0 || x >= camera.width_px ||
            y < 0 || y >= camera.height_px) {
            continue;
        }
        y = camera.height_px - y; // the cells count rows from the bottom
        const int c = (int)(y / side) * cx + (int)(x / side);
        nearest[c] = fmin(nearest[c], depth);
    }
    size_t checked = 0, occupied = 0;
    bool *seen = sta_calloc((size_t)(cx * cy), sizeof(bool));
    assert_non_null(seen);
    for (size_t k = 0; k < n; k++) {
        const size_t i = (size_t)(tags[k] - 1000000);
        assert_true(i < COUNT);
        assert_memory_equal(points[k], original[i], sizeof(points[k])); // tags travel
        const double w[3] = { points[k][0], points[k][1], points[k][2] };
        double x, y, depth;
        assert_true(sta_camera_project(&camera, w, &x, &y, &depth));
        assert_true(x >= 0 && x < camera.width_px && y >= 0 && y < camera.height_px);
        y = camera.height_px - y;
        const double fx = x / side - floor(x / side), fy = y / side - floor(y / side);
        if (fmin(fx, 1 - fx) * side < 1e-3 || fmin(fy, 1 - fy) * side < 1e-3) {
            continue;
        }
        const int c = (int)(y / side) * cx + (int)(x / side);
        assert_false(seen[c]); // one point per cell
        seen[c] = true;
        assert_true(fabs(depth - nearest[c]) < 1e-4 * depth); // the nearest of its cell
        checked++;
    }
    for (int c = 0; c < cx * cy; c++) {
        occupied += isfinite(nearest[c]);
    }
    printf("checked %zu kept points, %zu occupied cells\n", checked, occupied);
    assert_true(checked > n * 9 / 10);
    assert_true(occupied >= n - n / 100 && occupied <= n + n / 100);
    sta_free(seen);
    sta_free(nearest);
    sta_katz_cells_release(&cells);
    sta_free(points);
    sta_free(original);
    sta_free(tags);
}

// Few points: cells shrink to single pixels and keep all distinct pixels' points; points
// behind the eye or beside the view are dropped; nothing in view keeps nothing.
static void few_points_and_empty_views(void **state)
{
    (void)state;
    const sta_camera camera = test_camera();
    const double origin[3] = { 1.0, 2.0, 3.0 }; // points are relative to it
    float points[5][3] = {
        { 9.0f, -2.0f, -3.0f },   // (10, 0, 0): the centre of the view
        { 19.0f, -2.0f, -3.0f },  // behind it, same pixel: dropped for the nearer
        { -11.0f, -2.0f, -3.0f }, // behind the eye
        { 9.0f, 30.0f, -3.0f },   // far beside the view
        { 9.0f, -1.0f, -3.0f },   // another pixel
    };
    uint64_t tags[5] = { 10, 11, 12, 13, 14 };
    sta_katz_cells cells = { 0 };
    size_t n = 0; // nothing, before any scratch exists
    assert_int_equal(sta_katz_cells_select(&cells, &camera, origin, 100, points, tags, &n, NULL),
                     STA_OK);
    assert_int_equal(n, 0);
    assert_int_equal(cells.in_view, 0);
    n = 5;
    assert_int_equal(sta_katz_cells_select(&cells, &camera, origin, 100, points, tags, &n, NULL),
                     STA_OK);
    assert_int_equal(cells.in_view, 3);
    assert_true(cells.cell_px == 1.0);
    assert_int_equal(n, 2);
    assert_true((tags[0] == 10 && tags[1] == 14) || (tags[0] == 14 && tags[1] == 10));
    float away[2][3] = { { -5.0f, 0.0f, 0.0f }, { 0.0f, 0.0f, 50.0f } };
    uint64_t away_tags[2] = { 1, 2 };
    n = 2;
    const double zero[3] = { 0.0, 0.0, 0.0 };
    assert_int_equal(sta_katz_cells_select(&cells, &camera, zero, 100, away, away_tags, &n, NULL),
                     STA_OK);
    assert_int_equal(n, 0);
    n = 0;
    assert_int_equal(sta_katz_cells_select(&cells, &camera, zero, 100, away, away_tags, &n, NULL),
                     STA_OK);
    assert_int_equal(n, 0);
    sta_katz_cells_release(&cells);
    sta_katz_cells_release(&cells); // zeroed: no-op
}

static void sleep_ms(long ms)
{
    struct timespec t = { .tv_sec = ms / 1000, .tv_nsec = (ms % 1000) * 1000000L };
    nanosleep(&t, NULL);
}

// A dense sphere ahead of the camera, submitted with its view: the thread keeps one
// point per cell (the cap), and the hull shows its front hemisphere.
static void worker_keeps_cells_of_a_sphere(void **state)
{
    (void)state;
    enum {
        COUNT = 40000,
        CAP = 1500
    };
    float(*points)[3] = sta_alloc_array(COUNT, sizeof(*points));
    assert_non_null(points);
    const double centre[3] = { 5.0, 0.0, 0.0 };
    for (size_t i = 0; i < COUNT; i++) {
        double z = 2.0 * ((double)i + 0.5) / COUNT - 1.0;
        double phi = (double)i * 2.399963;
        double r = sqrt(1.0 - z * z);
        points[i][0] = (float)(centre[0] + r * cos(phi));
        points[i][1] = (float)(centre[1] + r * sin(phi));
        points[i][2] = (float)(centre[2] + z);
    }
    sta_katz_worker *worker = NULL;
    assert_int_equal(sta_katz_worker_create(NULL, &worker, NULL), STA_OK);
    sta_camera camera = test_camera();
    camera.width_px = 320; // the sphere covers about 6600 pixels
    camera.height_px = 240;
    const double origin[3] = { 0.0, 0.0, 0.0 };
    const double pitch = camera.fov_y / camera.height_px;
    assert_int_equal(sta_katz_worker_submit_view(worker, (const float(*)[3])points, NULL, COUNT,
                                                 &camera, origin, CAP,
                                                 sta_katz_view_radius(0.01, pitch), 1, NULL),
                     STA_OK);
    for (int i = 0; i < 20000 && sta_katz_worker_is_busy(worker); i++) {
        sleep_ms(1);
    }
    const sta_katz_set *set = NULL;
    assert_true(sta_katz_worker_acquire(worker, &set));
    assert_int_equal(set->candidates, COUNT);
    assert_true(set->count <= CAP && set->count > CAP / 2);
    assert_true(set->cell_px >= 1.0);
    size_t front = 0, visible_front = 0, visible_back = 0;
    for (size_t k = 0; k < set->count; k++) {
        const size_t i = (size_t)set->tags[k];
        assert_memory_equal(set->points[k], points[i], sizeof(points[i]));
        double n[3], v[3];
        for (int a = 0; a < 3; a++) {
            n[a] = (double)points[i][a] - centre[a];
            v[a] = camera.position[a] - (double)points[i][a];
        }
        bool truth = n[0] * v[0] + n[1] * v[1] + n[2] * v[2] > 0.0;
        front += truth;
        visible_front += truth && set->visible[k];
        visible_back += !truth && set->visible[k];
    }
    printf("sphere: %zu kept of %d, cells %.2f px, front %zu, visible front %zu back %zu\n",
           set->count, COUNT, set->cell_px, front, visible_front, visible_back);
    assert_true(front > set->count * 95 / 100); // the cells already prefer the front
    assert_true(visible_front > front * 98 / 100);
    assert_true(visible_back < set->count / 100 + 1);

    // Views that are none are refused, naming what is wrong.
    sta_error err = { 0 };
    sta_camera bad = camera;
    bad.width_px = 0;
    assert_int_equal(sta_katz_worker_submit_view(worker, (const float(*)[3])points, NULL, 10, &bad,
                                                 origin, CAP, 0.0, 2, &err),
                     STA_ERR_ARG);
    assert_non_null(strstr(err.message, "0x240 px"));
    assert_int_equal(sta_katz_worker_submit_view(worker, (const float(*)[3])points, NULL, 10,
                                                 &camera, origin, 0, 0.0, 2, &err),
                     STA_ERR_ARG);
    assert_non_null(strstr(err.message, "cell cap"));
    assert_int_equal(sta_katz_worker_submit_view(worker, (const float(*)[3])points, NULL, 10, NULL,
                                                 origin, CAP, 0.0, 2, &err),
                     STA_ERR_ARG);
    sta_katz_worker_destroy(worker);
    sta_free(points);
}

static const struct CMUnitTest tests[] = {
    cmocka_unit_test(nearest_point_of_each_cell),
    cmocka_unit_test(few_points_and_empty_views),
    cmocka_unit_test(worker_keeps_cells_of_a_sphere),
};

STA_TEST_MAIN(tests)
