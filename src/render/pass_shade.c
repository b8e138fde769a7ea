/* SPDX-License-Identifier: MIT
 * Shading passes. */
#include "render/pass_shade.h"

#include <stdio.h>
#include <string.h>

#include "render/bindings.h"
#include "render/gl.h"
#include "render/gl_image.h"

sta_status sta_shade_pass_init(sta_shade_pass *pass, sta_error *err)
{
    memset(pass, 0, sizeof(*pass));
    const char *edl[] = { "edl.comp" };
    sta_status status = STA_OK;
    for (int v = 0; v < STA_SHADE_VARIANTS && status == STA_OK; v++) {
        const char *names[] = { "normals_exact.glsl", "normals_upsample.glsl", "shade.comp" };
        status = sta_gl_program_create(names + (v ? 0 : 2), v ? 3 : 1,
                                       v ? "#define STA_SHADE_UPSAMPLE 1\n" : NULL,
                                       &pass->programs[v], err);
        if (status == STA_OK) {
            GLuint program = pass->programs[v];
            pass->shade_size[v] = glGetUniformLocation(program, "u_size");
            pass->shade_light[v] = glGetUniformLocation(program, "u_light");
            pass->shade_background[v] = glGetUniformLocation(program, "u_background");
            sta_normals_upsample_locate(program, &pass->upsample[v]);
        }
    }
    if (status == STA_OK) {
        status = sta_gl_program_create(edl, 1, NULL, &pass->edl_program, err);
    }
    if (status != STA_OK) {
        sta_shade_pass_release(pass);
        return status;
    }
    pass->edl_size = glGetUniformLocation(pass->edl_program, "u_size");
    pass->edl_radius = glGetUniformLocation(pass->edl_program, "u_radius");
    pass->edl_strength = glGetUniformLocation(pass->edl_program, "u_strength");
    pass->edl_background = glGetUniformLocation(pass->edl_program, "u_background");
    return STA_OK;
}

void sta_shade_pass_release(sta_shade_pass *pass)
{
    for (int v = 0; v < STA_SHADE_VARIANTS; v++) {
        if (pass->programs[v]) {
            glDeleteProgram(pass->programs[v]);
        }
    }
    if (pass->edl_program) {
        glDeleteProgram(pass->edl_program);
    }
    memset(pass, 0, sizeof(*pass));
}

void sta_shade_pass_run(const sta_shade_pass *pass, const sta_shade_params *params, int width,
                        int height, GLuint position, GLuint colour, GLuint normal,
                        const sta_normals_upsample_inputs *upsample, GLuint out)
{
    sta_shade_params p = *params;
    sta_shade_params_defaults(&p);
    int i = upsample ? 1 : 0;
    glUseProgram(pass->programs[i]);
    if (upsample) {
        sta_normals_upsample_bind(pass->programs[i], &pass->upsample[i], upsample);
    }
    glUniform2f(pass->shade_size[i], (float)width, (float)height);
    glUniform4f(pass->shade_light[i], p.ambient, p.diffuse, p.specular, p.shininess);
    glUniform3f(pass->shade_background[i], p.background[0], p.background[1], p.background[2]);
    glBindImageTexture(STA_SHADE_IMAGE_POSITION, position, 0, GL_FALSE, 0, GL_READ_ONLY,
                       GL_RGBA32F);
    glBindImageTexture(STA_SHADE_IMAGE_COLOUR, colour, 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA8);
    if (!upsample) {
        glBindImageTexture(STA_SHADE_IMAGE_NORMAL, normal, 0, GL_FALSE, 0, GL_READ_ONLY,
                           GL_RGBA32F);
    }
    glBindImageTexture(STA_SHADE_IMAGE_OUT, out, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA8);
    sta_gl_dispatch_2d(width, height);
}

void sta_edl_pass_run(const sta_shade_pass *pass, const sta_edl_params *params, int width,
                      int height, GLuint position, GLuint colour, GLuint out)
{
    sta_edl_params p = *params;
    sta_edl_params_defaults(&p);
    glUseProgram(pass->edl_program);
    glUniform2f(pass->edl_size, (float)width, (float)height);
    glUniform1f(pass->edl_radius, p.radius_px);
    glUniform1f(pass->edl_strength, p.strength);
    glUniform3f(pass->edl_background, p.background[0], p.background[1], p.background[2]);
    glBindImageTexture(STA_EDL_IMAGE_POSITION, position, 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
    glBindImageTexture(STA_EDL_IMAGE_COLOUR, colour, 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
    glBindImageTexture(STA_EDL_IMAGE_OUT, out, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA8);
    sta_gl_dispatch_2d(width, height);
}
