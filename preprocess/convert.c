/* SPDX-License-Identifier: MIT
 * The conversion pipeline (see convert.h for the design).
 *
 * Threads: the main thread runs counting, distribution and the merge; during the
 * index phase `threads` workers take chunks from an atomic counter (largest first)
 * and emit nodes through the node writer. Chunk roots are kept back for the merge in
 * a spill file (appended under spill_lock). Lock order: spill_lock, then the node
 * writer's lock (never nested in practice).
 */
#define _GNU_SOURCE // pthread_setname_np: name every thread (STYLE.md)
#include "convert.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <malloc.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "core/alloc.h"
#include "core/array.h"
#include "core/clock.h"
#include "core/file_io.h"
#include "core/log.h"
#include "distribute.h"
#include "format/strata_writer.h"
#include "halo.h"
#include "index.h"
#include "inputs.h"
#include "knn_normals.h"
#include "las_source.h"
#include "memory_governor.h"
#include "moment_normals.h"
#include "node_writer.h"
#include "path_checks.h"
#include "progress.h"
#include "refine.h"
#include "temp_runs.h"
#include "up_axis.h"

enum {
    FIXED_OVERHEAD_MIB = 96, /* counting pyramid, chunk map, reader batches, code */
    CHUNKS_PER_SCENE = 8,    /* chunk size = points / this, within the bounds below */
    CHUNK_MIN_POINTS = 1 << 20,
    CHUNK_MAX_POINTS = 3 << 20,
    PROGRESS_INTERVAL_NS = 100000000, /* progress redrawn every 0.1 s while indexing */
    /* Bytes a point the roughest scenes' normals took (BENCHMARKS.md: a 2 M sphere with
     * 5 cm of noise 1 921): the --memory an error suggests. */
    ROUGH_NORMALS_BYTES_PER_POINT = 2000,
};

/* A node kept back for the merge, its records in the spill file. */
typedef struct spilled_node {
    sta_node_key key;
    size_t list; /* its run list in spill_runs */
    uint64_t count;
    unsigned flags;
    int has_children;
} spilled_node;

typedef struct convert_job {
    const sta_convert_options *options;
    sta_input_set inputs;
    sta_chunk_plan plan;
    sta_progress progress;
    size_t leaf_capacity;
    size_t chunk_capacity;
    int threads;
    char *chunk_path; /* temporary file of distributed records */
    int chunk_fd;
    sta_temp_runs runs;        /* the distributed records, compressed, per chunk */
    uint8_t **chunk_records;   /* instead of runs when they fit --memory: each chunk's
                                  records (owned; freed once indexed), else NULL */
    sta_temp_runs spill_runs;  /* nodes kept for the merge, one list each */
    sta_temp_usage temp_usage; /* both stores' disk together */
    sta_run_codec *codecs;     /* one per index worker */
    char *spill_path;          /* temporary file of nodes kept for the merge */
    int spill_fd;
    pthread_mutex_t spill_lock; /* guards spilled, spilled_count/capacity */
    spilled_node *spilled;
    size_t spilled_count;
    size_t spilled_capacity;
    sta_strata_writer *writer;
    sta_node_writer node_writer;
    int up_axis;               /* STA_STRATA_UP_* of the header (orients the normals) */
    _Atomic size_t next_chunk; /* atomic: next chunk to index */
    size_t *chunk_order;       /* chunk indices, largest first */
    atomic_bool failed;        /* atomic: a worker failed; others stop */
    sta_error worker_error;    /* first worker error (guard: spill_lock) */
    char *halo_path;           /* --normals: temporary file of the chunks' halos */
    int halo_fd;
    sta_temp_runs halo_runs;      /* --normals: halo positions, one list per chunk */
    sta_normals_stats normals;    /* summed over workers (guard: spill_lock) */
    sta_trajectory trajectory;    /* --normals: the scanner's path from GPS time */
    sta_memory_governor governor; /* --normals: the workers' normals heap (index phase) */
    bool governed;                /* governor initialised */
    atomic_size_t normals_peak;   /* the most heap a chunk's normals took (with its halo) */
    atomic_size_t normals_rate;   /* the most of it a point (chunk_normals) */
    size_t index_bytes;           /* a worker's index buffers beyond its normals' share */
    bool below_plan; /* --memory below one planned worker (warned): the pool is no limit */
} convert_job;

// Creates a temporary file "<dir>/.<base>.<tag>.XXXXXX" and unlinks it at once: it
// lives only as the descriptor, so a killed process (SIGKILL, the OOM killer) leaves
// nothing behind. The name, for messages only, is returned in *out_path (owned).
// CPU seconds of all the process's threads, for the per-phase report.
static double process_cpu_s(void)
{
    return sta_clock_process_cpu_ms() * 1e-3;
}

static sta_status make_temp(const char *dir, const char *output, const char *tag, char **out_path,
                            int *out_fd, sta_error *err)
{
    const char *base = strrchr(output, '/');
    base = base ? base + 1 : output;
    char *path = sta_malloc(PATH_MAX);
    if (!path) {
        return sta_fail(err, STA_ERR_NOMEM, "out of memory");
    }
    int n = snprintf(path, PATH_MAX, "%s/.%s.%s.XXXXXX", dir, base, tag);
    if (n < 0 || n >= PATH_MAX) {
        sta_free(path);
        return sta_fail(err, STA_ERR_ARG, "%s: temporary path too long", dir);
    }
    int fd = mkstemp(path);
    if (fd < 0) {
        sta_status status = sta_fail(err, STA_ERR_IO, "%s: cannot create a temporary file: %s", dir,
                                     strerror(errno));
        sta_free(path);
        return status;
    }
    unlink(path);
    *out_path = path;
    *out_fd = fd;
    return STA_OK;
}

// Closes a temporary file (its space is freed: it has no name).
static void remove_temp(char **path, int *fd)
{
    if (*fd >= 0) {
        close(*fd);
        *fd = -1;
    }
    sta_free(*path);
    *path = NULL;
}

static char *output_folder(const char *output)
{
    const char *slash = strrchr(output, '/');
    if (!slash) {
        return sta_strdup(".");
    }
    size_t n = slash == output ? 1 : (size_t)(slash - output);
    char *dir = sta_malloc(n + 1);
    if (dir) {
        memcpy(dir, output, n);
        dir[n] = '\0';
    }
    return dir;
}

// Appends a node's records to the merge runs (compressed) and remembers it.
static sta_status spill(convert_job *job, sta_run_codec *codec, const sta_pending_node *node,
                        sta_error *err)
{
    const size_t rec = job->inputs.layout.size;
    size_t list = 0;
    sta_status status = sta_temp_runs_add_lists(&job->spill_runs, 1, &list, err);
    if (status != STA_OK) {
        return status;
    }
    pthread_mutex_lock(&job->spill_lock);
    if (sta_array_reserve((void **)&job->spilled, &job->spilled_capacity, job->spilled_count + 1,
                          sizeof(*job->spilled), 256, NULL) != STA_OK) {
        status = sta_fail(err, STA_ERR_NOMEM, "out of memory for the merge list");
    }
    if (status == STA_OK) {
        spilled_node *s = &job->spilled[job->spilled_count++];
        s->key = node->key;
        s->list = list;
        s->count = node->count;
        s->flags = node->flags;
        s->has_children = node->has_children;
    }
    pthread_mutex_unlock(&job->spill_lock);
    size_t per_block = STA_TEMP_RUNS_MAX_BLOCK_BYTES / rec;
    for (size_t done = 0, block = 0; status == STA_OK && done < node->count; block++) {
        size_t n = node->count - done < per_block ? node->count - done : per_block;
        status = sta_temp_runs_append(&job->spill_runs, codec, list, block,
                                      node->records + done * rec, n, err);
        done += n;
    }
    return status;
}

// Reads a kept node back (and frees its disk).
static sta_status unspill(convert_job *job, const spilled_node *s, uint8_t *records, sta_error *err)
{
    sta_status status =
        sta_temp_runs_read(&job->spill_runs, &job->codecs[0], s->list, records, err);
    sta_temp_runs_discard(&job->spill_runs, s->list);
    return status;
}

// The inputs' names for a message: the only one, or the first and how many more.
static void inputs_name(const convert_job *job, char *out, size_t size)
{
    const sta_convert_options *o = job->options;
    if (o->input_count > 1) {
        snprintf(out, size, "%s (and %zu more inputs)", o->inputs[0], (size_t)o->input_count - 1);
    } else {
        snprintf(out, size, "%s", o->input_count ? o->inputs[0] : "(no input)");
    }
}

static sta_status normals_too_large(convert_job *job, size_t count, size_t halo_count,
                                    sta_error *err)
{
    char name[512];
    inputs_name(job, name, sizeof(name));
    size_t pool_mib = job->governor.pool_bytes >> 20;
    size_t guess = ((count + halo_count) * (size_t)ROUGH_NORMALS_BYTES_PER_POINT) >> 20;
    size_t fit = job->options->memory_mib + (guess > pool_mib ? guess - pool_mib : 1);
    return sta_fail(err, STA_ERR_NOMEM,
                    "%s: the normals of a chunk of %zu points (and %zu halo points) need more "
                    "than the %zu MiB that --memory %zu MiB leaves them, even alone; about "
                    "--memory %zu MiB would fit (%d bytes a point, the roughest scenes "
                    "measured)",
                    name, count, halo_count, pool_mib, job->options->memory_mib, fit,
                    (int)ROUGH_NORMALS_BYTES_PER_POINT);
}

// Raises an atomic maximum to `value`.
static void raise_to(atomic_size_t *maximum, size_t value)
{
    size_t seen = atomic_load(maximum);
    while (value > seen && !atomic_compare_exchange_weak(maximum, &seen, value)) {
    }
}

// --normals: reads the chunk's halo (and frees its disk), then fills the records'
// SPLAT bytes. The halo and the normals' heap come from the governor's pool; a chunk
// the pool refuses is computed again alone (memory_governor.h).
static sta_status chunk_normals(convert_job *job, int worker, size_t chunk_index, uint8_t *records,
                                size_t count, sta_error *err)
{
    size_t halo_count = (size_t)job->halo_runs.lists[chunk_index].record_count;
    size_t halo_bytes = (halo_count ? halo_count : 1) * 3 * sizeof(int32_t);
    sta_memory_governor *g = &job->governor;
    bool alone = false;
    if (!sta_alloc_pool_take(&g->pool, halo_bytes)) {
        sta_memory_governor_go_alone(g);
        alone = true;
        if (!sta_alloc_pool_take(&g->pool, halo_bytes)) {
            sta_memory_governor_share(g);
            return normals_too_large(job, count, halo_count, err);
        }
    }
    int32_t *halo = sta_alloc_array(halo_count ? halo_count : 1, 3 * sizeof(int32_t));
    if (!halo) {
        sta_alloc_pool_give(&g->pool, halo_bytes);
        if (alone) {
            sta_memory_governor_share(g);
        }
        return sta_fail(err, STA_ERR_NOMEM, "out of memory for a halo of %zu points", halo_count);
    }
    sta_status status = sta_temp_runs_read(&job->halo_runs, &job->codecs[worker], chunk_index,
                                           (uint8_t *)halo, err);
    sta_temp_runs_discard(&job->halo_runs, chunk_index);
    sta_normals_chunk frame;
    sta_halo_chunk_frame(&job->plan, &job->inputs.grid, chunk_index, job->options->knn,
                         job->options->normals_method, &frame);
    frame.up_axis = job->up_axis == STA_STRATA_UP_Y ? 1 : 2;
    frame.trajectory = job->trajectory.usable ? &job->trajectory : NULL;
    sta_normals_stats stats = { 0 };
    // The most bytes a point a chunk took so far (or held when refused): a chunk that would
    // not fit what is left at that rate waits to run alone at once, not after a refusal.
    size_t points = count + halo_count;
    if (!alone && status == STA_OK &&
        (double)points * (double)atomic_load(&job->normals_rate) >
            (double)atomic_load(&g->pool.left)) {
        sta_memory_governor_go_alone(g);
        alone = true;
    }
    while (status == STA_OK) {
        memset(&stats, 0, sizeof(stats));
        sta_alloc_meter_begin(&g->pool);
        status = sta_normals_compute(&frame, &job->inputs.layout, records, count, halo, halo_count,
                                     &stats, err);
        size_t peak = 0;
        bool refused = sta_alloc_meter_end(&peak);
        if (status == STA_OK) {
            raise_to(&job->normals_peak, peak + halo_bytes);
        }
        raise_to(&job->normals_rate, (peak + halo_bytes) / (points ? points : 1));
        if (status == STA_OK || !refused) {
            break;
        }
        if (alone && !job->below_plan) {
            status = normals_too_large(job, count, halo_count, err);
            break;
        }
        if (alone) { // (--memory below one planned worker: over it anyway, with a warning)
            memset(&stats, 0, sizeof(stats));
            sta_alloc_pool unlimited = { LLONG_MAX / 2 }; // (counted for the report only)
            sta_alloc_meter_begin(&unlimited);
            status = sta_normals_compute(&frame, &job->inputs.layout, records, count, halo,
                                         halo_count, &stats, err);
            sta_alloc_meter_end(&peak);
            raise_to(&job->normals_peak, peak + halo_bytes);
            break;
        }
        // Refused beside other chunks: all it built is freed; again with the whole pool
        // (the same normals: the records' SPLAT bytes are written again).
        if (err) {
            memset(err, 0, sizeof(*err));
        }
        status = STA_OK;
        sta_memory_governor_go_alone(g);
        alone = true;
    }
    sta_free(halo);
    sta_alloc_pool_give(&g->pool, halo_bytes);
    if (alone) {
        sta_memory_governor_share(g);
    }
    pthread_mutex_lock(&job->spill_lock);
    job->normals.points += stats.points;
    job->normals.degenerate += stats.degenerate;
    job->normals.beyond_halo += stats.beyond_halo;
    job->normals.widened += stats.widened;
    job->normals.widened_exact += stats.widened_exact;
    pthread_mutex_unlock(&job->spill_lock);
    return status;
}

static void free_chunk_records(convert_job *job)
{
    for (size_t c = 0; job->chunk_records && c < job->plan.chunk_count; c++) {
        sta_free(job->chunk_records[c]);
    }
    sta_free(job->chunk_records);
    job->chunk_records = NULL;
}

typedef struct worker_args {
    convert_job *job;
    int index;
} worker_args;

static void *index_worker(void *argument)
{
    worker_args *args = argument;
    convert_job *job = args->job;
    const size_t rec = job->inputs.layout.size;
    sta_error err = { 0 };
    sta_status status = STA_OK;
    sta_index_scratch scratch = { 0 };
    uint8_t *records = NULL;
    size_t records_capacity = 0;
    sta_node_sink sink = sta_node_writer_sink(&job->node_writer);
    while (status == STA_OK && !atomic_load(&job->failed)) {
        size_t i = atomic_fetch_add(&job->next_chunk, 1);
        if (i >= job->plan.chunk_count) {
            break;
        }
        const size_t ci = job->chunk_order[i];
        const sta_chunk *chunk = &job->plan.chunks[ci];
        size_t count = (size_t)chunk->count;
        uint8_t *in_memory = job->chunk_records ? job->chunk_records[ci] : NULL;
        if (!in_memory && count > records_capacity) {
            sta_free(records);
            records = sta_alloc_array(count, rec);
            records_capacity = records ? count : 0;
            if (!records) {
                status =
                    sta_fail(&err, STA_ERR_NOMEM, "out of memory for a chunk of %zu points", count);
                break;
            }
        }
        // The chunk's payloads reach the file in chunk order (deterministic output).
        status = sta_node_writer_begin_chunk(&job->node_writer, args->index, i, &err);
        // (entered after its turn's wait: a chunk waiting to run alone waits for the
        // chunks inside, never for one that waits for its own turn)
        bool governed = status == STA_OK && job->governed;
        if (governed) {
            sta_memory_governor_enter(&job->governor);
        }
        if (status == STA_OK && !in_memory) {
            status = sta_temp_runs_read(&job->runs, &job->codecs[args->index], chunk->list, records,
                                        &err);
            sta_temp_runs_discard(&job->runs, chunk->list); // read once: free its disk
        }
        const uint8_t *data = in_memory ? in_memory : records;
        if (status == STA_OK && job->options->normals) {
            sta_index_scratch_release(&scratch); // never both at once (worker_bytes)
            status = chunk_normals(job, args->index, job->chunk_order[i],
                                   in_memory ? in_memory : records, count, &err);
        }
        sta_pending_node root = { 0 };
        bool took = status == STA_OK && governed; // (its index buffers: from the pool too)
        if (took) {
            sta_memory_governor_take(&job->governor, job->index_bytes);
        }
        if (status == STA_OK) {
            status =
                sta_index_chunk(&job->plan.space, &job->inputs.layout, &chunk->key, data, count,
                                job->leaf_capacity, args->index, &sink, &scratch, &root, &err);
        }
        if (took) { // (released before the next normals anyway)
            sta_index_scratch_release(&scratch);
            sta_memory_governor_give(&job->governor, job->index_bytes);
        }
        if (in_memory) { // indexed: its memory goes back at once
            sta_free(in_memory);
            job->chunk_records[ci] = NULL;
        }
        if (status == STA_OK) {
            status = sta_node_writer_end_chunk(&job->node_writer, args->index, &err);
        }
        if (status == STA_OK) {
            status = spill(job, &job->codecs[args->index], &root, &err);
        }
        sta_free(root.records);
        if (governed) {
            sta_memory_governor_leave(&job->governor);
        }
        sta_progress_add(&job->progress, count);
        if (job->options->cancel && atomic_load(job->options->cancel)) {
            status = sta_fail(&err, STA_ERR_CANCELLED, "cancelled");
        }
    }
    sta_free(records);
    sta_index_scratch_release(&scratch);
    if (status != STA_OK) {
        pthread_mutex_lock(&job->spill_lock);
        if (!atomic_load(&job->failed)) {
            job->worker_error = err;
            atomic_store(&job->failed, true);
        }
        pthread_mutex_unlock(&job->spill_lock);
        sta_node_writer_abort(&job->node_writer); // others may wait for this chunk's turn
    }
    return NULL;
}

// qsort has no context argument: the chunk array being sorted (main thread only).
static const sta_chunk *sort_chunks;

static int compare_chunk_size(const void *a, const void *b)
{
    size_t i = *(const size_t *)a, j = *(const size_t *)b;
    uint64_t x = sort_chunks[i].count;
    uint64_t y = sort_chunks[j].count;
    // Ties by index: this order is also the payloads' order in the file.
    return x < y ? 1 : x > y ? -1 : i < j ? -1 : i > j ? 1 : 0;
}

static sta_status run_index_phase(convert_job *job, sta_error *err)
{
    job->chunk_order = sta_alloc_array(job->plan.chunk_count, sizeof(size_t));
    if (!job->chunk_order) {
        return sta_fail(err, STA_ERR_NOMEM, "out of memory");
    }
    for (size_t i = 0; i < job->plan.chunk_count; i++) {
        job->chunk_order[i] = i;
    }
    sort_chunks = job->plan.chunks;
    qsort(job->chunk_order, job->plan.chunk_count, sizeof(size_t), compare_chunk_size);
    sta_status status = sta_node_writer_plan_chunks(&job->node_writer, job->plan.chunk_count, err);
    if (status != STA_OK) {
        return status;
    }

    pthread_t threads[256];
    worker_args args[256];
    int started = 0;
    for (int t = 0; t < job->threads; t++) {
        args[t].job = job;
        args[t].index = t;
        if (pthread_create(&threads[t], NULL, index_worker, &args[t]) != 0) {
            break;
        }
        char name[16];
        snprintf(name, sizeof(name), "sta-index-%d", t % 100);
        pthread_setname_np(threads[t], name);
        started++;
    }
    if (started == 0) {
        return sta_fail(err, STA_ERR_NOMEM, "cannot start worker threads");
    }
    // The main thread draws progress while the workers run, and joins each as soon as
    // it ends (a fixed sleep between checks left up to 0.1 s idle at the end).
    for (int t = 0; t < started; t++) {
        struct timespec deadline;
        clock_gettime(CLOCK_REALTIME, &deadline);
        while (true) {
            deadline.tv_nsec += PROGRESS_INTERVAL_NS;
            if (deadline.tv_nsec >= 1000000000L) {
                deadline.tv_sec++;
                deadline.tv_nsec -= 1000000000L;
            }
            if (pthread_timedjoin_np(threads[t], NULL, &deadline) != ETIMEDOUT) {
                break;
            }
            sta_progress_draw(&job->progress);
            if (job->options->cancel && atomic_load(job->options->cancel)) {
                atomic_store(&job->failed, true);
                sta_node_writer_abort(&job->node_writer);
            }
        }
    }
    if (atomic_load(&job->failed)) {
        if (job->worker_error.code == STA_OK) {
            return sta_fail(err, STA_ERR_CANCELLED, "cancelled");
        }
        *err = job->worker_error;
        return job->worker_error.code;
    }
    if (!sta_node_writer_all_committed(&job->node_writer)) {
        return sta_fail(err, STA_ERR_ARG, "internal error: chunk payloads left unwritten");
    }
    return STA_OK;
}

static int compare_spilled(const void *a, const void *b)
{
    const spilled_node *x = a, *y = b;
    // Deepest level first; within a level by parent, then key (siblings adjacent).
    if (x->key.level != y->key.level) {
        return x->key.level > y->key.level ? -1 : 1;
    }
    return sta_node_key_compare(&x->key, &y->key);
}

static int same_parent(const sta_node_key *a, const sta_node_key *b)
{
    return a->level == b->level && (a->x >> 1) == (b->x >> 1) && (a->y >> 1) == (b->y >> 1) &&
           (a->z >> 1) == (b->z >> 1);
}

// Hands a finished node to the writer: its points, or an empty entry that keeps the
// tree connected when the merge took all its points but it has children.
static sta_status finish_node(convert_job *job, const sta_pending_node *node, sta_error *err)
{
    if (node->count > 0) {
        sta_node_sink sink = sta_node_writer_sink(&job->node_writer);
        return sink.emit(sink.context, 0, &node->key, node->records, node->count, node->flags, err);
    }
    if (node->has_children || node->key.level == 0) {
        return sta_node_writer_add_empty(&job->node_writer, &node->key, err);
    }
    return STA_OK;
}

// Builds the tree above the chunks, level by level from the deepest, reading kept
// nodes back from the spill file one sibling group (at most 8 nodes) at a time.
static sta_status run_merge_phase(convert_job *job, sta_error *err)
{
    const size_t rec = job->inputs.layout.size;
    sta_index_scratch scratch = { 0 };
    sta_status status = STA_OK;
    while (status == STA_OK && job->spilled_count > 0) {
        qsort(job->spilled, job->spilled_count, sizeof(*job->spilled), compare_spilled);
        int level = job->spilled[0].key.level;
        if (level == 0) {
            // Only the root is left.
            spilled_node *s = &job->spilled[0];
            sta_pending_node root = { s->key, sta_malloc(s->count * rec + 1), s->count, s->flags,
                                      s->has_children };
            status = root.records ? STA_OK : sta_fail(err, STA_ERR_NOMEM, "out of memory");
            if (status == STA_OK) {
                status = unspill(job, s, root.records, err);
            }
            if (status == STA_OK) {
                status = finish_node(job, &root, err);
            }
            sta_free(root.records);
            job->spilled_count = 0;
            break;
        }
        // Merge every sibling group of this level; parents are appended as new entries.
        size_t end = 0;
        while (end < job->spilled_count && job->spilled[end].key.level == level) {
            end++;
        }
        size_t level_end = end;
        for (size_t begin = 0; begin < level_end && status == STA_OK;) {
            size_t group_end = begin + 1;
            while (group_end < level_end &&
                   same_parent(&job->spilled[begin].key, &job->spilled[group_end].key)) {
                group_end++;
            }
            sta_pending_node children[8];
            size_t n = group_end - begin;
            memset(children, 0, sizeof(children));
            for (size_t i = 0; i < n && status == STA_OK; i++) {
                spilled_node *s = &job->spilled[begin + i];
                children[i] = (sta_pending_node){ s->key, sta_malloc(s->count * rec + 1), s->count,
                                                  s->flags, s->has_children };
                if (!children[i].records) {
                    status = sta_fail(err, STA_ERR_NOMEM, "out of memory merging nodes");
                } else {
                    status = unspill(job, s, children[i].records, err);
                }
            }
            sta_pending_node parent = { 0 };
            if (status == STA_OK) {
                status = sta_index_merge_parent(&job->plan.space, &job->inputs.layout, children, n,
                                                &scratch, &parent, err);
            }
            for (size_t i = 0; i < n && status == STA_OK; i++) {
                status = finish_node(job, &children[i], err);
            }
            if (status == STA_OK) {
                status = spill(job, &job->codecs[0], &parent, err); // may grow job->spilled
            }
            for (size_t i = 0; i < n; i++) {
                sta_free(children[i].records);
            }
            sta_free(parent.records);
            begin = group_end;
        }
        // Drop the merged level: its entries are the first level_end ones.
        memmove(job->spilled, job->spilled + level_end,
                (job->spilled_count - level_end) * sizeof(*job->spilled));
        job->spilled_count -= level_end;
    }
    sta_index_scratch_release(&scratch);
    return status;
}

static sta_status convert_extra_dims(const sta_input_set *set, sta_strata_extra_dim **out_dims,
                                     uint32_t *out_count, sta_error *err)
{
    *out_dims = NULL;
    *out_count = 0;
    if (set->extra_size == 0) {
        return STA_OK;
    }
    const sta_cloud_info *info = set->extra_source;
    sta_strata_extra_dim *dims = sta_calloc(info->extra_dim_count, sizeof(*dims));
    if (!dims) {
        return sta_fail(err, STA_ERR_NOMEM, "out of memory");
    }
    for (size_t i = 0; i < info->extra_dim_count; i++) {
        const sta_extra_dim *d = &info->extra_dims[i];
        snprintf(dims[i].name, sizeof(dims[i].name), "%s", d->name);
        snprintf(dims[i].description, sizeof(dims[i].description), "%s", d->description);
        dims[i].data_type = d->data_type;
        dims[i].size_bytes = (uint16_t)d->size_bytes;
        memcpy(dims[i].scale, d->scale, sizeof(dims[i].scale));
        memcpy(dims[i].offset, d->offset, sizeof(dims[i].offset));
    }
    *out_dims = dims;
    *out_count = (uint32_t)info->extra_dim_count;
    return STA_OK;
}

static int log2_exact(int v)
{
    int n = 0;
    while ((1 << n) < v) {
        n++;
    }
    return (1 << n) == v ? n : -1;
}

// Chunk size: a function of the point count only, never of --threads or --memory,
// because the chunk cut shapes the tree (deterministic output). Several chunks per
// core keep the workers busy to the end (largest go first).
static size_t plan_chunk_capacity(uint64_t point_count)
{
    uint64_t cap = point_count / CHUNKS_PER_SCENE + 1;
    cap = cap < CHUNK_MIN_POINTS ? CHUNK_MIN_POINTS : cap;
    return (size_t)(cap > CHUNK_MAX_POINTS ? CHUNK_MAX_POINTS : cap);
}

// Bytes one index worker needs for a chunk of `cap` points: records, index arrays,
// the node buffers of its largest node (at most a full grid) and the chunk's packed
// payloads held until their turn (at most the raw records).
static size_t worker_bytes(size_t cap, size_t record_size, int grid_log2,
                           const sta_normals_method *normals)
{
    if (normals) {
        // The normals come first and the index scratch is freed before them
        // (index_worker), so a worker holds the normals' scratch (cells or the kNN grid,
        // over the chunk and a halo of up to half as many points) or the index's buffers,
        // never both: besides the records and the node writer's column buffer, the larger.
        size_t grid_cells = (size_t)1 << (3 * grid_log2);
        size_t largest_node = cap < grid_cells ? cap : grid_cells;
        size_t with_halo = cap + cap / 2;
        size_t knn = cap * record_size + largest_node * record_size +
                     sta_normals_memory_bytes(*normals, with_halo) +
                     (cap / 2) * 3 * sizeof(int32_t);
        size_t plain = worker_bytes(cap, record_size, grid_log2, NULL);
        return knn > plain ? knn : plain;
    }
    size_t grid_cells = (size_t)1 << (3 * grid_log2);
    size_t per_point = record_size + 2 * sizeof(sta_index_item) + 1; // records, items, labels
    // Node buffers: the gathered records, the node writer's columns and the encoder's
    // shuffled and compressed copies (nodes are encoded from the packed records, never
    // unpacked into sta_point).
    size_t per_node_point = 4 * record_size;
    size_t largest_node = cap < grid_cells ? cap : grid_cells;
    return cap * (per_point + record_size) + largest_node * per_node_point;
}

// Bytes of --memory left after the fixed overhead.
static size_t budget_bytes(size_t memory_mib)
{
    return memory_mib > FIXED_OVERHEAD_MIB ? (memory_mib - FIXED_OVERHEAD_MIB) << 20
                                           : (size_t)32 << 20;
}

// How many chunks are indexed at once within the budget (see docs/CONVERTER.md):
// the fixed overhead, an eighth for the distribution buffers, the rest for workers.
static int plan_index_threads(size_t memory_mib, int threads, size_t cap, size_t record_size,
                              int grid_log2, const sta_normals_method *normals,
                              size_t *out_buffer_bytes)
{
    size_t budget = budget_bytes(memory_mib);
    *out_buffer_bytes = budget / 8;
    size_t need = worker_bytes(cap, record_size, grid_log2, normals);
    size_t fit = (budget - budget / 8) / need;
    if (fit == 0) {
        sta_log_warn("--memory %zu MiB is less than one chunk of %zu points needs: the run "
                     "will use about %zu MiB (the chunk size depends on the input only, so "
                     "that the output does not depend on --memory)",
                     memory_mib, cap, ((need + need / 7) >> 20) + FIXED_OVERHEAD_MIB);
        fit = 1;
    }
    return fit < (size_t)threads ? (int)fit : threads;
}

// Keeps the distributed records in memory, one array per chunk (no temporary runs),
// when they fit the budget beside the index workers (each then needs no records
// buffer of its own; with --normals the normals' scratch: worker_bytes) and no chunk
// has to be split (refine.c works on runs); the halo pass then reads the arrays. On
// false, or when an array cannot be had, the records go through the temporary runs;
// the output is the same either way.
static bool keep_records_in_memory(convert_job *job, size_t memory_mib, int index_threads,
                                   int grid_log2)
{
    const sta_convert_options *o = job->options;
    const sta_chunk_plan *plan = &job->plan;
    if (o->runs_on_disk || plan->chunk_count == 0) {
        return false;
    }
    for (size_t c = 0; c < plan->chunk_count; c++) {
        if (plan->chunks[c].count > job->chunk_capacity &&
            plan->chunks[c].key.level < plan->space.max_level) {
            return false;
        }
    }
    // The workers' scratch is planned for the largest chunk there is, not the capacity
    // (a 20 M street's largest chunk holds 1.9 M of 2.5 M points), and for at least the
    // smallest capacity's points: the figures per point hold for chunks that large
    // (small chunks take more a point: the tables' minimum sizes; docs/CONVERTER.md).
    const size_t rec = job->inputs.layout.size, cap = job->chunk_capacity;
    size_t sized = cap < CHUNK_MIN_POINTS ? cap : CHUNK_MIN_POINTS;
    for (size_t c = 0; c < plan->chunk_count; c++) {
        sized = plan->chunks[c].count > sized ? (size_t)plan->chunks[c].count : sized;
    }
    size_t worker =
        worker_bytes(sized, rec, grid_log2, o->normals ? &o->normals_method : NULL) - sized * rec;
    uint64_t need = plan->point_count * rec + (uint64_t)index_threads * worker;
    if (need > budget_bytes(memory_mib)) {
        return false;
    }
    job->chunk_records = sta_calloc(plan->chunk_count, sizeof(*job->chunk_records));
    for (size_t c = 0; job->chunk_records && c < plan->chunk_count; c++) {
        job->chunk_records[c] = sta_alloc_array((size_t)plan->chunks[c].count, rec);
        if (!job->chunk_records[c]) {
            free_chunk_records(job);
        }
    }
    return job->chunk_records != NULL;
}

// --normals: the governor's pool (memory_governor.h), the budget less the records kept
// in memory and, for every worker, its records buffer and the node writer's column
// buffer (its halo and its normals' heap come from the pool). A worker's index buffers
// are taken from the pool too while it indexes: *out_index_bytes, the plan's index
// buffers beyond those two. Never below one worker's planned normals
// (sta_normals_memory_bytes): when --memory is below that, plan_index_threads has said
// what the run will use.
static size_t normals_pool_bytes(const convert_job *job, size_t memory_mib, int index_threads,
                                 int grid_log2, size_t *out_index_bytes)
{
    const sta_chunk_plan *plan = &job->plan;
    const size_t rec = job->inputs.layout.size;
    size_t largest = 1;
    for (size_t c = 0; c < plan->chunk_count; c++) {
        largest = plan->chunks[c].count > largest ? (size_t)plan->chunks[c].count : largest;
    }
    size_t grid_cells = (size_t)1 << (3 * grid_log2);
    size_t node = (largest < grid_cells ? largest : grid_cells) * rec;
    size_t own_records = job->chunk_records ? 0 : largest * rec;
    size_t besides = own_records + node;
    size_t index = worker_bytes(largest, rec, grid_log2, NULL) - (largest * rec - own_records);
    *out_index_bytes = index > besides ? index - besides : 0;
    size_t held = job->chunk_records ? (size_t)plan->point_count * rec : 0;
    size_t budget = budget_bytes(memory_mib);
    size_t taken = held + (size_t)index_threads * besides;
    size_t least = sta_normals_memory_bytes(job->options->normals_method, largest + largest / 2);
    least = least > *out_index_bytes ? least : *out_index_bytes;
    return budget > taken + least ? budget - taken : least;
}

size_t sta_convert_default_memory_mib(uint64_t ram_mib)
{
    uint64_t quarter = ram_mib / 4;
    return quarter < STA_CONVERT_DEFAULT_MEMORY_MIB       ? STA_CONVERT_DEFAULT_MEMORY_MIB
           : quarter > STA_CONVERT_DEFAULT_MEMORY_MAX_MIB ? STA_CONVERT_DEFAULT_MEMORY_MAX_MIB
                                                          : (size_t)quarter;
}

uint64_t sta_convert_memory_limit_mib(const char *text)
{
    char *end = NULL;
    errno = 0;
    unsigned long long bytes = text ? strtoull(text, &end, 10) : 0;
    if (!text || end == text || errno != 0 || (*end && *end != '\n')) {
        return 0; // "max", empty or unreadable: no limit
    }
    return (uint64_t)(bytes >> 20);
}

// The cgroup's memory limit in MiB (v2, then v1), 0 when there is none to read.
static uint64_t cgroup_limit_mib(void)
{
    static const char *const files[] = { "/sys/fs/cgroup/memory.max",
                                         "/sys/fs/cgroup/memory/memory.limit_in_bytes" };
    for (size_t i = 0; i < sizeof(files) / sizeof(files[0]); i++) {
        FILE *f = fopen(files[i], "r");
        if (!f) {
            continue;
        }
        char line[64] = { 0 };
        bool read = fgets(line, sizeof(line), f) != NULL;
        fclose(f);
        if (read) {
            return sta_convert_memory_limit_mib(line);
        }
    }
    return 0;
}

// The memory this process may use: the machine's, or a container's limit below it.
static uint64_t physical_memory_mib(void)
{
    long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
    uint64_t ram = pages > 0 && page > 0 ? (uint64_t)pages * (uint64_t)page >> 20 : 0;
    uint64_t limit = cgroup_limit_mib();
    return limit && (!ram || limit < ram) ? limit : ram;
}

void sta_convert_options_defaults(sta_convert_options *o)
{
    if (o->threads <= 0) {
        long cores = sysconf(_SC_NPROCESSORS_ONLN);
        o->threads = (int)(cores > 0 ? cores : 1);
    }
    o->memory_mib =
        o->memory_mib ? o->memory_mib : sta_convert_default_memory_mib(physical_memory_mib());
    o->grid_cells = o->grid_cells ? o->grid_cells : (int)STA_STRATA_DEFAULT_CELLS;
    o->leaf_capacity = o->leaf_capacity ? o->leaf_capacity : STA_CONVERT_DEFAULT_LEAF_CAPACITY;
    o->compress_level = o->compress_level ? o->compress_level : STA_CONVERT_DEFAULT_ZSTD_LEVEL;
    o->knn = o->knn ? o->knn : STA_NORMALS_DEFAULT_K;
}

sta_status sta_convert(const sta_convert_options *options, sta_convert_report *report,
                       sta_error *err)
{
    sta_convert_report local_report;
    if (!report) {
        report = &local_report;
    }
    memset(report, 0, sizeof(*report));
    double t_start = sta_clock_s();
    sta_convert_options resolved = *options;
    sta_convert_options_defaults(&resolved);
    options = &resolved;
    convert_job job;
    memset(&job, 0, sizeof(job));
    job.options = options;
    job.chunk_fd = job.spill_fd = job.halo_fd = -1;
    pthread_mutex_init(&job.spill_lock, NULL);
    char *tmp_dir = NULL;
    sta_strata_extra_dim *extra_dims = NULL;
    sta_mirror_set mirrors = { 0 };
    sta_status status = STA_OK;

    int grid_cells = options->grid_cells;
    int grid_log2 = log2_exact(grid_cells);
    if (grid_log2 < 4 || grid_log2 > 10) {
        status = sta_fail(err, STA_ERR_ARG,
                          "grid cells must be a power of two from 16 to 1024, "
                          "got %d",
                          grid_cells);
        goto out;
    }
    if (options->normals && (options->knn < 3 || options->knn > STA_NORMALS_MAX_K)) {
        status = sta_fail(err, STA_ERR_ARG, "--knn must be 3 to %d, got %d", STA_NORMALS_MAX_K,
                          options->knn);
        goto out;
    }
    job.threads = options->threads > 256 ? 256 : options->threads;
    job.leaf_capacity = options->leaf_capacity;
    size_t memory_mib = options->memory_mib;
    int level = options->compress_level == STA_CONVERT_STORE ? 0 : options->compress_level;

    status = sta_path_checks_run(options->inputs, options->input_count, options->output,
                                 options->force, err);
    if (status != STA_OK) {
        goto out;
    }
    tmp_dir = options->tmp_dir ? sta_strdup(options->tmp_dir) : output_folder(options->output);
    if (!tmp_dir) {
        status = sta_fail(err, STA_ERR_NOMEM, "out of memory");
        goto out;
    }

    // 1. scan
    status = sta_inputs_open(options->inputs, options->input_count, options->salvage,
                             options->keep_extra, &job.inputs, err);
    if (status != STA_OK) {
        goto out;
    }
    if (options->mirrors) {
        status = sta_mirror_set_load(options->mirrors, &mirrors, err);
        if (status != STA_OK) {
            goto out;
        }
        // Every point gets the MIRROR byte (0 real); distribute classifies them.
        job.inputs.mirrors = &mirrors;
        job.inputs.attributes |= STA_ATTR_MIRROR;
        sta_record_layout_init(&job.inputs.layout, job.inputs.attributes, job.inputs.extra_size);
    }
    job.chunk_capacity = plan_chunk_capacity(job.inputs.point_count);
    if (options->chunk_points) {
        job.chunk_capacity = options->chunk_points;
    }
    size_t buffer_bytes = 0;
    if (options->normals) { // computed normals replace PLY ones (one normal per point)
        job.inputs.attributes =
            (job.inputs.attributes & ~(uint32_t)STA_ATTR_NORMAL) | STA_ATTR_SPLAT;
        sta_record_layout_init(&job.inputs.layout, job.inputs.attributes, job.inputs.extra_size);
    }
    int index_threads = plan_index_threads(
        memory_mib, job.threads, job.chunk_capacity, job.inputs.layout.size, grid_log2,
        options->normals ? &options->normals_method : NULL, &buffer_bytes);

    // 2. count and plan
    job.progress.enabled = options->progress;
    double t0 = sta_clock_s(), c0 = process_cpu_s();
    status = sta_distribute_plan(&job.inputs, job.threads, grid_log2, job.chunk_capacity,
                                 &job.progress, options->cancel, &job.plan, err);
    if (status != STA_OK) {
        goto out;
    }
    report->seconds_count = sta_clock_s() - t0;
    report->cpu_count = process_cpu_s() - c0;

    // The output writer: geometry from the plan, layout from the inputs.
    uint32_t extra_count = 0;
    status = convert_extra_dims(&job.inputs, &extra_dims, &extra_count, err);
    if (status != STA_OK) {
        goto out;
    }
    sta_strata_writer_options wopt;
    memset(&wopt, 0, sizeof(wopt));
    wopt.geometry.grid = job.inputs.grid;
    for (int a = 0; a < 3; a++) {
        wopt.geometry.root_corner[a] = job.plan.space.root_min[a];
        wopt.geometry.root_size_log2[a] = (uint8_t)job.plan.space.root_log2[a];
    }
    wopt.geometry.grid_cells = (uint32_t)grid_cells;
    wopt.zstd_level = level;
    wopt.generator = "strata-convert 0.1";
    wopt.up_axis = sta_inputs_up_axis(&job.inputs, report->up_why, sizeof(report->up_why));
    report->up_axis = wopt.up_axis;
    job.up_axis = wopt.up_axis;
    sta_las_source_keep las_source;
    status = sta_las_source_collect(&job.inputs, &las_source, err);
    if (status != STA_OK) {
        goto out;
    }
    wopt.las_source = las_source.present ? &las_source.source : NULL;
    status = sta_strata_layout_init(&wopt.layout,
                                    sta_strata_attributes_from_sta_attr(job.inputs.attributes),
                                    extra_dims, extra_count, err);
    if (status != STA_OK) {
        goto out;
    }
    status = sta_strata_writer_create(options->output, &wopt, &job.writer, err);
    sta_las_source_release(&las_source); // the writer keeps a copy
    if (status != STA_OK) {
        goto out;
    }
    status = sta_node_writer_init(&job.node_writer, job.writer, &job.inputs.layout, &wopt.layout,
                                  &wopt.geometry, job.threads, err);
    if (status != STA_OK) {
        goto out;
    }

    // 3. distribute
    status = make_temp(tmp_dir, options->output, "chunks", &job.chunk_path, &job.chunk_fd, err);
    if (status == STA_OK) {
        status = make_temp(tmp_dir, options->output, "merge", &job.spill_path, &job.spill_fd, err);
    }
    if (status != STA_OK) {
        goto out;
    }
    t0 = sta_clock_s();
    c0 = process_cpu_s();
    sta_progress_begin(&job.progress, "distributing", job.inputs.point_count, options->progress);
    status = sta_temp_runs_init(&job.runs, job.chunk_fd, job.chunk_path, job.inputs.layout.size,
                                job.plan.chunk_count, STA_TEMP_RUNS_PAGE_ALIGNMENT, err);
    if (status == STA_OK) {
        status = sta_temp_runs_init(&job.spill_runs, job.spill_fd, job.spill_path,
                                    job.inputs.layout.size, 0, 0, err);
    }
    job.runs.usage = job.spill_runs.usage = &job.temp_usage;
    if (status == STA_OK && keep_records_in_memory(&job, memory_mib, index_threads, grid_log2)) {
        report->records_in_memory = true;
        status = sta_distribute_to_memory(&job.inputs, &job.plan, job.chunk_records, &job.progress,
                                          options->cancel, err);
    } else if (status == STA_OK) {
        status = sta_distribute_write(&job.inputs, &job.plan, &job.runs, buffer_bytes,
                                      &job.progress, options->cancel, err);
    }
    sta_progress_end(&job.progress);
    if (status != STA_OK) {
        goto out;
    }
    status = sta_refine_chunks(&job.plan, &job.inputs.layout, &job.runs, job.chunk_capacity,
                               buffer_bytes, err); // in memory: nothing to split
    if (status != STA_OK) {
        goto out;
    }
    report->seconds_distribute = sta_clock_s() - t0;
    report->cpu_distribute = process_cpu_s() - c0;
    if (options->normals && job.plan.chunk_count > 0) {
        t0 = sta_clock_s();
        status = make_temp(tmp_dir, options->output, "halo", &job.halo_path, &job.halo_fd, err);
        if (status == STA_OK) {
            status =
                sta_temp_runs_init(&job.halo_runs, job.halo_fd, job.halo_path, 3 * sizeof(int32_t),
                                   job.plan.chunk_count, STA_TEMP_RUNS_PAGE_ALIGNMENT, err);
            job.halo_runs.usage = &job.temp_usage;
        }
        if (status == STA_OK) {
            status =
                sta_halo_collect(&job.plan, &job.inputs.grid, &job.inputs.layout, &job.runs,
                                 job.chunk_records, &job.halo_runs, &job.trajectory, options->knn,
                                 options->normals_method, index_threads, options->cancel, err);
        }
        if (status != STA_OK) {
            goto out;
        }
        report->seconds_halo = sta_clock_s() - t0;
        report->normals_trajectory = job.trajectory.usable;
    }
    job.codecs = sta_calloc((size_t)job.threads, sizeof(*job.codecs));
    if (!job.codecs) {
        status = sta_fail(err, STA_ERR_NOMEM, "out of memory");
        goto out;
    }

    if (options->normals) {
        size_t pool =
            normals_pool_bytes(&job, memory_mib, index_threads, grid_log2, &job.index_bytes);
        size_t budget = budget_bytes(memory_mib);
        job.below_plan =
            budget - budget / 8 < worker_bytes(job.chunk_capacity, job.inputs.layout.size,
                                               grid_log2, &options->normals_method);
        sta_memory_governor_init(&job.governor, pool);
        job.governed = true;
    }

    // 4. index chunks in parallel
    t0 = sta_clock_s();
    c0 = process_cpu_s();
    sta_progress_begin(&job.progress, "indexing", job.inputs.point_count, options->progress);
    if (job.plan.chunk_count > 0) {
        job.threads = index_threads; // distribution used them all; the index phase fewer
        status = run_index_phase(&job, err);
    }
    sta_progress_end(&job.progress);
    if (status != STA_OK) {
        goto out;
    }
    report->seconds_index = sta_clock_s() - t0;
    report->cpu_index = process_cpu_s() - c0;
    remove_temp(&job.chunk_path, &job.chunk_fd); // free the disk before the merge
    if (job.halo_fd >= 0) {
        remove_temp(&job.halo_path, &job.halo_fd);
    }
    report->normals_degenerate = job.normals.degenerate;
    report->normals_beyond_halo = job.normals.beyond_halo;
    report->normals_widened = job.normals.widened;
    report->normals_widened_exact = job.normals.widened_exact;
    if (job.governed) {
        report->normals_pool_bytes = job.governor.pool_bytes;
        report->normals_alone = job.governor.alone_runs;
        report->normals_waited_s = job.governor.waited_s;
        report->normals_chunk_peak_bytes = atomic_load(&job.normals_peak);
    }

    // 5. merge the top of the tree, then write table and header
    t0 = sta_clock_s();
    c0 = process_cpu_s();
    if (job.spilled_count == 0) {
        const sta_pending_node empty_root = { { 0, 0, 0, 0 }, NULL, 0, 0, 0 };
        status = finish_node(&job, &empty_root, err);
    } else {
        status = run_merge_phase(&job, err);
    }
    if (status != STA_OK) {
        goto out;
    }
    report->seconds_merge = sta_clock_s() - t0;
    report->cpu_merge = process_cpu_s() - c0;
    report->temp_bytes = atomic_load(&job.temp_usage.peak_bytes);
    t0 = sta_clock_s();
    c0 = process_cpu_s();
    status = sta_node_writer_finish(&job.node_writer, &report->node_count, &report->max_level, err);
    if (status != STA_OK) {
        goto out;
    }
    report->seconds_finish = sta_clock_s() - t0;
    report->cpu_finish = process_cpu_s() - c0;
    report->point_count = job.node_writer.point_count;
    report->raw_bytes = job.node_writer.raw_bytes;
    report->stored_bytes = job.node_writer.stored_bytes;
    report->chunk_count = job.plan.chunk_count;
    if (report->point_count != job.inputs.point_count) {
        status = sta_fail(err, STA_ERR_FORMAT, "internal error: wrote %llu points of %llu read",
                          (unsigned long long)report->point_count,
                          (unsigned long long)job.inputs.point_count);
    }
out:
    for (int t = 0; job.codecs && t < job.threads; t++) {
        sta_run_codec_release(&job.codecs[t]);
    }
    sta_free(job.codecs);
    free_chunk_records(&job);
    sta_temp_runs_release(&job.runs);
    sta_temp_runs_release(&job.spill_runs);
    sta_temp_runs_release(&job.halo_runs);
    sta_trajectory_release(&job.trajectory);
    if (job.governed) {
        sta_memory_governor_release(&job.governor);
    }
    remove_temp(&job.chunk_path, &job.chunk_fd);
    remove_temp(&job.halo_path, &job.halo_fd);
    remove_temp(&job.spill_path, &job.spill_fd);
    sta_node_writer_release(&job.node_writer);
    sta_strata_writer_destroy(job.writer); // removes the temporary output unless finished
    if (status != STA_OK && job.writer) {
        // finish may have renamed before a later check failed: never leave a bad file.
        if (report->point_count != job.inputs.point_count && report->node_count) {
            unlink(options->output);
        }
    }
    sta_chunk_plan_release(&job.plan);
    sta_inputs_close(&job.inputs);
    sta_mirror_set_release(&mirrors);
    sta_free(job.spilled);
    sta_free(job.chunk_order);
    sta_free(extra_dims);
    sta_free(tmp_dir);
    pthread_mutex_destroy(&job.spill_lock);
    report->seconds_total = sta_clock_s() - t_start;
    return status;
}

bool sta_convert_keep_heap(void)
{
    // One arena: the workers' freed chunks serve the next chunk of any worker (a thread's
    // own arena gives its 64 MiB heaps back whole once empty). The mapping threshold at
    // glibc's highest (32 MiB) and no trimming: a freed block stays mapped for the next.
    bool ok = mallopt(M_ARENA_MAX, 1) == 1;
    ok = mallopt(M_MMAP_THRESHOLD, 32 << 20) == 1 && ok;
    ok = mallopt(M_TRIM_THRESHOLD, INT_MAX) == 1 && ok;
    return ok;
}
