/* SPDX-License-Identifier: MIT
 * Mirror rendering: the reflected view and its composite (pass_mirror.h). */
#include "render/pass_mirror.h"

#include <math.h>
#include <string.h>

#include "render/bindings.h"
#include "render/gl.h"
#include "render/gl_image.h"

_Static_assert(STA_MIRROR_OUTLINE_MAX == STA_MIRROR_MAX_VERTICES, "outline uniform size");

sta_status sta_pass_mirror_init(sta_pass_mirror *pass, sta_error *err)
{
    memset(pass, 0, sizeof(*pass));
    const char *names[] = { "mirror_composite.comp" };
    sta_status status = sta_gl_program_create(names, 1, NULL, &pass->program, err);
    if (status != STA_OK) {
        return status;
    }
    GLuint p = pass->program;
    pass->u_size = glGetUniformLocation(p, "u_size");
    pass->u_to_world = glGetUniformLocation(p, "u_to_world");
    pass->u_tan = glGetUniformLocation(p, "u_tan");
    pass->u_near = glGetUniformLocation(p, "u_near");
    pass->u_plane = glGetUniformLocation(p, "u_plane");
    pass->u_centre = glGetUniformLocation(p, "u_centre");
    pass->u_axis_u = glGetUniformLocation(p, "u_axis_u");
    pass->u_axis_v = glGetUniformLocation(p, "u_axis_v");
    pass->u_outline = glGetUniformLocation(p, "u_outline");
    pass->u_count = glGetUniformLocation(p, "u_count");
    pass->u_background = glGetUniformLocation(p, "u_background");
    pass->u_has_filled = glGetUniformLocation(p, "u_has_filled");
    return sta_gl_check("creating the mirror pass", err);
}

void sta_pass_mirror_release(sta_pass_mirror *pass)
{
    if (pass->program) {
        glDeleteProgram(pass->program);
    }
    sta_render_target_release(&pass->reflected);
    memset(pass, 0, sizeof(*pass));
}

/* The plane n . x + d = 0 with x relative to `eye` (d > 0 when eye is in front). */
static void relative_plane(const sta_mirror *m, const double eye[3], float out[4])
{
    double d = 0.0;
    for (int a = 0; a < 3; a++) {
        d += m->normal[a] * (eye[a] - m->centre[a]);
        out[a] = (float)m->normal[a];
    }
    out[3] = (float)d;
}

static void composite(const sta_pass_mirror *pass, const sta_mirror *m, const sta_camera *camera,
                      GLuint filled_position, sta_render_target *target)
{
    float view[16], to_world[9];
    sta_camera_view_rotation(camera, view);
    for (int row = 0; row < 3; row++) { // inverse of a rotation: its transpose
        for (int col = 0; col < 3; col++) {
            to_world[col * 3 + row] = view[row * 4 + col];
        }
    }
    double t = tan(camera->fov_y * 0.5);
    double aspect = (double)camera->width_px / (double)camera->height_px;
    float plane[4];
    relative_plane(m, camera->position, plane);
    float outline[STA_MIRROR_MAX_VERTICES][2];
    for (size_t i = 0; i < m->vertex_count; i++) {
        outline[i][0] = (float)m->uv[i][0];
        outline[i][1] = (float)m->uv[i][1];
    }
    glUseProgram(pass->program);
    glUniform2i(pass->u_size, camera->width_px, camera->height_px);
    glUniformMatrix3fv(pass->u_to_world, 1, GL_FALSE, to_world);
    glUniform2f(pass->u_tan, (float)(t * aspect), (float)t);
    glUniform1f(pass->u_near, (float)camera->near_m);
    glUniform4fv(pass->u_plane, 1, plane);
    glUniform3f(pass->u_centre, (float)(m->centre[0] - camera->position[0]),
                (float)(m->centre[1] - camera->position[1]),
                (float)(m->centre[2] - camera->position[2]));
    glUniform3f(pass->u_axis_u, (float)m->axis_u[0], (float)m->axis_u[1], (float)m->axis_u[2]);
    glUniform3f(pass->u_axis_v, (float)m->axis_v[0], (float)m->axis_v[1], (float)m->axis_v[2]);
    glUniform2fv(pass->u_outline, (GLsizei)m->vertex_count, &outline[0][0]);
    glUniform1i(pass->u_count, (GLint)m->vertex_count);
    glUniform3f(pass->u_background, 0.0f, 0.0f, 0.0f); // the geometry pass's background
    glBindImageTexture(STA_MIRROR_IMAGE_OUT, target->colour, 0, GL_FALSE, 0, GL_READ_WRITE,
                       GL_RGBA8);
    glBindTextureUnit(STA_MIRROR_SAMPLER_DEPTH, target->depth);
    glBindTextureUnit(STA_MIRROR_SAMPLER_REFLECTED, pass->reflected.colour);
    glBindTextureUnit(STA_MIRROR_SAMPLER_REFLECTED_DEPTH, pass->reflected.depth);
    glUniform1i(pass->u_has_filled, filled_position != 0);
    glBindTextureUnit(STA_MIRROR_SAMPLER_FILLED, filled_position);
    sta_gl_dispatch_2d(camera->width_px, camera->height_px);
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT |
                    GL_FRAMEBUFFER_BARRIER_BIT);
}

sta_status sta_pass_mirror_draw(sta_pass_mirror *pass, const sta_mirror *m,
                                const sta_camera *camera, const sta_camera *reflected,
                                const sta_geometry_colours *colours, sta_pass_geometry *geometry,
                                const sta_gpu_cache *cache, const sta_gpu_node_frame *frames,
                                const uint32_t *draw, size_t count, GLuint filled_position,
                                sta_render_target *target, sta_error *err)
{
    sta_status status =
        sta_render_target_resize(&pass->reflected, reflected->width_px, reflected->height_px, err);
    if (status != STA_OK) {
        return status;
    }
    sta_geometry_colours c = *colours;
    relative_plane(m, reflected->position, c.clip_plane); // keep the real side only
    status = sta_pass_geometry_draw(geometry, reflected, &c, cache, frames, draw, count,
                                    &pass->reflected, err);
    if (status != STA_OK) {
        return status;
    }
    composite(pass, m, camera, filled_position, target);
    return sta_gl_check("the mirror pass", err);
}
