/* SPDX-License-Identifier: MIT
 * Live Katz HPR worker threads with front, ready and back visibility sets (see
 * katz_worker.h for the design and the lock rules).
 */
#define _GNU_SOURCE // pthread_setname_np
#include "visibility/katz_worker.h"

#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <string.h>

#include "core/alloc.h"

// Points and the viewpoint of one submission. Held by one side at a time: the caller's
// staging buffer, the pending slot, or a thread's work buffer.
typedef struct request {
    float (*points)[3];
    uint64_t *tags; // NULL when the submission had none
    size_t count, capacity;
    double viewpoint[3];
    double radius_m;   // 0: the configured R
    sta_camera camera; // cell_cap > 0: the view, its position relative to the points' origin
    size_t cell_cap;   // 0: all points go to the hull; else one per screen cell, at most this
    uint64_t frame;
    uint64_t seq; // submission number, 0: empty
} request;

typedef struct hull_thread {
    sta_katz_worker *worker;
    pthread_t thread;
    int index;
    bool started;
    request *work;      // this thread's only
    sta_katz_set *back; // this thread's only until published
    double (*xyz)[3];   // the work's points in double, this thread's only
    size_t xyz_capacity;
    sta_katz_cells cells; // this thread's only
} hull_thread;

struct sta_katz_worker {
    sta_katz_worker_config config; // immutable after create
    pthread_mutex_t lock;
    pthread_cond_t wake;               // guarded by lock: a request is pending or stop is set
    bool stop;                         // guarded by lock
    request *staging;                  // caller only
    request *pending;                  // guarded by lock; pending->seq > 0: waiting
    sta_katz_set *ready;               // guarded by lock; newer than front when published
    sta_katz_set *front;               // caller only (the pointer is swapped under lock)
    uint64_t front_generation;         // guarded by lock
    int running;                       // guarded by lock: threads inside a hull
    sta_katz_worker_counters counters; // guarded by lock
    sta_status error_status;           // guarded by lock: last failure, STA_OK: none
    sta_error error;                   // guarded by lock
    hull_thread threads[STA_KATZ_WORKER_MAX_THREADS];
};

void sta_katz_worker_config_defaults(sta_katz_worker_config *config)
{
    if (config->thread_count == 0) {
        config->thread_count = STA_KATZ_WORKER_DEFAULT_THREADS;
    }
    sta_katz_params_defaults(&config->params);
}

static void set_free(sta_katz_set *set)
{
    if (set) {
        sta_free(set->points);
        sta_free(set->tags);
        sta_free(set->visible);
        sta_free(set);
    }
}

static void request_free(request *r)
{
    if (r) {
        sta_free(r->points);
        sta_free(r->tags);
        sta_free(r);
    }
}

// Grows the set to hold `count` points; its holder calls this outside the lock.
static sta_status set_reserve(sta_katz_set *set, size_t count, sta_error *err)
{
    if (set->capacity >= count) {
        return STA_OK;
    }
    float(*points)[3] = sta_alloc_array(count, sizeof(*points));
    uint64_t *tags = sta_alloc_array(count, sizeof(*tags));
    uint8_t *visible = sta_alloc_array(count, 1);
    if (!points || !tags || !visible) {
        sta_free(points);
        sta_free(tags);
        sta_free(visible);
        return sta_fail(err, STA_ERR_NOMEM, "katz worker: out of memory for %zu points", count);
    }
    sta_free(set->points);
    sta_free(set->tags);
    sta_free(set->visible);
    set->points = points;
    set->tags = tags;
    set->visible = visible;
    set->capacity = count;
    return STA_OK;
}

static sta_status request_reserve(request *r, size_t count, sta_error *err)
{
    if (r->capacity >= count) {
        return STA_OK;
    }
    float(*points)[3] = sta_alloc_array(count, sizeof(*points));
    uint64_t *tags = sta_alloc_array(count, sizeof(*tags));
    if (!points || !tags) {
        sta_free(points);
        sta_free(tags);
        return sta_fail(err, STA_ERR_NOMEM, "katz worker: out of memory for %zu points", count);
    }
    sta_free(r->points);
    sta_free(r->tags);
    r->points = points;
    r->tags = tags;
    r->capacity = count;
    return STA_OK;
}

// Runs the operator on the thread's work into its back set (outside the lock).
static sta_status compute(hull_thread *t, sta_error *err)
{
    const sta_katz_worker *w = t->worker;
    request *r = t->work;
    sta_katz_set *set = t->back;
    const size_t candidates = r->count;
    sta_status s = STA_OK;
    if (r->cell_cap > 0) {
        const double origin[3] = { 0.0, 0.0, 0.0 };
        s = sta_katz_cells_select(&t->cells, &r->camera, origin, r->cell_cap, r->points, r->tags,
                                  &r->count, err);
        if (s != STA_OK) {
            return s;
        }
    }
    s = set_reserve(set, r->count, err);
    if (s == STA_OK && t->xyz_capacity < r->count) {
        sta_free(t->xyz);
        t->xyz = sta_alloc_array(r->count, sizeof(*t->xyz));
        t->xyz_capacity = t->xyz ? r->count : 0;
        if (!t->xyz) {
            s = sta_fail(err, STA_ERR_NOMEM, "katz worker: out of memory for %zu points", r->count);
        }
    }
    if (s != STA_OK) {
        return s;
    }
    for (size_t i = 0; i < r->count; i++) {
        for (int a = 0; a < 3; a++) {
            t->xyz[i][a] = (double)r->points[i][a];
        }
    }
    sta_katz_params params = w->config.params;
    if (r->radius_m > 0.0) {
        params.radius_m = r->radius_m;
    }
    memset(&set->stats, 0, sizeof(set->stats));
    set->plain_hull_ms = set->plain_hull_cpu_ms = 0.0;
    s = sta_katz_visible((const double(*)[3])t->xyz, r->count, r->viewpoint, &params, set->visible,
                         &set->stats, err);
    if (s == STA_OK && w->config.compare_plain && params.perturbation > 0.0) {
        // The same input without the perturbation, for its speed-up; its flags are not
        // kept (set->points is free until the copy below, so it holds them meanwhile).
        sta_katz_params plain = params;
        plain.perturbation = 0.0;
        sta_katz_stats plain_stats;
        s = sta_katz_visible((const double(*)[3])t->xyz, r->count, r->viewpoint, &plain,
                             (uint8_t *)set->points, &plain_stats, err);
        set->plain_hull_ms = plain_stats.hull_ms;
        set->plain_hull_cpu_ms = plain_stats.hull_cpu_ms;
    }
    if (s != STA_OK) {
        return s;
    }
    if (r->count > 0) {
        memcpy(set->points, r->points, r->count * sizeof(*r->points));
        memcpy(set->tags, r->tags, r->count * sizeof(*r->tags));
    }
    set->count = r->count;
    set->candidates = candidates;
    set->cell_px = r->cell_cap > 0 ? t->cells.cell_px : 0.0;
    set->visible_count = r->count > 0 ? set->stats.visible_count : 0;
    memcpy(set->viewpoint, r->viewpoint, sizeof(set->viewpoint));
    set->generation = r->seq;
    set->frame = r->frame;
    return STA_OK;
}

static void *thread_main(void *arg)
{
    hull_thread *t = arg;
    sta_katz_worker *w = t->worker;
    pthread_mutex_lock(&w->lock);
    while (!w->stop) {
        if (w->pending->seq == 0) {
            pthread_cond_wait(&w->wake, &w->lock);
            continue;
        }
        request *taken = w->pending;
        w->pending = t->work;
        w->pending->seq = 0;
        t->work = taken;
        w->running++;
        pthread_mutex_unlock(&w->lock);

        sta_error err = { 0 };
        sta_status s = compute(t, &err);

        pthread_mutex_lock(&w->lock);
        w->running--;
        w->counters.computed++;
        if (s != STA_OK) {
            w->counters.failed++;
            w->error_status = s;
            w->error = err;
            continue;
        }
        uint64_t newest =
            w->ready->generation > w->front_generation ? w->ready->generation : w->front_generation;
        if (t->back->generation > newest) {
            sta_katz_set *published = t->back;
            t->back = w->ready;
            w->ready = published;
            w->counters.published++;
        } else {
            w->counters.dropped++;
        }
    }
    pthread_mutex_unlock(&w->lock);
    return NULL;
}

sta_status sta_katz_worker_create(const sta_katz_worker_config *config, sta_katz_worker **out,
                                  sta_error *err)
{
    *out = NULL;
    sta_katz_worker_config c = config ? *config : (sta_katz_worker_config){ 0 };
    sta_katz_worker_config_defaults(&c);
    if (c.thread_count < 1 || c.thread_count > STA_KATZ_WORKER_MAX_THREADS) {
        return sta_fail(err, STA_ERR_ARG, "katz worker: thread count %d is outside 1..%d",
                        c.thread_count, STA_KATZ_WORKER_MAX_THREADS);
    }
    // Checks the parameters now rather than at the first hull.
    uint8_t flag;
    sta_katz_stats stats;
    const double origin[3] = { 0.0, 0.0, 0.0 };
    sta_status s = sta_katz_visible(NULL, 0, origin, &c.params, &flag, &stats, err);
    if (s != STA_OK) {
        return s;
    }
    sta_katz_worker *w = sta_calloc(1, sizeof(*w));
    if (!w) {
        return sta_fail(err, STA_ERR_NOMEM, "katz worker: out of memory");
    }
    w->config = c;
    pthread_mutex_init(&w->lock, NULL);
    pthread_cond_init(&w->wake, NULL);
    w->staging = sta_calloc(1, sizeof(request));
    w->pending = sta_calloc(1, sizeof(request));
    w->ready = sta_calloc(1, sizeof(sta_katz_set));
    w->front = sta_calloc(1, sizeof(sta_katz_set));
    bool ok = w->staging && w->pending && w->ready && w->front;
    for (int i = 0; i < c.thread_count && ok; i++) {
        hull_thread *t = &w->threads[i];
        t->worker = w;
        t->index = i;
        t->work = sta_calloc(1, sizeof(request));
        t->back = sta_calloc(1, sizeof(sta_katz_set));
        ok = t->work && t->back;
    }
    if (!ok) {
        sta_katz_worker_destroy(w);
        return sta_fail(err, STA_ERR_NOMEM, "katz worker: out of memory");
    }
    for (int i = 0; i < c.thread_count; i++) {
        hull_thread *t = &w->threads[i];
        if (pthread_create(&t->thread, NULL, thread_main, t) != 0) {
            sta_katz_worker_destroy(w);
            return sta_fail(err, STA_ERR_IO, "katz worker: cannot start hull thread %d", i);
        }
        t->started = true;
        char name[16]; // the kernel's limit, with the NUL
        snprintf(name, sizeof(name), "sta-katz-%d", i % STA_KATZ_WORKER_MAX_THREADS);
        pthread_setname_np(t->thread, name);
    }
    *out = w;
    return STA_OK;
}

void sta_katz_worker_destroy(sta_katz_worker *worker)
{
    if (!worker) {
        return;
    }
    pthread_mutex_lock(&worker->lock);
    worker->stop = true;
    pthread_cond_broadcast(&worker->wake);
    pthread_mutex_unlock(&worker->lock);
    for (int i = 0; i < STA_KATZ_WORKER_MAX_THREADS; i++) {
        hull_thread *t = &worker->threads[i];
        if (t->started) {
            pthread_join(t->thread, NULL);
        }
        request_free(t->work);
        set_free(t->back);
        sta_free(t->xyz);
        sta_katz_cells_release(&t->cells);
    }
    request_free(worker->staging);
    request_free(worker->pending);
    set_free(worker->ready);
    set_free(worker->front);
    pthread_cond_destroy(&worker->wake);
    pthread_mutex_destroy(&worker->lock);
    sta_free(worker);
}

// Checks and copies a submission into the staging buffer, then makes it the pending one.
static sta_status submit(sta_katz_worker *worker, const float (*points)[3], const uint64_t *tags,
                         size_t count, const double viewpoint[3], const sta_camera *camera,
                         size_t cell_cap, double radius_m, uint64_t frame, sta_error *err)
{
    if (!worker || !viewpoint || (count > 0 && !points)) {
        return sta_fail(err, STA_ERR_ARG, "katz worker: NULL argument to submit");
    }
    if (!(isfinite(viewpoint[0]) && isfinite(viewpoint[1]) && isfinite(viewpoint[2]))) {
        return sta_fail(err, STA_ERR_ARG, "katz worker: viewpoint (%g, %g, %g) is not finite",
                        viewpoint[0], viewpoint[1], viewpoint[2]);
    }
    if (!(radius_m >= 0.0) || !isfinite(radius_m)) {
        return sta_fail(err, STA_ERR_ARG, "katz worker: radius %g m is not >= 0", radius_m);
    }
    for (size_t i = 0; i < count; i++) {
        if (!(isfinite(points[i][0]) && isfinite(points[i][1]) && isfinite(points[i][2]))) {
            return sta_fail(err, STA_ERR_ARG, "katz worker: point %zu is (%g, %g, %g), not finite",
                            i, (double)points[i][0], (double)points[i][1], (double)points[i][2]);
        }
    }
    request *r = worker->staging;
    sta_status s = request_reserve(r, count, err);
    if (s != STA_OK) {
        return s;
    }
    if (count > 0) {
        memcpy(r->points, points, count * sizeof(*points));
        for (size_t i = 0; i < count; i++) {
            r->tags[i] = tags ? tags[i] : (uint64_t)i;
        }
    }
    r->count = count;
    memcpy(r->viewpoint, viewpoint, sizeof(r->viewpoint));
    r->cell_cap = cell_cap;
    if (cell_cap > 0) {
        r->camera = *camera;
        memcpy(r->camera.position, viewpoint, sizeof(r->camera.position));
    }
    r->radius_m = radius_m;
    r->frame = frame;
    pthread_mutex_lock(&worker->lock);
    worker->counters.submitted++;
    if (worker->pending->seq != 0) {
        worker->counters.replaced++;
    }
    r->seq = worker->counters.submitted;
    worker->staging = worker->pending;
    worker->pending = r;
    pthread_cond_signal(&worker->wake);
    pthread_mutex_unlock(&worker->lock);
    return STA_OK;
}

sta_status sta_katz_worker_submit(sta_katz_worker *worker, const float (*points)[3],
                                  const uint64_t *tags, size_t count, const double viewpoint[3],
                                  double radius_m, uint64_t frame, sta_error *err)
{
    return submit(worker, points, tags, count, viewpoint, NULL, 0, radius_m, frame, err);
}

sta_status sta_katz_worker_submit_view(sta_katz_worker *worker, const float (*points)[3],
                                       const uint64_t *tags, size_t count, const sta_camera *camera,
                                       const double origin[3], size_t cell_cap, double radius_m,
                                       uint64_t frame, sta_error *err)
{
    if (!camera || !origin || cell_cap == 0) {
        return sta_fail(err, STA_ERR_ARG,
                        "katz worker: submit_view needs a camera, an origin "
                        "and a cell cap above 0");
    }
    if (!(camera->width_px > 0 && camera->height_px > 0 && camera->fov_y > 0.0 &&
          camera->fov_y < 3.14159 && camera->near_m > 0.0)) {
        return sta_fail(err, STA_ERR_ARG,
                        "katz worker: camera %dx%d px, fov %g rad, near %g m is not a view",
                        camera->width_px, camera->height_px, camera->fov_y, camera->near_m);
    }
    const double viewpoint[3] = { camera->position[0] - origin[0], camera->position[1] - origin[1],
                                  camera->position[2] - origin[2] };
    return submit(worker, points, tags, count, viewpoint, camera, cell_cap, radius_m, frame, err);
}

bool sta_katz_worker_acquire(sta_katz_worker *worker, const sta_katz_set **out)
{
    bool is_new = false;
    pthread_mutex_lock(&worker->lock);
    if (worker->ready->generation > worker->front_generation) {
        sta_katz_set *previous = worker->front;
        worker->front = worker->ready;
        worker->ready = previous;
        worker->front_generation = worker->front->generation;
        is_new = true;
    }
    *out = worker->front;
    pthread_mutex_unlock(&worker->lock);
    return is_new;
}

bool sta_katz_worker_is_busy(sta_katz_worker *worker)
{
    pthread_mutex_lock(&worker->lock);
    bool busy = worker->pending->seq != 0 || worker->running > 0;
    pthread_mutex_unlock(&worker->lock);
    return busy;
}

void sta_katz_worker_counters_get(sta_katz_worker *worker, sta_katz_worker_counters *out)
{
    pthread_mutex_lock(&worker->lock);
    *out = worker->counters;
    pthread_mutex_unlock(&worker->lock);
}

sta_status sta_katz_worker_take_error(sta_katz_worker *worker, sta_error *err)
{
    pthread_mutex_lock(&worker->lock);
    sta_status s = worker->error_status;
    if (s != STA_OK && err) {
        *err = worker->error;
    }
    worker->error_status = STA_OK;
    pthread_mutex_unlock(&worker->lock);
    return s;
}
