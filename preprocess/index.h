/* SPDX-License-Identifier: MIT
 * Builds the nested octree of one chunk in memory (phase 3 of the conversion).
 *
 * Based on: Wimmer & Scheiblauer, "Instant Points", 2006: each node keeps the first
 * point that falls into each empty cell of its grid, the others go to the child that
 * contains them; a node with few points left is a leaf bucket.
 */
#ifndef STA_PREPROCESS_INDEX_H
#define STA_PREPROCESS_INDEX_H

#include <stddef.h>
#include <stdint.h>

#include "node_sink.h"
#include "octree.h"
#include "record.h"

/* One point being indexed: its position (read once from its record) and where the
 * record is. `cell` is scratch for the node being split. */
typedef struct sta_index_item {
    int32_t xyz[3];
    uint32_t index; /* record index in the chunk */
    uint32_t cell;
} sta_index_item;

/* Reusable per-worker memory; zero-initialise, free with sta_index_scratch_release. */
typedef struct sta_index_scratch {
    uint64_t *cell_bits; /* one bit per cell of a node grid; all zero between nodes */
    size_t cell_words;
    sta_index_item *items; /* points being partitioned */
    sta_index_item *spare; /* partition target, same size */
    uint8_t *labels;       /* bucket of each point being partitioned, same size */
    size_t order_capacity;
    uint8_t *gather;        /* one node's records, contiguous */
    size_t gather_capacity; /* bytes */
} sta_index_scratch;

void sta_index_scratch_release(sta_index_scratch *scratch);

/* Bytes of scratch memory that indexing `count` points needs besides the records. */
size_t sta_index_memory_bytes(const sta_octree_space *space, const sta_record_layout *layout,
                              size_t count);

/* A node kept back for the merge above the chunks: its records (owned). */
typedef struct sta_pending_node {
    sta_node_key key;
    uint8_t *records; /* count * layout size bytes, owned (sta_free) */
    size_t count;
    unsigned flags;   /* STA_NODE_* */
    int has_children; /* 1 when nodes below it were emitted (keep it even if emptied) */
} sta_pending_node;

/* Indexes `count` packed records (all inside the node `chunk_key`): emits every node
 * of the chunk's subtree to `sink` except the chunk's own root, which is returned in
 * `out_root` for the merge. Nodes with at most `leaf_capacity` points, at the deepest
 * level, or whose points are all identical become leaf buckets. */
sta_status sta_index_chunk(const sta_octree_space *space, const sta_record_layout *layout,
                           const sta_node_key *chunk_key, const uint8_t *records, size_t count,
                           size_t leaf_capacity, int worker, const sta_node_sink *sink,
                           sta_index_scratch *scratch, sta_pending_node *out_root, sta_error *err);

/* Builds the parent of `children` (pending nodes with one common parent): the first
 * point of each parent cell moves up, in the children's order. Afterwards each child
 * holds what is left; the parent is returned in `out_parent`. */
sta_status sta_index_merge_parent(const sta_octree_space *space, const sta_record_layout *layout,
                                  sta_pending_node *children, size_t child_count,
                                  sta_index_scratch *scratch, sta_pending_node *out_parent,
                                  sta_error *err);

#endif
