/* SPDX-License-Identifier: MIT
 * The --normals memory bound (issue 12, part 1): core/alloc.h's metered pool,
 * preprocess/memory_governor.c's turns (a chunk alone waits for the others and keeps
 * new ones out), and whole conversions of a rough scene (a ground with bushes) within a
 * small --memory: the same bytes as with plenty, a clear error where one chunk cannot
 * fit. */
#include "test_support.h"

#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "convert.h"
#include "core/alloc.h"
#include "core/log.h"
#include "io/las_write.h"
#include "memory_governor.h"

static void metered_allocations_stop_at_the_pool(void **state)
{
    (void)state;
    sta_alloc_pool pool = { 0 };
    atomic_store(&pool.left, 100000);
    void *before = sta_malloc(20000); // (not the pool's)
    assert_non_null(before);
    sta_alloc_meter_begin(&pool);
    void *a = sta_malloc(60000);
    assert_non_null(a);
    assert_true(atomic_load(&pool.left) <= 40000);
    assert_null(sta_calloc(1, 60000)); // refused: only about 40 000 left
    void *b = sta_alloc_array(10, 1000);
    assert_non_null(b);
    b = sta_realloc_array(b, 20, 1000); // (the new block is drawn before the old returns)
    assert_non_null(b);
    sta_free(a);
    assert_true(atomic_load(&pool.left) >= 100000 - 21000);
    sta_free(before); // freed in the meter, allocated before it: the pool gains nothing
    sta_free(b);
    size_t peak = 0;
    assert_true(sta_alloc_meter_end(&peak)); // one refusal
    assert_true(peak >= 60000 && peak < 100000);
    assert_int_equal(atomic_load(&pool.left), 100000);
    sta_alloc_meter_begin(&pool);
    sta_free(sta_malloc(1000));
    assert_false(sta_alloc_meter_end(NULL));
    assert_int_equal(atomic_load(&pool.left), 100000);
    void *free_again = sta_malloc(200000); // no meter: no limit
    assert_non_null(free_again);
    sta_free(free_again);
}

typedef struct turn_args {
    sta_memory_governor *g;
    atomic_int step; /* 1 inside, 2 alone, 3 done */
} turn_args;

static void *goes_alone(void *argument)
{
    turn_args *t = argument;
    sta_memory_governor_enter(t->g);
    atomic_store(&t->step, 1);
    sta_memory_governor_go_alone(t->g);
    atomic_store(&t->step, 2);
    return NULL;
}

static void *enters(void *argument)
{
    turn_args *t = argument;
    sta_memory_governor_enter(t->g);
    atomic_store(&t->step, 1);
    sta_memory_governor_leave(t->g);
    atomic_store(&t->step, 3);
    return NULL;
}

static void pause_ms(int ms)
{
    struct timespec ts = { 0, (long)ms * 1000000L };
    nanosleep(&ts, NULL);
}

static void a_chunk_alone_waits_for_the_others_and_keeps_new_ones_out(void **state)
{
    (void)state;
    sta_memory_governor g;
    sta_memory_governor_init(&g, 1000);
    assert_int_equal(atomic_load(&g.pool.left), 1000);
    sta_memory_governor_enter(&g); // this thread: a chunk inside
    turn_args alone = { .g = &g }, later = { .g = &g };
    pthread_t a, b;
    assert_int_equal(pthread_create(&a, NULL, goes_alone, &alone), 0);
    while (atomic_load(&alone.step) < 1) {
        pause_ms(1);
    }
    pause_ms(50);
    assert_int_equal(atomic_load(&alone.step), 1); // waits: this chunk is still inside
    pthread_mutex_lock(&g.lock);
    bool wants = g.alone;
    pthread_mutex_unlock(&g.lock);
    assert_true(wants);
    assert_int_equal(pthread_create(&b, NULL, enters, &later), 0);
    pause_ms(50);
    assert_int_equal(atomic_load(&later.step), 0); // kept out while one waits to be alone
    sta_memory_governor_leave(&g);
    assert_int_equal(pthread_join(a, NULL), 0);
    assert_int_equal(atomic_load(&alone.step), 2);
    pause_ms(50);
    assert_int_equal(atomic_load(&later.step), 0); // still out while it runs alone
    sta_memory_governor_share(&g);
    assert_int_equal(pthread_join(b, NULL), 0);
    assert_int_equal(atomic_load(&later.step), 3);
    sta_memory_governor_leave(&g); // (the lone chunk's own leave)
    assert_int_equal(g.inside, 0);
    assert_int_equal(g.alone_runs, 1);
    sta_memory_governor_release(&g);
}

static void *alone_and_leaves(void *argument)
{
    turn_args *t = argument;
    sta_memory_governor_enter(t->g);
    sta_memory_governor_go_alone(t->g);
    atomic_fetch_add(&t->step, 1);
    pause_ms(10);
    sta_memory_governor_share(t->g);
    sta_memory_governor_leave(t->g);
    return NULL;
}

static void two_chunks_that_want_to_be_alone_take_turns(void **state)
{
    (void)state;
    sta_memory_governor g;
    sta_memory_governor_init(&g, 1);
    turn_args t = { .g = &g };
    pthread_t threads[4];
    for (int i = 0; i < 4; i++) {
        assert_int_equal(pthread_create(&threads[i], NULL, alone_and_leaves, &t), 0);
    }
    for (int i = 0; i < 4; i++) {
        assert_int_equal(pthread_join(threads[i], NULL), 0); // (a deadlock hangs: ctest's timeout)
    }
    assert_int_equal(atomic_load(&t.step), 4);
    assert_int_equal(g.alone_runs, 4);
    assert_int_equal(g.inside, 0);
    sta_memory_governor_release(&g);
}

typedef struct take_args {
    sta_memory_governor *g;
    atomic_int taken;
} take_args;

static void *takes_600(void *argument)
{
    take_args *t = argument;
    sta_memory_governor_take(t->g, 600);
    atomic_store(&t->taken, 1);
    return NULL;
}

/* The index buffers' take waits while another holds the pool, and takes anyway (the
 * pool goes below zero) when nothing else is held. */
static void an_index_take_waits_for_the_pool(void **state)
{
    (void)state;
    sta_memory_governor g;
    sta_memory_governor_init(&g, 1000);
    assert_true(sta_alloc_pool_take(&g.pool, 700)); // another chunk's normals
    take_args t = { .g = &g };
    pthread_t a;
    assert_int_equal(pthread_create(&a, NULL, takes_600, &t), 0);
    pause_ms(50);
    assert_int_equal(atomic_load(&t.taken), 0);
    sta_alloc_pool_give(&g.pool, 700);
    assert_int_equal(pthread_join(a, NULL), 0);
    assert_int_equal(atomic_load(&t.taken), 1);
    assert_int_equal(atomic_load(&g.pool.left), 400);
    sta_memory_governor_give(&g, 600);
    sta_memory_governor_take(&g, 1500); // more than the pool, nothing else held: taken
    assert_int_equal(atomic_load(&g.pool.left), -500);
    sta_memory_governor_give(&g, 1500);
    assert_int_equal(atomic_load(&g.pool.left), 1000);
    sta_memory_governor_release(&g);
}

enum {
    GROUND = 450000,   /* points 6 cm apart on a gently curved ground (15 mm noise) */
    BUSHES = 1000,     /* of 1 m: dense clusters, each point rough */
    BUSH_POINTS = 200, /* a bush's points */
    CHUNK = 120000,    /* points a chunk: several, so that two run at once */
};

// A ground with bushes (the rough points the memory plan did not count before).
static void write_bush_scene(const char *path)
{
    const sta_grid grid = { { 0.001, 0.001, 0.001 }, { 0.0, 0.0, 0.0 } };
    sta_las_write_options wo = { .version_minor = 2, .point_format = 0, .grid = grid };
    sta_las_writer *w = NULL;
    sta_error err = { 0 };
    assert_int_equal(sta_las_writer_open(path, &wo, &w, &err), STA_OK);
    size_t n = GROUND + (size_t)BUSHES * BUSH_POINTS;
    sta_point *points = calloc(n, sizeof(*points));
    assert_non_null(points);
    const double side = sqrt((double)GROUND) * 0.06;
    uint32_t seed = 777u;
    for (size_t i = 0; i < GROUND; i++) {
        double x = side * (sta_test_next_random(&seed) % 1000000u) * 1e-6;
        double y = side * (sta_test_next_random(&seed) % 1000000u) * 1e-6;
        double z = 0.3 * sin(x / 7.0) + 0.2 * cos(y / 5.0) +
                   0.001 * (double)(sta_test_next_random(&seed) % 31) - 0.015;
        points[i].X = (int32_t)llround(x * 1000.0) + 1000;
        points[i].Y = (int32_t)llround(y * 1000.0) + 1000;
        points[i].Z = (int32_t)llround(z * 1000.0) + 1000;
    }
    for (size_t b = 0, i = GROUND; b < BUSHES; b++) {
        double cx = side * (sta_test_next_random(&seed) % 1000u) * 1e-3;
        double cy = side * (sta_test_next_random(&seed) % 1000u) * 1e-3;
        for (int j = 0; j < BUSH_POINTS; j++, i++) {
            double d[3];
            do { // uniform in a ball of 0.5 m
                for (int a = 0; a < 3; a++) {
                    d[a] = (sta_test_next_random(&seed) % 100000u) * 1e-5 - 0.5;
                }
            } while (d[0] * d[0] + d[1] * d[1] + d[2] * d[2] > 0.25);
            points[i].X = (int32_t)llround((cx + d[0]) * 1000.0) + 1000;
            points[i].Y = (int32_t)llround((cy + d[1]) * 1000.0) + 1000;
            points[i].Z = (int32_t)llround((0.6 + d[2]) * 1000.0) + 1000;
        }
    }
    for (size_t i = 0; i < n; i++) {
        points[i].return_number = points[i].number_of_returns = 1;
    }
    assert_int_equal(sta_las_writer_write(w, points, n, &err), STA_OK);
    assert_int_equal(sta_las_writer_close(w, &err), STA_OK);
    free(points);
}

static sta_status convert_bushes(const char *in, const char *out, size_t memory_mib,
                                 sta_convert_report *report, sta_error *err)
{
    const char *one[] = { in };
    sta_convert_options o = { .inputs = one,
                              .input_count = 1,
                              .output = out,
                              .threads = 2,
                              .memory_mib = memory_mib,
                              .chunk_points = CHUNK,
                              .normals = true,
                              .force = true };
    sta_log_set_level(STA_LOG_QUIET);
    sta_status status = sta_convert(&o, report, err);
    sta_log_set_level(STA_LOG_WARN);
    return status;
}

/* Plenty of --memory, then a pool of about one and a half of the largest chunk's need
 * (two chunks no longer fit at once: one runs alone; the same bytes; a child process's
 * peak RSS grows by less than --memory), then half a chunk's (a clear error). */
static void rough_chunks_stay_within_a_small_memory(void **state)
{
    (void)state;
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
    print_message("skipped under a sanitizer: the release build checks the heap\n");
    skip();
#endif
    char in[4096], out[4096], small[4096];
    snprintf(in, sizeof(in), "%s/bushes.las", sta_test_tmpdir());
    snprintf(out, sizeof(out), "%s/bushes.strata", sta_test_tmpdir());
    snprintf(small, sizeof(small), "%s/bushes-small.strata", sta_test_tmpdir());
    write_bush_scene(in);
    sta_convert_report plenty;
    sta_error err = { 0 };
    const size_t wide = 4096;
    if (convert_bushes(in, out, wide, &plenty, &err) != STA_OK) {
        fail_msg("--memory %zu: %s", wide, err.message);
    }
    assert_int_equal(plenty.normals_alone, 0);
    size_t need = plenty.normals_chunk_peak_bytes, pool = plenty.normals_pool_bytes;
    print_message("largest chunk's normals %zu MB (of the pool's %zu MB)\n", need >> 20,
                  pool >> 20);
    assert_true(need > 0 && need < pool);
    // The pool moves with --memory MiB for MiB (the same two workers).
    size_t tight = wide - ((pool - need - need / 2) >> 20);
    fflush(NULL);
    pid_t child = fork();
    assert_true(child >= 0);
    if (child == 0) {
        double start = sta_test_resident_bytes();
        if (start < 0.0) {
            _exit(2);
        }
        sta_convert_report report;
        sta_error child_err = { 0 };
        if (convert_bushes(in, small, tight, &report, &child_err) != STA_OK) {
            printf("--memory %zu: %s\n", tight, child_err.message);
            _exit(3);
        }
        double grew = sta_test_peak_growth(start);
        printf("--memory %zu MiB: pool %zu MiB, %zu chunks alone, peak RSS grew %.0f MiB\n", tight,
               report.normals_pool_bytes >> 20, report.normals_alone, grew / 1048576.0);
        fflush(stdout);
        _exit(report.normals_alone == 0 ? 4 : grew <= (double)(tight << 20) ? 0 : 1);
    }
    int status = 0;
    assert_int_equal(waitpid(child, &status, 0), child);
    assert_true(WIFEXITED(status));
    assert_int_equal(WEXITSTATUS(status), 0); // 4: nothing ran alone; 1: over --memory
    assert_true(sta_test_files_equal(out, small));
    // Half the largest chunk's need: not even alone.
    size_t too_small = wide - ((pool - need / 2) >> 20);
    sta_convert_report report;
    memset(&err, 0, sizeof(err));
    unlink(small);
    assert_int_equal(convert_bushes(in, small, too_small, &report, &err), STA_ERR_NOMEM);
    print_message("--memory %zu: %s\n", too_small, err.message);
    assert_non_null(strstr(err.message, in));
    assert_non_null(strstr(err.message, "even alone"));
    assert_non_null(strstr(err.message, "--memory"));
    assert_int_equal(access(small, F_OK), -1); // nothing left behind
    unlink(in);
    unlink(out);
    unlink(small);
}

static const struct CMUnitTest tests[] = {
    cmocka_unit_test(metered_allocations_stop_at_the_pool),
    cmocka_unit_test(a_chunk_alone_waits_for_the_others_and_keeps_new_ones_out),
    cmocka_unit_test(two_chunks_that_want_to_be_alone_take_turns),
    cmocka_unit_test(an_index_take_waits_for_the_pool),
    cmocka_unit_test(rough_chunks_stay_within_a_small_memory),
};

STA_TEST_MAIN(tests)
