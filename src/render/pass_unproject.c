/* SPDX-License-Identifier: MIT
 * The unproject pass. */
#include "render/pass_unproject.h"

#include <math.h>
#include <string.h>

#include "render/bindings.h"
#include "render/gl.h"
#include "render/gl_image.h"

sta_status sta_unproject_pass_init(sta_unproject_pass *pass, sta_error *err)
{
    memset(pass, 0, sizeof(*pass));
    const char *names[] = { "unproject_pixel.glsl", "unproject.comp" };
    sta_status status = sta_gl_program_create(names, 2, NULL, &pass->program, err);
    if (status != STA_OK) {
        return status;
    }
    pass->u_size = glGetUniformLocation(pass->program, "u_size");
    pass->u_tan_half = glGetUniformLocation(pass->program, "u_tan_half");
    pass->u_near = glGetUniformLocation(pass->program, "u_near");
    return STA_OK;
}

void sta_unproject_pass_release(sta_unproject_pass *pass)
{
    if (pass->program) {
        glDeleteProgram(pass->program);
    }
    memset(pass, 0, sizeof(*pass));
}

void sta_unproject_pass_run(const sta_unproject_pass *pass, const sta_view_params *view,
                            GLuint depth_texture, GLuint position_texture)
{
    float size[2], tan_half[2];
    sta_unproject_uniforms(view, size, tan_half);
    glUseProgram(pass->program);
    glUniform2f(pass->u_size, size[0], size[1]);
    glUniform2f(pass->u_tan_half, tan_half[0], tan_half[1]);
    glUniform1f(pass->u_near, view->near_m);
    glBindTextureUnit(STA_UNPROJECT_SAMPLER_DEPTH, depth_texture);
    glBindImageTexture(STA_UNPROJECT_IMAGE_POSITION, position_texture, 0, GL_FALSE, 0,
                       GL_WRITE_ONLY, GL_RGBA32F);
    sta_gl_dispatch_2d(view->width_px, view->height_px);
}

void sta_unproject_uniforms(const sta_view_params *view, float size[2], float tan_half[2])
{
    float tan_y = tanf(0.5f * view->fov_y);
    size[0] = (float)view->width_px;
    size[1] = (float)view->height_px;
    tan_half[0] = tan_y * (float)view->width_px / (float)view->height_px;
    tan_half[1] = tan_y;
}
