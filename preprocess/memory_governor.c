/* SPDX-License-Identifier: MIT
 * The index phase's memory governor for --normals (see memory_governor.h). */
#include "memory_governor.h"

#include <stdatomic.h>
#include <string.h>
#include <time.h>

#include "core/clock.h"

enum {
    TAKE_POLL_NS = 1000000 /* a take that waits looks again every millisecond */
};

void sta_memory_governor_init(sta_memory_governor *g, size_t pool_bytes)
{
    memset(g, 0, sizeof(*g));
    g->pool_bytes = pool_bytes;
    atomic_store(&g->pool.left, (long long)pool_bytes);
    pthread_mutex_init(&g->lock, NULL);
    pthread_cond_init(&g->change, NULL);
}

void sta_memory_governor_release(sta_memory_governor *g)
{
    pthread_mutex_destroy(&g->lock);
    pthread_cond_destroy(&g->change);
}

void sta_memory_governor_enter(sta_memory_governor *g)
{
    pthread_mutex_lock(&g->lock);
    if (g->alone) {
        double t0 = sta_clock_s();
        while (g->alone) {
            pthread_cond_wait(&g->change, &g->lock);
        }
        g->waited_s += sta_clock_s() - t0;
    }
    g->inside++;
    pthread_mutex_unlock(&g->lock);
}

void sta_memory_governor_leave(sta_memory_governor *g)
{
    pthread_mutex_lock(&g->lock);
    g->inside--;
    pthread_cond_broadcast(&g->change);
    pthread_mutex_unlock(&g->lock);
}

void sta_memory_governor_go_alone(sta_memory_governor *g)
{
    double t0 = sta_clock_s();
    pthread_mutex_lock(&g->lock);
    // Not counted while waiting: two chunks that both want to be alone take turns.
    g->inside--;
    pthread_cond_broadcast(&g->change);
    while (g->alone) {
        pthread_cond_wait(&g->change, &g->lock);
    }
    g->alone = true;
    while (g->inside > 0) {
        pthread_cond_wait(&g->change, &g->lock);
    }
    g->inside = 1;
    g->alone_runs++;
    g->waited_s += sta_clock_s() - t0;
    pthread_mutex_unlock(&g->lock);
}

void sta_memory_governor_share(sta_memory_governor *g)
{
    pthread_mutex_lock(&g->lock);
    g->alone = false;
    pthread_cond_broadcast(&g->change);
    pthread_mutex_unlock(&g->lock);
}

void sta_memory_governor_take(sta_memory_governor *g, size_t bytes)
{
    // (the pool's frees do not signal: alloc.c knows no governor; a waiting take polls)
    double t0 = 0.0;
    bool force = false;
    while (!force && !sta_alloc_pool_take(&g->pool, bytes)) {
        t0 = t0 > 0.0 ? t0 : sta_clock_s();
        pthread_mutex_lock(&g->lock);
        force = g->alone || atomic_load(&g->pool.left) >= (long long)g->pool_bytes;
        pthread_mutex_unlock(&g->lock);
        if (force) {
            atomic_fetch_sub(&g->pool.left, (long long)bytes);
        } else {
            struct timespec ts = { 0, TAKE_POLL_NS };
            nanosleep(&ts, NULL);
        }
    }
    if (t0 > 0.0) {
        pthread_mutex_lock(&g->lock);
        g->waited_s += sta_clock_s() - t0;
        pthread_mutex_unlock(&g->lock);
    }
}

void sta_memory_governor_give(sta_memory_governor *g, size_t bytes)
{
    sta_alloc_pool_give(&g->pool, bytes);
}
