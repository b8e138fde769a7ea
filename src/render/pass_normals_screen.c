/* SPDX-License-Identifier: MIT
 * The screen-space normals pass and its smoothing pass. */
#include "render/pass_normals_screen.h"

#include <stdio.h>
#include <string.h>

#include "render/bindings.h"
#include "render/gl.h"
#include "render/gl_image.h"

sta_status sta_normals_screen_pass_init(sta_normals_screen_pass *pass, sta_error *err)
{
    memset(pass, 0, sizeof(*pass));
    sta_status status = STA_OK;
    for (int m = STA_NORMALS_SCREEN_LD; m <= STA_NORMALS_SCREEN_TI && status == STA_OK; m++) {
        char defines[256];
        snprintf(defines, sizeof(defines),
                 "#define STA_NORMALS_SCREEN_LD %d\n#define STA_NORMALS_SCREEN_PD %d\n"
                 "#define STA_NORMALS_SCREEN_PC %d\n#define STA_NORMALS_SCREEN_TI %d\n"
                 "#define STA_NORMALS_METHOD %d",
                 STA_NORMALS_SCREEN_LD, STA_NORMALS_SCREEN_PD, STA_NORMALS_SCREEN_PC,
                 STA_NORMALS_SCREEN_TI, m);
        // Only TI needs the eigen solver.
        const char *names[] = { "eigen3.glsl", "normals_screen.comp" };
        int first = m == STA_NORMALS_SCREEN_TI ? 0 : 1;
        status = sta_gl_program_create(names + first, (size_t)(2 - first), defines,
                                       &pass->programs[m], err);
        if (status == STA_OK) {
            GLuint program = pass->programs[m];
            pass->u_size[m] = glGetUniformLocation(program, "u_size");
            pass->u_samples[m] = glGetUniformLocation(program, "u_samples");
            pass->u_max_distance2[m] = glGetUniformLocation(program, "u_max_distance2");
        }
    }
    if (status == STA_OK) {
        const char *names[] = { "normals_smooth.comp" };
        status = sta_gl_program_create(names, 1, NULL, &pass->smooth_program, err);
    }
    if (status != STA_OK) {
        sta_normals_screen_pass_release(pass);
        return status;
    }
    pass->smooth_u_size = glGetUniformLocation(pass->smooth_program, "u_size");
    pass->smooth_u_max_distance2 = glGetUniformLocation(pass->smooth_program, "u_max_distance2");
    return STA_OK;
}

void sta_normals_screen_pass_release(sta_normals_screen_pass *pass)
{
    for (int m = 0; m < STA_NORMALS_SCREEN_METHOD_COUNT; m++) {
        if (pass->programs[m]) {
            glDeleteProgram(pass->programs[m]);
        }
    }
    if (pass->smooth_program) {
        glDeleteProgram(pass->smooth_program);
    }
    memset(pass, 0, sizeof(*pass));
}

sta_status sta_normals_screen_pass_run(const sta_normals_screen_pass *pass,
                                       const sta_view_params *view,
                                       const sta_normals_screen_params *params,
                                       GLuint position_texture, GLuint normal_texture,
                                       sta_error *err)
{
    sta_normals_screen_params p = *params;
    sta_normals_screen_params_defaults(&p);
    sta_status status = sta_normals_screen_params_check(&p, err);
    if (status != STA_OK) {
        return status;
    }
    int m = p.method;
    glUseProgram(pass->programs[m]);
    glUniform2i(pass->u_size[m], view->width_px, view->height_px);
    glUniform1i(pass->u_samples[m], p.samples);
    glUniform1f(pass->u_max_distance2[m], sta_normals_screen_max_distance2(view, &p));
    glBindImageTexture(STA_NORMALS_SCREEN_IMAGE_NORMAL, normal_texture, 0, GL_FALSE, 0,
                       GL_WRITE_ONLY, GL_RGBA32F);
    glBindImageTexture(STA_NORMALS_SCREEN_IMAGE_POSITION, position_texture, 0, GL_FALSE, 0,
                       GL_READ_ONLY, GL_RGBA32F);
    sta_gl_dispatch_2d(view->width_px, view->height_px);
    return STA_OK;
}

sta_status sta_normals_smooth_pass_run(const sta_normals_screen_pass *pass,
                                       const sta_view_params *view,
                                       const sta_normals_screen_params *params,
                                       GLuint position_texture, GLuint normal_texture,
                                       GLuint out_texture, sta_error *err)
{
    sta_normals_screen_params p = *params;
    sta_normals_screen_params_defaults(&p);
    sta_status status = sta_normals_screen_params_check(&p, err);
    if (status != STA_OK) {
        return status;
    }
    if (out_texture == normal_texture) {
        return sta_fail(err, STA_ERR_ARG, "normals smoothing cannot run in place (texture %u)",
                        out_texture);
    }
    glUseProgram(pass->smooth_program);
    glUniform2i(pass->smooth_u_size, view->width_px, view->height_px);
    glUniform1f(pass->smooth_u_max_distance2, sta_normals_screen_max_distance2(view, &p));
    glBindImageTexture(STA_NORMALS_SMOOTH_IMAGE_SMOOTHED, out_texture, 0, GL_FALSE, 0,
                       GL_WRITE_ONLY, GL_RGBA32F);
    glBindImageTexture(STA_NORMALS_SMOOTH_IMAGE_POSITION, position_texture, 0, GL_FALSE, 0,
                       GL_READ_ONLY, GL_RGBA32F);
    glBindImageTexture(STA_NORMALS_SMOOTH_IMAGE_NORMAL, normal_texture, 0, GL_FALSE, 0,
                       GL_READ_ONLY, GL_RGBA32F);
    sta_gl_dispatch_2d(view->width_px, view->height_px);
    return STA_OK;
}
