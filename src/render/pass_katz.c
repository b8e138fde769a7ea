/* SPDX-License-Identifier: MIT
 * The live Katz HPR mode: subsample, submit, take the newest set, draw its visible points
 * (see pass_katz.h). */
#include "render/pass_katz.h"

#include <math.h>
#include <string.h>

#include "core/alloc.h"
#include "render/gl.h"

void sta_katz_view_options_defaults(sta_katz_view_options *o)
{
    if (o->sample_points == 0) {
        o->sample_points = STA_DEFAULT_KATZ_SAMPLE_POINTS;
    }
    if (o->threads == 0) {
        o->threads = STA_KATZ_WORKER_DEFAULT_THREADS;
    }
    if (o->tolerance == 0.0) {
        o->tolerance = STA_KATZ_VIEW_DEFAULT_TOLERANCE;
    }
    if (o->oversample == 0.0) {
        o->oversample = STA_KATZ_VIEW_OVERSAMPLE;
    }
}

void sta_pass_katz_init(sta_pass_katz *p, uint32_t node_count, const double origin[3],
                        const sta_katz_view_options *options)
{
    memset(p, 0, sizeof(*p));
    p->options = options ? *options : (sta_katz_view_options){ 0 };
    sta_katz_view_options_defaults(&p->options);
    memcpy(p->origin, origin, sizeof(p->origin));
    p->node_count = node_count;
}

// The subsample's candidates per submission: the screen cells keep the nearest of them,
// about sample_points (katz_cells.h).
static size_t candidate_points(const sta_katz_view_options *o)
{
    double n = ceil((double)o->sample_points * (o->oversample >= 1.0 ? o->oversample : 1.0));
    return (size_t)n;
}

// The subsample and the gather scratch for options.sample_points at a draw list of
// `drawn_points`, filled from the nodes resident now (read back from the GPU cache once) and kept
// in step by sta_pass_katz_apply.
static sta_status make_sample(sta_pass_katz *p, const sta_gpu_cache *cache, uint64_t drawn_points,
                              sta_error *err)
{
    sta_point_sample_destroy(p->sample);
    p->sample = NULL;
    sta_free(p->points);
    sta_free(p->tags);
    p->capacity = candidate_points(&p->options);
    p->points = sta_alloc_array(p->capacity, sizeof(*p->points));
    p->tags = sta_alloc_array(p->capacity, sizeof(*p->tags));
    if (!p->points || !p->tags) {
        return sta_fail(err, STA_ERR_NOMEM, "katz view: out of memory for %zu points", p->capacity);
    }
    sta_status s =
        sta_point_sample_create(p->node_count, p->capacity, drawn_points, &p->sample, err);
    uint8_t *scratch = NULL;
    size_t scratch_count = 0;
    for (uint32_t node = 0; node < cache->node_count && s == STA_OK; node++) {
        const sta_gpu_cache_entry *e = &cache->entries[node];
        if (!e->is_resident || e->count == 0) {
            continue;
        }
        if (scratch_count < e->count) {
            sta_free(scratch);
            scratch = sta_alloc_array(e->count, STA_GPU_POINT_SIZE);
            scratch_count = scratch ? e->count : 0;
            if (!scratch) {
                s = sta_fail(err, STA_ERR_NOMEM, "katz view: out of memory for %u points",
                             e->count);
                break;
            }
        }
        glGetNamedBufferSubData(cache->buffer, (GLintptr)e->offset * STA_GPU_POINT_SIZE,
                                (GLsizeiptr)e->count * STA_GPU_POINT_SIZE, scratch);
        const sta_stream_upload upload = { node, e->count, scratch };
        const sta_stream_frame refill = { .upload = &upload, .upload_count = 1 };
        s = sta_point_sample_apply(p->sample, &refill, err);
    }
    sta_free(scratch);
    if (s == STA_OK) {
        s = sta_gl_check("reading the resident points back", err);
    }
    return s;
}

void sta_pass_katz_release(sta_pass_katz *p)
{
    sta_katz_worker_destroy(p->worker);
    sta_point_sample_destroy(p->sample);
    if (p->buffer) {
        glDeleteBuffers(1, &p->buffer);
    }
    sta_pass_geometry_release(&p->geometry);
    sta_free(p->points);
    sta_free(p->tags);
    sta_free(p->records);
    sta_free(p->ranges);
    memset(p, 0, sizeof(*p));
}

void sta_pass_katz_set_options(sta_pass_katz *p, const sta_katz_view_options *options)
{
    sta_katz_view_options o = *options;
    sta_katz_view_options_defaults(&o);
    bool restart = p->options.threads != o.threads || p->options.perturbation != o.perturbation ||
                   p->options.compare_plain != o.compare_plain;
    if (o.sample_points != p->options.sample_points || o.oversample != p->options.oversample) {
        sta_point_sample_destroy(p->sample); // remade (and refilled) on the next frame
        p->sample = NULL;
    }
    p->options = o;
    if (restart && p->worker) {
        sta_katz_worker_destroy(p->worker);
        p->worker = NULL;
    }
    p->submitted = 0; // resubmit on the next frame
}

sta_status sta_pass_katz_apply(sta_pass_katz *p, const sta_stream_frame *frame, sta_error *err)
{
    return p->sample ? sta_point_sample_apply(p->sample, frame, err) : STA_OK;
}

const sta_katz_set *sta_pass_katz_set(const sta_pass_katz *p)
{
    return p->drawn_generation ? p->drawn_set : NULL;
}

// Starts the subsample, the worker and the GL objects on the first enabled frame.
static sta_status start(sta_pass_katz *p, const sta_gpu_cache *cache, uint64_t drawn_points,
                        sta_error *err)
{
    // Remade when the draw list outgrew or shrank far from what the stride was made for
    // (4x: hysteresis), so that a submission has about sample_points points.
    const uint64_t candidates = candidate_points(&p->options);
    uint64_t wanted = drawn_points > candidates ? drawn_points : candidates;
    if (p->sample && drawn_points > 0) {
        uint64_t kept = drawn_points / sta_point_sample_stride(p->sample);
        if ((kept < candidates / 4 && sta_point_sample_stride(p->sample) > 1) ||
            kept > 4 * candidates) {
            sta_point_sample_destroy(p->sample);
            p->sample = NULL;
        }
    }
    if (!p->sample) {
        sta_status s = make_sample(p, cache, wanted, err);
        if (s != STA_OK) {
            return s;
        }
    }
    if (!p->geometry.program) {
        // GL_POINTS: the set is a few runs of points in a buffer of its own.
        const sta_geometry_options points = { .raster = STA_RASTER_POINTS };
        sta_status s = sta_pass_geometry_init(&p->geometry, &points, err);
        if (s != STA_OK) {
            return s;
        }
        glCreateBuffers(1, &p->buffer);
    }
    if (!p->worker) {
        sta_katz_worker_config config = { .thread_count = p->options.threads,
                                          .params = { .perturbation = p->options.perturbation },
                                          .compare_plain = p->options.compare_plain };
        sta_status s = sta_katz_worker_create(&config, &p->worker, err);
        if (s != STA_OK) {
            return s;
        }
        p->drawn_generation = 0;
        p->drawn_set = NULL;
        p->range_count = 0;
    }
    return sta_gl_check("starting the katz view", err);
}

// Changes to the draw list that call for a new submission: nodes and points drawn, and
// the nodes themselves (FNV-1a over the list).
static uint64_t draw_signature(const sta_stream_frame *frame)
{
    uint64_t h = 1469598103934665603ull ^ frame->points_drawn;
    for (size_t i = 0; i < frame->draw_count; i++) {
        h = (h ^ frame->draw[i]) * 1099511628211ull;
    }
    return h;
}

static bool same_camera(const sta_camera *a, const sta_camera *b)
{
    return memcmp(a->position, b->position, sizeof(a->position)) == 0 && a->yaw == b->yaw &&
           a->pitch == b->pitch && a->fov_y == b->fov_y && a->width_px == b->width_px &&
           a->height_px == b->height_px;
}

static sta_status submit(sta_pass_katz *p, const sta_camera *camera,
                         const sta_gpu_node_frame *frames, const sta_stream_frame *frame,
                         double s0_m, sta_error *err)
{
    size_t n = sta_point_sample_gather(p->sample, frames, frame->draw, frame->draw_count, p->origin,
                                       p->points, p->tags, p->capacity);
    // The cells give the hull about one point per cell; R stays the one-point-per-pixel
    // rule's (docs/KATZ.md, "Live mode": it measured better than R for the cell's pitch).
    double radius_m = sta_katz_view_radius(p->options.tolerance * s0_m,
                                           camera->fov_y / (double)camera->height_px);
    sta_status s =
        sta_katz_worker_submit_view(p->worker, (const float(*)[3])p->points, p->tags, n, camera,
                                    p->origin, p->options.sample_points, radius_m, p->frame, err);
    if (s != STA_OK) {
        return s;
    }
    sta_katz_worker_counters c;
    sta_katz_worker_counters_get(p->worker, &c);
    p->submitted = c.submitted;
    p->last_camera = *camera;
    p->last_signature = draw_signature(frame);
    p->last_radius_m = radius_m;
    return STA_OK;
}

// Copies the set's visible records, grouped into runs of one node, into the buffer.
static sta_status stage(sta_pass_katz *p, const sta_katz_set *set, sta_error *err)
{
    if (p->records_capacity < set->visible_count || p->range_capacity < set->visible_count) {
        size_t want = set->visible_count ? set->visible_count : 1;
        uint8_t *records = sta_alloc_array(want, STA_GPU_POINT_SIZE);
        struct sta_katz_range *ranges = sta_alloc_array(want, sizeof(*ranges));
        if (!records || !ranges) {
            sta_free(records);
            sta_free(ranges);
            return sta_fail(err, STA_ERR_NOMEM, "katz view: out of memory for %zu points", want);
        }
        sta_free(p->records);
        sta_free(p->ranges);
        p->records = records;
        p->ranges = ranges;
        p->records_capacity = p->range_capacity = want;
    }
    size_t n = 0;
    p->range_count = 0;
    for (size_t i = 0; i < set->count; i++) {
        if (!set->visible[i]) {
            continue;
        }
        uint32_t node = (uint32_t)(set->tags[i] >> 32);
        uint32_t index = (uint32_t)set->tags[i];
        uint32_t count = 0;
        const uint8_t *gpu = sta_point_sample_records(p->sample, node, &count);
        if (index >= count) {
            continue; // evicted since the submission
        }
        memcpy(p->records + n * STA_GPU_POINT_SIZE, gpu + (size_t)index * STA_GPU_POINT_SIZE,
               STA_GPU_POINT_SIZE);
        struct sta_katz_range *last = p->range_count ? &p->ranges[p->range_count - 1] : NULL;
        if (last && last->node == node) {
            last->count++;
        } else {
            p->ranges[p->range_count++] = (struct sta_katz_range){ node, (uint32_t)n, 1 };
        }
        n++;
    }
    glNamedBufferData(p->buffer, (GLsizeiptr)(n ? n : 1) * STA_GPU_POINT_SIZE, p->records,
                      GL_DYNAMIC_DRAW);
    p->drawn_generation = set->generation;
    return sta_gl_check("uploading the katz set", err);
}

static void draw(const sta_pass_katz *p, const sta_camera *camera,
                 const sta_geometry_colours *colours, const sta_gpu_node_frame *frames,
                 sta_render_target *target)
{
    const sta_pass_geometry *g = &p->geometry;
    sta_pass_geometry_begin_points(g, camera, colours, target);
    for (size_t i = 0; i < p->range_count; i++) {
        const struct sta_katz_range *r = &p->ranges[i];
        const sta_gpu_node_frame *f = &frames[r->node];
        glUniform3f(g->u_node_origin, (float)(f->corner[0] - camera->position[0]),
                    (float)(f->corner[1] - camera->position[1]),
                    (float)(f->corner[2] - camera->position[2]));
        glUniform3f(g->u_step, (float)f->step[0], (float)f->step[1], (float)f->step[2]);
        glUniform1ui(g->u_node_slot, r->node); // ids: the node and the run's point index
        glUniform1ui(g->u_arena_offset, 0);
        glVertexArrayVertexBuffer(g->vao, 0, p->buffer, (GLintptr)r->first * STA_GPU_POINT_SIZE,
                                  STA_GPU_POINT_SIZE);
        glDrawArrays(GL_POINTS, 0, (GLsizei)r->count);
    }
    glBindVertexArray(0);
}

sta_status sta_pass_katz_frame(sta_pass_katz *p, const sta_camera *camera,
                               const sta_geometry_colours *colours,
                               const sta_gpu_node_frame *frames, const sta_stream_frame *frame,
                               const sta_gpu_cache *cache, double s0_m, sta_render_target *target,
                               sta_katz_frame_stats *out, sta_error *err)
{
    p->frame++;
    sta_status s = start(p, cache, frame->points_drawn, err);
    if (s == STA_OK && (p->submitted == 0 || !same_camera(camera, &p->last_camera) ||
                        draw_signature(frame) != p->last_signature)) {
        s = submit(p, camera, frames, frame, s0_m, err);
    }
    if (s == STA_OK) {
        s = sta_katz_worker_take_error(p->worker, err);
    }
    const sta_katz_set *set = NULL;
    if (s == STA_OK && sta_katz_worker_acquire(p->worker, &set)) {
        s = stage(p, set, err);
        p->last = (sta_katz_frame_stats){ .generation = set->generation,
                                          .points = set->count,
                                          .visible = set->visible_count,
                                          .hull_ms = set->stats.hull_ms,
                                          .plain_hull_ms = set->plain_hull_ms,
                                          .radius_m = set->stats.radius };
        p->last_frame_of_set = set->frame;
        p->drawn_set = set;
    }
    if (s != STA_OK) {
        return s;
    }
    draw(p, camera, colours, frames, target);
    *out = p->last;
    out->age_frames = p->drawn_generation ? p->frame - p->last_frame_of_set : 0;
    out->current = p->drawn_generation != 0 && p->drawn_generation == p->submitted;
    return sta_gl_check("drawing the katz set", err);
}
