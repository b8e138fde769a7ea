/* SPDX-License-Identifier: MIT
 * Counting, chunk planning and distribution into one temporary file.
 *
 * Design: the counting grid is the octree's level min(7, max_level); its cells are
 * summed into a pyramid and cut top-down into chunks (a node becomes a chunk when it
 * holds at most chunk_capacity points or is a counting cell). Chunk regions in the
 * temporary file are laid out by prefix sums, so each point is written exactly where
 * it belongs with buffered pwrite calls.
 */
#include "distribute.h"

#include <errno.h>
#include <string.h>
#include <unistd.h>

#include "core/alloc.h"

enum {
    READ_BATCH_POINTS = 65536,
    MAX_COUNT_LEVEL = 7
};

static size_t cell_index(int level, uint32_t x, uint32_t y, uint32_t z)
{
    return ((size_t)z << (2 * level)) | ((size_t)y << level) | (size_t)x;
}

// Counting cell of a point at `level`, or false when it lies outside the root box.
static bool counting_cell(const sta_octree_space *s, int level, const int32_t xyz[3],
                          size_t *out_cell)
{
    uint32_t c[3];
    for (int a = 0; a < 3; a++) {
        int64_t rel = (int64_t)xyz[a] - s->root_min[a];
        if (rel < 0 || rel >= ((int64_t)1 << s->root_log2[a])) {
            return false;
        }
        c[a] = (uint32_t)(rel >> (s->root_log2[a] - level));
    }
    *out_cell = cell_index(level, c[0], c[1], c[2]);
    return true;
}

static sta_status read_error(const sta_input_set *set, size_t input, sta_point *p, sta_error *err)
{
    const sta_cloud_info *info = sta_cloud_reader_info(set->readers[input]);
    return sta_fail(err, STA_ERR_FORMAT,
                    "%s: point at %d %d %d does not fit the output grid (scale %g)", info->path,
                    p->X, p->Y, p->Z, set->grid.scale[0]);
}

// One counting pass: counts per cell (when `counts` is given) and tight bounds.
// Sets *outside when a point is not inside the root box.
static sta_status count_pass(sta_input_set *set, const sta_octree_space *space, int level,
                             uint64_t *counts, int64_t min[3], int64_t max[3], bool *outside,
                             sta_progress *progress, atomic_bool *cancel, sta_error *err)
{
    *outside = false;
    for (int a = 0; a < 3; a++) {
        min[a] = INT64_MAX;
        max[a] = INT64_MIN;
    }
    sta_status status = STA_OK;
    for (size_t in = 0; in < set->count && status == STA_OK; in++) {
        const sta_cloud_info *info = sta_cloud_reader_info(set->readers[in]);
        sta_point_batch batch;
        status = sta_point_batch_init(&batch, READ_BATCH_POINTS, info->extra_size, err);
        if (status == STA_OK) {
            status = sta_cloud_seek(set->readers[in], 0, err);
        }
        while (status == STA_OK) {
            status = sta_cloud_read(set->readers[in], &batch, err);
            if (status != STA_OK || batch.count == 0) {
                break;
            }
            for (size_t i = 0; i < batch.count; i++) {
                sta_point *p = &batch.points[i];
                if (!sta_inputs_to_output(set, in, p)) {
                    status = read_error(set, in, p, err);
                    break;
                }
                const int32_t xyz[3] = { p->X, p->Y, p->Z };
                for (int a = 0; a < 3; a++) {
                    min[a] = xyz[a] < min[a] ? xyz[a] : min[a];
                    max[a] = xyz[a] > max[a] ? xyz[a] : max[a];
                }
                size_t cell;
                if (!counting_cell(space, level, xyz, &cell)) {
                    *outside = true;
                } else if (counts) {
                    counts[cell]++;
                }
            }
            sta_progress_add(progress, batch.count);
            sta_progress_draw(progress);
            if (cancel && atomic_load(cancel)) {
                status = sta_fail(err, STA_ERR_CANCELLED, "cancelled");
            }
        }
        sta_point_batch_release(&batch);
    }
    return status;
}

// Root box is acceptable when it holds every point and is not much larger than needed.
static bool box_fits(const sta_octree_space *guess, const sta_grid *grid, const int64_t min[3],
                     const int64_t max[3])
{
    sta_octree_space tight;
    if (sta_octree_space_init(&tight, grid, min, max, guess->grid_log2, NULL) != STA_OK) {
        return false;
    }
    for (int a = 0; a < 3; a++) {
        if (guess->root_log2[a] > tight.root_log2[a] + 1) {
            return false;
        }
    }
    return true;
}

static sta_status add_chunk(sta_chunk_plan *plan, size_t *capacity, const sta_node_key *key,
                            uint64_t count, sta_error *err)
{
    if (plan->chunk_count == *capacity) {
        size_t grown = *capacity ? 2 * *capacity : 64;
        sta_chunk *chunks = sta_realloc_array(plan->chunks, grown, sizeof(*chunks));
        if (!chunks) {
            return sta_fail(err, STA_ERR_NOMEM, "out of memory planning chunks");
        }
        plan->chunks = chunks;
        *capacity = grown;
    }
    sta_chunk *c = &plan->chunks[plan->chunk_count++];
    c->key = *key;
    c->count = count;
    c->first = 0;
    return STA_OK;
}

// Pyramid of counts: levels[l] has 8^l cells; levels[count_level] is the counting grid.
static sta_status cut_chunks(sta_chunk_plan *plan, uint64_t **levels, uint64_t chunk_capacity,
                             sta_error *err)
{
    const int top = plan->count_level;
    size_t capacity = 0;
    // Explicit stack of nodes to visit (depth-first; at most 7 * top + 1 entries).
    sta_node_key stack[8 * MAX_COUNT_LEVEL + 8];
    size_t depth = 0;
    stack[depth++] = (sta_node_key){ 0, 0, 0, 0 };
    while (depth > 0) {
        sta_node_key k = stack[--depth];
        uint64_t n = levels[k.level][cell_index(k.level, k.x, k.y, k.z)];
        if (n == 0) {
            continue;
        }
        if (n <= chunk_capacity || k.level == top) {
            sta_status status = add_chunk(plan, &capacity, &k, n, err);
            if (status != STA_OK) {
                return status;
            }
            continue;
        }
        for (int o = 7; o >= 0; o--) {
            stack[depth++] = sta_node_child(&k, o);
        }
    }
    // Regions in the temporary file, and the cell -> chunk map for distribution.
    size_t cells = (size_t)1 << (3 * top);
    plan->chunk_of_cell = sta_alloc_array(cells, sizeof(int32_t));
    if (!plan->chunk_of_cell) {
        return sta_fail(err, STA_ERR_NOMEM, "out of memory for the chunk map");
    }
    for (size_t i = 0; i < cells; i++) {
        plan->chunk_of_cell[i] = -1;
    }
    uint64_t first = 0;
    for (size_t c = 0; c < plan->chunk_count; c++) {
        sta_chunk *chunk = &plan->chunks[c];
        chunk->first = first;
        first += chunk->count;
        int shift = top - chunk->key.level;
        uint32_t span = 1u << shift;
        for (uint32_t z = 0; z < span; z++) {
            for (uint32_t y = 0; y < span; y++) {
                for (uint32_t x = 0; x < span; x++) {
                    size_t cell =
                        cell_index(top, (chunk->key.x << shift) + x, (chunk->key.y << shift) + y,
                                   (chunk->key.z << shift) + z);
                    plan->chunk_of_cell[cell] = (int32_t)c;
                }
            }
        }
    }
    return STA_OK;
}

sta_status sta_distribute_plan(sta_input_set *set, int grid_log2, uint64_t chunk_capacity,
                               sta_progress *progress, atomic_bool *cancel,
                               sta_chunk_plan *out_plan, sta_error *err)
{
    memset(out_plan, 0, sizeof(*out_plan));
    uint64_t *levels[MAX_COUNT_LEVEL + 1] = { 0 };
    sta_status status = STA_OK;

    // First guess of the root box from the declared bounds (when they make sense).
    bool have_guess = set->header_min[0] <= set->header_max[0] &&
                      set->header_min[1] <= set->header_max[1] &&
                      set->header_min[2] <= set->header_max[2];
    sta_octree_space space;
    const int64_t zero[3] = { 0, 0, 0 };
    if (!have_guess || sta_octree_space_init(&space, &set->grid, set->header_min, set->header_max,
                                             grid_log2, NULL) != STA_OK) {
        status = sta_octree_space_init(&space, &set->grid, zero, zero, grid_log2, err);
        if (status != STA_OK) {
            goto out;
        }
    }
    for (int attempt = 0; attempt < 2; attempt++) {
        int level = space.max_level < MAX_COUNT_LEVEL ? space.max_level : MAX_COUNT_LEVEL;
        size_t cells = (size_t)1 << (3 * level);
        sta_free(levels[level]);
        levels[level] = sta_calloc(cells, sizeof(uint64_t));
        if (!levels[level]) {
            status = sta_fail(err, STA_ERR_NOMEM, "out of memory for the counting grid");
            goto out;
        }
        bool outside = false;
        sta_progress_begin(progress, attempt == 0 ? "counting" : "recounting", set->point_count,
                           progress->enabled);
        status = count_pass(set, &space, level, levels[level], out_plan->actual_min,
                            out_plan->actual_max, &outside, progress, cancel, err);
        sta_progress_end(progress);
        if (status != STA_OK) {
            goto out;
        }
        if (set->point_count == 0 || (!outside && box_fits(&space, &set->grid, out_plan->actual_min,
                                                           out_plan->actual_max))) {
            out_plan->count_level = level;
            break;
        }
        // The declared bounds were wrong: use the tight ones and count again.
        status = sta_octree_space_init(&space, &set->grid, out_plan->actual_min,
                                       out_plan->actual_max, grid_log2, err);
        if (status != STA_OK) {
            goto out;
        }
        sta_free(levels[level]);
        levels[level] = NULL;
        if (attempt == 1) {
            status = sta_fail(err, STA_ERR_FORMAT, "inputs changed while being read");
            goto out;
        }
    }
    out_plan->space = space;
    out_plan->point_count = set->point_count;
    if (set->point_count == 0) {
        goto out;
    }
    for (int l = out_plan->count_level - 1; l >= 0; l--) {
        levels[l] = sta_calloc((size_t)1 << (3 * l), sizeof(uint64_t));
        if (!levels[l]) {
            status = sta_fail(err, STA_ERR_NOMEM, "out of memory for the counting pyramid");
            goto out;
        }
        uint32_t n = 1u << (l + 1);
        for (uint32_t z = 0; z < n; z++) {
            for (uint32_t y = 0; y < n; y++) {
                for (uint32_t x = 0; x < n; x++) {
                    levels[l][cell_index(l, x >> 1, y >> 1, z >> 1)] +=
                        levels[l + 1][cell_index(l + 1, x, y, z)];
                }
            }
        }
    }
    status = cut_chunks(out_plan, levels, chunk_capacity, err);
out:
    for (int l = 0; l <= MAX_COUNT_LEVEL; l++) {
        sta_free(levels[l]);
    }
    if (status != STA_OK) {
        sta_chunk_plan_release(out_plan);
    }
    return status;
}

void sta_chunk_plan_release(sta_chunk_plan *plan)
{
    sta_free(plan->chunks);
    sta_free(plan->chunk_of_cell);
    memset(plan, 0, sizeof(*plan));
}

// Buffered writer of one chunk's region.
typedef struct chunk_buffer {
    uint8_t *data;
    size_t used;      /* bytes */
    uint64_t written; /* records already written to the file */
} chunk_buffer;

static sta_status write_all(int fd, const uint8_t *data, size_t size, uint64_t offset,
                            const char *path, sta_error *err)
{
    while (size > 0) {
        ssize_t n = pwrite(fd, data, size, (off_t)offset);
        if (n < 0 && errno == EINTR) {
            continue;
        }
        if (n <= 0) {
            return sta_fail(err, STA_ERR_IO, "%s: cannot write %zu bytes at %llu: %s", path, size,
                            (unsigned long long)offset, n < 0 ? strerror(errno) : "no space");
        }
        data += n;
        size -= (size_t)n;
        offset += (uint64_t)n;
    }
    return STA_OK;
}

static sta_status flush_chunk(int fd, const char *path, const sta_chunk *chunk, chunk_buffer *b,
                              size_t record_size, sta_error *err)
{
    if (b->used == 0) {
        return STA_OK;
    }
    uint64_t offset = (chunk->first + b->written) * record_size;
    sta_status status = write_all(fd, b->data, b->used, offset, path, err);
    b->written += b->used / record_size;
    b->used = 0;
    return status;
}

sta_status sta_distribute_write(sta_input_set *set, const sta_chunk_plan *plan, int fd,
                                const char *tmp_path, size_t buffer_bytes, sta_progress *progress,
                                atomic_bool *cancel, sta_error *err)
{
    const size_t rec = set->layout.size;
    if (plan->chunk_count == 0) {
        return STA_OK;
    }
    if (ftruncate(fd, (off_t)(plan->point_count * rec)) != 0) {
        return sta_fail(err, STA_ERR_IO, "%s: cannot size the temporary file to %llu bytes: %s",
                        tmp_path, (unsigned long long)(plan->point_count * rec), strerror(errno));
    }
    size_t per_chunk = buffer_bytes / plan->chunk_count;
    per_chunk = per_chunk < rec * 16 ? rec * 16 : per_chunk;
    per_chunk -= per_chunk % rec;
    chunk_buffer *buffers = sta_calloc(plan->chunk_count, sizeof(*buffers));
    uint8_t *arena = sta_alloc_array(plan->chunk_count, per_chunk);
    if (!buffers || !arena) {
        sta_free(buffers);
        sta_free(arena);
        return sta_fail(err, STA_ERR_NOMEM, "out of memory for %zu chunk buffers",
                        plan->chunk_count);
    }
    for (size_t c = 0; c < plan->chunk_count; c++) {
        buffers[c].data = arena + c * per_chunk;
    }
    sta_status status = STA_OK;
    for (size_t in = 0; in < set->count && status == STA_OK; in++) {
        const sta_cloud_info *info = sta_cloud_reader_info(set->readers[in]);
        sta_point_batch batch;
        status = sta_point_batch_init(&batch, READ_BATCH_POINTS, info->extra_size, err);
        if (status == STA_OK) {
            status = sta_cloud_seek(set->readers[in], 0, err);
        }
        while (status == STA_OK) {
            status = sta_cloud_read(set->readers[in], &batch, err);
            if (status != STA_OK || batch.count == 0) {
                break;
            }
            for (size_t i = 0; i < batch.count && status == STA_OK; i++) {
                sta_point *p = &batch.points[i];
                bool fits = sta_inputs_to_output(set, in, p);
                const int32_t xyz[3] = { p->X, p->Y, p->Z };
                size_t cell;
                if (!fits || !counting_cell(&plan->space, plan->count_level, xyz, &cell) ||
                    plan->chunk_of_cell[cell] < 0) {
                    status =
                        sta_fail(err, STA_ERR_FORMAT, "%s: point %llu changed since it was counted",
                                 info->path, (unsigned long long)(batch.first_index + i));
                    break;
                }
                size_t c = (size_t)plan->chunk_of_cell[cell];
                chunk_buffer *b = &buffers[c];
                const uint8_t *extra = set->extra_size ? batch.extra + i * batch.extra_size : NULL;
                sta_record_pack(&set->layout, p, extra, b->data + b->used);
                b->used += rec;
                if (b->used == per_chunk) {
                    status = flush_chunk(fd, tmp_path, &plan->chunks[c], b, rec, err);
                }
            }
            sta_progress_add(progress, batch.count);
            sta_progress_draw(progress);
            if (status == STA_OK && cancel && atomic_load(cancel)) {
                status = sta_fail(err, STA_ERR_CANCELLED, "cancelled");
            }
        }
        sta_point_batch_release(&batch);
    }
    for (size_t c = 0; c < plan->chunk_count && status == STA_OK; c++) {
        status = flush_chunk(fd, tmp_path, &plan->chunks[c], &buffers[c], rec, err);
        if (status == STA_OK && buffers[c].written != plan->chunks[c].count) {
            status = sta_fail(err, STA_ERR_FORMAT,
                              "chunk %zu received %llu points, %llu were counted (an input "
                              "changed while being read)",
                              c, (unsigned long long)buffers[c].written,
                              (unsigned long long)plan->chunks[c].count);
        }
    }
    sta_free(arena);
    sta_free(buffers);
    return status;
}
