/* SPDX-License-Identifier: MIT
 * Node payloads into the .strata writer, and the node table.
 *
 * Lock order: commit_lock, then nw->lock (the strata writer has its own, never held
 * together with either); see node_writer.h for the ordered commit of chunk batches.
 */
#include "node_writer.h"

#include <stdlib.h>
#include <string.h>

#include "core/alloc.h"
#include "core/array.h"
#include "format/strata.h"

static sta_strata_key to_strata_key(const sta_node_key *k)
{
    sta_strata_key s = { k->level, k->x, k->y, k->z };
    return s;
}

static sta_status append_node(sta_node_writer *nw, const sta_strata_node *node, size_t raw,
                              sta_error *err)
{
    sta_status status = STA_OK;
    pthread_mutex_lock(&nw->lock);
    if (sta_array_reserve((void **)&nw->nodes, &nw->node_capacity, nw->node_count + 1,
                          sizeof(*nw->nodes), 1024, NULL) != STA_OK) {
        status = sta_fail(err, STA_ERR_NOMEM, "out of memory for the node table");
    }
    if (status == STA_OK) {
        nw->nodes[nw->node_count++] = *node;
        nw->raw_bytes += raw;
        nw->stored_bytes += node->payload.stored_size;
        nw->point_count += node->point_count;
    }
    pthread_mutex_unlock(&nw->lock);
    return status;
}

static sta_status emit(void *context, int worker_index, const sta_node_key *key,
                       const uint8_t *records, size_t count, unsigned flags, sta_error *err)
{
    sta_node_writer *nw = context;
    sta_node_worker *w = &nw->workers[worker_index];
    size_t bytes = count * nw->column_record_size;
    if (sta_array_reserve((void **)&w->columns, &w->capacity, bytes, 1, 0, NULL) != STA_OK) {
        return sta_fail(err, STA_ERR_NOMEM, "out of memory for a node of %zu points", count);
    }
    sta_strata_node node;
    memset(&node, 0, sizeof(node));
    node.key = to_strata_key(key);
    node.flags = (flags & STA_NODE_UNGRIDDED) ? STA_STRATA_NODE_OVERFLOW : 0;
    node.point_count = count;
    // Columns straight from the packed records: no unpacking into sta_point.
    int64_t corner[3], size[3];
    sta_strata_node_grid_bounds(nw->geometry, node.key, corner, size);
    if (!sta_record_encode_columns(nw->layout, records, count, corner, nw->extra_dim_sizes,
                                   nw->extra_dim_count, w->columns)) {
        return sta_fail(err, STA_ERR_ARG, "internal error: a point of %s lies outside it",
                        "a node");
    }
    if (w->batch) {
        // Index phase: packed into the chunk's batch, placed in the file in chunk order.
        sta_node_batch *b = w->batch;
        if (sta_array_reserve((void **)&b->nodes, &b->node_capacity, b->node_count + 1,
                              sizeof(*b->nodes), 64, NULL) != STA_OK) {
            return sta_fail(err, STA_ERR_NOMEM, "out of memory for the node table");
        }
        sta_status status = sta_strata_writer_pack_node(
            nw->writer, w->encoder, node.key, w->columns, count, &b->payloads, &node.payload, err);
        if (status == STA_OK) {
            b->nodes[b->node_count++] = node;
        }
        return status;
    }
    sta_status status = sta_strata_writer_add_node(nw->writer, w->encoder, node.key, w->columns,
                                                   count, &node.payload, err);
    if (status != STA_OK) {
        return status;
    }
    return append_node(nw, &node, (size_t)node.payload.raw_size, err);
}

static void batch_destroy(sta_node_batch *b)
{
    if (b) {
        sta_strata_batch_release(&b->payloads);
        sta_free(b->nodes);
        sta_free(b);
    }
}

// Writes one batch and adds its nodes to the table with their file offsets.
static sta_status write_batch(sta_node_writer *nw, sta_node_batch *b, sta_error *err)
{
    uint64_t base = 0;
    sta_status status = sta_strata_writer_add_batch(nw->writer, &b->payloads, &base, err);
    for (size_t i = 0; i < b->node_count && status == STA_OK; i++) {
        sta_strata_node *node = &b->nodes[i];
        if (node->payload.stored_size > 0) {
            node->payload.offset += base;
        }
        status = append_node(nw, node, (size_t)node->payload.raw_size, err);
    }
    return status;
}

sta_status sta_node_writer_plan_chunks(sta_node_writer *nw, size_t chunk_count, sta_error *err)
{
    nw->pending = sta_calloc(chunk_count ? chunk_count : 1, sizeof(*nw->pending));
    if (!nw->pending) {
        return sta_fail(err, STA_ERR_NOMEM, "out of memory for %zu chunks", chunk_count);
    }
    nw->chunk_count = chunk_count;
    nw->committed = 0;
    nw->window = 2 * (size_t)nw->worker_count + 2;
    return STA_OK;
}

sta_status sta_node_writer_begin_chunk(sta_node_writer *nw, int worker, size_t order,
                                       sta_error *err)
{
    sta_node_batch *b = sta_calloc(1, sizeof(*b));
    if (!b) {
        return sta_fail(err, STA_ERR_NOMEM, "out of memory");
    }
    pthread_mutex_lock(&nw->commit_lock);
    while (!nw->aborted && order >= nw->committed + nw->window) {
        pthread_cond_wait(&nw->committed_cv, &nw->commit_lock);
    }
    bool aborted = nw->aborted;
    pthread_mutex_unlock(&nw->commit_lock);
    if (aborted) {
        sta_free(b);
        return sta_fail(err, STA_ERR_CANCELLED, "cancelled");
    }
    nw->workers[worker].batch = b;
    nw->workers[worker].order = order;
    return STA_OK;
}

sta_status sta_node_writer_end_chunk(sta_node_writer *nw, int worker, sta_error *err)
{
    sta_node_worker *w = &nw->workers[worker];
    sta_node_batch *mine = w->batch;
    w->batch = NULL;
    sta_status status = STA_OK;
    pthread_mutex_lock(&nw->commit_lock);
    nw->pending[w->order] = mine;
    if (nw->committing) {
        pthread_mutex_unlock(&nw->commit_lock);
        return STA_OK; // the thread writing now also writes this one when its turn comes
    }
    nw->committing = true;
    while (status == STA_OK && nw->committed < nw->chunk_count && nw->pending[nw->committed]) {
        sta_node_batch *next = nw->pending[nw->committed];
        nw->pending[nw->committed] = NULL;
        pthread_mutex_unlock(&nw->commit_lock); // no I/O under the lock
        status = write_batch(nw, next, err);
        batch_destroy(next);
        pthread_mutex_lock(&nw->commit_lock);
        if (status == STA_OK) {
            nw->committed++;
        } else {
            nw->aborted = true;
        }
        pthread_cond_broadcast(&nw->committed_cv);
    }
    nw->committing = false;
    pthread_mutex_unlock(&nw->commit_lock);
    return status;
}

void sta_node_writer_abort(sta_node_writer *nw)
{
    pthread_mutex_lock(&nw->commit_lock);
    nw->aborted = true;
    pthread_cond_broadcast(&nw->committed_cv);
    pthread_mutex_unlock(&nw->commit_lock);
}

bool sta_node_writer_all_committed(sta_node_writer *nw)
{
    pthread_mutex_lock(&nw->commit_lock);
    bool all = nw->committed == nw->chunk_count;
    pthread_mutex_unlock(&nw->commit_lock);
    return all;
}

sta_status sta_node_writer_add_empty(sta_node_writer *nw, const sta_node_key *key, sta_error *err)
{
    // An empty payload still gets its descriptor (checksum of no bytes) from the writer.
    sta_strata_node node;
    memset(&node, 0, sizeof(node));
    node.key = to_strata_key(key);
    sta_status status = sta_strata_writer_add_points(nw->writer, nw->workers[0].encoder, node.key,
                                                     NULL, NULL, 0, &node.payload, err);
    if (status != STA_OK) {
        return status;
    }
    return append_node(nw, &node, 0, err);
}

sta_node_sink sta_node_writer_sink(sta_node_writer *nw)
{
    sta_node_sink sink = { emit, nw };
    return sink;
}

sta_status sta_node_writer_init(sta_node_writer *nw, sta_strata_writer *writer,
                                const sta_record_layout *layout,
                                const sta_strata_layout *strata_layout,
                                const sta_strata_geometry *geometry, int worker_count,
                                sta_error *err)
{
    memset(nw, 0, sizeof(*nw));
    nw->writer = writer;
    nw->layout = layout;
    nw->geometry = geometry;
    nw->column_record_size = strata_layout->record_size;
    nw->extra_dim_count = strata_layout->extra_dim_count;
    for (uint32_t d = 0; d < strata_layout->extra_dim_count; d++) {
        nw->extra_dim_sizes[d] = strata_layout->extra_dims[d].size_bytes;
    }
    nw->workers = sta_calloc((size_t)worker_count, sizeof(*nw->workers));
    if (!nw->workers) {
        return sta_fail(err, STA_ERR_NOMEM, "out of memory for %d workers", worker_count);
    }
    nw->worker_count = worker_count;
    pthread_mutex_init(&nw->lock, NULL);
    pthread_mutex_init(&nw->commit_lock, NULL);
    pthread_cond_init(&nw->committed_cv, NULL);
    for (int i = 0; i < worker_count; i++) {
        sta_status status = sta_strata_encoder_create(&nw->workers[i].encoder, err);
        if (status != STA_OK) {
            sta_node_writer_release(nw);
            return status;
        }
    }
    return STA_OK;
}

void sta_node_writer_release(sta_node_writer *nw)
{
    if (!nw->workers) {
        return;
    }
    for (int i = 0; i < nw->worker_count; i++) {
        sta_strata_encoder_destroy(nw->workers[i].encoder);
        sta_free(nw->workers[i].columns);
        batch_destroy(nw->workers[i].batch);
    }
    for (size_t i = 0; nw->pending && i < nw->chunk_count; i++) {
        batch_destroy(nw->pending[i]);
    }
    sta_free(nw->pending);
    sta_free(nw->workers);
    sta_free(nw->nodes);
    pthread_mutex_destroy(&nw->lock);
    pthread_mutex_destroy(&nw->commit_lock);
    pthread_cond_destroy(&nw->committed_cv);
    memset(nw, 0, sizeof(*nw));
}

static int compare_nodes(const void *a, const void *b)
{
    const sta_strata_key *x = &((const sta_strata_node *)a)->key;
    const sta_strata_key *y = &((const sta_strata_node *)b)->key;
    sta_node_key kx = { x->x, x->y, x->z, x->level };
    sta_node_key ky = { y->x, y->y, y->z, y->level };
    return sta_node_key_compare(&kx, &ky);
}

// Index of the node with `key` in the sorted table, or -1.
static long find_node(const sta_strata_node *nodes, size_t count, const sta_strata_key *key)
{
    sta_strata_node probe;
    memset(&probe, 0, sizeof(probe));
    probe.key = *key;
    const sta_strata_node *hit = bsearch(&probe, nodes, count, sizeof(*nodes), compare_nodes);
    return hit ? (long)(hit - nodes) : -1;
}

sta_status sta_node_writer_finish(sta_node_writer *nw, uint32_t *out_node_count, int *out_max_level,
                                  sta_error *err)
{
    sta_strata_node *nodes = nw->nodes;
    size_t count = nw->node_count;
    if (count == 0 || count > UINT32_MAX) {
        return sta_fail(err, STA_ERR_ARG, "cannot write a tree of %zu nodes", count);
    }
    qsort(nodes, count, sizeof(*nodes), compare_nodes);
    // Children of one parent are adjacent in this order and in slot order: link them.
    int max_level = 0;
    for (size_t i = 1; i < count; i++) {
        const sta_strata_key *k = &nodes[i].key;
        max_level = k->level > max_level ? k->level : max_level;
        sta_strata_key parent_key = { (uint8_t)(k->level - 1), k->x >> 1, k->y >> 1, k->z >> 1 };
        long parent = find_node(nodes, count, &parent_key);
        if (parent < 0) {
            char label[64];
            return sta_fail(err, STA_ERR_ARG, "internal error: %s has no parent",
                            sta_strata_node_label(label, sizeof(label), (uint32_t)i, *k));
        }
        int slot = (int)((k->x & 1) | ((k->y & 1) << 1) | ((k->z & 1) << 2));
        if (nodes[parent].child_mask == 0) {
            nodes[parent].first_child = (uint32_t)i;
        }
        nodes[parent].child_mask |= (uint8_t)(1u << slot);
    }
    *out_node_count = (uint32_t)count;
    *out_max_level = max_level;
    return sta_strata_writer_finish(nw->writer, nodes, count, err);
}
