/* SPDX-License-Identifier: MIT
 * Halo collection: chunk runs read once more, border points copied to their neighbours. */
#include "halo.h"

#include <math.h>
#include <pthread.h>
#include <stdint.h>
#include <string.h>

#include "core/alloc.h"
#include "moment_normals.h"
#include "octree.h"

// The moments' finest level, from the whole scene (the same in every chunking).
static int scene_base_level(const sta_chunk_plan *plan, const sta_grid *grid,
                            sta_normals_method method)
{
    uint64_t points = 0;
    double extent[3], unit = 0.0;
    for (size_t c = 0; c < plan->chunk_count; c++) {
        points += plan->chunks[c].count;
    }
    for (int a = 0; a < 3; a++) {
        extent[a] = (double)(plan->actual_max[a] - plan->actual_min[a]) * grid->scale[a];
        unit = fmax(unit, grid->scale[a]);
    }
    return sta_moment_normals_base_level(method, points, extent, unit);
}

// A chunk's box (grid units, [min, max)) and its own margin in metres: kNN, a multiple
// of its estimated point spacing, at most its box edge; moments, the reach of the widest
// box (the same for every chunk, whatever its size: else a box could reach past it).
static double own_margin(const sta_chunk_plan *plan, const sta_grid *grid, size_t chunk, int k,
                         sta_normals_method method, int base_level, int64_t box[2][3])
{
    const sta_chunk *c = &plan->chunks[chunk];
    double edge = 0.0;
    for (int a = 0; a < 3; a++) {
        box[0][a] = sta_node_min(&plan->space, &c->key, a);
        box[1][a] = box[0][a] + ((int64_t)1 << sta_node_side_log2(&plan->space, c->key.level, a));
        edge = fmax(edge, (double)(box[1][a] - box[0][a]) * grid->scale[a]);
    }
    if (method != STA_NORMALS_KNN) {
        double unit = fmax(grid->scale[0], fmax(grid->scale[1], grid->scale[2]));
        return sta_moment_normals_reach(method, base_level, unit);
    }
    double spacing = edge / sqrt(fmax(1.0, (double)c->count));
    // Sized for the widest neighbourhood a point may be widened to (adaptive
    // neighbourhoods, knn_normals.h), not K: no larger than --knn 64's margin.
    double widest = (double)sta_normals_widest_k(k);
    return fmin(edge, STA_HALO_SPACINGS_PER_SQRT_K * sqrt(widest) * spacing);
}

static void grow_box(int64_t box[2][3], double margin, const sta_grid *grid, int64_t out[2][3])
{
    for (int a = 0; a < 3; a++) {
        int64_t m = (int64_t)ceil(margin / grid->scale[a]);
        out[0][a] = box[0][a] - m;
        out[1][a] = box[1][a] + m;
    }
}

static bool overlaps(int64_t a[2][3], int64_t b[2][3])
{
    for (int i = 0; i < 3; i++) {
        if (a[1][i] <= b[0][i] || b[1][i] <= a[0][i]) {
            return false;
        }
    }
    return true;
}

void sta_halo_chunk_frame(const sta_chunk_plan *plan, const sta_grid *grid, size_t chunk, int k,
                          sta_normals_method method, sta_normals_chunk *out)
{
    memset(out, 0, sizeof(*out));
    int64_t box[2][3], grown[2][3];
    int base_level = scene_base_level(plan, grid, method);
    double margin = own_margin(plan, grid, chunk, k, method, base_level, box);
    grow_box(box, margin, grid, grown);
    // What the chunk receives from a neighbour reaches min(its margin, the neighbour's)
    // into it (sta_halo_collect): the smallest over its neighbours bounds every face.
    double effective = margin;
    for (size_t c = 0; c < plan->chunk_count; c++) {
        int64_t other[2][3];
        double m = own_margin(plan, grid, c, k, method, base_level, other);
        if (c != chunk && plan->chunks[c].count > 0 && overlaps(grown, other)) {
            effective = fmin(effective, m);
        }
    }
    for (int a = 0; a < 3; a++) {
        out->scale[a] = grid->scale[a];
        out->box_min[a] = box[0][a];
        out->box_max[a] = box[1][a];
        out->scene_min[a] = plan->actual_min[a];
        out->scene_max[a] = plan->actual_max[a];
        out->scene_centre[a] = 0.5 * ((double)plan->actual_min[a] + (double)plan->actual_max[a]);
    }
    out->margin = effective;
    out->k = k;
    out->method = method;
    out->base_level = base_level;
}

typedef struct halo_job {
    const sta_chunk_plan *plan;
    const sta_grid *grid;
    const sta_record_layout *layout;
    sta_temp_runs *runs;
    uint8_t *const *in_memory; /* NULL: the records are read from `runs` */
    sta_temp_runs *halo;
    sta_trajectory *trajectory; /* NULL: none wanted (guard: lock) */
    int k;
    sta_normals_method method;
    int base_level;
    atomic_bool *cancel;
    int64_t (*box)[2][3];   /* per chunk: its box, grid units [min, max) */
    int64_t (*grown)[2][3]; /* per chunk: box grown by its own margin */
    double *margin;         /* per chunk: its own margin, metres */
    atomic_size_t next;
    atomic_bool failed;
    pthread_mutex_t lock;
    sta_error error; /* first failure (guard: lock) */
} halo_job;

typedef struct halo_out {
    size_t chunk;
    int64_t box[2][3]; /* the receiving chunk's box grown by min(its margin, the source's) */
    int32_t *xyz;
    size_t count, capacity;
} halo_out;

static bool inside(int64_t box[2][3], const int32_t p[3])
{
    return p[0] >= box[0][0] && p[0] < box[1][0] && p[1] >= box[0][1] && p[1] < box[1][1] &&
           p[2] >= box[0][2] && p[2] < box[1][2];
}

// A box inside `box` that meets none of the receivers' boxes (possibly empty): each
// receiver's box cut off by the cheapest of the six half-spaces beyond one of its faces.
// Its points, most of a chunk's, need no test against each receiver.
static void clear_of(const halo_out *outs, size_t out_count, int64_t box[2][3], int64_t clear[2][3])
{
    memcpy(clear, box, 2 * sizeof(clear[0]));
    for (size_t o = 0; o < out_count; o++) {
        const int64_t(*r)[3] = outs[o].box;
        int best_axis = -1, best_side = 0;
        int64_t best_cut = INT64_MAX;
        for (int a = 0; a < 3 && best_cut > 0; a++) {
            int64_t raise = r[1][a] - clear[0][a]; // clear's min up to r's max
            int64_t lower = clear[1][a] - r[0][a]; // clear's max down to r's min
            if (raise < best_cut) {
                best_cut = raise, best_axis = a, best_side = 0;
            }
            if (lower < best_cut) {
                best_cut = lower, best_axis = a, best_side = 1;
            }
        }
        if (best_cut <= 0) {
            continue; // (apart already)
        }
        if (best_side == 0) {
            clear[0][best_axis] = r[1][best_axis];
        } else {
            clear[1][best_axis] = r[0][best_axis];
        }
    }
}

// Appends one chunk's halo points for `out->chunk`, in blocks ordered after `source`.
static sta_status flush(halo_job *job, sta_run_codec *codec, size_t source, halo_out *out,
                        sta_error *err)
{
    const size_t per_block = STA_TEMP_RUNS_MAX_BLOCK_BYTES / (3 * sizeof(int32_t));
    sta_status status = STA_OK;
    uint64_t seq = 0;
    for (size_t at = 0; at < out->count && status == STA_OK; at += per_block, seq++) {
        size_t n = out->count - at < per_block ? out->count - at : per_block;
        status = sta_temp_runs_append(job->halo, codec, out->chunk, ((uint64_t)source << 32) | seq,
                                      (const uint8_t *)(out->xyz + 3 * at), n, err);
    }
    return status;
}

static sta_status one_chunk(halo_job *job, sta_run_codec *codec, size_t s, uint8_t **records,
                            size_t *capacity, sta_trajectory *path, sta_error *err)
{
    const sta_chunk_plan *plan = job->plan;
    const sta_chunk *chunk = &plan->chunks[s];
    size_t count = (size_t)chunk->count, rec = job->layout->size;
    halo_out *outs = NULL;
    size_t out_count = 0;
    for (size_t c = 0; c < plan->chunk_count; c++) {
        if (c != s && plan->chunks[c].count > 0 && overlaps(job->grown[c], job->box[s])) {
            halo_out *grown = sta_realloc_array(outs, out_count + 1, sizeof(*outs));
            if (!grown) {
                sta_free(outs);
                return sta_fail(err, STA_ERR_NOMEM, "halo: out of memory");
            }
            outs = grown;
            // A dense neighbour needs only a thin slice of this chunk, and this chunk's
            // points near a dense one find their neighbours there: the smaller margin.
            halo_out *o = &outs[out_count++];
            *o = (halo_out){ .chunk = c };
            grow_box(job->box[c], fmin(job->margin[c], job->margin[s]), job->grid, o->box);
        }
    }
    int64_t clear[2][3];
    clear_of(outs, out_count, job->box[s], clear);
    sta_status status = STA_OK;
    bool timed = path && (job->layout->attributes & STA_ATTR_GPS_TIME);
    const uint8_t *data = job->in_memory ? job->in_memory[s] : NULL;
    if ((out_count > 0 || timed) && count > 0 && !data) {
        if (count > *capacity) {
            sta_free(*records);
            *records = sta_alloc_array(count, rec);
            *capacity = *records ? count : 0;
        }
        status = *records
                     ? sta_temp_runs_read(job->runs, codec, chunk->list, *records, err)
                     : sta_fail(err, STA_ERR_NOMEM, "halo: out of memory for %zu points", count);
        data = *records;
    }
    for (size_t i = 0; status == STA_OK && (out_count > 0 || timed) && i < count; i++) {
        int32_t p[3];
        sta_record_position(data + i * rec, p);
        if (timed) {
            double t;
            memcpy(&t, data + i * rec + job->layout->gps_offset, sizeof(t));
            status = sta_trajectory_add(path, t, p, err);
        }
        bool near = out_count > 0 && !inside(clear, p);
        for (size_t o = 0; near && o < out_count; o++) {
            halo_out *out = &outs[o];
            if (!inside(out->box, p)) {
                continue;
            }
            if (out->count == out->capacity) {
                size_t cap = out->capacity ? 2 * out->capacity : 4096;
                int32_t *xyz = sta_realloc_array(out->xyz, cap, 3 * sizeof(int32_t));
                if (!xyz) {
                    status = sta_fail(err, STA_ERR_NOMEM, "halo: out of memory");
                    break;
                }
                out->xyz = xyz, out->capacity = cap;
            }
            memcpy(out->xyz + 3 * out->count++, p, sizeof(p));
        }
    }
    for (size_t o = 0; o < out_count; o++) {
        if (status == STA_OK) {
            status = flush(job, codec, s, &outs[o], err);
        }
        sta_free(outs[o].xyz);
    }
    sta_free(outs);
    return status;
}

static void *halo_worker(void *argument)
{
    halo_job *job = argument;
    sta_run_codec codec = { 0 };
    uint8_t *records = NULL;
    size_t capacity = 0;
    sta_error err = { 0 };
    sta_status status = STA_OK;
    sta_trajectory path = { 0 };
    while (status == STA_OK && !atomic_load(&job->failed)) {
        size_t s = atomic_fetch_add(&job->next, 1);
        if (s >= job->plan->chunk_count) {
            break;
        }
        status =
            one_chunk(job, &codec, s, &records, &capacity, job->trajectory ? &path : NULL, &err);
        if (status == STA_OK && job->cancel && atomic_load(job->cancel)) {
            status = sta_fail(&err, STA_ERR_CANCELLED, "cancelled");
        }
    }
    sta_free(records);
    sta_run_codec_release(&codec);
    if (status == STA_OK && job->trajectory) { // integer sums: any merge order
        pthread_mutex_lock(&job->lock);
        status = sta_trajectory_merge(job->trajectory, &path, &err);
        pthread_mutex_unlock(&job->lock);
    }
    sta_trajectory_release(&path);
    if (status != STA_OK) {
        pthread_mutex_lock(&job->lock);
        if (!atomic_load(&job->failed)) {
            job->error = err;
            atomic_store(&job->failed, true);
        }
        pthread_mutex_unlock(&job->lock);
    }
    return NULL;
}

sta_status sta_halo_collect(const sta_chunk_plan *plan, const sta_grid *grid,
                            const sta_record_layout *layout, sta_temp_runs *runs,
                            uint8_t *const *in_memory, sta_temp_runs *halo,
                            sta_trajectory *trajectory, int k, sta_normals_method method,
                            int threads, atomic_bool *cancel, sta_error *err)
{
    halo_job job = { .plan = plan,
                     .method = method,
                     .base_level = scene_base_level(plan, grid, method),
                     .trajectory = trajectory,
                     .grid = grid,
                     .layout = layout,
                     .runs = runs,
                     .in_memory = in_memory,
                     .halo = halo,
                     .k = k,
                     .cancel = cancel };
    size_t chunks = plan->chunk_count ? plan->chunk_count : 1;
    job.box = sta_alloc_array(chunks, sizeof(*job.box));
    job.grown = sta_alloc_array(chunks, sizeof(*job.grown));
    job.margin = sta_alloc_array(chunks, sizeof(*job.margin));
    if (!job.box || !job.grown || !job.margin) {
        sta_free(job.box);
        sta_free(job.grown);
        sta_free(job.margin);
        return sta_fail(err, STA_ERR_NOMEM, "halo: out of memory");
    }
    for (size_t c = 0; c < plan->chunk_count; c++) {
        job.margin[c] = own_margin(plan, grid, c, k, method, job.base_level, job.box[c]);
        grow_box(job.box[c], job.margin[c], grid, job.grown[c]);
    }
    atomic_init(&job.next, 0);
    atomic_init(&job.failed, false);
    pthread_mutex_init(&job.lock, NULL);
    threads = threads < 1 ? 1 : threads > 256 ? 256 : threads;
    pthread_t ids[256];
    int started = 0;
    for (int t = 0; t < threads; t++) {
        if (pthread_create(&ids[t], NULL, halo_worker, &job) != 0) {
            break;
        }
        started++;
    }
    if (started == 0) {
        halo_worker(&job);
    }
    for (int t = 0; t < started; t++) {
        pthread_join(ids[t], NULL);
    }
    pthread_mutex_destroy(&job.lock);
    sta_free(job.box);
    sta_free(job.grown);
    sta_free(job.margin);
    if (atomic_load(&job.failed)) {
        *err = job.error;
        return job.error.code;
    }
    for (size_t c = 0; c < plan->chunk_count; c++) {
        sta_temp_runs_sort(halo, c);
    }
    if (trajectory) {
        sta_trajectory_finish(trajectory, plan->actual_min, plan->actual_max);
    }
    return STA_OK;
}
