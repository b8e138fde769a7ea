/* SPDX-License-Identifier: MIT
 * In-memory nested octree of one chunk.
 *
 * Design: records are never moved; an array of (position, record index) items is
 * partitioned instead, node by node, depth first, so the hot loop reads positions
 * sequentially. A node's "stay" points (first in each empty cell) are gathered
 * into a contiguous buffer and emitted; the others are split by octant into the
 * children's ranges. The cell bitmap is cleared by visiting the set cells again, so
 * a node costs O(its points), not O(cells).
 */
#include "index.h"

#include <stdbool.h>
#include <string.h>

#include "core/alloc.h"

void sta_index_scratch_release(sta_index_scratch *scratch)
{
    sta_free(scratch->cell_bits);
    sta_free(scratch->items);
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
    return cell_words_for(space) * 8 + count * (2 * sizeof(sta_index_item) + 1) +
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
        sta_free(s->items);
        sta_free(s->spare);
        sta_free(s->labels);
        s->items = sta_alloc_array(count, sizeof(sta_index_item));
        s->spare = sta_alloc_array(count, sizeof(sta_index_item));
        s->labels = sta_malloc(count);
        s->order_capacity = s->items && s->spare && s->labels ? count : 0;
        if (!s->order_capacity) {
            return sta_fail(err, STA_ERR_NOMEM, "out of memory indexing %zu points", count);
        }
    }
    return STA_OK;
}

static sta_status gather(sta_index_scratch *s, const sta_record_layout *layout,
                         const uint8_t *records, const sta_index_item *items, size_t count,
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
    // Word copies instead of a memcpy call per record (records are at least 12 bytes:
    // the position); the last word overlaps the one before when the size is not a
    // multiple of 8. A call per record was 6 % of a conversion's CPU.
    const size_t rec = layout->size;
    uint8_t *out = s->gather;
    for (size_t i = 0; i < count; i++, out += rec) {
        const uint8_t *in = records + (size_t)items[i].index * rec;
        size_t k = 0;
        for (; k + 8 < rec; k += 8) {
            uint64_t w;
            memcpy(&w, in + k, 8);
            memcpy(out + k, &w, 8);
        }
        uint64_t w;
        memcpy(&w, in + rec - 8, 8);
        memcpy(out + rec - 8, &w, 8);
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

// Labels each item with its bucket (0: first point of an empty cell, marked in
// `bits`, its cell kept in the item; 1 + octant: pushed down) and counts the buckets.
// For nodes of at least one grid unit per cell on every axis (cell_shift >= 0): the
// octant is then the top bit of each cell coordinate.
static void classify_coarse(uint64_t *bits, int g, const int64_t node_min[3],
                            const int cell_shift[3], sta_index_item *items, size_t count,
                            uint8_t *labels, size_t bucket_count[9])
{
    const int64_t m0 = node_min[0], m1 = node_min[1], m2 = node_min[2];
    const int s0 = cell_shift[0], s1 = cell_shift[1], s2 = cell_shift[2];
    const int top = g - 1;
    for (size_t i = 0; i < count; i++) {
        uint32_t cx = (uint32_t)((uint64_t)((int64_t)items[i].xyz[0] - m0) >> s0);
        uint32_t cy = (uint32_t)((uint64_t)((int64_t)items[i].xyz[1] - m1) >> s1);
        uint32_t cz = (uint32_t)((uint64_t)((int64_t)items[i].xyz[2] - m2) >> s2);
        uint32_t cell = (((cx << g) | cy) << g) | cz;
        uint32_t octant = (cx >> top) | ((cy >> top) << 1) | ((cz >> top) << 2);
        uint64_t mask = (uint64_t)1 << (cell & 63);
        uint64_t word = bits[cell >> 6];
        bits[cell >> 6] = word | mask;
        int bucket = (word & mask) ? 1 + (int)octant : 0;
        labels[i] = (uint8_t)bucket;
        bucket_count[bucket]++;
        items[i].cell = cell; // used (to clear the mark) only for bucket 0
    }
}

// The same for any node (cells finer than a grid unit on some axis: deep levels of
// flat or thin scenes).
static void classify_fine(uint64_t *bits, int g, const int64_t node_min[3], const int cell_shift[3],
                          const int half_shift[3], sta_index_item *items, size_t count,
                          uint8_t *labels, size_t bucket_count[9])
{
    for (size_t i = 0; i < count; i++) {
        uint32_t cell = 0;
        int octant = 0;
        for (int a = 0; a < 3; a++) {
            uint64_t rel = (uint64_t)((int64_t)items[i].xyz[a] - node_min[a]);
            uint32_t ca = cell_shift[a] >= 0 ? (uint32_t)(rel >> cell_shift[a])
                                             : (uint32_t)(rel << -cell_shift[a]);
            cell = (cell << g) | ca;
            octant |= (int)((rel >> half_shift[a]) & 1) << a;
        }
        int bucket = test_and_set(bits, cell) ? 1 + octant : 0;
        labels[i] = (uint8_t)bucket;
        bucket_count[bucket]++;
        items[i].cell = cell;
    }
}

static bool all_identical(const sta_index_item *items, size_t count)
{
    for (size_t i = 1; i < count; i++) {
        if (items[i].xyz[0] != items[0].xyz[0] || items[i].xyz[1] != items[0].xyz[1] ||
            items[i].xyz[2] != items[0].xyz[2]) {
            return false;
        }
    }
    return true;
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

static sta_status hand_over(build_context *c, const sta_node_key *key, const sta_index_item *items,
                            size_t count, unsigned flags, int has_children, sta_error *err)
{
    sta_status status = gather(c->scratch, c->layout, c->records, items, count, err);
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

// Builds the subtree of `key` over [begin, end) of one of the two item buffers
// (`in_spare` says which); the partition goes into the other one, so the buffers swap
// roles level by level instead of copying back.
static sta_status build(build_context *c, const sta_node_key *key, size_t begin, size_t end,
                        bool in_spare, sta_error *err)
{
    sta_index_scratch *s = c->scratch;
    const size_t count = end - begin;
    sta_index_item *items = (in_spare ? s->spare : s->items) + begin;
    if (count <= c->leaf_capacity || key->level >= c->space->max_level) {
        return hand_over(c, key, items, count, STA_NODE_UNGRIDDED, 0, err);
    }
    // Per-axis integer geometry of this node, hoisted out of the point loop.
    const int g = c->space->grid_log2;
    int64_t node_min[3];
    int cell_shift[3], half_shift[3];
    for (int a = 0; a < 3; a++) {
        node_min[a] = sta_node_min(c->space, key, a);
        int side = sta_node_side_log2(c->space, key->level, a);
        cell_shift[a] = side - g;
        half_shift[a] = side - 1;
    }

    // Bucket 0 keeps the first point of each empty cell; buckets 1..8 are the octants.
    size_t bucket_count[9] = { 0 };
    uint8_t *labels = s->labels + begin;
    sta_index_item *spare = (in_spare ? s->items : s->spare) + begin;
    if (cell_shift[0] >= 0 && cell_shift[1] >= 0 && cell_shift[2] >= 0) {
        classify_coarse(s->cell_bits, g, node_min, cell_shift, items, count, labels, bucket_count);
    } else {
        classify_fine(s->cell_bits, g, node_min, cell_shift, half_shift, items, count, labels,
                      bucket_count);
    }
    size_t bucket_start[9];
    size_t running = 0;
    for (int b = 0; b < 9; b++) {
        bucket_start[b] = running;
        running += bucket_count[b];
    }
    // Partition stably by bucket, then clear the marks: exactly the cells of the kept
    // points, now the first bucket_count[0] items (no branch per point).
    size_t fill[9];
    memcpy(fill, bucket_start, sizeof(fill));
    for (size_t i = 0; i < count; i++) {
        spare[fill[labels[i]]++] = items[i];
    }
    for (size_t i = 0; i < bucket_count[0]; i++) {
        uint32_t cell = spare[i].cell;
        s->cell_bits[cell >> 6] &= ~((uint64_t)1 << (cell & 63));
    }
    items = spare; // the partitioned order; children continue from this buffer

    // All points identical (exact duplicates): they stop splitting. Identical points
    // share one cell, so only a node with one kept point can be one. And when only a
    // few points would go down, children would be tiny nodes (costly to store, select
    // and draw): keep everything here as a leaf bucket instead.
    bool identical = bucket_count[0] == 1 && all_identical(items, count);
    size_t pushed_down = count - bucket_count[0];
    if (identical || (pushed_down > 0 && pushed_down <= c->leaf_capacity / 16)) {
        return hand_over(c, key, items, count, STA_NODE_UNGRIDDED, 0, err);
    }
    int has_children = pushed_down > 0;
    sta_status status = hand_over(c, key, items, bucket_count[0], 0, has_children, err);
    for (int b = 1; b < 9 && status == STA_OK; b++) {
        if (bucket_count[b] > 0) {
            sta_node_key child = sta_node_child(key, b - 1);
            status = build(c, &child, begin + bucket_start[b],
                           begin + bucket_start[b] + bucket_count[b], !in_spare, err);
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
        scratch->items[i].index = (uint32_t)i;
        sta_record_position(records + i * layout->size, scratch->items[i].xyz);
    }
    build_context c = { space, layout,  records,  leaf_capacity, worker,
                        sink,  scratch, out_root, chunk_key };
    status = build(&c, chunk_key, 0, count, false, err);
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
