/* SPDX-License-Identifier: MIT
 * The pull-push pass: one pull dispatch per level going up, one push dispatch per level
 * coming down (in place), the last one writing the outputs. */
#include "render/pass_pullpush.h"

#include <stdbool.h>
#include <stdio.h>
#include <string.h>

#include "render/bindings.h"
#include "render/gl.h"
#include "render/gl_image.h"
#include "render/gl_staged.h"

const char *sta_pullpush_shader_defines(void)
{
    static char defines[384];
    if (!defines[0]) {
        snprintf(defines, sizeof(defines),
                 "#define PP_LABEL_BACKGROUND %.1f\n#define PP_LABEL_VISIBLE %.1f\n"
                 "#define PP_POSITION_W_MARKED %.1f\n#define PP_POSITION_W_SEE_THROUGH_MIN %.9e\n"
                 "#define PP_DEPTH_TAU %.9e\n#define PP_PULL_TAU %.9e\n"
                 "#define PP_GLASS_SHARE %.9e\n#define PP_GLASS_GAP %.9e\n",
                 (double)STA_LABEL_BACKGROUND, (double)STA_LABEL_VISIBLE,
                 (double)STA_POSITION_W_MARKED, (double)STA_POSITION_W_SEE_THROUGH_MIN,
                 (double)STA_PULLPUSH_DEPTH_TAU, (double)STA_PULLPUSH_PULL_DEPTH_TAU,
                 (double)STA_PULLPUSH_GLASS_SHARE, (double)STA_PULLPUSH_GLASS_GAP);
    }
    return defines;
}

static sta_status build(const char *stage, const char *variant, bool staged,
                        sta_pullpush_program *out, sta_error *err)
{
    char defines[576];
    snprintf(defines, sizeof(defines), "%s%s%s", sta_pullpush_shader_defines(),
             sta_gl_staged_define(staged), variant);
    const char *names[] = { "pullpush_common.glsl", stage };
    sta_status status = sta_gl_program_create(names, 2, defines, &out->program, err);
    if (status != STA_OK) {
        return status;
    }
    bool pull = strstr(stage, "pull.") != NULL;
    out->size = glGetUniformLocation(out->program, pull ? "u_fine_size" : "u_size");
    out->coarse_size = glGetUniformLocation(out->program, "u_coarse_size");
    out->has_label = glGetUniformLocation(out->program, "u_has_label");
    out->has_coarse = glGetUniformLocation(out->program, "u_has_coarse");
    return STA_OK;
}

sta_status sta_pullpush_pass_init(sta_pullpush_pass *pass, sta_error *err)
{
    memset(pass, 0, sizeof(*pass));
    bool staged = pass->staged = sta_gl_staged_stores();
    sta_status status =
        build("pullpush_pull.comp", "#define PP_FROM_INPUT 1\n", staged, &pass->pull_input, err);
    if (status == STA_OK) {
        status = build("pullpush_pull.comp", "#define PP_FROM_INPUT 1\n#define PP_BOX 1\n", staged,
                       &pass->pull_box, err);
    }
    if (status == STA_OK) {
        status = build("pullpush_pull.comp", "", staged, &pass->pull_level, err);
    }
    if (status == STA_OK) {
        status = build("pullpush_push.comp", "", staged, &pass->push_level, err);
    }
    if (status == STA_OK) {
        status =
            build("pullpush_push.comp", "#define PP_LEVEL0 1\n", staged, &pass->push_output, err);
    }
    if (status != STA_OK) {
        sta_pullpush_pass_release(pass);
    }
    return status;
}

static void release_pyramid(sta_pullpush_pyramid *pyramid)
{
    for (int l = 0; l < STA_PULLPUSH_MAX_LEVELS; l++) {
        if (pyramid->position[l]) {
            glDeleteTextures(1, &pyramid->position[l]);
        }
        if (pyramid->colour[l]) {
            glDeleteTextures(1, &pyramid->colour[l]);
        }
    }
    memset(pyramid, 0, sizeof(*pyramid));
}

void sta_pullpush_pass_release(sta_pullpush_pass *pass)
{
    sta_pullpush_program *programs[] = { &pass->pull_input, &pass->pull_box, &pass->pull_level,
                                         &pass->push_level, &pass->push_output };
    for (size_t i = 0; i < sizeof(programs) / sizeof(programs[0]); i++) {
        if (programs[i]->program) {
            glDeleteProgram(programs[i]->program);
        }
    }
    release_pyramid(&pass->pyramid);
    sta_gl_staging_release(&pass->own_staging);
    memset(pass, 0, sizeof(*pass));
}

// Allocates the level textures for a w x h view unless they already fit.
static sta_status ensure_pyramid(sta_pullpush_pyramid *pyramid, int w, int h, sta_error *err)
{
    if (pyramid->level_count > 0 && pyramid->width_px[0] == w && pyramid->height_px[0] == h) {
        return STA_OK;
    }
    release_pyramid(pyramid);
    int count = sta_pullpush_level_count(w, h);
    if (count == 0) {
        return sta_fail(err, STA_ERR_ARG, "pull-push: view %dx%d is out of range (1..32768)", w, h);
    }
    for (int l = 0; l < count; l++) {
        pyramid->width_px[l] = sta_pullpush_level_size(w, l);
        pyramid->height_px[l] = sta_pullpush_level_size(h, l);
        if (l == 0) {
            continue;
        }
        sta_status status = sta_gl_texture_create(pyramid->width_px[l], pyramid->height_px[l], 4, 1,
                                                  &pyramid->position[l], err);
        if (status == STA_OK) {
            status = sta_gl_texture_create(pyramid->width_px[l], pyramid->height_px[l], 4, 1,
                                           &pyramid->colour[l], err);
        }
        if (status != STA_OK) {
            release_pyramid(pyramid);
            return status;
        }
    }
    pyramid->level_count = count;
    return STA_OK;
}

static void bind_image(GLuint unit, GLuint texture, GLenum access, GLenum format)
{
    glBindImageTexture(unit, texture, 0, GL_FALSE, 0, access, format);
}

static void set_sizes(const sta_pullpush_program *p, const sta_pullpush_pyramid *pyr, int level,
                      int coarse_level)
{
    glProgramUniform2i(p->program, p->size, pyr->width_px[level], pyr->height_px[level]);
    glProgramUniform2i(p->program, p->coarse_size, pyr->width_px[coarse_level],
                       pyr->height_px[coarse_level]);
}

// One dispatch over a w x h level whose results are `position` and `colour` (0: the
// shader stores the colour itself): bound as images, or staged through two ranges of the
// staging buffer (position, then colour: their bindings are consecutive) and copied in
// afterwards (render/gl_staged.h).
static sta_status dispatch_level(sta_pullpush_pass *pass, int w, int h, GLuint position,
                                 GLuint colour, sta_error *err)
{
    if (!pass->staged) {
        sta_gl_dispatch_2d(w, h);
        return STA_OK;
    }
    _Static_assert(STA_PULLPUSH_BUFFER_OUT_COLOUR == STA_PULLPUSH_BUFFER_OUT_POSITION + 1,
                   "the staged colour's range follows the position's");
    sta_gl_staging *staging = sta_gl_staging_pick(&pass->own_staging, pass->shared_staging);
    sta_status status =
        sta_gl_staging_bind(staging, STA_PULLPUSH_BUFFER_OUT_POSITION, colour ? 2 : 1, w, h, err);
    if (status != STA_OK) {
        return status;
    }
    sta_gl_dispatch_2d(w, h);
    sta_gl_staging_copy(staging, 0, position, 0, 0, w, h);
    if (colour) {
        sta_gl_staging_copy(staging, 1, colour, 0, 0, w, h);
    }
    return STA_OK;
}

sta_status sta_pullpush_pass_run(sta_pullpush_pass *pass, const sta_view_params *view,
                                 GLuint position_tex, GLuint colour_tex, GLuint label_tex,
                                 GLuint out_position_tex, GLuint out_colour_tex, sta_error *err)
{
    sta_pullpush_pyramid *pyr = &pass->pyramid;
    sta_status status = ensure_pyramid(pyr, view->width_px, view->height_px, err);
    if (status != STA_OK) {
        return status;
    }
    int count = pyr->level_count;
    GLint has_label = label_tex != 0;
    glBindTextureUnit(STA_PULLPUSH_SAMPLER_INPUT_COLOUR, colour_tex);
    bind_image(STA_PULLPUSH_IMAGE_LABEL, label_tex, GL_READ_ONLY, STA_GL_LABEL_FORMAT);

    // Pull: level 1 from the inputs, level l from level l - 1.
    for (int l = 1; l < count; l++) {
        const sta_pullpush_program *first =
            sta_pullpush_box_first_pull(view->height_px) ? &pass->pull_box : &pass->pull_input;
        const sta_pullpush_program *p = l == 1 ? first : &pass->pull_level;
        glUseProgram(p->program);
        if (l == 1) {
            glProgramUniform1i(p->program, p->has_label, has_label);
            bind_image(STA_PULLPUSH_IMAGE_FINE_POSITION, position_tex, GL_READ_ONLY, GL_RGBA32F);
        } else {
            bind_image(STA_PULLPUSH_IMAGE_FINE_POSITION, pyr->position[l - 1], GL_READ_ONLY,
                       GL_RGBA32F);
            bind_image(STA_PULLPUSH_IMAGE_FINE_COLOUR, pyr->colour[l - 1], GL_READ_ONLY,
                       GL_RGBA32F);
        }
        if (!pass->staged) { // staged: dispatch_level binds the staging ranges instead
            bind_image(STA_PULLPUSH_IMAGE_OUT_POSITION, pyr->position[l], GL_WRITE_ONLY,
                       GL_RGBA32F);
            bind_image(STA_PULLPUSH_IMAGE_OUT_COLOUR, pyr->colour[l], GL_WRITE_ONLY, GL_RGBA32F);
        }
        set_sizes(p, pyr, l - 1, l);
        status = dispatch_level(pass, pyr->width_px[l], pyr->height_px[l], pyr->position[l],
                                pyr->colour[l], err);
        if (status != STA_OK) {
            return status;
        }
    }

    // Push: level l from the pushed level l + 1, in place, down to level 1.
    const sta_pullpush_program *p = &pass->push_level;
    glUseProgram(p->program);
    glProgramUniform1i(p->program, p->has_coarse, 1);
    for (int l = count - 2; l >= 1; l--) {
        bind_image(STA_PULLPUSH_IMAGE_OUT_POSITION, pyr->position[l], GL_READ_WRITE, GL_RGBA32F);
        bind_image(STA_PULLPUSH_IMAGE_OUT_COLOUR, pyr->colour[l], GL_READ_WRITE, GL_RGBA32F);
        bind_image(STA_PULLPUSH_IMAGE_COARSE_POSITION, pyr->position[l + 1], GL_READ_ONLY,
                   GL_RGBA32F);
        bind_image(STA_PULLPUSH_IMAGE_COARSE_COLOUR, pyr->colour[l + 1], GL_READ_ONLY, GL_RGBA32F);
        set_sizes(p, pyr, l, l + 1);
        status = dispatch_level(pass, pyr->width_px[l], pyr->height_px[l], pyr->position[l],
                                pyr->colour[l], err);
        if (status != STA_OK) {
            return status;
        }
    }

    // Level 0: the inputs over level 1, into the outputs, background restored. A 1 x 1
    // view has no level 1: its output is the input weighted by its label.
    p = &pass->push_output;
    glUseProgram(p->program);
    glProgramUniform1i(p->program, p->has_label, has_label);
    glProgramUniform1i(p->program, p->has_coarse, count > 1);
    bind_image(STA_PULLPUSH_IMAGE_FINE_POSITION, position_tex, GL_READ_ONLY, GL_RGBA32F);
    if (!pass->staged) {
        bind_image(STA_PULLPUSH_IMAGE_OUT_POSITION, out_position_tex, GL_WRITE_ONLY, GL_RGBA32F);
    }
    bind_image(STA_PULLPUSH_IMAGE_OUT_COLOUR, out_colour_tex, GL_WRITE_ONLY, GL_RGBA8);
    bind_image(STA_PULLPUSH_IMAGE_COARSE_POSITION, count > 1 ? pyr->position[1] : 0, GL_READ_ONLY,
               GL_RGBA32F);
    bind_image(STA_PULLPUSH_IMAGE_COARSE_COLOUR, count > 1 ? pyr->colour[1] : 0, GL_READ_ONLY,
               GL_RGBA32F);
    set_sizes(p, pyr, 0, count > 1 ? 1 : 0);
    status = dispatch_level(pass, pyr->width_px[0], pyr->height_px[0], out_position_tex, 0, err);
    if (status != STA_OK) {
        return status;
    }

    glBindTextureUnit(STA_PULLPUSH_SAMPLER_INPUT_COLOUR, 0);
    for (GLuint unit = 0; unit <= STA_PULLPUSH_IMAGE_LAST; unit++) {
        bind_image(unit, 0, GL_READ_ONLY, GL_RGBA32F);
    }
    return sta_gl_check("pull-push pass", err);
}

const sta_pullpush_pyramid *sta_pullpush_pass_pyramid(const sta_pullpush_pass *pass)
{
    return &pass->pyramid;
}
