/* SPDX-License-Identifier: MIT
 * The unproject pass. */
#include "render/pass_unproject.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "render/bindings.h"
#include "render/gl.h"
#include "render/gl_image.h"
#include "render/gl_staged.h"

sta_status sta_unproject_pass_init(sta_unproject_pass *pass, sta_error *err)
{
    memset(pass, 0, sizeof(*pass));
    pass->staged = sta_gl_staged_stores();
    const char *names[] = { "unproject_pixel.glsl", "unproject.comp" };
    const char *staged = sta_gl_staged_define(pass->staged);
    char plain[64], mark[160];
    snprintf(plain, sizeof(plain), "%s", staged);
    snprintf(mark, sizeof(mark),
             "%s#define STA_UNPROJECT_MARK 1\n#define STA_POSITION_W_MARKED %.1f\n", staged,
             (double)STA_POSITION_W_MARKED);
    // Variant v: 0 plain, 1 with the volumetric mark.
    for (int v = 0; v < 2; v++) {
        sta_status status =
            sta_gl_program_create(names, 2, v ? mark : plain, &pass->programs[v], err);
        if (status != STA_OK) {
            sta_unproject_pass_release(pass);
            return status;
        }
        pass->u_size[v] = glGetUniformLocation(pass->programs[v], "u_size");
        pass->u_tan_half[v] = glGetUniformLocation(pass->programs[v], "u_tan_half");
        pass->u_near[v] = glGetUniformLocation(pass->programs[v], "u_near");
    }
    pass->u_classes = glGetUniformLocation(pass->programs[1], "u_classes");
    return STA_OK;
}

void sta_unproject_pass_release(sta_unproject_pass *pass)
{
    for (int v = 0; v < 2; v++) {
        if (pass->programs[v]) {
            glDeleteProgram(pass->programs[v]);
        }
    }
    sta_gl_staging_release(&pass->own_staging);
    memset(pass, 0, sizeof(*pass));
}

sta_status sta_unproject_pass_run(sta_unproject_pass *pass, const sta_view_params *view,
                                  GLuint depth_texture, GLuint position_texture, sta_error *err)
{
    return sta_unproject_pass_run_marked(pass, view, depth_texture, NULL, position_texture, err);
}

sta_status sta_unproject_pass_run_marked(sta_unproject_pass *pass, const sta_view_params *view,
                                         GLuint depth_texture, const sta_unproject_mark *mark,
                                         GLuint position_texture, sta_error *err)
{
    float size[2], tan_half[2];
    sta_unproject_uniforms(view, size, tan_half);
    int v = mark ? 1 : 0;
    glUseProgram(pass->programs[v]);
    glUniform2f(pass->u_size[v], size[0], size[1]);
    glUniform2f(pass->u_tan_half[v], tan_half[0], tan_half[1]);
    glUniform1f(pass->u_near[v], view->near_m);
    if (v) {
        glUniform1uiv(pass->u_classes, STA_UNPROJECT_CLASS_WORDS, mark->class_set);
        glBindImageTexture(STA_UNPROJECT_IMAGE_CLASS, mark->class_texture, 0, GL_FALSE, 0,
                           GL_READ_ONLY, GL_R8UI);
        glBindImageTexture(STA_UNPROJECT_IMAGE_TILES, mark->tile_flags, 0, GL_FALSE, 0,
                           GL_WRITE_ONLY, GL_R32UI);
    }
    glBindTextureUnit(STA_UNPROJECT_SAMPLER_DEPTH, depth_texture);
    sta_gl_staging *staging = sta_gl_staging_pick(&pass->own_staging, pass->shared_staging);
    if (pass->staged) {
        sta_status status = sta_gl_staging_bind(staging, STA_UNPROJECT_BUFFER_POSITION, 1,
                                                view->width_px, view->height_px, err);
        if (status != STA_OK) {
            return status;
        }
    } else {
        glBindImageTexture(STA_UNPROJECT_IMAGE_POSITION, position_texture, 0, GL_FALSE, 0,
                           GL_WRITE_ONLY, GL_RGBA32F);
    }
    sta_gl_dispatch_2d(view->width_px, view->height_px);
    if (pass->staged) {
        sta_gl_staging_copy(staging, 0, position_texture, 0, 0, view->width_px, view->height_px);
    }
    return STA_OK;
}

void sta_unproject_uniforms(const sta_view_params *view, float size[2], float tan_half[2])
{
    float tan_y = tanf(0.5f * view->fov_y);
    size[0] = (float)view->width_px;
    size[1] = (float)view->height_px;
    tan_half[0] = tan_y * (float)view->width_px / (float)view->height_px;
    tan_half[1] = tan_y;
}
