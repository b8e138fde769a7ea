/* SPDX-License-Identifier: MIT
 * Compute rasteriser (Schütz et al. 2021): node table, batches, atomics, resolve. */
#include "render/raster_compute.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/alloc.h"
#include "core/array.h"
#include "render/bindings.h"
#include "render/gl.h"
#include "render/pass_unproject.h"

/* One entry of the node table, as raster_common.glsl's raster_node (std430). */
typedef struct raster_node {
    float origin[4];
    float step[4];
    uint32_t info[4];         /* arena offset, count, first draw-order index, node slot */
    sta_raster_ref_rows rows; /* one-pixel projection and clip plane */
} raster_node;
_Static_assert(sizeof(raster_node) == 128, "raster_node mirrors the std430 struct");
_Static_assert(STA_RASTER_NO_POINT == STA_TARGET_NO_POINT, "the resolve writes the target's id");
_Static_assert(STA_RASTER_BATCH_POINTS <= 32 * STA_RASTER_WORKGROUP_SIZE,
               "an invocation's candidates are the bits of one uint");

static void uniforms(sta_raster_compute *r, int slot, GLuint program)
{
    r->u_view_rotation[slot] = glGetUniformLocation(program, "u_view_rotation");
    r->u_projection[slot] = glGetUniformLocation(program, "u_projection");
    r->u_size[slot] = glGetUniformLocation(program, "u_size");
    r->u_hide_flags[slot] = glGetUniformLocation(program, "u_hide_flags");
    r->u_clip_plane[slot] = glGetUniformLocation(program, "u_clip_plane");
    sta_footprint_uniforms_locate(&r->footprint[slot], program);
}

// The resolve of colour `mode` (writing positions or not), built on first use.
static sta_status resolve_program(sta_raster_compute *r, int mode, int position,
                                  sta_raster_resolve **out, sta_error *err)
{
    sta_raster_resolve *v = &r->resolve[mode][position];
    *out = v;
    if (v->program) {
        return STA_OK;
    }
    char defines[sizeof(r->resolve_defines) + 224];
    snprintf(defines, sizeof(defines),
             "%s#define STA_RASTER_COLOUR_MODE %d\n#define STA_RASTER_POSITION %d\n"
             "#define STA_POSITION_W_MARKED %.1f\n#define STA_POSITION_W_SEE_THROUGH %.1f\n"
             "#define STA_SEE_THROUGH_MIN_CLASS %d\n",
             r->resolve_defines, mode, position, (double)STA_POSITION_W_MARKED,
             (double)STA_POSITION_W_SEE_THROUGH, STA_SEE_THROUGH_MIN_CLASS);
    const char *sources[] = { "geometry_colour.glsl", "raster_common.glsl", "unproject_pixel.glsl",
                              "raster_resolve.vert", "raster_resolve.frag" };
    sta_status status = sta_gl_program_create(sources, 5, defines, &v->program, err);
    if (status != STA_OK) {
        return status;
    }
    GLuint p = v->program;
    v->u_view_rotation = glGetUniformLocation(p, "u_view_rotation");
    v->u_projection = glGetUniformLocation(p, "u_projection");
    v->u_size = glGetUniformLocation(p, "u_size");
    v->u_elevation = glGetUniformLocation(p, "u_elevation");
    v->u_intensity_scale = glGetUniformLocation(p, "u_intensity_scale");
    v->u_background = glGetUniformLocation(p, "u_background");
    v->u_unproject_size = glGetUniformLocation(p, "u_unproject_size");
    v->u_mark_classes = glGetUniformLocation(p, "u_mark_classes");
    v->u_tan_half = glGetUniformLocation(p, "u_tan_half");
    v->u_near = glGetUniformLocation(p, "u_near");
    return STA_OK;
}

enum {
    VARIANT_PIXEL,
    VARIANT_WIDE,
    VARIANT_PIXEL_PLANE
};

const char *sta_raster_int64_extensions(void)
{
    if (epoxy_has_gl_extension("GL_ARB_shader_atomic_int64") &&
        epoxy_has_gl_extension("GL_ARB_gpu_shader_int64")) {
        return "#extension GL_ARB_gpu_shader_int64 : require\n"
               "#extension GL_ARB_shader_atomic_int64 : require\n";
    }
    // NVIDIA's drivers expose the same atomics on uint64_t in buffers under their own name.
    if (epoxy_has_gl_extension("GL_NV_shader_atomic_int64") &&
        epoxy_has_gl_extension("GL_ARB_gpu_shader_int64")) {
        return "#extension GL_ARB_gpu_shader_int64 : require\n"
               "#extension GL_NV_shader_atomic_int64 : require\n";
    }
    return NULL;
}

// The point program of `slot`, built on first use. llvmpipe runs both sides of a branch
// even on a uniform, so the variants are separate programs: the one-pixel ones leave the
// footprint loop out (the depth step took 1.9x the CPU time with it, docs/BENCHMARKS.md)
// and, without a clip plane (every view but a mirror's), the plane's row.
static sta_status points_program(sta_raster_compute *r, int slot, sta_error *err)
{
    if (r->points_program[slot]) {
        return STA_OK;
    }
    const char *extensions = r->is_packed ? sta_raster_int64_extensions() : "";
    int step = r->is_packed                      ? STA_RASTER_STEP_PACKED
               : slot / STA_RASTER_VARIANTS == 0 ? STA_RASTER_STEP_DEPTH
                                                 : STA_RASTER_STEP_PAYLOAD;
    int variant = slot % STA_RASTER_VARIANTS;
    // The snapping of raster_common.glsl follows the driver's sub-pixel precision.
    char defines[512];
    snprintf(defines, sizeof(defines),
             "%s#define STA_RASTER_PACKED %d\n#define STA_RASTER_SUBPIXEL_BITS %d\n"
             "#define STA_RASTER_STEP %d\n#define STA_RASTER_WIDE %d\n%s",
             extensions, r->is_packed ? 1 : 0, r->subpixel_bits, step,
             variant == VARIANT_WIDE ? 1 : 0,
             variant == VARIANT_PIXEL ? "#define STA_RASTER_NO_PLANE\n" : "");
    const char *points[] = { "raster_common.glsl", "point_footprint.glsl", "raster_points.comp" };
    sta_status status = sta_gl_program_create(points, 3, defines, &r->points_program[slot], err);
    if (status == STA_OK) {
        uniforms(r, slot, r->points_program[slot]);
    }
    return status;
}

sta_status sta_raster_compute_init(sta_raster_compute *r, bool packed, sta_error *err)
{
    memset(r, 0, sizeof(*r));
    r->is_packed = packed;
    r->steps = packed ? 1 : 2;
    GLint subpixel_bits = 8;
    glGetIntegerv(GL_SUBPIXEL_BITS, &subpixel_bits);
    r->subpixel_bits = (int)subpixel_bits;
    glGetIntegerv(GL_MAX_TEXTURE_BUFFER_SIZE, &r->max_texels);
    sta_status status = STA_OK;
    for (int step = 0; step < r->steps && status == STA_OK; step++) {
        status = points_program(r, STA_RASTER_VARIANTS * step + VARIANT_PIXEL, err);
        if (status == STA_OK) {
            status = points_program(r, STA_RASTER_VARIANTS * step + VARIANT_WIDE, err);
        }
    }
    snprintf(r->resolve_defines, sizeof(r->resolve_defines),
             "%s#define STA_RASTER_PACKED %d\n#define STA_RASTER_SUBPIXEL_BITS %d\n",
             packed ? sta_raster_int64_extensions() : "", packed ? 1 : 0, (int)subpixel_bits);
    sta_raster_resolve *resolve = NULL;
    if (status == STA_OK) { // the default colours' resolve now, so that errors show early
        status = resolve_program(r, STA_COLOUR_RGB, 0, &resolve, err);
    }
    if (status != STA_OK) {
        sta_raster_compute_release(r);
        return status;
    }
    glCreateVertexArrays(1, &r->vao);
    glCreateTextures(GL_TEXTURE_BUFFER, 1, &r->points_texture);
    glCreateBuffers(1, &r->indirect);
    glNamedBufferStorage(r->indirect, 3 * sizeof(GLuint), NULL, GL_DYNAMIC_STORAGE_BIT);
    return sta_gl_check("creating the compute rasteriser", err);
}

static void delete_buffer(GLuint *buffer)
{
    if (*buffer) {
        glDeleteBuffers(1, buffer);
    }
    *buffer = 0;
}

void sta_raster_compute_release(sta_raster_compute *r)
{
    for (int i = 0; i < STA_RASTER_PROGRAMS; i++) {
        if (r->points_program[i]) {
            glDeleteProgram(r->points_program[i]);
        }
    }
    for (int i = 0; i < STA_COLOUR_MODE_COUNT; i++) {
        for (int k = 0; k < 2; k++) {
            if (r->resolve[i][k].program) {
                glDeleteProgram(r->resolve[i][k].program);
            }
        }
    }
    if (r->vao) {
        glDeleteVertexArrays(1, &r->vao);
    }
    if (r->points_texture) {
        glDeleteTextures(1, &r->points_texture);
    }
    delete_buffer(&r->nodes);
    delete_buffer(&r->batches);
    delete_buffer(&r->near_batches);
    delete_buffer(&r->candidates);
    delete_buffer(&r->indirect);
    delete_buffer(&r->depth);
    delete_buffer(&r->payload);
    sta_free(r->node_table);
    sta_free(r->batch_table);
    sta_free(r->near_table);
    sta_free(r->near_keys);
    memset(r, 0, sizeof(*r));
}

// (Re)creates `buffer` with at least `bytes` when it holds less.
static void ensure_buffer(GLuint *buffer, size_t *capacity, size_t bytes)
{
    if (*buffer && *capacity >= bytes) {
        return;
    }
    delete_buffer(buffer);
    size_t size = bytes + bytes / 2 + 256;
    glCreateBuffers(1, buffer);
    glNamedBufferStorage(*buffer, (GLsizeiptr)size, NULL, GL_DYNAMIC_STORAGE_BIT);
    *capacity = size;
}

static void ensure_pixels(sta_raster_compute *r, int width_px, int height_px)
{
    if (r->depth && r->width_px == width_px && r->height_px == height_px) {
        return;
    }
    delete_buffer(&r->depth);
    delete_buffer(&r->payload);
    size_t pixels = (size_t)width_px * (size_t)height_px;
    glCreateBuffers(1, &r->depth);
    glNamedBufferStorage(r->depth, (GLsizeiptr)(pixels * (r->is_packed ? 8 : 4)), NULL, 0);
    if (!r->is_packed) {
        glCreateBuffers(1, &r->payload);
        glNamedBufferStorage(r->payload, (GLsizeiptr)(pixels * 4), NULL, 0);
    }
    r->width_px = width_px;
    r->height_px = height_px;
}

// The node table and batch list of the frame, on the CPU; returns the batch count.
static sta_status build_tables(sta_raster_compute *r, const sta_camera *camera,
                               const sta_raster_ref_view *view, const sta_gpu_cache *cache,
                               const sta_gpu_node_frame *frames, const uint32_t *draw, size_t count,
                               size_t *out_batches, sta_error *err)
{
    sta_status status = sta_array_reserve(&r->node_table, &r->node_table_capacity,
                                          count ? count : 1, sizeof(raster_node), 64, err);
    size_t batches = 0;
    for (size_t i = 0; i < count && status == STA_OK; i++) {
        const sta_gpu_cache_entry *e = &cache->entries[draw[i]];
        const sta_gpu_node_frame *f = &frames[draw[i]];
        uint32_t points = e->is_resident ? e->count : 0;
        raster_node *n = (raster_node *)r->node_table + i;
        // As the GL_POINTS path: corner minus camera in double, then float.
        for (int axis = 0; axis < 3; axis++) {
            n->origin[axis] = (float)(f->corner[axis] - camera->position[axis]);
            n->step[axis] = (float)f->step[axis];
        }
        n->origin[3] = (float)f->spacing; // the adaptive point size reads it
        n->step[3] = 0.0f;
        sta_raster_ref_node_rows(view, n->origin, n->step, &n->rows);
        n->info[0] = e->offset;
        n->info[1] = points;
        n->info[2] = (uint32_t)batches;
        n->info[3] = draw[i];
        size_t node_batches = (points + STA_RASTER_BATCH_POINTS - 1) / STA_RASTER_BATCH_POINTS;
        // Draw-order indices are batch * STA_RASTER_BATCH_POINTS + point: below 2^32 - 1.
        if ((uint64_t)(batches + node_batches) * STA_RASTER_BATCH_POINTS >= STA_RASTER_NO_POINT) {
            return sta_fail(err, STA_ERR_ARG, "compute rasteriser: more than %llu batches",
                            (unsigned long long)(STA_RASTER_NO_POINT / STA_RASTER_BATCH_POINTS));
        }
        void *table = r->batch_table;
        status = sta_array_reserve(&table, &r->batch_table_capacity, batches + node_batches,
                                   2 * sizeof(uint32_t), 1024, err);
        r->batch_table = table;
        for (size_t b = 0; b < node_batches && status == STA_OK; b++) {
            r->batch_table[2 * batches] = (uint32_t)i;
            r->batch_table[2 * batches + 1] = (uint32_t)(b * STA_RASTER_BATCH_POINTS);
            batches++;
        }
    }
    *out_batches = batches;
    return status;
}

typedef struct near_key {
    float distance; /* camera to the node's box, m */
    uint32_t node;  /* node table index */
} near_key;

static int compare_near(const void *a, const void *b)
{
    const near_key *x = a, *y = b;
    if (x->distance != y->distance) {
        return x->distance < y->distance ? -1 : 1;
    }
    return x->node < y->node ? -1 : x->node > y->node;
}

// The batches again, nearest node first: the point steps' dispatch order. Depths only
// grow, so near points first leave the later, farther ones fewer atomics and fewer
// candidates; the result does not depend on the order (the draw-order indices come
// from the node table, and the atomics keep the nearest, then the smallest index).
static sta_status build_near_order(sta_raster_compute *r, size_t count, size_t batches,
                                   sta_error *err)
{
    sta_status status = sta_array_reserve(&r->near_keys, &r->near_keys_capacity, count ? count : 1,
                                          sizeof(near_key), 64, err);
    if (status == STA_OK) {
        void *table = r->near_table;
        status = sta_array_reserve(&table, &r->near_table_capacity, batches ? batches : 1,
                                   2 * sizeof(uint32_t), 1024, err);
        r->near_table = table;
    }
    if (status != STA_OK) {
        return status;
    }
    near_key *keys = r->near_keys;
    const raster_node *nodes = r->node_table;
    for (size_t i = 0; i < count; i++) {
        // The box of quantised positions 0..65535 per axis, relative to the camera.
        float d2 = 0.0f;
        for (int axis = 0; axis < 3; axis++) {
            float lo = nodes[i].origin[axis], hi = lo + 65535.0f * nodes[i].step[axis];
            float d = lo > 0.0f ? lo : hi < 0.0f ? -hi : 0.0f;
            d2 += d * d;
        }
        keys[i] = (near_key){ d2, (uint32_t)i };
    }
    qsort(keys, count, sizeof(near_key), compare_near);
    size_t b = 0;
    for (size_t k = 0; k < count; k++) {
        const uint32_t *info = nodes[keys[k].node].info;
        for (uint32_t first = 0; first < info[1]; first += STA_RASTER_BATCH_POINTS, b++) {
            r->near_table[2 * b] = keys[k].node;
            r->near_table[2 * b + 1] = first;
        }
    }
    return b == batches ? STA_OK
                        : sta_fail(err, STA_ERR_ARG,
                                   "compute rasteriser: %zu of %zu batches ordered", b, batches);
}

static void set_view(const sta_raster_compute *r, int slot, const float view[16],
                     const float projection[16], int width_px, int height_px)
{
    glUniformMatrix4fv(r->u_view_rotation[slot], 1, GL_FALSE, view);
    glUniformMatrix4fv(r->u_projection[slot], 1, GL_FALSE, projection);
    glUniform2i(r->u_size[slot], width_px, height_px);
}

sta_status sta_raster_compute_draw(sta_raster_compute *r, const sta_camera *camera,
                                   const sta_geometry_colours *colours,
                                   const sta_raster_ref_footprint *footprint,
                                   const sta_gpu_cache *cache, const sta_gpu_node_frame *frames,
                                   const uint32_t *draw, size_t count, sta_render_target *target,
                                   sta_error *err)
{
    static const float background[3] = { 0.0f, 0.0f, 0.0f };
    if (cache->capacity > (uint32_t)r->max_texels) {
        return sta_fail(err, STA_ERR_NOMEM,
                        "compute rasteriser: the GPU arena holds %u points, a texture buffer "
                        "shows at most %d (lower the GPU memory cap or use --raster points)",
                        cache->capacity, (int)r->max_texels);
    }
    // The view as the twin sees it: the node rows are formed from it.
    sta_raster_ref_view view = { .width_px = target->width_px,
                                 .height_px = target->height_px,
                                 .subpixel_bits = r->subpixel_bits,
                                 .node_rows = 1 };
    sta_camera_view_rotation(camera, view.view);
    sta_camera_projection(camera, view.projection);
    memcpy(view.clip_plane, colours->clip_plane, sizeof(view.clip_plane));
    size_t batches = 0;
    sta_status status = build_tables(r, camera, &view, cache, frames, draw, count, &batches, err);
    if (status != STA_OK) {
        return status;
    }
    if (status == STA_OK) {
        status = build_near_order(r, count, batches, err);
    }
    if (status != STA_OK) {
        return status;
    }
    if (batches == 0 || !cache->buffer) {
        sta_render_target_begin(target, background);
        return STA_OK;
    }
    int w = target->width_px, h = target->height_px;
    ensure_pixels(r, w, h);
    ensure_buffer(&r->nodes, &r->node_bytes, count * sizeof(raster_node));
    ensure_buffer(&r->batches, &r->batch_bytes, batches * 2 * sizeof(uint32_t));
    ensure_buffer(&r->near_batches, &r->near_batch_bytes, batches * 2 * sizeof(uint32_t));
    if (r->steps == 2) {
        ensure_buffer(&r->candidates, &r->candidate_bytes,
                      batches * STA_RASTER_WORKGROUP_SIZE * sizeof(uint32_t));
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, STA_RASTER_BUFFER_CANDIDATES, r->candidates);
    }
    glNamedBufferSubData(r->nodes, 0, (GLsizeiptr)(count * sizeof(raster_node)), r->node_table);
    glNamedBufferSubData(r->batches, 0, (GLsizeiptr)(batches * 2 * sizeof(uint32_t)),
                         r->batch_table);
    glNamedBufferSubData(r->near_batches, 0, (GLsizeiptr)(batches * 2 * sizeof(uint32_t)),
                         r->near_table);
    const GLuint groups[3] = { (GLuint)batches, 1, 1 };
    glNamedBufferSubData(r->indirect, 0, sizeof(groups), groups);
    if (r->arena_viewed != cache->buffer || r->arena_generation != cache->generation) {
        glTextureBuffer(r->points_texture, GL_RGBA32UI, cache->buffer);
        r->arena_viewed = cache->buffer;
        r->arena_generation = cache->generation;
    }
    const GLuint zero = 0, none = STA_RASTER_NO_POINT;
    glClearNamedBufferData(r->depth, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
    if (r->payload) {
        glClearNamedBufferData(r->payload, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &none);
    }
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, STA_RASTER_BUFFER_NODES, r->nodes);
    // The point steps read the batches nearest first; the resolve, in draw order.
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, STA_RASTER_BUFFER_BATCHES, r->near_batches);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, STA_RASTER_BUFFER_DEPTH, r->depth);
    if (r->payload) {
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, STA_RASTER_BUFFER_PAYLOAD, r->payload);
    }
    glBindTextureUnit(STA_RASTER_SAMPLER_POINTS, r->points_texture);
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, r->indirect);
    const float *rotation = view.view, *projection = view.projection;
    const float *plane = colours->clip_plane;
    bool has_plane = plane[0] != 0.0f || plane[1] != 0.0f || plane[2] != 0.0f || plane[3] != 0.0f;
    for (int step = 0; step < r->steps; step++) {
        int variant = footprint->wide ? VARIANT_WIDE
                      : has_plane     ? VARIANT_PIXEL_PLANE
                                      : VARIANT_PIXEL;
        int slot = STA_RASTER_VARIANTS * step + variant;
        status = points_program(r, slot, err);
        if (status != STA_OK) {
            glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, 0);
            return status;
        }
        glUseProgram(r->points_program[slot]);
        set_view(r, slot, rotation, projection, w, h);
        if (footprint->wide) {
            sta_footprint_uniforms_set(&r->footprint[slot], footprint);
        }
        glUniform1ui(r->u_hide_flags[slot], colours->hide_flags);
        glUniform4fv(r->u_clip_plane[slot], 1, colours->clip_plane);
        glDispatchComputeIndirect(0);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    }
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, 0);

    // Resolve: colour, depth and id of the kept point into the target.
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, STA_RASTER_BUFFER_BATCHES, r->batches);
    sta_raster_resolve *v = NULL;
    int mode = colours->mode >= 0 && colours->mode < STA_COLOUR_MODE_COUNT ? colours->mode
                                                                           : STA_COLOUR_RGB;
    int position = r->position_out ? 1 : 0;
    status = resolve_program(r, mode, position, &v, err);
    if (status != STA_OK) {
        return status;
    }
    glUseProgram(v->program);
    if (position) {
        glUniform2fv(v->u_unproject_size, 1, r->unproject_size);
        glUniform2fv(v->u_tan_half, 1, r->unproject_tan_half);
        glUniform1f(v->u_near, r->unproject_near);
        glUniform1uiv(v->u_mark_classes, STA_RASTER_MARK_CLASS_WORDS, r->mark_classes);
    }
    glUniformMatrix4fv(v->u_view_rotation, 1, GL_FALSE, rotation);
    glUniformMatrix4fv(v->u_projection, 1, GL_FALSE, projection);
    glUniform2i(v->u_size, w, h);
    double span = colours->elevation_span;
    glUniform2f(v->u_elevation, (float)(camera->position[2] - colours->elevation_min),
                (float)(1.0 / (span > 0 ? span : 1.0)));
    glUniform1f(v->u_intensity_scale, colours->intensity_scale);
    sta_ground_texture_use(colours->ground, v->program, camera);
    glUniform3fv(v->u_background, 1, background);
    sta_render_target_bind(target);
    if (position) { // a third colour attachment for this draw only
        glNamedFramebufferTexture(target->framebuffer, GL_COLOR_ATTACHMENT2, r->position_out, 0);
        glNamedFramebufferTexture(target->framebuffer, GL_COLOR_ATTACHMENT3, r->class_out, 0);
        const GLenum four[4] = { GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2,
                                 GL_COLOR_ATTACHMENT3 };
        glNamedFramebufferDrawBuffers(target->framebuffer, 4, four);
    }
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_ALWAYS);
    glBindVertexArray(r->vao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindVertexArray(0);
    glDepthFunc(GL_LESS);
    glDisable(GL_DEPTH_TEST);
    if (position) {
        const GLenum two[2] = { GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1 };
        glNamedFramebufferDrawBuffers(target->framebuffer, 2, two);
        glNamedFramebufferTexture(target->framebuffer, GL_COLOR_ATTACHMENT2, 0, 0);
        glNamedFramebufferTexture(target->framebuffer, GL_COLOR_ATTACHMENT3, 0, 0);
        glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT |
                        GL_FRAMEBUFFER_BARRIER_BIT);
    }
    return STA_OK;
}

void sta_raster_compute_set_position_out(sta_raster_compute *r, GLuint position_texture,
                                         GLuint class_texture, const sta_view_params *view,
                                         const uint32_t *mark_classes)
{
    r->position_out = position_texture;
    r->class_out = position_texture ? class_texture : 0;
    for (int i = 0; i < STA_RASTER_MARK_CLASS_WORDS; i++) {
        r->mark_classes[i] = mark_classes ? mark_classes[i] : 0;
    }
    if (position_texture) {
        sta_unproject_uniforms(view, r->unproject_size, r->unproject_tan_half);
        r->unproject_near = view->near_m;
    }
}
