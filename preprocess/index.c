/* SPDX-License-Identifier: MIT
 * In-memory nested octree of one chunk.
 *
 * Design: points are never moved; an array of indices is partitioned instead, node by
 * node, depth first. A node's "stay" points (first in each empty cell) are gathered
 * into a contiguous buffer and emitted; the others are split by octant into the
 * children's ranges. The cell bitmap is cleared by visiting the set cells again, so
 * a node costs O(its points), not O(cells).
 */
#include "index.h"

#include <string.h>

#include "core/alloc.h"

void sta_index_scratch_release(sta_index_scratch *scratch)
{
    sta_free(scratch->cell_bits);
    sta_free(scratch->order);
    sta_free(scratch->spare);
    sta_free(scratch->labels);
    sta_free(scratch->gather);
    memset(scratch, 0, sizeof(*scratch));
}

static size_t cell_words_for(const sta_octree_space *space)
{
    return ((size_t)1 << (3 * space->grid_log2)) / 64 + 1;
}

size_t sta_index_memory_bytes(const sta_octree_space *space, const sta_record_layout *layout,
                              size_t count)
{
    size_t grid_cells = (size_t)1 << (3 * space->grid_log2);
    size_t largest_node = count < grid_cells ? count : grid_cells;
    return cell_words_for(space) * 8 + count * (2 * sizeof(uint32_t) + 1) +
           largest_node * layout->size;
}

static sta_status reserve(sta_index_scratch *s, const sta_octree_space *space, size_t count,
                          sta_error *err)
{
    if (!s->cell_bits) {
        s->cell_words = cell_words_for(space);
        s->cell_bits = sta_calloc(s->cell_words, sizeof(uint64_t));
        if (!s->cell_bits) {
            return sta_fail(err, STA_ERR_NOMEM, "out of memory for a %d^3 cell grid",
                            1 << space->grid_log2);
        }
    }
    if (count > s->order_capacity) {
        sta_free(s->order);
        sta_free(s->spare);
        sta_free(s->labels);
        s->order = sta_alloc_array(count, sizeof(uint32_t));
        s->spare = sta_alloc_array(count, sizeof(uint32_t));
        s->labels = sta_malloc(count);
        s->order_capacity = s->order && s->spare && s->labels ? count : 0;
        if (!s->order_capacity) {
            return sta_fail(err, STA_ERR_NOMEM, "out of memory indexing %zu points", count);
        }
    }
    return STA_OK;
}

static sta_status gather(sta_index_scratch *s, const sta_record_layout *layout,
                         const uint8_t *records, const uint32_t *indices, size_t count,
                         sta_error *err)
{
    size_t bytes = count * layout->size;
    if (bytes > s->gather_capacity) {
        uint8_t *grown = sta_realloc_array(s->gather, bytes, 1);
        if (!grown) {
            return sta_fail(err, STA_ERR_NOMEM, "out of memory for a node of %zu points", count);
        }
        s->gather = grown;
        s->gather_capacity = bytes;
    }
    for (size_t i = 0; i < count; i++) {
        memcpy(s->gather + i * layout->size, records + (size_t)indices[i] * layout->size,
               layout->size);
    }
    return STA_OK;
}

static int test_and_set(uint64_t *bits, uint32_t cell)
{
    uint64_t mask = (uint64_t)1 << (cell & 63);
    int was_set = (bits[cell >> 6] & mask) != 0;
    bits[cell >> 6] |= mask;
    return was_set;
}

static int all_identical(const sta_record_layout *layout, const uint8_t *records,
                         const uint32_t *indices, size_t count)
{
    int32_t first[3], p[3];
    sta_record_position(records + (size_t)indices[0] * layout->size, first);
    for (size_t i = 1; i < count; i++) {
        sta_record_position(records + (size_t)indices[i] * layout->size, p);
        if (p[0] != first[0] || p[1] != first[1] || p[2] != first[2]) {
            return 0;
        }
    }
    return 1;
}

typedef struct build_context {
    const sta_octree_space *space;
    const sta_record_layout *layout;
    const uint8_t *records;
    size_t leaf_capacity;
    int worker;
    const sta_node_sink *sink;
    sta_index_scratch *scratch;
    sta_pending_node *root_out; /* receives the chunk root instead of the sink */
    const sta_node_key *root_key;
} build_context;

static sta_status hand_over(build_context *c, const sta_node_key *key, const uint32_t *indices,
                            size_t count, unsigned flags, int has_children, sta_error *err)
{
    sta_status status = gather(c->scratch, c->layout, c->records, indices, count, err);
    if (status != STA_OK) {
        return status;
    }
    if (key->level == c->root_key->level) {
        size_t bytes = count * c->layout->size;
        sta_pending_node *root = c->root_out;
        root->records = sta_malloc(bytes);
        if (!root->records) {
            return sta_fail(err, STA_ERR_NOMEM, "out of memory keeping a node of %zu points",
                            count);
        }
        memcpy(root->records, c->scratch->gather, bytes);
        root->key = *key;
        root->count = count;
        root->flags = flags;
        root->has_children = has_children;
        return STA_OK;
    }
    return c->sink->emit(c->sink->context, c->worker, key, c->scratch->gather, count, flags, err);
}

// Builds the subtree of `key` over order[begin, end); uses spare[begin, end).
static sta_status build(build_context *c, const sta_node_key *key, size_t begin, size_t end,
                        sta_error *err)
{
    sta_index_scratch *s = c->scratch;
    const size_t count = end - begin;
    uint32_t *order = s->order + begin;
    if (count <= c->leaf_capacity || key->level >= c->space->max_level ||
        all_identical(c->layout, c->records, order, count)) {
        return hand_over(c, key, order, count, STA_NODE_UNGRIDDED, 0, err);
    }

    // Bucket 0 keeps the first point of each empty cell; buckets 1..8 are the octants.
    size_t bucket_count[9] = { 0 };
    uint8_t *labels = s->labels + begin;
    uint32_t *spare = s->spare + begin;
    int32_t p[3];
    for (size_t i = 0; i < count; i++) {
        sta_record_position(c->records + (size_t)order[i] * c->layout->size, p);
        uint32_t cell = sta_node_cell(c->space, key, p);
        int bucket = test_and_set(s->cell_bits, cell) ? 1 + sta_node_octant(c->space, key, p) : 0;
        labels[i] = (uint8_t)bucket;
        bucket_count[bucket]++;
    }
    size_t bucket_start[9];
    size_t running = 0;
    for (int b = 0; b < 9; b++) {
        bucket_start[b] = running;
        running += bucket_count[b];
    }
    // Clear the marks (only kept points set one) and partition stably by bucket.
    size_t fill[9];
    memcpy(fill, bucket_start, sizeof(fill));
    for (size_t i = 0; i < count; i++) {
        if (labels[i] == 0) {
            sta_record_position(c->records + (size_t)order[i] * c->layout->size, p);
            uint32_t cell = sta_node_cell(c->space, key, p);
            s->cell_bits[cell >> 6] &= ~((uint64_t)1 << (cell & 63));
        }
        spare[fill[labels[i]]++] = order[i];
    }
    memcpy(order, spare, count * sizeof(uint32_t));

    // When only a few points would go down, children would be tiny nodes (costly to
    // store, select and draw): keep everything here as a leaf bucket instead.
    size_t pushed_down = count - bucket_count[0];
    if (pushed_down > 0 && pushed_down <= c->leaf_capacity / 16) {
        return hand_over(c, key, order, count, STA_NODE_UNGRIDDED, 0, err);
    }
    int has_children = pushed_down > 0;
    sta_status status = hand_over(c, key, order, bucket_count[0], 0, has_children, err);
    for (int b = 1; b < 9 && status == STA_OK; b++) {
        if (bucket_count[b] > 0) {
            sta_node_key child = sta_node_child(key, b - 1);
            status = build(c, &child, begin + bucket_start[b],
                           begin + bucket_start[b] + bucket_count[b], err);
        }
    }
    return status;
}

sta_status sta_index_chunk(const sta_octree_space *space, const sta_record_layout *layout,
                           const sta_node_key *chunk_key, const uint8_t *records, size_t count,
                           size_t leaf_capacity, int worker, const sta_node_sink *sink,
                           sta_index_scratch *scratch, sta_pending_node *out_root, sta_error *err)
{
    memset(out_root, 0, sizeof(*out_root));
    out_root->key = *chunk_key;
    if (count == 0) {
        return STA_OK;
    }
    if (count > UINT32_MAX) {
        return sta_fail(err, STA_ERR_ARG, "chunk of %zu points is too large to index", count);
    }
    sta_status status = reserve(scratch, space, count, err);
    if (status != STA_OK) {
        return status;
    }
    for (size_t i = 0; i < count; i++) {
        scratch->order[i] = (uint32_t)i;
    }
    build_context c = { space, layout,  records,  leaf_capacity, worker,
                        sink,  scratch, out_root, chunk_key };
    status = build(&c, chunk_key, 0, count, err);
    if (status != STA_OK) {
        sta_free(out_root->records);
        out_root->records = NULL;
        out_root->count = 0;
    }
    return status;
}

sta_status sta_index_merge_parent(const sta_octree_space *space, const sta_record_layout *layout,
                                  sta_pending_node *children, size_t child_count,
                                  sta_index_scratch *scratch, sta_pending_node *out_parent,
                                  sta_error *err)
{
    memset(out_parent, 0, sizeof(*out_parent));
    out_parent->key = sta_node_parent(&children[0].key);
    out_parent->has_children = 1;
    size_t total = 0;
    for (size_t i = 0; i < child_count; i++) {
        total += children[i].count;
    }
    sta_status status = reserve(scratch, space, 1, err);
    if (status != STA_OK) {
        return status;
    }
    const size_t rec = layout->size;
    uint8_t *parent = sta_malloc(total * rec);
    if (!parent) {
        return sta_fail(err, STA_ERR_NOMEM, "out of memory merging %zu points", total);
    }
    size_t taken = 0;
    int32_t p[3];
    for (size_t i = 0; i < child_count; i++) {
        sta_pending_node *child = &children[i];
        size_t kept = 0;
        for (size_t j = 0; j < child->count; j++) {
            const uint8_t *r = child->records + j * rec;
            sta_record_position(r, p);
            uint32_t cell = sta_node_cell(space, &out_parent->key, p);
            if (!test_and_set(scratch->cell_bits, cell)) {
                memcpy(parent + taken * rec, r, rec);
                taken++;
            } else {
                memmove(child->records + kept * rec, r, rec);
                kept++;
            }
        }
        child->count = kept;
    }
    // Clear the marks: exactly the cells of the points moved up.
    for (size_t j = 0; j < taken; j++) {
        sta_record_position(parent + j * rec, p);
        uint32_t cell = sta_node_cell(space, &out_parent->key, p);
        scratch->cell_bits[cell >> 6] &= ~((uint64_t)1 << (cell & 63));
    }
    out_parent->records = parent;
    out_parent->count = taken;
    return STA_OK;
}
