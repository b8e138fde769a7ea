/* SPDX-License-Identifier: MIT
 * Ground model texture. */
#include "render/ground_texture.h"

#include <string.h>

#include "render/bindings.h"
#include "render/gl.h"

sta_status sta_ground_texture_upload(sta_ground_texture *t, const sta_ground *g, sta_error *err)
{
    sta_ground_texture_release(t);
    glCreateTextures(GL_TEXTURE_2D, 1, &t->texture);
    glTextureStorage2D(t->texture, 1, GL_R32F, g->width, g->height);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTextureSubImage2D(t->texture, 0, 0, 0, g->width, g->height, GL_RED, GL_FLOAT, g->z);
    // Linear between cell centres and clamped at the edges, as sta_ground_at.
    glTextureParameteri(t->texture, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTextureParameteri(t->texture, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTextureParameteri(t->texture, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(t->texture, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    t->corner[0] = g->min[0];
    t->corner[1] = g->min[1];
    t->size_m[0] = g->cell_m * g->width;
    t->size_m[1] = g->cell_m * g->height;
    t->z_origin = g->z_origin;
    t->height_span_m = g->height_span_m > 0 ? g->height_span_m : 1.0;
    return sta_gl_check("uploading the ground model", err);
}

void sta_ground_texture_use(const sta_ground_texture *t, GLuint program, const sta_camera *c)
{
    if (!t || !t->texture) {
        glBindTextureUnit(STA_GEOMETRY_SAMPLER_GROUND, 0);
        return;
    }
    glBindTextureUnit(STA_GEOMETRY_SAMPLER_GROUND, t->texture);
    // Differences in double first: the scene may sit far from the origin.
    glUniform4f(glGetUniformLocation(program, "u_ground_frame"),
                (float)(t->corner[0] - c->position[0]), (float)(t->corner[1] - c->position[1]),
                (float)t->size_m[0], (float)t->size_m[1]);
    glUniform2f(glGetUniformLocation(program, "u_ground_height"),
                (float)(t->z_origin - c->position[2]), (float)(1.0 / t->height_span_m));
}

void sta_ground_texture_release(sta_ground_texture *t)
{
    if (t->texture) {
        glDeleteTextures(1, &t->texture);
    }
    memset(t, 0, sizeof(*t));
}
