/* SPDX-License-Identifier: MIT
 * The index phase's memory governor for --normals (docs/CONVERTER.md, "Memory").
 *
 * The normals' scratch of a chunk depends on how rough its points are (150 to 2 000
 * bytes a point measured), which is known only while they are computed. So the
 * workers' normals draw their heap from one shared pool (core/alloc.h's meter), sized
 * from --memory less everything else the plan holds; a chunk whose allocation the pool
 * refuses drops what it built, waits until it is the only chunk in the index phase and
 * computes again with the whole pool; refused alone, the conversion stops with an
 * error. The output does not depend on it (a chunk's normals are the same however
 * often they are computed).
 */
#ifndef STA_PREPROCESS_MEMORY_GOVERNOR_H
#define STA_PREPROCESS_MEMORY_GOVERNOR_H

#include <pthread.h>
#include <stdbool.h>
#include <stddef.h>

#include "core/alloc.h"

typedef struct sta_memory_governor {
    sta_alloc_pool pool;   /* the normals' heap of all workers together */
    size_t pool_bytes;     /* its size */
    pthread_mutex_t lock;  /* guards the two below */
    pthread_cond_t change; /* a chunk left, or one stopped running alone */
    int inside;            /* chunks in the index phase now */
    bool alone;            /* a chunk runs (or waits to run) alone */
    size_t alone_runs;     /* chunks that ran alone (reported) */
    double waited_s;       /* seconds workers waited, summed (reported) */
} sta_memory_governor;

void sta_memory_governor_init(sta_memory_governor *g, size_t pool_bytes);
void sta_memory_governor_release(sta_memory_governor *g);

/* A worker starts a chunk: waits while a chunk runs alone. */
void sta_memory_governor_enter(sta_memory_governor *g);
/* It is done with the chunk. */
void sta_memory_governor_leave(sta_memory_governor *g);

/* From inside a chunk: waits until every other chunk has left (one waits at a time;
 * the others start no chunk meanwhile). */
void sta_memory_governor_go_alone(sta_memory_governor *g);
/* Back to sharing the phase with the others (still inside the chunk). */
void sta_memory_governor_share(sta_memory_governor *g);

/* Takes `bytes` from the pool for a part that cannot be refused (a chunk's index
 * buffers): waits while others hold enough of the pool that it would not fit, but takes
 * them anyway when nothing else is held or a chunk waits to run alone (its tables are
 * freed then: waiting could only deadlock); sta_memory_governor_give returns them. */
void sta_memory_governor_take(sta_memory_governor *g, size_t bytes);
void sta_memory_governor_give(sta_memory_governor *g, size_t bytes);

#endif
