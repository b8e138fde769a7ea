/* SPDX-License-Identifier: MIT
 * The converter's node sink: turns finished nodes into .strata payloads (in the
 * emitting worker's thread) and collects the node table.
 */
#ifndef STA_PREPROCESS_NODE_WRITER_H
#define STA_PREPROCESS_NODE_WRITER_H

#include <pthread.h>

#include "format/strata_writer.h"
#include "node_sink.h"
#include "record.h"

/* Per-worker buffers for unpacking records. */
typedef struct sta_node_worker {
    sta_strata_encoder *encoder;
    uint8_t *columns; /* one node's payload in the .strata column layout */
    size_t capacity;  /* bytes */
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
    uint64_t raw_bytes;    /* guard: lock */
    uint64_t stored_bytes; /* guard: lock */
    uint64_t point_count;  /* guard: lock */
} sta_node_writer;

/* `strata_layout` and `geometry` are the writer's (payload columns are encoded straight
 * from the packed records; node corners come from the geometry); both borrowed. */
sta_status sta_node_writer_init(sta_node_writer *nw, sta_strata_writer *writer,
                                const sta_record_layout *layout,
                                const sta_strata_layout *strata_layout,
                                const sta_strata_geometry *geometry, int worker_count,
                                sta_error *err);

void sta_node_writer_release(sta_node_writer *nw);

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
