/* SPDX-License-Identifier: MIT
 * The live Katz worker (visibility/katz_worker.h) without GL: sets handed over from the
 * hull threads are never torn (each set's points, viewpoint and flags belong to one
 * submission, and its flags equal the operator's on those points), generations only
 * grow (tags travel with their points), the last submission is the one finally shown, a sphere's
 * front hemisphere comes back through the worker, bad input is refused at submit, a failing hull is
 * reported, and the perturbed hull is compared with the plain one on the same input. Meant to run
 * under the thread sanitizer too (cmake --preset tsan; docs/KATZ.md).
 */
#include "test_support.h"

#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "core/alloc.h"
#include "visibility/katz_worker.h"

#define PI 3.14159265358979323846

// Points of submission `seq`: a sphere of radius 1 around (0, 0, -4), a count and a
// rotation that depend on seq, so that a set mixing two submissions shows.
static size_t fill_submission(uint64_t seq, float (*out)[3], double viewpoint[3])
{
    size_t count = 200 + (size_t)(seq % 7) * 37;
    double spin = 0.37 * (double)seq;
    for (size_t i = 0; i < count; i++) {
        double z = 2.0 * ((double)i + 0.5) / (double)count - 1.0;
        double phi = (double)i * 2.399963 + spin; // golden angle spiral
        double r = sqrt(1.0 - z * z);
        out[i][0] = (float)(r * cos(phi));
        out[i][1] = (float)(r * sin(phi));
        out[i][2] = (float)(z - 4.0);
    }
    viewpoint[0] = (double)seq * 1e-3; // tells the submission apart
    viewpoint[1] = 0.0;
    viewpoint[2] = 0.0;
    return count;
}

static void sleep_ms(long ms)
{
    struct timespec t = { .tv_sec = ms / 1000, .tv_nsec = (ms % 1000) * 1000000L };
    nanosleep(&t, NULL);
}

// Waits until the worker has nothing left to do (bounded: the hulls here take ms).
static void wait_idle(sta_katz_worker *worker)
{
    for (int i = 0; i < 20000 && sta_katz_worker_is_busy(worker); i++) {
        sleep_ms(1);
    }
    assert_false(sta_katz_worker_is_busy(worker));
}

// The set is one submission's, whole: points, count and viewpoint as submitted for its
// generation, and flags equal to the operator's on them.
static void check_set(const sta_katz_set *set, float (*scratch)[3], double (*xyz)[3],
                      uint8_t *flags)
{
    double viewpoint[3];
    size_t count = fill_submission(set->generation, scratch, viewpoint);
    assert_int_equal(set->count, count);
    assert_true(set->viewpoint[0] == viewpoint[0]);
    assert_memory_equal(set->points, scratch, count * sizeof(*scratch));
    for (size_t i = 0; i < count; i++) {
        for (int a = 0; a < 3; a++) {
            xyz[i][a] = (double)scratch[i][a];
        }
    }
    sta_katz_stats stats;
    assert_int_equal(
        sta_katz_visible((const double(*)[3])xyz, count, viewpoint, NULL, flags, &stats, NULL),
        STA_OK);
    assert_memory_equal(set->visible, flags, count);
    assert_int_equal(set->visible_count, stats.visible_count);
    assert_int_equal(set->frame, set->generation + 1000);
    for (size_t i = 0; i < count; i++) {
        assert_int_equal(set->tags[i], set->generation * 1000000u + i);
    }
}

// Many submissions, two hull threads, the caller acquiring between them: every set seen
// is whole and newer than the last; at the end the last submission is shown.
static void handover_is_whole_and_ordered(void **state)
{
    (void)state;
    enum {
        SUBMISSIONS = 120,
        MAX_POINTS = 512
    };
    sta_katz_worker_config config = { .thread_count = 2 };
    sta_katz_worker *worker = NULL;
    assert_int_equal(sta_katz_worker_create(&config, &worker, NULL), STA_OK);
    float(*points)[3] = sta_alloc_array(MAX_POINTS, sizeof(*points));
    float(*scratch)[3] = sta_alloc_array(MAX_POINTS, sizeof(*scratch));
    double(*xyz)[3] = sta_alloc_array(MAX_POINTS, sizeof(*xyz));
    uint8_t *flags = sta_alloc_array(MAX_POINTS, 1);
    uint64_t *tags = sta_alloc_array(MAX_POINTS, sizeof(*tags));
    assert_true(points && scratch && xyz && flags && tags);

    const sta_katz_set *set = NULL;
    assert_false(sta_katz_worker_acquire(worker, &set));
    assert_int_equal(set->generation, 0);
    uint64_t last_generation = 0;
    size_t new_sets = 0;
    for (uint64_t seq = 1; seq <= SUBMISSIONS; seq++) {
        double viewpoint[3];
        size_t count = fill_submission(seq, points, viewpoint);
        for (size_t i = 0; i < count; i++) {
            tags[i] = seq * 1000000u + i;
        }
        assert_int_equal(sta_katz_worker_submit(worker, (const float(*)[3])points, tags, count,
                                                viewpoint, 0.0, seq + 1000, NULL),
                         STA_OK);
        if (seq % 3 == 0) {
            sleep_ms(1); // let some hulls finish between submissions
        }
        if (sta_katz_worker_acquire(worker, &set)) {
            assert_true(set->generation > last_generation);
            last_generation = set->generation;
            check_set(set, scratch, xyz, flags);
            new_sets++;
        } else {
            assert_int_equal(set->generation, last_generation);
        }
    }
    wait_idle(worker);
    sta_katz_worker_acquire(worker, &set);
    assert_int_equal(set->generation, SUBMISSIONS);
    check_set(set, scratch, xyz, flags);
    sta_katz_worker_counters c;
    sta_katz_worker_counters_get(worker, &c);
    printf("%zu new sets seen; submitted %llu, replaced %llu, computed %llu, published %llu, "
           "dropped %llu\n",
           new_sets, (unsigned long long)c.submitted, (unsigned long long)c.replaced,
           (unsigned long long)c.computed, (unsigned long long)c.published,
           (unsigned long long)c.dropped);
    assert_int_equal(c.submitted, SUBMISSIONS);
    assert_int_equal(c.computed + c.replaced, c.submitted);
    assert_int_equal(c.published + c.dropped + c.failed, c.computed);
    assert_int_equal(c.failed, 0);
    assert_int_equal(sta_katz_worker_take_error(worker, NULL), STA_OK);
    sta_katz_worker_destroy(worker);
    sta_free(points);
    sta_free(scratch);
    sta_free(xyz);
    sta_free(flags);
    sta_free(tags);
}

// A sphere seen from outside through the worker: visible iff dot(p - c, v - p) > 0
// (the front hemisphere less its rim), with R from the view rule.
static void sphere_front_hemisphere(void **state)
{
    (void)state;
    enum {
        COUNT = 4000
    };
    float(*points)[3] = sta_alloc_array(COUNT, sizeof(*points));
    assert_non_null(points);
    const double centre[3] = { 0.0, 0.0, -5.0 };
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
    const double eye[3] = { 0.0, 0.0, 0.0 };
    assert_int_equal(sta_katz_worker_submit(worker, (const float(*)[3])points, NULL, COUNT, eye,
                                            sta_katz_view_radius(0.01, 1e-3), 1, NULL),
                     STA_OK);
    wait_idle(worker);
    const sta_katz_set *set = NULL;
    assert_true(sta_katz_worker_acquire(worker, &set));
    size_t tp = 0, fp = 0, fn = 0;
    for (size_t i = 0; i < COUNT; i++) {
        double n[3], v[3];
        for (int a = 0; a < 3; a++) {
            n[a] = (double)points[i][a] - centre[a];
            v[a] = eye[a] - (double)points[i][a];
        }
        bool truth = n[0] * v[0] + n[1] * v[1] + n[2] * v[2] > 0.0;
        tp += truth && set->visible[i];
        fp += !truth && set->visible[i];
        fn += truth && !set->visible[i];
    }
    printf("sphere: tp %zu fp %zu fn %zu\n", tp, fp, fn);
    assert_true((double)tp / (double)(tp + fn) > 0.99);
    assert_true((double)tp / (double)(tp + fp) > 0.9);
    sta_katz_worker_destroy(worker);
    sta_free(points);
}

// Bad input is refused at submit with a message; a bad configuration at create; a hull
// that fails on the thread is reported through take_error, and the previous set stays.
static void errors_are_reported(void **state)
{
    (void)state;
    sta_error err = { 0 };
    sta_katz_worker *worker = NULL;
    sta_katz_worker_config bad = { .thread_count = STA_KATZ_WORKER_MAX_THREADS + 1 };
    assert_int_equal(sta_katz_worker_create(&bad, &worker, &err), STA_ERR_ARG);
    assert_null(worker);
    assert_non_null(strstr(err.message, "thread count"));
    sta_katz_worker_config bad_params = { .params = { .radius_factor = 0.5 } };
    assert_int_equal(sta_katz_worker_create(&bad_params, &worker, &err), STA_ERR_ARG);
    assert_non_null(strstr(err.message, "radius_factor"));

    assert_int_equal(sta_katz_worker_create(NULL, &worker, NULL), STA_OK);
    float points[5][3] = { { 1, 0, -3 }, { -1, 0, -3 }, { 0, 1, -3 }, { 0, -1, -3 }, { 0, 0, -4 } };
    const double eye[3] = { 0, 0, 0 };
    points[2][1] = NAN;
    assert_int_equal(
        sta_katz_worker_submit(worker, (const float(*)[3])points, NULL, 5, eye, 0.0, 1, &err),
        STA_ERR_ARG);
    assert_non_null(strstr(err.message, "point 2"));
    points[2][1] = 1.0f;
    const double nan_eye[3] = { 0, NAN, 0 };
    assert_int_equal(
        sta_katz_worker_submit(worker, (const float(*)[3])points, NULL, 5, nan_eye, 0.0, 1, &err),
        STA_ERR_ARG);
    assert_non_null(strstr(err.message, "viewpoint"));

    // A good set first, then one whose radius is out of range: the hull thread fails.
    assert_int_equal(
        sta_katz_worker_submit(worker, (const float(*)[3])points, NULL, 5, eye, 0.0, 1, NULL),
        STA_OK);
    wait_idle(worker);
    const sta_katz_set *set = NULL;
    assert_true(sta_katz_worker_acquire(worker, &set));
    assert_int_equal(set->generation, 1);
    assert_int_equal(set->visible_count, 5); // the far point is seen past the near four
    assert_int_equal(
        sta_katz_worker_submit(worker, (const float(*)[3])points, NULL, 5, eye, 1e300, 2, NULL),
        STA_OK);
    wait_idle(worker);
    assert_false(sta_katz_worker_acquire(worker, &set));
    assert_int_equal(set->generation, 1);
    assert_int_equal(sta_katz_worker_take_error(worker, &err), STA_ERR_ARG);
    assert_non_null(strstr(err.message, "radius"));
    assert_int_equal(sta_katz_worker_take_error(worker, NULL), STA_OK);

    // Degenerate input goes through: nothing, and fewer than four points (all visible).
    assert_int_equal(sta_katz_worker_submit(worker, NULL, NULL, 0, eye, 0.0, 3, NULL), STA_OK);
    wait_idle(worker);
    assert_true(sta_katz_worker_acquire(worker, &set));
    assert_int_equal(set->count, 0);
    assert_int_equal(
        sta_katz_worker_submit(worker, (const float(*)[3])points, NULL, 3, eye, 0.0, 4, NULL),
        STA_OK);
    wait_idle(worker);
    assert_true(sta_katz_worker_acquire(worker, &set));
    assert_int_equal(set->visible_count, 3);
    sta_katz_worker_destroy(worker);
    sta_katz_worker_destroy(NULL);
}

// With the perturbation and compare_plain, each set also carries the plain hull's time on
// the same input; the flags are the perturbed operator's.
static void perturbation_is_compared(void **state)
{
    (void)state;
    enum {
        COUNT = 3000
    };
    float(*points)[3] = sta_alloc_array(COUNT, sizeof(*points));
    double(*xyz)[3] = sta_alloc_array(COUNT, sizeof(*xyz));
    uint8_t *flags = sta_alloc_array(COUNT, 1);
    assert_true(points && xyz && flags);
    double viewpoint[3];
    size_t count = fill_submission(5, points, viewpoint);
    for (size_t i = 0; i < count; i++) {
        for (int a = 0; a < 3; a++) {
            xyz[i][a] = (double)points[i][a];
        }
    }
    sta_katz_worker_config config = { .params = { .perturbation = 1e-4 }, .compare_plain = true };
    sta_katz_worker *worker = NULL;
    assert_int_equal(sta_katz_worker_create(&config, &worker, NULL), STA_OK);
    assert_int_equal(sta_katz_worker_submit(worker, (const float(*)[3])points, NULL, count,
                                            viewpoint, 0.0, 9, NULL),
                     STA_OK);
    wait_idle(worker);
    const sta_katz_set *set = NULL;
    assert_true(sta_katz_worker_acquire(worker, &set));
    assert_true(set->plain_hull_ms > 0.0);
    assert_true(set->stats.hull_ms > 0.0);
    assert_true(set->stats.perturbation_abs > 0.0);
    sta_katz_params perturbed = { .perturbation = 1e-4 };
    sta_katz_stats stats;
    assert_int_equal(sta_katz_visible((const double(*)[3])xyz, count, viewpoint, &perturbed, flags,
                                      &stats, NULL),
                     STA_OK);
    assert_memory_equal(set->visible, flags, count);
    printf("hull %.2f ms perturbed, %.2f ms plain\n", set->stats.hull_ms, set->plain_hull_ms);
    sta_katz_worker_destroy(worker);
    sta_free(points);
    sta_free(xyz);
    sta_free(flags);
}

static const struct CMUnitTest tests[] = {
    cmocka_unit_test(handover_is_whole_and_ordered),
    cmocka_unit_test(sphere_front_hemisphere),
    cmocka_unit_test(errors_are_reported),
    cmocka_unit_test(perturbation_is_compared),
};

STA_TEST_MAIN(tests)
