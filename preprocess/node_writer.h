/* SPDX-License-Identifier: MIT
 * The converter's node sink: turns finished nodes into .strata payloads (in the
 * emitting worker's thread) and collects the node table.
 *
 * Design (deterministic output): during the index phase each worker packs its
 * chunk's payloads into a private batch (begin_chunk .. end_chunk); batches reach the
 * file in chunk order, whatever the order workers finish in, so the same input gives
 * the same bytes with any number of threads. A finished batch whose turn has not come
 * waits in `pending`; the thread that completes the next one in order writes every
 * consecutive ready batch (one writer at a time: `committing`). A worker may start
 * chunk `order` only when order < committed + window, which bounds the batches held.
 * Lock order: commit_lock, then lock (never nested in practice).
 */
#ifndef STA_PREPROCESS_NODE_WRITER_H
#define STA_PREPROCESS_NODE_WRITER_H

#include <pthread.h>
#include <stdbool.h>

#include "format/strata_writer.h"
#include "node_sink.h"
#include "record.h"

/* A chunk's packed payloads and their table entries (offsets relative to the batch). */
typedef struct sta_node_batch {
    sta_strata_batch payloads;
    sta_strata_node *nodes;
    size_t node_count;
    size_t node_capacity;
} sta_node_batch;

/* Per-worker buffers for unpacking records. */
typedef struct sta_node_worker {
    sta_strata_encoder *encoder;
    uint8_t *columns;      /* one node's payload in the .strata column layout */
    size_t capacity;       /* bytes */
    sta_node_batch *batch; /* the chunk being packed (begin..end_chunk), else NULL */
    size_t order;          /* that chunk's place in the file order */
} sta_node_worker;

typedef struct sta_node_writer {
    sta_strata_writer *writer;           /* borrowed */
    const sta_record_layout *layout;     /* borrowed */
    const sta_strata_geometry *geometry; /* borrowed: node corners */
    size_t column_record_size;           /* bytes per point of the .strata payload */
    uint16_t extra_dim_sizes[STA_STRATA_MAX_EXTRA_DIMS]; /* per extra dimension */
    uint32_t extra_dim_count;
    sta_node_worker *workers; /* one per worker, owned */
    int worker_count;
    pthread_mutex_t lock;   /* guards nodes, node_count, node_capacity, totals */
    sta_strata_node *nodes; /* emitted nodes, any order (guard: lock) */
    size_t node_count;
    size_t node_capacity;
    uint64_t raw_bytes;          /* guard: lock */
    uint64_t stored_bytes;       /* guard: lock */
    uint64_t point_count;        /* guard: lock */
    pthread_mutex_t commit_lock; /* guards the fields below */
    pthread_cond_t committed_cv; /* signalled when `committed` grows or on abort */
    sta_node_batch **pending;    /* chunk_count slots, finished batches (commit_lock) */
    size_t chunk_count;          /* commit_lock */
    size_t committed;            /* commit_lock: batches written, in order */
    size_t window;               /* chunks a worker may run ahead of `committed` */
    bool committing;             /* commit_lock: a thread is writing batches */
    bool aborted;                /* commit_lock: a worker failed; waits return */
} sta_node_writer;

/* `strata_layout` and `geometry` are the writer's (payload columns are encoded straight
 * from the packed records; node corners come from the geometry); both borrowed. */
sta_status sta_node_writer_init(sta_node_writer *nw, sta_strata_writer *writer,
                                const sta_record_layout *layout,
                                const sta_strata_layout *strata_layout,
                                const sta_strata_geometry *geometry, int worker_count,
                                sta_error *err);

void sta_node_writer_release(sta_node_writer *nw);

/* Prepares ordered commits of `chunk_count` chunk batches. Main thread, before the
 * workers start. */
sta_status sta_node_writer_plan_chunks(sta_node_writer *nw, size_t chunk_count, sta_error *err);

/* Starts packing chunk number `order` (0 .. chunk_count-1, each once) for worker
 * `worker`: waits until it is within the window of the file order. Returns
 * STA_ERR_CANCELLED after sta_node_writer_abort. */
sta_status sta_node_writer_begin_chunk(sta_node_writer *nw, int worker, size_t order,
                                       sta_error *err);

/* Ends worker `worker`'s chunk: its batch joins the file in order (written now by
 * this thread when its turn has come, or later by the thread whose batch completes
 * the sequence). */
sta_status sta_node_writer_end_chunk(sta_node_writer *nw, int worker, sta_error *err);

/* Wakes and fails every begin_chunk wait (a worker failed or the run was cancelled). */
void sta_node_writer_abort(sta_node_writer *nw);

/* True when every planned chunk batch has been written. */
bool sta_node_writer_all_committed(sta_node_writer *nw);

/* The sink to give the octree builders (context = nw). */
sta_node_sink sta_node_writer_sink(sta_node_writer *nw);

/* Records an empty inner node (no points) so the tree stays connected. Main thread,
 * while no worker runs (it uses worker 0's encoder). */
sta_status sta_node_writer_add_empty(sta_node_writer *nw, const sta_node_key *key, sta_error *err);

/* Sorts the collected nodes breadth-first, links children and writes the table and
 * header (sta_strata_writer_finish). */
sta_status sta_node_writer_finish(sta_node_writer *nw, uint32_t *out_node_count, int *out_max_level,
                                  sta_error *err);

#endif
