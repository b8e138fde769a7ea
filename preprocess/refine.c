/* SPDX-License-Identifier: MIT
 * Out-of-core splitting of oversized chunks.
 *
 * Design: for a chunk at level L, records are streamed twice from its run list, block
 * by block: once to count them on the chunk's sub-grid at level L + 3 (512 cells),
 * once to copy each into its sub-chunk's buffer, appended as blocks to the
 * sub-chunk's new run list (in order). The chunk's list is then discarded (its disk
 * space punched out), so a dense scene re-split several times, or one stray point
 * that crowds every other point into one chunk, never holds a record twice.
 * Sub-chunks are cut from the counts top-down as in distribute.c. A sub-chunk that is
 * still too large is split again in a later round, one level finer each time, so the
 * loop ends at the deepest level at the latest.
 */
#include "refine.h"

#include <errno.h>
#include <string.h>
#include <unistd.h>

#include "core/alloc.h"
#include "core/file_io.h"

enum {
    SUB_LEVELS = 3,
    SUB_CELLS = 1 << (3 * SUB_LEVELS)
};

// Sub-cell (0..SUB_CELLS-1) of a position inside chunk `key` at `depth` levels below.
static uint32_t sub_cell(const sta_octree_space *s, const sta_node_key *key, int depth,
                         const int32_t xyz[3])
{
    uint32_t c[3];
    for (int a = 0; a < 3; a++) {
        int64_t rel = (int64_t)xyz[a] - sta_node_min(s, key, a);
        c[a] = (uint32_t)(rel >> (sta_node_side_log2(s, key->level, a) - depth));
    }
    return (c[2] << (2 * depth)) | (c[1] << depth) | c[0];
}

typedef struct sub_chunk {
    sta_node_key key;
    uint64_t count;
    size_t list;      /* its run list */
    uint64_t written; /* records written so far */
    size_t used;      /* bytes in its buffer */
} sub_chunk;

// Cuts the sub-grid counts of `parent` into sub-chunks; returns how many.
static size_t cut(const sta_node_key *parent, int depth, const uint64_t *counts, uint64_t capacity,
                  sub_chunk *out, int16_t *chunk_of_cell)
{
    size_t n = 0;
    sta_node_key stack[8 * SUB_LEVELS + 8];
    int stack_depth[8 * SUB_LEVELS + 8];
    size_t top = 0;
    stack[top] = *parent;
    stack_depth[top++] = 0;
    while (top > 0) {
        top--;
        sta_node_key k = stack[top];
        int d = stack_depth[top];
        // Cells of the sub-grid covered by k: a cube of 2^(depth - d) per axis.
        int span_log2 = depth - d;
        uint32_t ox = (k.x - (parent->x << d)) << span_log2;
        uint32_t oy = (k.y - (parent->y << d)) << span_log2;
        uint32_t oz = (k.z - (parent->z << d)) << span_log2;
        uint32_t span = 1u << span_log2;
        uint64_t sum = 0;
        for (uint32_t z = 0; z < span; z++) {
            for (uint32_t y = 0; y < span; y++) {
                for (uint32_t x = 0; x < span; x++) {
                    sum += counts[((oz + z) << (2 * depth)) | ((oy + y) << depth) | (ox + x)];
                }
            }
        }
        if (sum == 0) {
            continue;
        }
        if (sum <= capacity || d == depth) {
            memset(&out[n], 0, sizeof(out[n]));
            out[n].key = k;
            out[n].count = sum;
            for (uint32_t z = 0; z < span; z++) {
                for (uint32_t y = 0; y < span; y++) {
                    for (uint32_t x = 0; x < span; x++) {
                        chunk_of_cell[((oz + z) << (2 * depth)) | ((oy + y) << depth) | (ox + x)] =
                            (int16_t)n;
                    }
                }
            }
            n++;
            continue;
        }
        for (int o = 7; o >= 0; o--) {
            stack[top] = sta_node_child(&k, o);
            stack_depth[top++] = d + 1;
        }
    }
    return n;
}

static sta_status split_one(const sta_chunk_plan *plan, const sta_chunk *chunk,
                            const sta_record_layout *layout, sta_temp_runs *runs,
                            sta_run_codec *codec, uint64_t capacity, uint8_t *batch, uint8_t *arena,
                            size_t per_sub, uint64_t *sequence, sub_chunk *subs,
                            size_t *out_sub_count, sta_error *err)
{
    const size_t rec = layout->size;
    int depth = plan->space.max_level - chunk->key.level;
    depth = depth > SUB_LEVELS ? SUB_LEVELS : depth;
    uint64_t counts[SUB_CELLS];
    int16_t chunk_of_cell[SUB_CELLS];
    memset(counts, 0, sizeof(counts));
    int32_t xyz[3];
    sta_temp_runs_sort(runs, chunk->list);
    for (int pass = 0; pass < 2; pass++) {
        size_t blocks = runs->lists[chunk->list].block_count;
        for (size_t k = 0; k < blocks; k++) {
            size_t n = runs->lists[chunk->list].blocks[k].count;
            sta_status status = sta_temp_runs_read_block(runs, codec, chunk->list, k, batch, err);
            if (status != STA_OK) {
                return status;
            }
            for (size_t i = 0; i < n; i++) {
                sta_record_position(batch + i * rec, xyz);
                uint32_t cell = sub_cell(&plan->space, &chunk->key, depth, xyz);
                if (pass == 0) {
                    counts[cell]++;
                    continue;
                }
                sub_chunk *s = &subs[chunk_of_cell[cell]];
                uint8_t *buffer = arena + (size_t)chunk_of_cell[cell] * per_sub;
                memcpy(buffer + s->used, batch + i * rec, rec);
                s->used += rec;
                if (s->used == per_sub) {
                    status = sta_temp_runs_append(runs, codec, s->list, (*sequence)++, buffer,
                                                  s->used / rec, err);
                    if (status != STA_OK) {
                        return status;
                    }
                    s->written += s->used / rec;
                    s->used = 0;
                }
            }
            if (pass == 1) {
                // Read for the last time: its disk goes as its records move on, so the
                // split never holds the chunk twice.
                sta_temp_runs_discard_block(runs, chunk->list, k);
            }
        }
        if (pass == 0) {
            *out_sub_count = cut(&chunk->key, depth, counts, capacity, subs, chunk_of_cell);
            if (*out_sub_count == 1 && subs[0].count == chunk->count) {
                // Every record in one sub-cell (a stray point made the root huge): the
                // records stay where they are, only the chunk's key moves down.
                subs[0].list = chunk->list;
                return STA_OK;
            }
            size_t first = 0;
            sta_status status = sta_temp_runs_add_lists(runs, *out_sub_count, &first, err);
            if (status != STA_OK) {
                return status;
            }
            for (size_t s = 0; s < *out_sub_count; s++) {
                subs[s].list = first + s;
            }
        }
    }
    for (size_t s = 0; s < *out_sub_count; s++) {
        uint8_t *buffer = arena + s * per_sub;
        sta_status status = sta_temp_runs_append(runs, codec, subs[s].list, (*sequence)++, buffer,
                                                 subs[s].used / rec, err);
        if (status != STA_OK) {
            return status;
        }
    }
    sta_temp_runs_discard(runs, chunk->list);
    return STA_OK;
}

sta_status sta_refine_chunks(sta_chunk_plan *plan, const sta_record_layout *layout,
                             sta_temp_runs *runs, uint64_t chunk_capacity, size_t buffer_bytes,
                             sta_error *err)
{
    const size_t rec = layout->size;
    size_t per_sub = buffer_bytes / 2 / SUB_CELLS;
    per_sub = per_sub > STA_TEMP_RUNS_MAX_BLOCK_BYTES ? STA_TEMP_RUNS_MAX_BLOCK_BYTES : per_sub;
    per_sub = per_sub < STA_TEMP_RUNS_MIN_BLOCK_BYTES ? STA_TEMP_RUNS_MIN_BLOCK_BYTES : per_sub;
    per_sub -= per_sub % rec;
    uint8_t *batch = sta_malloc(STA_TEMP_RUNS_MAX_BLOCK_BYTES + rec);
    uint8_t *arena = sta_alloc_array(SUB_CELLS, per_sub);
    sub_chunk *subs = sta_alloc_array(SUB_CELLS, sizeof(*subs));
    sta_run_codec codec = { 0 };
    uint64_t sequence = 0;
    sta_status status = STA_OK;
    if (!batch || !arena || !subs) {
        status = sta_fail(err, STA_ERR_NOMEM, "out of memory splitting large chunks");
    }
    for (size_t c = 0; c < plan->chunk_count && status == STA_OK;) {
        sta_chunk chunk = plan->chunks[c];
        if (chunk.count <= chunk_capacity || chunk.key.level >= plan->space.max_level) {
            c++;
            continue;
        }
        size_t sub_count = 0;
        memset(subs, 0, SUB_CELLS * sizeof(*subs));
        status = split_one(plan, &chunk, layout, runs, &codec, chunk_capacity, batch, arena,
                           per_sub, &sequence, subs, &sub_count, err);
        if (status != STA_OK) {
            break;
        }
        // Replace the chunk by its sub-chunks (appended; this index gets the last).
        size_t total = plan->chunk_count - 1 + sub_count;
        sta_chunk *grown = sta_realloc_array(plan->chunks, total, sizeof(*grown));
        if (!grown) {
            status = sta_fail(err, STA_ERR_NOMEM, "out of memory splitting large chunks");
            break;
        }
        plan->chunks = grown;
        plan->chunks[c] = plan->chunks[plan->chunk_count - 1];
        plan->chunk_count--;
        for (size_t s = 0; s < sub_count; s++) {
            sta_chunk *n = &plan->chunks[plan->chunk_count++];
            n->key = subs[s].key;
            n->count = subs[s].count;
            n->first = 0;
            n->list = subs[s].list;
        }
        // Do not advance: slot c now holds another chunk that may need splitting.
    }
    sta_run_codec_release(&codec);
    sta_free(batch);
    sta_free(arena);
    sta_free(subs);
    return status;
}
