/* SPDX-License-Identifier: MIT
 * Phase 2 of the conversion: count points on a coarse grid, merge cells into chunks
 * that fit in memory, and write every point into its chunk's region of one
 * temporary file. Both passes run on `threads` threads, each over its own contiguous
 * range of the inputs' points.
 */
#ifndef STA_PREPROCESS_DISTRIBUTE_H
#define STA_PREPROCESS_DISTRIBUTE_H

#include <stdatomic.h>
#include <stdint.h>

#include "inputs.h"
#include "octree.h"
#include "progress.h"
#include "temp_runs.h"

/* One chunk: a node of the octree whose whole subtree is built in memory. */
typedef struct sta_chunk {
    sta_node_key key;
    uint64_t count; /* points */
    uint64_t first; /* where its records would start in one flat file (planning only) */
    size_t list;    /* its run list in the temporary runs */
} sta_chunk;

typedef struct sta_chunk_plan {
    sta_octree_space space;
    int count_level;   /* level of the counting grid */
    sta_chunk *chunks; /* owned */
    size_t chunk_count;
    int32_t *chunk_of_cell; /* chunk index of each counting cell, -1 when empty; owned */
    int64_t actual_min[3];  /* tight integer bounds of all points */
    int64_t actual_max[3];
    uint64_t point_count;
    int threads;            /* ranges the inputs were split into */
    uint64_t *range_begin;  /* threads + 1 global point indices; owned */
    uint64_t *thread_first; /* threads x chunk_count: where each thread's points of a
                               chunk start in the temporary file (record index); owned */
} sta_chunk_plan;

/* Reads every input once (twice when the declared bounds prove wrong), finds the
 * tight bounds, chooses the root box and plans chunks of at most `chunk_capacity`
 * points where the counting grid allows. `cancel` (may be NULL) stops the work. */
sta_status sta_distribute_plan(sta_input_set *set, int threads, int grid_log2,
                               uint64_t chunk_capacity, sta_progress *progress, atomic_bool *cancel,
                               sta_chunk_plan *out_plan, sta_error *err);

/* Reads every input again and appends each point's packed record to its chunk's run
 * list in `runs` (compressed blocks; list `chunk.list`), on the plan's threads. Within
 * a chunk the records read back in input order. `buffer_bytes` bounds the write
 * buffers. */
sta_status sta_distribute_write(sta_input_set *set, const sta_chunk_plan *plan, sta_temp_runs *runs,
                                size_t buffer_bytes, sta_progress *progress, atomic_bool *cancel,
                                sta_error *err);

/* As sta_distribute_write, into memory: chunk c's records go to chunk_records[c]
 * (room for plan->chunks[c].count records, the caller's), in the order the runs
 * would give back (thread 0's points, then thread 1's, ..., each in input order), so
 * the tree built from them is the same. Each thread packs straight into its share
 * of each chunk (plan->thread_first): no buffers, no compression, no file. */
sta_status sta_distribute_to_memory(sta_input_set *set, const sta_chunk_plan *plan,
                                    uint8_t *const *chunk_records, sta_progress *progress,
                                    atomic_bool *cancel, sta_error *err);

void sta_chunk_plan_release(sta_chunk_plan *plan);

#endif
