/* SPDX-License-Identifier: MIT
 * Geometry pass: the chosen rasteriser; GL_POINTS (one pixel per point) drawn here. */
#include "render/pass_geometry.h"

#include <stdio.h>
#include <string.h>

#include "core/log.h"
#include "render/bindings.h"
#include "render/gl.h"

static sta_status init_points(sta_pass_geometry *p, sta_error *err)
{
    const char *names[] = { "geometry_colour.glsl", "geometry.vert", "geometry.frag" };
    sta_status status = sta_gl_program_create(names, 3, NULL, &p->program, err);
    if (status != STA_OK) {
        return status;
    }
    p->u_node_origin = glGetUniformLocation(p->program, "u_node_origin");
    p->u_step = glGetUniformLocation(p->program, "u_step");
    p->u_view_rotation = glGetUniformLocation(p->program, "u_view_rotation");
    p->u_projection = glGetUniformLocation(p->program, "u_projection");
    p->u_colour_mode = glGetUniformLocation(p->program, "u_colour_mode");
    p->u_elevation = glGetUniformLocation(p->program, "u_elevation");
    p->u_intensity_scale = glGetUniformLocation(p->program, "u_intensity_scale");
    p->u_node_slot = glGetUniformLocation(p->program, "u_node_slot");
    p->u_arena_offset = glGetUniformLocation(p->program, "u_arena_offset");
    p->u_hide_flags = glGetUniformLocation(p->program, "u_hide_flags");
    p->u_clip_plane = glGetUniformLocation(p->program, "u_clip_plane");
    glCreateVertexArrays(1, &p->vao);
    glVertexArrayAttribIFormat(p->vao, STA_ATTRIB_POSITION_INTENSITY, 4, GL_UNSIGNED_SHORT, 0);
    glVertexArrayAttribIFormat(p->vao, STA_ATTRIB_COLOUR_CLASS, 4, GL_UNSIGNED_BYTE, 8);
    glVertexArrayAttribIFormat(p->vao, STA_ATTRIB_RETURNS, 4, GL_UNSIGNED_BYTE, 12);
    const GLuint attributes[3] = { STA_ATTRIB_POSITION_INTENSITY, STA_ATTRIB_COLOUR_CLASS,
                                   STA_ATTRIB_RETURNS };
    for (int i = 0; i < 3; i++) {
        glVertexArrayAttribBinding(p->vao, attributes[i], 0);
        glEnableVertexArrayAttrib(p->vao, attributes[i]);
    }
    return sta_gl_check("creating the geometry pass", err);
}

static sta_status init_wide(sta_pass_geometry *p, sta_error *err)
{
    // The footprint snaps as the rasteriser does, to the driver's sub-pixel precision.
    GLint subpixel_bits = 8;
    glGetIntegerv(GL_SUBPIXEL_BITS, &subpixel_bits);
    char defines[64];
    snprintf(defines, sizeof(defines), "#define STA_RASTER_SUBPIXEL_BITS %d\n", (int)subpixel_bits);
    const char *names[] = { "geometry_colour.glsl", "point_footprint.glsl", "geometry_wide.vert",
                            "geometry_wide.frag" };
    sta_status status = sta_gl_program_create(names, 4, defines, &p->wide_program, err);
    if (status != STA_OK) {
        return status;
    }
    GLuint w = p->wide_program;
    p->w_node_origin = glGetUniformLocation(w, "u_node_origin");
    p->w_step = glGetUniformLocation(w, "u_step");
    p->w_spacing = glGetUniformLocation(w, "u_spacing");
    p->w_view_rotation = glGetUniformLocation(w, "u_view_rotation");
    p->w_projection = glGetUniformLocation(w, "u_projection");
    p->w_size = glGetUniformLocation(w, "u_size");
    p->w_colour_mode = glGetUniformLocation(w, "u_colour_mode");
    p->w_elevation = glGetUniformLocation(w, "u_elevation");
    p->w_intensity_scale = glGetUniformLocation(w, "u_intensity_scale");
    p->w_node_slot = glGetUniformLocation(w, "u_node_slot");
    p->w_arena_offset = glGetUniformLocation(w, "u_arena_offset");
    p->w_hide_flags = glGetUniformLocation(w, "u_hide_flags");
    p->w_clip_plane = glGetUniformLocation(w, "u_clip_plane");
    sta_footprint_uniforms_locate(&p->w_footprint, w);
    return sta_gl_check("creating the wide-point program", err);
}

sta_status sta_pass_geometry_init(sta_pass_geometry *p, const sta_geometry_options *options,
                                  sta_error *err)
{
    memset(p, 0, sizeof(*p));
    sta_geometry_choose(options, sta_raster_int64_extensions() != NULL, &p->choice);
    sta_log_info("%s", p->choice.reason);
    sta_status status = p->choice.raster == STA_RASTER_COMPUTE
                            ? sta_raster_compute_init(&p->compute, p->choice.packed, err)
                            : init_points(p, err);
    if (status == STA_OK && p->choice.raster != STA_RASTER_COMPUTE) {
        status = init_wide(p, err);
    }
    if (status != STA_OK) {
        sta_pass_geometry_release(p);
    }
    return status;
}

void sta_pass_geometry_release(sta_pass_geometry *p)
{
    if (p->program) {
        glDeleteProgram(p->program);
        glDeleteVertexArrays(1, &p->vao);
    }
    if (p->wide_program) {
        glDeleteProgram(p->wide_program);
    }
    sta_raster_compute_release(&p->compute);
    memset(p, 0, sizeof(*p));
}

void sta_pass_geometry_begin_points(const sta_pass_geometry *p, const sta_camera *camera,
                                    const sta_geometry_colours *colours, sta_render_target *target)
{
    static const float background[3] = { 0.0f, 0.0f, 0.0f };
    sta_render_target_begin(target, background);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_GREATER); // reverse-Z: larger is nearer
    glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
    glEnable(GL_PROGRAM_POINT_SIZE);
    glUseProgram(p->program);
    glBindVertexArray(p->vao);
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
    glUniform1ui(p->u_hide_flags, colours->hide_flags);
    const float *plane = colours->clip_plane;
    glUniform4fv(p->u_clip_plane, 1, plane);
    if (plane[0] != 0.0f || plane[1] != 0.0f || plane[2] != 0.0f || plane[3] != 0.0f) {
        glEnable(GL_CLIP_DISTANCE0);
    } else {
        glDisable(GL_CLIP_DISTANCE0);
    }
    sta_ground_texture_use(colours->ground, p->program, camera);
}

void sta_pass_geometry_set_point_size(sta_pass_geometry *p, const sta_point_size *size)
{
    if (size) {
        p->point_size = *size;
    } else {
        sta_point_size_defaults(&p->point_size);
    }
}

// The wide program in place of the one-pixel one: the same view and colours, plus the
// target size and the footprint.
static void begin_wide(const sta_pass_geometry *p, const sta_camera *camera,
                       const sta_geometry_colours *colours,
                       const sta_raster_ref_footprint *footprint, sta_render_target *target)
{
    glUseProgram(p->wide_program);
    float view[16], projection[16];
    sta_camera_view_rotation(camera, view);
    sta_camera_projection(camera, projection);
    glUniformMatrix4fv(p->w_view_rotation, 1, GL_FALSE, view);
    glUniformMatrix4fv(p->w_projection, 1, GL_FALSE, projection);
    glUniform2i(p->w_size, target->width_px, target->height_px);
    glUniform1i(p->w_colour_mode, colours->mode);
    double span = colours->elevation_span;
    glUniform2f(p->w_elevation, (float)(camera->position[2] - colours->elevation_min),
                (float)(1.0 / (span > 0 ? span : 1.0)));
    glUniform1f(p->w_intensity_scale, colours->intensity_scale);
    glUniform1ui(p->w_hide_flags, colours->hide_flags);
    glUniform4fv(p->w_clip_plane, 1, colours->clip_plane); // GL_CLIP_DISTANCE0 as begin set it
    sta_ground_texture_use(colours->ground, p->wide_program, camera);
    sta_footprint_uniforms_set(&p->w_footprint, footprint);
}

static void draw_points(const sta_pass_geometry *p, const sta_camera *camera,
                        const sta_geometry_colours *colours,
                        const sta_raster_ref_footprint *footprint, const sta_gpu_cache *cache,
                        const sta_gpu_node_frame *frames, const uint32_t *draw, size_t count,
                        sta_render_target *target)
{
    sta_pass_geometry_begin_points(p, camera, colours, target);
    bool wide = footprint->wide != 0;
    if (wide) {
        begin_wide(p, camera, colours, footprint, target);
    }
    bool classes = p->class_out && !wide;
    if (classes) { // a class attachment for this draw only
        glNamedFramebufferTexture(target->framebuffer, GL_COLOR_ATTACHMENT3, p->class_out, 0);
        const GLenum four[4] = { GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_NONE,
                                 GL_COLOR_ATTACHMENT3 };
        glNamedFramebufferDrawBuffers(target->framebuffer, 4, four);
    }
    if (cache->buffer) {
        glVertexArrayVertexBuffer(p->vao, 0, cache->buffer, 0, STA_GPU_POINT_SIZE);
    }
    for (size_t i = 0; i < count; i++) {
        const sta_gpu_cache_entry *e = &cache->entries[draw[i]];
        const sta_gpu_node_frame *f = &frames[draw[i]];
        if (!e->is_resident || e->count == 0) {
            continue;
        }
        // Node corner relative to the camera in double, then float: exact enough
        // wherever the scene sits on Earth.
        glUniform3f(wide ? p->w_node_origin : p->u_node_origin,
                    (float)(f->corner[0] - camera->position[0]),
                    (float)(f->corner[1] - camera->position[1]),
                    (float)(f->corner[2] - camera->position[2]));
        glUniform3f(wide ? p->w_step : p->u_step, (float)f->step[0], (float)f->step[1],
                    (float)f->step[2]);
        glUniform1ui(wide ? p->w_node_slot : p->u_node_slot, draw[i]);
        glUniform1ui(wide ? p->w_arena_offset : p->u_arena_offset, e->offset);
        if (wide) {
            glUniform1f(p->w_spacing, (float)f->spacing);
        }
        glDrawArrays(GL_POINTS, (GLint)e->offset, (GLsizei)e->count);
    }
    glBindVertexArray(0);
    glDisable(GL_CLIP_DISTANCE0);
    if (classes) {
        const GLenum two[2] = { GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1 };
        glNamedFramebufferDrawBuffers(target->framebuffer, 2, two);
        glNamedFramebufferTexture(target->framebuffer, GL_COLOR_ATTACHMENT3, 0, 0);
        glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT);
    }
}

sta_status sta_pass_geometry_draw(sta_pass_geometry *p, const sta_camera *camera,
                                  const sta_geometry_colours *colours, const sta_gpu_cache *cache,
                                  const sta_gpu_node_frame *frames, const uint32_t *draw,
                                  size_t count, sta_render_target *target, sta_error *err)
{
    sta_raster_ref_footprint footprint;
    sta_point_size_footprint(&p->point_size, camera, &footprint);
    if (p->choice.raster == STA_RASTER_COMPUTE) {
        return sta_raster_compute_draw(&p->compute, camera, colours, &footprint, cache, frames,
                                       draw, count, target, err);
    }
    draw_points(p, camera, colours, &footprint, cache, frames, draw, count, target);
    return STA_OK;
}

bool sta_pass_geometry_set_class_out(sta_pass_geometry *p, GLuint class_texture)
{
    p->class_out = p->choice.raster == STA_RASTER_COMPUTE ? 0 : class_texture;
    return p->class_out != 0;
}

bool sta_pass_geometry_set_position_out(sta_pass_geometry *p, GLuint position_texture,
                                        GLuint class_texture, const sta_view_params *view,
                                        const uint32_t *mark_classes)
{
    if (p->choice.raster != STA_RASTER_COMPUTE) {
        return false;
    }
    sta_raster_compute_set_position_out(&p->compute, position_texture, class_texture, view,
                                        mark_classes);
    return position_texture != 0;
}
