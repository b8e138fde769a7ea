/* SPDX-License-Identifier: MIT
 * Splat pass: instanced quads or a geometry shader, one disk per point. */
#include "render/pass_splats.h"

#include <math.h>
#include <string.h>

#include "core/log.h"
#include "render/bindings.h"
#include "render/gl.h"
#include "render/ref/shade_ref.h"
#include "stream/gpu_splats.h"

static const char *const method_names[STA_SPLAT_METHOD_COUNT] = { "default", "instanced",
                                                                  "geometry", "pulled" };

void sta_splat_options_defaults(sta_splat_options *o)
{
    if (o->method <= STA_SPLAT_DEFAULT || o->method >= STA_SPLAT_METHOD_COUNT) {
        o->method = STA_SPLAT_DEFAULT_METHOD;
    }
    if (!(o->scale > 0.0f)) {
        o->scale = STA_SPLAT_DEFAULT_SCALE;
    }
    if (!(o->min_radius_px > 0.0f)) {
        o->min_radius_px = STA_SPLAT_DEFAULT_MIN_RADIUS_PX;
    }
}

int sta_splat_default_method(const char *renderer)
{
    if (!renderer || strstr(renderer, "llvmpipe") || strstr(renderer, "softpipe")) {
        return STA_SPLAT_DEFAULT_METHOD;
    }
    return STA_SPLAT_INSTANCED;
}

int sta_splat_method_from_name(const char *name)
{
    for (int i = STA_SPLAT_INSTANCED; i < STA_SPLAT_METHOD_COUNT; i++) {
        if (strcmp(name, method_names[i]) == 0) {
            return i;
        }
    }
    return -1;
}

const char *sta_splat_method_name(int method)
{
    return method >= 0 && method < STA_SPLAT_METHOD_COUNT ? method_names[method] : "?";
}

sta_status sta_pass_splats_init(sta_pass_splats *p, int method, sta_error *err)
{
    memset(p, 0, sizeof(*p));
    bool is_default = !(method > STA_SPLAT_DEFAULT && method < STA_SPLAT_METHOD_COUNT);
    p->method =
        is_default ? sta_splat_default_method((const char *)glGetString(GL_RENDERER)) : method;
    sta_log_info("splats: %s (%s)", method_names[p->method],
                 is_default ? "the default on this renderer" : "as asked");
    const char *instanced[] = { "geometry_colour.glsl", "splat_common.glsl", "splat_quad.vert",
                                "splat_disk.frag" };
    const char *geometry[] = { "geometry_colour.glsl", "splat_common.glsl", "splat_point.vert",
                               "splat_disk.geom", "splat_disk.frag" };
    const char *pulled[] = { "geometry_colour.glsl", "splat_common.glsl", "splat_pulled.vert",
                             "splat_disk.frag" };
    sta_status status = p->method == STA_SPLAT_INSTANCED
                            ? sta_gl_program_create(instanced, 4, NULL, &p->program, err)
                        : p->method == STA_SPLAT_GEOMETRY
                            ? sta_gl_program_create(geometry, 5, NULL, &p->program, err)
                            : sta_gl_program_create(pulled, 4, NULL, &p->program, err);
    if (status != STA_OK) {
        return status;
    }
    GLuint g = p->program;
    p->u_node_origin = glGetUniformLocation(g, "u_node_origin");
    p->u_step = glGetUniformLocation(g, "u_step");
    p->u_view_rotation = glGetUniformLocation(g, "u_view_rotation");
    p->u_projection = glGetUniformLocation(g, "u_projection");
    p->u_colour_mode = glGetUniformLocation(g, "u_colour_mode");
    p->u_elevation = glGetUniformLocation(g, "u_elevation");
    p->u_intensity_scale = glGetUniformLocation(g, "u_intensity_scale");
    p->u_node_slot = glGetUniformLocation(g, "u_node_slot");
    p->u_arena_offset = glGetUniformLocation(g, "u_arena_offset");
    p->u_splat_scale = glGetUniformLocation(g, "u_splat_scale");
    p->u_default_radius = glGetUniformLocation(g, "u_default_radius");
    p->u_min_radius_px = glGetUniformLocation(g, "u_min_radius_px");
    p->u_pixel_angle = glGetUniformLocation(g, "u_pixel_angle");
    p->u_light = glGetUniformLocation(g, "u_light");
    p->u_lit = glGetUniformLocation(g, "u_lit");
    p->u_hide_flags = glGetUniformLocation(g, "u_hide_flags");

    // Points and splats from two buffers (bindings 0 and 1), the arena's slots in step;
    // per instance on the instanced path, per vertex on the geometry-shader path.
    glCreateVertexArrays(1, &p->vao);
    glVertexArrayAttribIFormat(p->vao, STA_ATTRIB_POSITION_INTENSITY, 4, GL_UNSIGNED_SHORT, 0);
    glVertexArrayAttribIFormat(p->vao, STA_ATTRIB_COLOUR_CLASS, 4, GL_UNSIGNED_BYTE, 8);
    glVertexArrayAttribIFormat(p->vao, STA_ATTRIB_RETURNS, 4, GL_UNSIGNED_BYTE, 12);
    glVertexArrayAttribIFormat(p->vao, STA_ATTRIB_SPLAT, 2, GL_UNSIGNED_INT, 0);
    const GLuint attributes[4] = { STA_ATTRIB_POSITION_INTENSITY, STA_ATTRIB_COLOUR_CLASS,
                                   STA_ATTRIB_RETURNS, STA_ATTRIB_SPLAT };
    for (int i = 0; i < 4; i++) {
        glVertexArrayAttribBinding(p->vao, attributes[i], i == 3 ? 1 : 0);
        glEnableVertexArrayAttrib(p->vao, attributes[i]);
    }
    GLuint divisor = p->method == STA_SPLAT_INSTANCED ? 1 : 0;
    glVertexArrayBindingDivisor(p->vao, 0, divisor);
    glVertexArrayBindingDivisor(p->vao, 1, divisor);
    if (p->method == STA_SPLAT_PULLED) {
        glCreateTextures(GL_TEXTURE_BUFFER, 1, &p->points_texture);
        glCreateTextures(GL_TEXTURE_BUFFER, 1, &p->splats_texture);
    }
    status = sta_gl_check("creating the splat pass", err);
    if (status != STA_OK) {
        sta_pass_splats_release(p);
    }
    return status;
}

void sta_pass_splats_release(sta_pass_splats *p)
{
    if (p->program) {
        glDeleteProgram(p->program);
        glDeleteVertexArrays(1, &p->vao);
    }
    if (p->points_texture) {
        glDeleteTextures(1, &p->points_texture);
        glDeleteTextures(1, &p->splats_texture);
    }
    memset(p, 0, sizeof(*p));
}

static void set_uniforms(const sta_pass_splats *p, const sta_splat_options *o,
                         const sta_camera *camera, const sta_geometry_colours *colours,
                         float default_radius_m)
{
    float view[16], projection[16];
    sta_camera_view_rotation(camera, view);
    sta_camera_projection(camera, projection);
    glUniformMatrix4fv(p->u_view_rotation, 1, GL_FALSE, view);
    glUniformMatrix4fv(p->u_projection, 1, GL_FALSE, projection);
    glUniform1i(p->u_colour_mode, colours->mode);
    double span = colours->elevation_span;
    glUniform2f(p->u_elevation, (float)(camera->position[2] - colours->elevation_min),
                (float)(1.0 / (span > 0 ? span : 1.0)));
    glUniform1f(p->u_intensity_scale, colours->intensity_scale);
    glUniform1ui(p->u_hide_flags, colours->hide_flags); // mirror ghosts, as the geometry pass
    sta_ground_texture_use(colours->ground, p->program, camera);
    glUniform1f(p->u_splat_scale, o->scale);
    glUniform1f(p->u_default_radius, default_radius_m);
    glUniform1f(p->u_min_radius_px, o->min_radius_px);
    glUniform1f(p->u_pixel_angle, sta_splat_pixel_angle(camera));
    glUniform4f(p->u_light, STA_SHADE_DEFAULT_AMBIENT, STA_SHADE_DEFAULT_DIFFUSE,
                STA_SHADE_DEFAULT_SPECULAR, STA_SHADE_DEFAULT_SHININESS);
    glUniform1i(p->u_lit, o->unlit ? 0 : 1);
}

// The pulled path reads the arenas through texture buffers; a repack makes new ones.
static void view_arenas(sta_pass_splats *p, const sta_gpu_cache *cache)
{
    if (p->points_viewed != cache->buffer || p->arenas_generation != cache->generation) {
        glTextureBuffer(p->points_texture, GL_RGBA32UI, cache->buffer);
        glTextureBuffer(p->splats_texture, GL_RG32UI, cache->splat_buffer);
        p->points_viewed = cache->buffer;
        p->arenas_generation = cache->generation;
    }
    glBindTextureUnit(STA_SPLAT_SAMPLER_POINTS, p->points_texture);
    glBindTextureUnit(STA_SPLAT_SAMPLER_SPLATS, p->splats_texture);
}

sta_status sta_pass_splats_draw(sta_pass_splats *p, const sta_splat_options *options,
                                const sta_camera *camera, const sta_geometry_colours *colours,
                                const sta_gpu_cache *cache, const sta_gpu_node_frame *frames,
                                const uint32_t *draw, size_t count, float default_radius_m,
                                sta_render_target *target, sta_error *err)
{
    sta_splat_options o = *options;
    sta_splat_options_defaults(&o);
    static const float background[3] = { 0.0f, 0.0f, 0.0f };
    sta_render_target_begin(target, background);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_GREATER); // reverse-Z: larger is nearer
    glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
    glUseProgram(p->program);
    glBindVertexArray(p->vao);
    set_uniforms(p, &o, camera, colours, default_radius_m);
    if (cache->buffer && cache->splat_buffer) {
        glVertexArrayVertexBuffer(p->vao, 0, cache->buffer, 0, STA_GPU_POINT_SIZE);
        glVertexArrayVertexBuffer(p->vao, 1, cache->splat_buffer, 0, STA_GPU_SPLAT_SIZE);
        if (p->method == STA_SPLAT_PULLED) {
            view_arenas(p, cache);
        }
        for (size_t i = 0; i < count; i++) {
            const sta_gpu_cache_entry *e = &cache->entries[draw[i]];
            const sta_gpu_node_frame *f = &frames[draw[i]];
            if (!e->is_resident || e->count == 0) {
                continue;
            }
            // Node corner relative to the camera in double, then float (as the geometry pass).
            glUniform3f(p->u_node_origin, (float)(f->corner[0] - camera->position[0]),
                        (float)(f->corner[1] - camera->position[1]),
                        (float)(f->corner[2] - camera->position[2]));
            glUniform3f(p->u_step, (float)f->step[0], (float)f->step[1], (float)f->step[2]);
            glUniform1ui(p->u_node_slot, draw[i]);
            glUniform1ui(p->u_arena_offset, e->offset);
            if (p->method == STA_SPLAT_INSTANCED) {
                glDrawArraysInstancedBaseInstance(GL_TRIANGLE_STRIP, 0, 4, (GLsizei)e->count,
                                                  e->offset);
            } else if (p->method == STA_SPLAT_GEOMETRY) {
                glDrawArrays(GL_POINTS, (GLint)e->offset, (GLsizei)e->count);
            } else {
                glDrawArrays(GL_TRIANGLES, (GLint)(6 * (uint64_t)e->offset),
                             (GLsizei)(6 * (uint64_t)e->count));
            }
        }
    }
    glBindVertexArray(0);
    return sta_gl_check("drawing splats", err);
}
