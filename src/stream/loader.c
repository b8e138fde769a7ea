/* SPDX-License-Identifier: MIT
 * Loader threads. */
#define _GNU_SOURCE // pthread_setname_np
#include "stream/loader.h"

#include <pthread.h>
#include <stdio.h>
#include <string.h>

#include "core/alloc.h"
#include "core/clock.h"
#include "stream/gpu_points.h"

enum {
    STATE_IDLE = 0,
    STATE_LOADING = 1,
    STATE_READY = 2,
    STATE_FAILED = 3
};
enum {
    MAX_THREADS = 16
};

typedef struct result_item {
    sta_loaded_node node;
    struct result_item *next;
} result_item;

struct sta_loader {
    const sta_node_source *source; /* borrowed; safe to load from several workers */
    sta_loader_options options;
    pthread_t threads[MAX_THREADS];
    int thread_count;
    pthread_mutex_t lock;
    pthread_cond_t work_ready;  /* wanted list changed, or stopping */
    pthread_cond_t space_ready; /* results were taken */
    /* guarded by lock: */
    bool stopping;
    uint32_t *wanted; /* priority order */
    size_t wanted_count, wanted_capacity, wanted_cursor;
    uint8_t *state; /* STATE_* per node */
    result_item *ready_head, *ready_tail;
    size_t ready_bytes;
    size_t loading;
    uint64_t points_done;
    double busy_s;
};

// Next wanted node that is idle, or UINT32_MAX. Called under the lock.
static uint32_t next_wanted(sta_loader *l)
{
    while (l->wanted_cursor < l->wanted_count) {
        uint32_t node = l->wanted[l->wanted_cursor++];
        if (l->state[node] == STATE_IDLE) {
            return node;
        }
    }
    return UINT32_MAX;
}

static void load_node(sta_loader *l, void *worker, uint32_t index, sta_loaded_node *out)
{
    memset(out, 0, sizeof(*out));
    out->node = index;
    sta_error err = { 0 };
    out->status = l->source->load(l->source->context, worker, index, &out->gpu, &out->count, &err);
    if (out->status != STA_OK) {
        sta_free(out->gpu);
        out->gpu = NULL;
        out->count = 0;
        snprintf(out->message, sizeof(out->message), "%s", err.message);
    }
}

static void *worker_main(void *argument)
{
    sta_loader *l = argument;
    void *worker = NULL;
    sta_error err = { 0 };
    bool have_worker = !l->source->worker_begin ||
                       l->source->worker_begin(l->source->context, &worker, &err) == STA_OK;
    pthread_mutex_lock(&l->lock);
    while (!l->stopping) {
        uint32_t index = have_worker && l->ready_bytes < l->options.ready_bytes_cap ? next_wanted(l)
                                                                                    : UINT32_MAX;
        if (index == UINT32_MAX) {
            pthread_cond_wait(l->ready_bytes >= l->options.ready_bytes_cap ? &l->space_ready
                                                                           : &l->work_ready,
                              &l->lock);
            continue;
        }
        l->state[index] = STATE_LOADING;
        l->loading++;
        pthread_mutex_unlock(&l->lock);

        double t0 = sta_clock_s();
        result_item *item = sta_malloc(sizeof(*item));
        if (item) {
            load_node(l, worker, index, &item->node);
            item->next = NULL;
        }
        double busy = sta_clock_s() - t0;

        pthread_mutex_lock(&l->lock);
        l->loading--;
        l->busy_s += busy;
        if (!item) {
            l->state[index] = STATE_IDLE; // try again later
            continue;
        }
        l->state[index] = item->node.status == STA_OK ? STATE_READY : STATE_FAILED;
        l->points_done += item->node.count;
        l->ready_bytes += item->node.count * l->options.point_bytes;
        if (l->ready_tail) {
            l->ready_tail->next = item;
        } else {
            l->ready_head = item;
        }
        l->ready_tail = item;
    }
    pthread_mutex_unlock(&l->lock);
    if (have_worker && l->source->worker_end) {
        l->source->worker_end(l->source->context, worker);
    }
    return NULL;
}

void sta_loader_options_defaults(sta_loader_options *o)
{
    o->threads = o->threads > 0 ? o->threads : 1;
    o->threads = o->threads > MAX_THREADS ? MAX_THREADS : o->threads;
    if (!o->point_bytes) {
        o->point_bytes = STA_GPU_POINT_SIZE;
    }
    if (!o->ready_bytes_cap) {
        o->ready_bytes_cap = (size_t)256 << 20;
    }
}

sta_status sta_loader_create(const sta_node_source *source, const sta_loader_options *options,
                             sta_loader **out_loader, sta_error *err)
{
    *out_loader = NULL;
    sta_loader *l = sta_calloc(1, sizeof(*l));
    if (!l) {
        return sta_fail(err, STA_ERR_NOMEM, "out of memory for the loader");
    }
    l->source = source;
    if (options) {
        l->options = *options;
    }
    sta_loader_options_defaults(&l->options);
    l->state = sta_calloc(source->node_count ? source->node_count : 1, 1);
    if (!l->state) {
        sta_free(l);
        return sta_fail(err, STA_ERR_NOMEM, "out of memory for the loader");
    }
    pthread_mutex_init(&l->lock, NULL);
    pthread_cond_init(&l->work_ready, NULL);
    pthread_cond_init(&l->space_ready, NULL);
    for (int t = 0; t < l->options.threads; t++) {
        if (pthread_create(&l->threads[t], NULL, worker_main, l) != 0) {
            break;
        }
        char name[16];
        snprintf(name, sizeof(name), "sta-loader-%d", t % 10);
        pthread_setname_np(l->threads[t], name);
        l->thread_count++;
    }
    if (l->thread_count == 0) {
        sta_loader_destroy(l);
        return sta_fail(err, STA_ERR_NOMEM, "cannot start loader threads");
    }
    *out_loader = l;
    return STA_OK;
}

sta_status sta_loader_request(sta_loader *l, const uint32_t *nodes, size_t count, sta_error *err)
{
    // wanted_capacity changes only here, on the main thread: reading it unlocked is safe.
    uint32_t *fresh = NULL;
    size_t fresh_capacity = 0;
    if (count > l->wanted_capacity) {
        fresh_capacity = count * 2;
        fresh = sta_alloc_array(fresh_capacity, sizeof(*fresh));
        if (!fresh) {
            return sta_fail(err, STA_ERR_NOMEM, "out of memory for the load queue");
        }
    }
    uint32_t node_count = l->source->node_count;
    uint32_t *old = NULL;
    pthread_mutex_lock(&l->lock);
    if (fresh) {
        old = l->wanted;
        l->wanted = fresh;
        l->wanted_capacity = fresh_capacity;
    }
    size_t n = 0;
    for (size_t i = 0; i < count; i++) {
        if (nodes[i] < node_count) {
            l->wanted[n++] = nodes[i];
        }
    }
    l->wanted_count = n;
    l->wanted_cursor = 0;
    pthread_cond_broadcast(&l->work_ready);
    pthread_mutex_unlock(&l->lock);
    sta_free(old);
    return STA_OK;
}

bool sta_loader_take(sta_loader *l, sta_loaded_node *out)
{
    pthread_mutex_lock(&l->lock);
    result_item *item = l->ready_head;
    if (item) {
        l->ready_head = item->next;
        if (!l->ready_head) {
            l->ready_tail = NULL;
        }
        l->ready_bytes -= item->node.count * l->options.point_bytes;
        // A failed node stays FAILED so it is never loaded again.
        if (l->state[item->node.node] == STATE_READY) {
            l->state[item->node.node] = STATE_IDLE;
        }
        pthread_cond_broadcast(&l->space_ready);
    }
    pthread_mutex_unlock(&l->lock);
    if (!item) {
        return false;
    }
    *out = item->node;
    sta_free(item);
    return true;
}

void sta_loaded_node_release(sta_loaded_node *node)
{
    sta_free(node->gpu);
    node->gpu = NULL;
    node->count = 0;
}

size_t sta_loader_backlog(sta_loader *l)
{
    pthread_mutex_lock(&l->lock);
    size_t backlog = l->loading;
    for (size_t i = l->wanted_cursor; i < l->wanted_count; i++) {
        backlog += l->state[l->wanted[i]] == STATE_IDLE;
    }
    for (result_item *r = l->ready_head; r; r = r->next) {
        backlog++;
    }
    pthread_mutex_unlock(&l->lock);
    return backlog;
}

void sta_loader_stats(sta_loader *l, uint64_t *out_points, double *out_busy_s)
{
    pthread_mutex_lock(&l->lock);
    *out_points = l->points_done;
    *out_busy_s = l->busy_s;
    pthread_mutex_unlock(&l->lock);
}

void sta_loader_destroy(sta_loader *l)
{
    if (!l) {
        return;
    }
    pthread_mutex_lock(&l->lock);
    l->stopping = true;
    pthread_cond_broadcast(&l->work_ready);
    pthread_cond_broadcast(&l->space_ready);
    pthread_mutex_unlock(&l->lock);
    for (int t = 0; t < l->thread_count; t++) {
        pthread_join(l->threads[t], NULL);
    }
    while (l->ready_head) {
        result_item *next = l->ready_head->next;
        sta_loaded_node_release(&l->ready_head->node);
        sta_free(l->ready_head);
        l->ready_head = next;
    }
    sta_free(l->wanted);
    sta_free(l->state);
    pthread_cond_destroy(&l->work_ready);
    pthread_cond_destroy(&l->space_ready);
    pthread_mutex_destroy(&l->lock);
    sta_free(l);
}
