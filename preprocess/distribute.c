/* SPDX-License-Identifier: MIT
 * Counting, chunk planning and distribution into one temporary file.
 *
 * Design: the inputs' points, numbered across files, are split into one contiguous
 * range per thread; each thread reads its range through its own readers (thread 0
 * uses the set's). Counting: each thread counts on its own copy of the counting grid
 * (the octree's level min(7, max_level)) and tracks tight bounds; the grids are summed
 * into a pyramid and cut top-down into chunks (a node becomes a chunk when it holds at
 * most chunk_capacity points or is a counting cell). Distribution appends each
 * thread's per-chunk buffers as compressed blocks to the chunk's run list
 * (temp_runs.c), keyed (thread, sequence): reading a chunk back gives thread 0's
 * points, then thread 1's, ..., each in input order, so the records' order (and the
 * tree built from it) does not depend on the number of threads.
 */
#include "distribute.h"

#include <errno.h>
#include <pthread.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "core/alloc.h"
#include "core/array.h"
#include "core/file_io.h"

enum {
    READ_BATCH_POINTS = 65536,
    MAX_COUNT_LEVEL = 7,
    MAX_THREADS = 64
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

typedef struct chunk_buffer {
    uint8_t *data;
    size_t used;      /* bytes */
    uint64_t written; /* records of this thread already written */
} chunk_buffer;

/* One thread's share of a pass. */
typedef struct range_task {
    sta_input_set *set;
    int thread;
    uint64_t begin, end;    /* global point indices */
    sta_cloud_reader **own; /* readers this task opened (threads > 0), per input */
    sta_progress *progress;
    atomic_bool *cancel;
    sta_status status;
    sta_error err;
    sta_status (*per_batch)(struct range_task *t, size_t input, sta_point_batch *batch);
    sta_status (*at_end)(struct range_task *t); /* optional, in the task's thread */
    bool positions_only;                        /* per_batch reads only X, Y, Z (the count) */
    // counting
    const sta_octree_space *space;
    int level;
    uint64_t *counts; /* owned: 8^level cells */
    int64_t min[3], max[3];
    bool outside;
    // distribution
    const sta_chunk_plan *plan;
    sta_temp_runs *runs;
    sta_run_codec codec;   /* owned */
    uint64_t sequence;     /* blocks appended by this thread */
    size_t per_chunk;      /* buffer bytes per chunk */
    chunk_buffer *buffers; /* owned, one per chunk */
    uint8_t *arena;        /* owned */
    // distribution into memory
    uint8_t *const *chunk_records; /* borrowed: each chunk's records */
    uint64_t *next;                /* owned: this thread's next record slot per chunk */
    uint64_t *limit;               /* owned: the end of this thread's share per chunk */
} range_task;

static sta_cloud_reader *task_reader(range_task *t, size_t input)
{
    if (t->thread == 0) {
        return t->set->readers[input];
    }
    if (!t->own[input]) {
        sta_read_options options = { .salvage_truncated = t->set->salvage };
        sta_status s = sta_cloud_open(t->set->paths[input], &options, &t->own[input], &t->err);
        if (s != STA_OK) {
            t->status = s;
            return NULL;
        }
    }
    return t->own[input];
}

// Reads the task's range batch by batch and hands each to t->per_batch.
static void run_range(range_task *t)
{
    uint64_t file_start = 0;
    for (size_t in = 0; in < t->set->count && t->status == STA_OK; in++) {
        const sta_cloud_info *info = sta_cloud_reader_info(t->set->readers[in]);
        uint64_t file_end = file_start + info->point_count;
        uint64_t lo = t->begin > file_start ? t->begin : file_start;
        uint64_t hi = t->end < file_end ? t->end : file_end;
        if (lo < hi) {
            sta_cloud_reader *reader = task_reader(t, in);
            sta_point_batch batch;
            if (reader) {
                t->status =
                    sta_point_batch_init(&batch, READ_BATCH_POINTS, info->extra_size, &t->err);
            }
            if (reader && t->status == STA_OK) {
                t->status = sta_cloud_seek(reader, lo - file_start, &t->err);
                uint64_t left = hi - lo;
                while (t->status == STA_OK && left > 0) {
                    t->status = t->positions_only
                                    ? sta_cloud_read_positions(reader, &batch, &t->err)
                                    : sta_cloud_read(reader, &batch, &t->err);
                    if (t->status != STA_OK) {
                        break;
                    }
                    if (batch.count == 0) {
                        t->status = sta_fail(&t->err, STA_ERR_FORMAT,
                                             "%s: fewer points than "
                                             "announced",
                                             info->path);
                        break;
                    }
                    if (batch.count > left) {
                        batch.count = (size_t)left;
                    }
                    left -= batch.count;
                    t->status = t->per_batch(t, in, &batch);
                    sta_progress_add(t->progress, batch.count);
                    if (t->status == STA_OK && t->cancel && atomic_load(t->cancel)) {
                        t->status = sta_fail(&t->err, STA_ERR_CANCELLED, "cancelled");
                    }
                }
                sta_point_batch_release(&batch);
            }
        }
        file_start = file_end;
    }
    if (t->status == STA_OK && t->at_end) {
        t->status = t->at_end(t);
    }
}

static void *range_thread(void *argument)
{
    run_range(argument);
    return NULL;
}

// Runs `tasks` (one per thread) to completion; the calling thread runs task 0 and
// draws progress in between is left to the workers' counters.
static sta_status run_tasks(range_task *tasks, int count, sta_progress *progress, sta_error *err)
{
    pthread_t threads[MAX_THREADS];
    int started = 1;
    for (int t = 1; t < count; t++) {
        if (pthread_create(&threads[t], NULL, range_thread, &tasks[t]) != 0) {
            tasks[t].status = sta_fail(&tasks[t].err, STA_ERR_NOMEM, "cannot start a thread");
            break;
        }
        started++;
    }
    run_range(&tasks[0]);
    sta_progress_draw(progress);
    for (int t = 1; t < started; t++) {
        pthread_join(threads[t], NULL);
    }
    for (int t = 0; t < count; t++) {
        if (tasks[t].status != STA_OK) {
            *err = tasks[t].err;
            return tasks[t].status;
        }
    }
    return STA_OK;
}

static sta_status split_ranges(sta_chunk_plan *plan, uint64_t point_count, int threads,
                               sta_error *err)
{
    plan->threads = threads;
    plan->range_begin = sta_alloc_array((size_t)threads + 1, sizeof(uint64_t));
    if (!plan->range_begin) {
        return sta_fail(err, STA_ERR_NOMEM, "out of memory");
    }
    for (int t = 0; t <= threads; t++) {
        plan->range_begin[t] = point_count / (uint64_t)threads * (uint64_t)t +
                               (point_count % (uint64_t)threads) * (uint64_t)t / (uint64_t)threads;
    }
    return STA_OK;
}

static void release_tasks(range_task *tasks, int count, size_t inputs)
{
    for (int t = 0; t < count; t++) {
        if (tasks[t].own) {
            for (size_t i = 0; i < inputs; i++) {
                sta_cloud_close(tasks[t].own[i]);
            }
        }
        sta_free(tasks[t].own);
        sta_free(tasks[t].counts);
        sta_free(tasks[t].buffers);
        sta_free(tasks[t].arena);
        sta_free(tasks[t].next);
        sta_free(tasks[t].limit);
        sta_run_codec_release(&tasks[t].codec);
    }
    sta_free(tasks);
}

static range_task *create_tasks(sta_input_set *set, const sta_chunk_plan *plan,
                                sta_progress *progress, atomic_bool *cancel, sta_error *err)
{
    range_task *tasks = sta_calloc((size_t)plan->threads, sizeof(*tasks));
    if (!tasks) {
        sta_fail(err, STA_ERR_NOMEM, "out of memory");
        return NULL;
    }
    for (int t = 0; t < plan->threads; t++) {
        range_task *k = &tasks[t];
        k->set = set;
        k->thread = t;
        k->begin = plan->range_begin[t];
        k->end = plan->range_begin[t + 1];
        k->progress = progress;
        k->cancel = cancel;
        k->own = sta_calloc(set->count, sizeof(*k->own));
        if (!k->own) {
            release_tasks(tasks, plan->threads, set->count);
            sta_fail(err, STA_ERR_NOMEM, "out of memory");
            return NULL;
        }
    }
    return tasks;
}

static sta_status count_batch(range_task *t, size_t input, sta_point_batch *batch)
{
    for (size_t i = 0; i < batch->count; i++) {
        sta_point *p = &batch->points[i];
        if (!sta_inputs_to_output(t->set, input, p)) {
            const sta_cloud_info *info = sta_cloud_reader_info(t->set->readers[input]);
            return sta_fail(&t->err, STA_ERR_FORMAT,
                            "%s: point %llu does not fit the output grid (scale %g)", info->path,
                            (unsigned long long)(batch->first_index + i), t->set->grid.scale[0]);
        }
        const int32_t xyz[3] = { p->X, p->Y, p->Z };
        for (int a = 0; a < 3; a++) {
            t->min[a] = xyz[a] < t->min[a] ? xyz[a] : t->min[a];
            t->max[a] = xyz[a] > t->max[a] ? xyz[a] : t->max[a];
        }
        size_t cell;
        if (!counting_cell(t->space, t->level, xyz, &cell)) {
            t->outside = true;
        } else {
            t->counts[cell]++;
        }
    }
    return STA_OK;
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

// One parallel counting pass over all inputs into tasks[t].counts.
static sta_status count_pass(range_task *tasks, int threads, const sta_octree_space *space,
                             int level, sta_chunk_plan *plan, bool *outside, sta_error *err)
{
    size_t cells = (size_t)1 << (3 * level);
    for (int t = 0; t < threads; t++) {
        range_task *k = &tasks[t];
        sta_free(k->counts);
        k->counts = sta_calloc(cells, sizeof(uint64_t));
        if (!k->counts) {
            return sta_fail(err, STA_ERR_NOMEM, "out of memory for the counting grid");
        }
        k->space = space;
        k->level = level;
        k->outside = false;
        k->per_batch = count_batch;
        k->positions_only = true; // count_batch and the regrid read nothing else
        for (int a = 0; a < 3; a++) {
            k->min[a] = INT64_MAX;
            k->max[a] = INT64_MIN;
        }
    }
    sta_status status = run_tasks(tasks, threads, tasks[0].progress, err);
    if (status != STA_OK) {
        return status;
    }
    *outside = false;
    for (int a = 0; a < 3; a++) {
        plan->actual_min[a] = INT64_MAX;
        plan->actual_max[a] = INT64_MIN;
    }
    for (int t = 0; t < threads; t++) {
        *outside = *outside || tasks[t].outside;
        for (int a = 0; a < 3; a++) {
            plan->actual_min[a] =
                tasks[t].min[a] < plan->actual_min[a] ? tasks[t].min[a] : plan->actual_min[a];
            plan->actual_max[a] =
                tasks[t].max[a] > plan->actual_max[a] ? tasks[t].max[a] : plan->actual_max[a];
        }
    }
    return STA_OK;
}

static sta_status add_chunk(sta_chunk_plan *plan, size_t *capacity, const sta_node_key *key,
                            uint64_t count, sta_error *err)
{
    if (sta_array_reserve((void **)&plan->chunks, capacity, plan->chunk_count + 1,
                          sizeof(*plan->chunks), 64, NULL) != STA_OK) {
        return sta_fail(err, STA_ERR_NOMEM, "out of memory planning chunks");
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
        chunk->list = c;
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

// Where each thread's share of each chunk starts: thread t's points of chunk c follow
// threads 0..t-1's.
static sta_status place_threads(sta_chunk_plan *plan, range_task *tasks, sta_error *err)
{
    size_t n = plan->chunk_count;
    plan->thread_first = sta_calloc((size_t)plan->threads * (n ? n : 1), sizeof(uint64_t));
    if (!plan->thread_first) {
        return sta_fail(err, STA_ERR_NOMEM, "out of memory planning chunks");
    }
    size_t cells = (size_t)1 << (3 * plan->count_level);
    uint64_t *next = sta_alloc_array(n ? n : 1, sizeof(uint64_t));
    if (!next) {
        return sta_fail(err, STA_ERR_NOMEM, "out of memory planning chunks");
    }
    for (size_t c = 0; c < n; c++) {
        next[c] = plan->chunks[c].first;
    }
    for (int t = 0; t < plan->threads; t++) {
        uint64_t *first = plan->thread_first + (size_t)t * n;
        for (size_t c = 0; c < n; c++) {
            first[c] = next[c];
        }
        for (size_t cell = 0; cell < cells; cell++) {
            if (tasks[t].counts[cell]) {
                next[plan->chunk_of_cell[cell]] += tasks[t].counts[cell];
            }
        }
    }
    sta_free(next);
    return STA_OK;
}

sta_status sta_distribute_plan(sta_input_set *set, int threads, int grid_log2,
                               uint64_t chunk_capacity, sta_progress *progress, atomic_bool *cancel,
                               sta_chunk_plan *out_plan, sta_error *err)
{
    memset(out_plan, 0, sizeof(*out_plan));
    uint64_t *levels[MAX_COUNT_LEVEL + 1] = { 0 };
    threads = threads < 1 ? 1 : (threads > MAX_THREADS ? MAX_THREADS : threads);
    // Tiny inputs are not worth a thread each.
    if ((uint64_t)threads > set->point_count / 100000 + 1) {
        threads = (int)(set->point_count / 100000 + 1);
    }
    range_task *tasks = NULL;
    sta_status status = split_ranges(out_plan, set->point_count, threads, err);
    if (status == STA_OK) {
        tasks = create_tasks(set, out_plan, progress, cancel, err);
        status = tasks ? STA_OK : err->code;
    }
    if (status != STA_OK) {
        goto out;
    }

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
    int level = 0;
    for (int attempt = 0; attempt < 2; attempt++) {
        level = space.max_level < MAX_COUNT_LEVEL ? space.max_level : MAX_COUNT_LEVEL;
        bool outside = false;
        sta_progress_begin(progress, attempt == 0 ? "counting" : "recounting", set->point_count,
                           progress->enabled);
        status = count_pass(tasks, threads, &space, level, out_plan, &outside, err);
        sta_progress_end(progress);
        if (status != STA_OK) {
            goto out;
        }
        if (set->point_count == 0 || (!outside && box_fits(&space, &set->grid, out_plan->actual_min,
                                                           out_plan->actual_max))) {
            break;
        }
        if (attempt == 1) {
            status = sta_fail(err, STA_ERR_FORMAT, "inputs changed while being read");
            goto out;
        }
        // The declared bounds were wrong: use the tight ones and count again.
        status = sta_octree_space_init(&space, &set->grid, out_plan->actual_min,
                                       out_plan->actual_max, grid_log2, err);
        if (status != STA_OK) {
            goto out;
        }
    }
    out_plan->space = space;
    out_plan->count_level = level;
    out_plan->point_count = set->point_count;
    if (set->point_count == 0) {
        goto out;
    }
    size_t cells = (size_t)1 << (3 * level);
    levels[level] = sta_calloc(cells, sizeof(uint64_t));
    if (!levels[level]) {
        status = sta_fail(err, STA_ERR_NOMEM, "out of memory for the counting pyramid");
        goto out;
    }
    for (int t = 0; t < threads; t++) {
        for (size_t c = 0; c < cells; c++) {
            levels[level][c] += tasks[t].counts[c];
        }
    }
    for (int l = level - 1; l >= 0; l--) {
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
    if (status == STA_OK) {
        status = place_threads(out_plan, tasks, err);
    }
out:
    if (tasks) {
        release_tasks(tasks, out_plan->threads, set->count);
    }
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
    sta_free(plan->range_begin);
    sta_free(plan->thread_first);
    memset(plan, 0, sizeof(*plan));
}

static sta_status flush_chunk(range_task *t, size_t c)
{
    chunk_buffer *b = &t->buffers[c];
    if (b->used == 0) {
        return STA_OK;
    }
    const size_t rec = t->set->layout.size;
    uint64_t order = ((uint64_t)t->thread << 48) | t->sequence++;
    sta_status status = sta_temp_runs_append(t->runs, &t->codec, t->plan->chunks[c].list, order,
                                             b->data, b->used / rec, &t->err);
    b->written += b->used / rec;
    b->used = 0;
    return status;
}

// Moves point i of the batch onto the output grid, flags mirror ghosts and finds its
// chunk; fails when the point no longer lies where it was counted.
static sta_status locate(range_task *t, size_t input, sta_point_batch *batch, size_t i,
                         size_t *out_chunk)
{
    const sta_chunk_plan *plan = t->plan;
    sta_point *p = &batch->points[i];
    bool fits = sta_inputs_to_output(t->set, input, p);
    const int32_t xyz[3] = { p->X, p->Y, p->Z };
    size_t cell;
    if (!fits || !counting_cell(&plan->space, plan->count_level, xyz, &cell) ||
        plan->chunk_of_cell[cell] < 0) {
        const sta_cloud_info *info = sta_cloud_reader_info(t->set->readers[input]);
        return sta_fail(&t->err, STA_ERR_FORMAT, "%s: point %llu changed since it was counted",
                        info->path, (unsigned long long)(batch->first_index + i));
    }
    if (t->set->mirrors) {
        const double world[3] = { sta_grid_apply(&t->set->grid, 0, p->X),
                                  sta_grid_apply(&t->set->grid, 1, p->Y),
                                  sta_grid_apply(&t->set->grid, 2, p->Z) };
        p->mirror = sta_mirror_ghost_of(t->set->mirrors, p->point_source_id, world);
    }
    *out_chunk = (size_t)plan->chunk_of_cell[cell];
    return STA_OK;
}

static sta_status distribute_batch(range_task *t, size_t input, sta_point_batch *batch)
{
    const size_t rec = t->set->layout.size;
    for (size_t i = 0; i < batch->count; i++) {
        size_t c;
        sta_status located = locate(t, input, batch, i, &c);
        if (located != STA_OK) {
            return located;
        }
        sta_point *p = &batch->points[i];
        chunk_buffer *b = &t->buffers[c];
        const uint8_t *extra = t->set->extra_size ? batch->extra + i * batch->extra_size : NULL;
        sta_record_pack(&t->set->layout, p, extra, b->data + b->used);
        b->used += rec;
        if (b->used == t->per_chunk) {
            sta_status status = flush_chunk(t, c);
            if (status != STA_OK) {
                return status;
            }
        }
    }
    return STA_OK;
}

// The thread's partly filled chunk buffers, compressed in its own thread (in parallel).
static sta_status flush_all(range_task *t)
{
    sta_status status = STA_OK;
    for (size_t c = 0; c < t->plan->chunk_count && status == STA_OK; c++) {
        status = flush_chunk(t, c);
    }
    return status;
}

sta_status sta_distribute_write(sta_input_set *set, const sta_chunk_plan *plan, sta_temp_runs *runs,
                                size_t buffer_bytes, sta_progress *progress, atomic_bool *cancel,
                                sta_error *err)
{
    const size_t rec = set->layout.size;
    if (plan->chunk_count == 0) {
        return STA_OK;
    }
    range_task *tasks = create_tasks(set, plan, progress, cancel, err);
    if (!tasks) {
        return err->code;
    }
    size_t per_chunk = buffer_bytes / (size_t)plan->threads / plan->chunk_count;
    per_chunk =
        per_chunk < STA_TEMP_RUNS_MIN_BLOCK_BYTES ? STA_TEMP_RUNS_MIN_BLOCK_BYTES : per_chunk;
    per_chunk =
        per_chunk > STA_TEMP_RUNS_MAX_BLOCK_BYTES ? STA_TEMP_RUNS_MAX_BLOCK_BYTES : per_chunk;
    per_chunk -= per_chunk % rec;
    sta_status status = STA_OK;
    for (int t = 0; t < plan->threads && status == STA_OK; t++) {
        range_task *k = &tasks[t];
        k->plan = plan;
        k->runs = runs;
        k->per_chunk = per_chunk;
        k->per_batch = distribute_batch;
        k->at_end = flush_all;
        k->buffers = sta_calloc(plan->chunk_count, sizeof(*k->buffers));
        k->arena = sta_alloc_array(plan->chunk_count, per_chunk);
        if (!k->buffers || !k->arena) {
            status = sta_fail(err, STA_ERR_NOMEM, "out of memory for %zu chunk buffers",
                              plan->chunk_count);
            break;
        }
        for (size_t c = 0; c < plan->chunk_count; c++) {
            k->buffers[c].data = k->arena + c * per_chunk;
        }
    }
    if (status == STA_OK) {
        status = run_tasks(tasks, plan->threads, progress, err);
    }
    // Every thread flushed what it had left (flush_all); check each wrote what it counted.
    for (size_t c = 0; c < plan->chunk_count && status == STA_OK; c++) {
        uint64_t written = 0;
        for (int t = 0; t < plan->threads; t++) {
            written += tasks[t].buffers[c].written;
        }
        if (written != plan->chunks[c].count) {
            status =
                sta_fail(err, STA_ERR_FORMAT,
                         "chunk %zu received %llu points, %llu were counted (an input "
                         "changed while being read)",
                         c, (unsigned long long)written, (unsigned long long)plan->chunks[c].count);
        }
    }
    release_tasks(tasks, plan->threads, set->count);
    return status;
}

static sta_status distribute_batch_to_memory(range_task *t, size_t input, sta_point_batch *batch)
{
    const size_t rec = t->set->layout.size;
    for (size_t i = 0; i < batch->count; i++) {
        size_t c;
        sta_status located = locate(t, input, batch, i, &c);
        if (located != STA_OK) {
            return located;
        }
        if (t->next[c] == t->limit[c]) {
            return sta_fail(&t->err, STA_ERR_FORMAT,
                            "chunk %zu received more points than were counted (an input "
                            "changed while being read)",
                            c);
        }
        const uint8_t *extra = t->set->extra_size ? batch->extra + i * batch->extra_size : NULL;
        sta_record_pack(&t->set->layout, &batch->points[i], extra,
                        t->chunk_records[c] + t->next[c]++ * rec);
    }
    return STA_OK;
}

sta_status sta_distribute_to_memory(sta_input_set *set, const sta_chunk_plan *plan,
                                    uint8_t *const *chunk_records, sta_progress *progress,
                                    atomic_bool *cancel, sta_error *err)
{
    const size_t n = plan->chunk_count;
    if (n == 0) {
        return STA_OK;
    }
    range_task *tasks = create_tasks(set, plan, progress, cancel, err);
    if (!tasks) {
        return err->code;
    }
    sta_status status = STA_OK;
    for (int t = 0; t < plan->threads && status == STA_OK; t++) {
        range_task *k = &tasks[t];
        k->plan = plan;
        k->chunk_records = chunk_records;
        k->per_batch = distribute_batch_to_memory;
        k->next = sta_alloc_array(n, sizeof(uint64_t));
        k->limit = sta_alloc_array(n, sizeof(uint64_t));
        if (!k->next || !k->limit) {
            status = sta_fail(err, STA_ERR_NOMEM, "out of memory for %zu chunks", n);
            break;
        }
        // Thread t's share of chunk c: from its first slot to the next thread's.
        for (size_t c = 0; c < n; c++) {
            uint64_t first = plan->chunks[c].first;
            k->next[c] = plan->thread_first[(size_t)t * n + c] - first;
            k->limit[c] = (t + 1 < plan->threads ? plan->thread_first[(size_t)(t + 1) * n + c]
                                                 : first + plan->chunks[c].count) -
                          first;
        }
    }
    if (status == STA_OK) {
        status = run_tasks(tasks, plan->threads, progress, err);
    }
    for (int t = 0; t < plan->threads && status == STA_OK; t++) {
        for (size_t c = 0; c < n && status == STA_OK; c++) {
            if (tasks[t].next[c] != tasks[t].limit[c]) {
                status = sta_fail(err, STA_ERR_FORMAT,
                                  "chunk %zu received fewer points than were counted (an "
                                  "input changed while being read)",
                                  c);
            }
        }
    }
    release_tasks(tasks, plan->threads, set->count);
    return status;
}
