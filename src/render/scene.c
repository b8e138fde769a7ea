/* SPDX-License-Identifier: MIT
 * Scene rendering: selection, streaming, geometry pass. */
#include "render/scene.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "core/alloc.h"
#include "core/log.h"
#include "render/bindings.h"
#include "render/gl.h"
#include "render/gpu_cache.h"
#include "stream/gpu_points.h"
#include "stream/loader.h"
#include "stream/select.h"

typedef struct s0_sample {
    double spacing;
    uint64_t weight;
} s0_sample;

struct sta_scene {
    sta_strata_reader *reader;
    sta_lod_tree tree;
    sta_gpu_node_frame *frames; /* per node dequantisation */
    sta_loader *loader;
    sta_gpu_cache cache;
    sta_selection selection;
    sta_scene_options options;
    uint8_t *bad; /* 1 for nodes refused by the loader */
    uint32_t bad_count;
    uint32_t *requests; /* scratch: selected, not resident */
    GLuint program;
    GLuint vao;
    GLint u_node_origin, u_step, u_view_rotation, u_projection, u_colour_mode, u_elevation,
        u_intensity_scale;
    int colour_mode;
    float intensity_scale;
    sta_pipeline pipeline; /* initialised on first use */
    bool has_pipeline;
    sta_pipeline_options pipeline_options;
    bool timing;           /* drain and time each pass */
    uint8_t *bad_scratch;  /* one byte per node, for estimate_s0 */
    s0_sample *s0_samples; /* one per node, for estimate_s0 */
};

// 16-bit colour files store 0..65535; 8-bit writers use 0..255. The root is a uniform
// subsample of the scene, so its largest value tells which.
static int detect_colour_shift(const sta_strata_reader *reader, float *out_intensity_scale)
{
    sta_strata_decoder *decoder = NULL;
    sta_error err = { 0 };
    int shift = 8;
    *out_intensity_scale = 1.0f / 65535.0f;
    if (sta_strata_decoder_create(&decoder, &err) != STA_OK) {
        return shift;
    }
    sta_strata_points points;
    if (sta_strata_decode_node(reader, 0, decoder, &points, &err) == STA_OK && points.count) {
        uint16_t colour_max = 0, intensity_max = 0;
        for (size_t i = 0; i < points.count; i++) {
            const sta_point *p = &points.points[i];
            uint16_t m = p->red > p->green ? p->red : p->green;
            m = m > p->blue ? m : p->blue;
            colour_max = m > colour_max ? m : colour_max;
            intensity_max = p->intensity > intensity_max ? p->intensity : intensity_max;
        }
        shift = colour_max > 255 ? 8 : 0;
        *out_intensity_scale = 1.0f / (float)(intensity_max > 0 ? intensity_max : 1);
    }
    sta_strata_decoder_destroy(decoder);
    return shift;
}

static sta_status create_pipeline(sta_scene *s, sta_error *err)
{
    const char *names[] = { "geometry.vert", "geometry.frag" };
    sta_status status = sta_gl_program_create(names, 2, NULL, &s->program, err);
    if (status != STA_OK) {
        return status;
    }
    s->u_node_origin = glGetUniformLocation(s->program, "u_node_origin");
    s->u_step = glGetUniformLocation(s->program, "u_step");
    s->u_view_rotation = glGetUniformLocation(s->program, "u_view_rotation");
    s->u_projection = glGetUniformLocation(s->program, "u_projection");
    s->u_colour_mode = glGetUniformLocation(s->program, "u_colour_mode");
    s->u_elevation = glGetUniformLocation(s->program, "u_elevation");
    s->u_intensity_scale = glGetUniformLocation(s->program, "u_intensity_scale");
    glCreateVertexArrays(1, &s->vao);
    glVertexArrayAttribIFormat(s->vao, STA_ATTRIB_POSITION_INTENSITY, 4, GL_UNSIGNED_SHORT, 0);
    glVertexArrayAttribIFormat(s->vao, STA_ATTRIB_COLOUR_CLASS, 4, GL_UNSIGNED_BYTE, 8);
    glVertexArrayAttribIFormat(s->vao, STA_ATTRIB_RETURNS, 4, GL_UNSIGNED_BYTE, 12);
    const GLuint attributes[3] = { STA_ATTRIB_POSITION_INTENSITY, STA_ATTRIB_COLOUR_CLASS,
                                   STA_ATTRIB_RETURNS };
    for (int i = 0; i < 3; i++) {
        glVertexArrayAttribBinding(s->vao, attributes[i], 0);
        glEnableVertexArrayAttrib(s->vao, attributes[i]);
    }
    return sta_gl_check("creating the geometry pass", err);
}

sta_status sta_scene_open(const char *path, const sta_scene_options *options, sta_scene **out_scene,
                          sta_error *err)
{
    *out_scene = NULL;
    sta_scene *s = sta_calloc(1, sizeof(*s));
    if (!s) {
        return sta_fail(err, STA_ERR_NOMEM, "out of memory");
    }
    if (options) {
        s->options = *options;
    }
    if (!s->options.gpu_bytes_cap) {
        s->options.gpu_bytes_cap = (uint64_t)1 << 30;
    }
    if (!s->options.upload_bytes_per_frame) {
        s->options.upload_bytes_per_frame = (uint64_t)64 << 20;
    }
    if (!s->options.loader_threads) {
        long cores = sysconf(_SC_NPROCESSORS_ONLN);
        s->options.loader_threads = cores > 1 ? (int)cores - 1 : 1;
    }
    sta_status status = sta_strata_open(path, NULL, &s->reader, err);
    if (status == STA_OK) {
        status = sta_lod_tree_init(&s->tree, s->reader, err);
    }
    const sta_strata_info *info = status == STA_OK ? sta_strata_reader_info(s->reader) : NULL;
    if (status == STA_OK) {
        s->frames = sta_alloc_array(info->node_count, sizeof(*s->frames));
        s->bad = sta_calloc(info->node_count, 1);
        s->requests = sta_alloc_array(info->node_count, sizeof(*s->requests));
        s->bad_scratch = sta_alloc_array(info->node_count, 1);
        s->s0_samples = sta_alloc_array(info->node_count, sizeof(*s->s0_samples));
        if (!s->frames || !s->bad || !s->requests || !s->bad_scratch || !s->s0_samples) {
            status = sta_fail(err, STA_ERR_NOMEM, "%s: out of memory", path);
        }
    }
    if (status == STA_OK) {
        for (uint32_t i = 0; i < info->node_count; i++) {
            sta_gpu_node_frame_init(&s->frames[i], &info->geometry,
                                    sta_strata_reader_node(s->reader, i)->key);
        }
        status = sta_gpu_cache_init(&s->cache, info->node_count, s->options.gpu_bytes_cap, err);
    }
    if (status == STA_OK) {
        sta_loader_options lo = { .threads = s->options.loader_threads };
        lo.colour_shift = detect_colour_shift(s->reader, &s->intensity_scale);
        status = sta_loader_create(s->reader, &lo, &s->loader, err);
    }
    if (status == STA_OK) {
        status = create_pipeline(s, err);
    }
    if (status != STA_OK) {
        sta_scene_close(s);
        return status;
    }
    *out_scene = s;
    return STA_OK;
}

void sta_scene_close(sta_scene *s)
{
    if (!s) {
        return;
    }
    sta_loader_destroy(s->loader); // before the reader it reads from
    if (s->program) {
        glDeleteProgram(s->program);
        glDeleteVertexArrays(1, &s->vao);
    }
    if (s->has_pipeline) {
        sta_pipeline_release(&s->pipeline);
    }
    if (s->cache.entries) {
        sta_gpu_cache_release(&s->cache);
    }
    sta_selection_release(&s->selection);
    sta_lod_tree_release(&s->tree);
    sta_strata_close(s->reader);
    sta_free(s->frames);
    sta_free(s->bad);
    sta_free(s->requests);
    sta_free(s->bad_scratch);
    sta_free(s->s0_samples);
    sta_free(s);
}

const sta_strata_info *sta_scene_info(const sta_scene *s)
{
    return sta_strata_reader_info(s->reader);
}

static int compare_doubles(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : (x > y ? 1 : 0);
}

void sta_scene_robust_bounds(const sta_scene *s, double out_min[3], double out_max[3])
{
    const sta_strata_info *info = sta_scene_info(s);
    memcpy(out_min, info->bounds_min, 3 * sizeof(double));
    memcpy(out_max, info->bounds_max, 3 * sizeof(double));
    sta_strata_decoder *decoder = NULL;
    sta_error err = { 0 };
    if (sta_strata_decoder_create(&decoder, &err) != STA_OK) {
        return;
    }
    sta_strata_points points;
    double *values = NULL;
    if (sta_strata_decode_node(s->reader, 0, decoder, &points, &err) == STA_OK &&
        points.count >= 100 && (values = sta_alloc_array(points.count, sizeof(double)))) {
        const sta_grid *grid = &info->geometry.grid;
        for (int a = 0; a < 3; a++) {
            for (size_t i = 0; i < points.count; i++) {
                const int32_t xyz[3] = { points.points[i].X, points.points[i].Y,
                                         points.points[i].Z };
                values[i] = sta_grid_apply(grid, a, xyz[a]);
            }
            qsort(values, points.count, sizeof(double), compare_doubles);
            out_min[a] = values[points.count / 100];
            out_max[a] = values[points.count - 1 - points.count / 100];
        }
    }
    sta_free(values);
    sta_strata_decoder_destroy(decoder);
}

void sta_scene_set_pipeline(sta_scene *s, const sta_pipeline_options *options)
{
    s->pipeline_options = *options;
}

void sta_scene_set_timing(sta_scene *s, bool on)
{
    s->timing = on;
}

// Bouchiba's s0, the typical distance between neighbouring points: for each selected
// node none of whose children is selected (where refinement stops), points are taken
// to lie on a surface crossing the node, so their spacing is about edge / sqrt(n), n
// counting the node's points plus the ancestors' share in its box (1/4 per level up:
// n * 4/3). s0 is the point-weighted median of these estimates.

static int compare_s0(const void *a, const void *b)
{
    double x = ((const s0_sample *)a)->spacing, y = ((const s0_sample *)b)->spacing;
    return x < y ? -1 : (x > y ? 1 : 0);
}

static float estimate_s0(sta_scene *s)
{
    const sta_selection *sel = &s->selection;
    if (sel->count == 0) {
        return 0.0f;
    }
    // Mark selected nodes (requests scratch is free here: it holds uint32 per node).
    uint8_t *selected = s->bad_scratch;
    memset(selected, 0, s->tree.count);
    for (size_t i = 0; i < sel->count; i++) {
        selected[sel->nodes[i]] = 1;
    }
    size_t n = 0;
    uint64_t total = 0;
    for (size_t i = 0; i < sel->count; i++) {
        const sta_lod_node *node = &s->tree.nodes[sel->nodes[i]];
        bool refined = false;
        uint32_t child = node->first_child;
        for (int slot = 0; slot < 8; slot++) {
            if (node->child_mask & (1u << slot)) {
                refined = refined || (child < s->tree.count && selected[child]);
                child++;
            }
        }
        if (refined || node->point_count == 0) {
            continue;
        }
        double edge = fmax(node->max[0] - node->min[0],
                           fmax(node->max[1] - node->min[1], node->max[2] - node->min[2]));
        s->s0_samples[n].spacing = edge / sqrt((double)node->point_count * 4.0 / 3.0);
        s->s0_samples[n].weight = node->point_count;
        total += node->point_count;
        n++;
    }
    if (n == 0) {
        return 0.0f;
    }
    qsort(s->s0_samples, n, sizeof(s0_sample), compare_s0);
    uint64_t seen = 0;
    for (size_t i = 0; i < n; i++) {
        seen += s->s0_samples[i].weight;
        if (2 * seen >= total) {
            return (float)s->s0_samples[i].spacing;
        }
    }
    return (float)s->s0_samples[n - 1].spacing;
}

int sta_scene_pipeline_mode(const sta_scene *s)
{
    return s->pipeline_options.mode;
}

const sta_pipeline *sta_scene_pipeline(const sta_scene *s)
{
    return s->has_pipeline ? &s->pipeline : NULL;
}

void sta_scene_set_colour_mode(sta_scene *s, int mode)
{
    s->colour_mode = mode >= 0 && mode < STA_COLOUR_MODE_COUNT ? mode : STA_COLOUR_RGB;
}

// Takes finished nodes from the loader and uploads up to the per-frame byte budget.
static uint32_t upload_finished(sta_scene *s)
{
    uint64_t uploaded = 0;
    uint32_t uploads = 0;
    sta_loaded_node done;
    while (uploaded < s->options.upload_bytes_per_frame && sta_loader_take(s->loader, &done)) {
        if (done.status != STA_OK) {
            if (!s->bad[done.node]) {
                s->bad[done.node] = 1;
                s->bad_count++;
                sta_log_warn("%s: skipping a node that cannot be shown: %s",
                             sta_scene_info(s)->path, done.message);
            }
        } else if (sta_gpu_cache_upload(&s->cache, done.node, done.gpu, (uint32_t)done.count)) {
            uploaded += done.count * STA_GPU_POINT_SIZE;
            uploads++;
        }
        sta_loaded_node_release(&done);
    }
    return uploads;
}

sta_status sta_scene_render(sta_scene *s, const sta_camera *camera, sta_render_target *target,
                            sta_frame_stats *stats, sta_error *err)
{
    memset(stats, 0, sizeof(*stats));
    sta_status status = sta_render_target_resize(target, camera->width_px, camera->height_px, err);
    if (status != STA_OK) {
        return status;
    }
    sta_gpu_cache_begin_frame(&s->cache);
    // The budget can never ask for more than the GPU cache holds.
    uint64_t budget = s->options.budget_points ? s->options.budget_points : 30000000;
    uint64_t cache_points = s->options.gpu_bytes_cap / STA_GPU_POINT_SIZE;
    sta_select_params params = { budget < cache_points ? budget : cache_points,
                                 s->options.min_spacing_px };
    status = sta_select(&s->tree, camera, &params, &s->selection, err);
    if (status != STA_OK) {
        return status;
    }
    // Keep what this frame wants from being evicted by its own uploads.
    for (size_t i = 0; i < s->selection.count; i++) {
        uint32_t node = s->selection.nodes[i];
        if (sta_gpu_cache_is_resident(&s->cache, node)) {
            sta_gpu_cache_touch(&s->cache, node);
        }
    }
    stats->uploads = upload_finished(s);
    size_t wanted = 0;
    bool complete = true;
    for (size_t i = 0; i < s->selection.count; i++) {
        uint32_t node = s->selection.nodes[i];
        if (!sta_gpu_cache_is_resident(&s->cache, node) && !s->bad[node]) {
            s->requests[wanted++] = node;
            complete = false;
        }
    }
    status = sta_loader_request(s->loader, s->requests, wanted, err);
    if (status != STA_OK) {
        return status;
    }

    static const float background[3] = { 0.0f, 0.0f, 0.0f };
    struct timespec geometry_start;
    if (s->timing) {
        glFinish();
        clock_gettime(CLOCK_MONOTONIC, &geometry_start);
    }
    sta_render_target_begin(target, background);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_GREATER); // reverse-Z: larger is nearer
    glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
    glEnable(GL_PROGRAM_POINT_SIZE);
    glUseProgram(s->program);
    glBindVertexArray(s->vao);
    float view[16], projection[16];
    sta_camera_view_rotation(camera, view);
    sta_camera_projection(camera, projection);
    glUniformMatrix4fv(s->u_view_rotation, 1, GL_FALSE, view);
    glUniformMatrix4fv(s->u_projection, 1, GL_FALSE, projection);
    glUniform1i(s->u_colour_mode, s->colour_mode);
    const sta_strata_info *info = sta_scene_info(s);
    double z_range = info->bounds_max[2] - info->bounds_min[2];
    glUniform2f(s->u_elevation, (float)(camera->position[2] - info->bounds_min[2]),
                (float)(1.0 / (z_range > 0 ? z_range : 1.0)));
    glUniform1f(s->u_intensity_scale, s->intensity_scale);
    for (size_t i = 0; i < s->selection.count; i++) {
        uint32_t node = s->selection.nodes[i];
        if (!sta_gpu_cache_is_resident(&s->cache, node)) {
            continue;
        }
        const sta_cache_entry *e = &s->cache.entries[node];
        sta_gpu_cache_touch(&s->cache, node);
        const sta_gpu_node_frame *f = &s->frames[node];
        // Node corner relative to the camera in double, then float: exact enough
        // wherever the scene sits on Earth.
        glUniform3f(s->u_node_origin, (float)(f->corner[0] - camera->position[0]),
                    (float)(f->corner[1] - camera->position[1]),
                    (float)(f->corner[2] - camera->position[2]));
        glUniform3f(s->u_step, (float)f->step[0], (float)f->step[1], (float)f->step[2]);
        if (e->count > 0) {
            glVertexArrayVertexBuffer(s->vao, 0, e->buffer, 0, STA_GPU_POINT_SIZE);
            glDrawArrays(GL_POINTS, 0, (GLsizei)e->count);
        }
        stats->points_drawn += e->count;
        stats->nodes_drawn++;
    }
    glBindVertexArray(0);
    if (s->timing) {
        glFinish();
        struct timespec end;
        clock_gettime(CLOCK_MONOTONIC, &end);
        stats->geometry_ms = (double)(end.tv_sec - geometry_start.tv_sec) * 1e3 +
                             (double)(end.tv_nsec - geometry_start.tv_nsec) * 1e-6;
    }
    stats->s0_m = s->pipeline_options.s0_m > 0 ? s->pipeline_options.s0_m : estimate_s0(s);
    if (s->pipeline_options.mode != STA_PIPELINE_RAW) {
        if (!s->has_pipeline) {
            status = sta_pipeline_init(&s->pipeline, err);
            if (status != STA_OK) {
                return status;
            }
            s->has_pipeline = true;
        }
        sta_view_params screen = { camera->width_px, camera->height_px, (float)camera->fov_y,
                                   (float)camera->near_m, stats->s0_m > 0 ? stats->s0_m : 0.01f };
        status = sta_pipeline_run(&s->pipeline, &s->pipeline_options, &screen, target->depth,
                                  target->colour, s->timing ? &stats->timing : NULL, err);
        if (status != STA_OK) {
            return status;
        }
    }
    stats->points_selected = s->selection.point_count;
    stats->nodes_selected = (uint32_t)s->selection.count;
    stats->nodes_resident = s->cache.resident_count;
    stats->gpu_bytes = s->cache.bytes_used;
    stats->loader_backlog = sta_loader_backlog(s->loader);
    stats->bad_nodes = s->bad_count;
    stats->evictions = s->cache.evictions;
    stats->complete = complete && stats->loader_backlog == 0;
    return sta_gl_check("drawing the scene", err);
}
