/* SPDX-License-Identifier: MIT
 * The pyramidal normal estimator: one dispatch per level into the normal atlas, then
 * one gather dispatch over the view. */
#include "render/pass_normals_pyramid.h"

#include <string.h>

#include "render/bindings.h"
#include "render/gl.h"
#include "render/gl_image.h"

sta_status sta_normals_pyramid_pass_init(sta_normals_pyramid_pass *pass, sta_error *err)
{
    memset(pass, 0, sizeof(*pass));
    pass->staged = sta_gl_staged_stores();
    const char *level[] = { "normals_exact.glsl", "pullpush_normals.glsl",
                            "normals_pyramid_level.comp" };
    const char *gather[] = { "normals_exact.glsl", "pullpush_normals.glsl",
                             "normals_pyramid_gather.comp" };
    const char *upsample[] = { "normals_exact.glsl", "pullpush_normals.glsl",
                               "normals_upsample.glsl",
                               "normals_pyramid_upsample.comp" }; // u_points, np_upsample
    sta_status status = sta_gl_program_create(level, 3, sta_gl_staged_define(pass->staged),
                                              &pass->level_program, err);
    if (status == STA_OK) {
        status = sta_gl_program_create(gather, 3, NULL, &pass->gather_program, err);
    }
    if (status == STA_OK) {
        status =
            sta_gl_program_create(gather, 3, "#define NP_ANCHORS 1\n", &pass->anchor_program, err);
    }
    if (status == STA_OK) {
        status = sta_gl_program_create(upsample, 4, NULL, &pass->upsample_program, err);
    }
    if (status != STA_OK) {
        sta_normals_pyramid_pass_release(pass);
        return status;
    }
    pass->level_size = glGetUniformLocation(pass->level_program, "u_size");
    pass->level_offset = glGetUniformLocation(pass->level_program, "u_offset");
    pass->level_jump2 = glGetUniformLocation(pass->level_program, "u_jump2");
    pass->level_texel_m = glGetUniformLocation(pass->level_program, "u_texel_m");
    for (int i = 0; i < 2; i++) {
        GLuint g = i == 0 ? pass->gather_program : pass->anchor_program;
        pass->gather_size[i] = glGetUniformLocation(g, "u_size");
        pass->gather_level_count[i] = glGetUniformLocation(g, "u_level_count");
        pass->gather_level_offset[i] = glGetUniformLocation(g, "u_level_offset");
        pass->gather_level_size[i] = glGetUniformLocation(g, "u_level_size");
        pass->gather_radius_px_m[i] = glGetUniformLocation(g, "u_radius_px_m");
        pass->gather_near[i] = glGetUniformLocation(g, "u_near");
        pass->gather_plane_tolerance_m[i] = glGetUniformLocation(g, "u_plane_tolerance_m");
        pass->gather_jump2[i] = glGetUniformLocation(g, "u_jump2");
        pass->gather_texel_m[i] = glGetUniformLocation(g, "u_texel_m");
        pass->gather_coherence[i] = glGetUniformLocation(g, "u_coherence");
        pass->gather_fine_coherence[i] = glGetUniformLocation(g, "u_fine_coherence");
        pass->gather_fine_min_level[i] = glGetUniformLocation(g, "u_fine_min_level");
    }
    GLuint u = pass->upsample_program;
    pass->upsample_size = glGetUniformLocation(u, "u_size");
    sta_normals_upsample_locate(u, &pass->upsample);
    return STA_OK;
}

void sta_normals_pyramid_pass_release(sta_normals_pyramid_pass *pass)
{
    if (pass->level_program) {
        glDeleteProgram(pass->level_program);
    }
    GLuint programs[] = { pass->gather_program, pass->anchor_program, pass->upsample_program };
    for (size_t i = 0; i < sizeof(programs) / sizeof(programs[0]); i++) {
        if (programs[i]) {
            glDeleteProgram(programs[i]);
        }
    }
    if (pass->atlas) {
        glDeleteTextures(1, &pass->atlas);
    }
    sta_gl_staging_release(&pass->own_staging);
    if (pass->half) {
        glDeleteTextures(1, &pass->half);
    }
    memset(pass, 0, sizeof(*pass));
}

// Atlas of the normals of levels >= 1 (level 0 is computed where it is used): level 1
// at (0, 0), level l >= 2 at (width of level 1, sum of the heights of levels 2..l-1).
// Size: (width of level 1 + width of level 2) x max(height of level 1, sum of the
// heights of levels >= 2); 1 x 1 when there is no level 1.
static sta_status ensure_atlas(sta_normals_pyramid_pass *pass, const sta_pullpush_pyramid *pyr,
                               sta_error *err)
{
    int w = pyr->width_px[0], h = pyr->height_px[0];
    if (pass->atlas && pass->view_width_px == w && pass->view_height_px == h) {
        return STA_OK;
    }
    if (pass->atlas) {
        glDeleteTextures(1, &pass->atlas);
        pass->atlas = 0;
    }
    if (pass->half) {
        glDeleteTextures(1, &pass->half);
        pass->half = 0;
    }
    memset(pass->offset_x, 0, sizeof(pass->offset_x));
    memset(pass->offset_y, 0, sizeof(pass->offset_y));
    int column_height = 0;
    for (int l = 2; l < pyr->level_count; l++) {
        pass->offset_x[l] = pyr->width_px[1];
        pass->offset_y[l] = column_height;
        column_height += pyr->height_px[l];
    }
    pass->atlas_width_px = 1;
    pass->atlas_height_px = 1;
    if (pyr->level_count > 1) {
        pass->atlas_width_px = pyr->width_px[1] + (pyr->level_count > 2 ? pyr->width_px[2] : 0);
        pass->atlas_height_px =
            pyr->height_px[1] > column_height ? pyr->height_px[1] : column_height;
    }
    sta_status status =
        sta_gl_texture_create(pass->atlas_width_px, pass->atlas_height_px, 4, 1, &pass->atlas, err);
    if (status == STA_OK) {
        status = sta_gl_texture_create((w + 1) / 2, (h + 1) / 2, 4, 1, &pass->half, err);
    }
    if (status != STA_OK) {
        return status;
    }
    pass->view_width_px = w;
    pass->view_height_px = h;
    return STA_OK;
}

void sta_normals_upsample_locate(GLuint program, sta_normals_upsample_uniforms *u)
{
    u->half_size = glGetUniformLocation(program, "u_half_size");
    u->near = glGetUniformLocation(program, "u_upsample_near");
    u->level_count = glGetUniformLocation(program, "u_level_count");
    u->radius_px_m = glGetUniformLocation(program, "u_radius_px_m");
    u->plane_tolerance_m = glGetUniformLocation(program, "u_plane_tolerance_m");
    u->anchor_level = glGetUniformLocation(program, "u_anchor_level");
}

void sta_normals_upsample_bind(GLuint program, const sta_normals_upsample_uniforms *u,
                               const sta_normals_upsample_inputs *in)
{
    glProgramUniform2i(program, u->half_size, in->half_width_px, in->half_height_px);
    glProgramUniform1f(program, u->near, in->near_m);
    glProgramUniform1i(program, u->level_count, in->level_count);
    glProgramUniform1f(program, u->radius_px_m, in->radius_px_m);
    glProgramUniform1f(program, u->plane_tolerance_m, in->plane_tolerance_m);
    glProgramUniform1i(program, u->anchor_level, in->anchor_level);
    glBindImageTexture(STA_NORMALS_UPSAMPLE_IMAGE_HALF, in->half, 0, GL_FALSE, 0, GL_READ_ONLY,
                       GL_RGBA32F);
}

static sta_status run(sta_normals_pyramid_pass *pass, const sta_view_params *view,
                      const sta_normals_pyramid_params *params, const sta_pullpush_pyramid *pyramid,
                      GLuint filled_position_tex, GLuint out_normal_tex,
                      sta_normals_upsample_inputs *deferred, sta_error *err)
{
    int count = pyramid->level_count;
    if (count == 0 || pyramid->width_px[0] != view->width_px ||
        pyramid->height_px[0] != view->height_px) {
        return sta_fail(err, STA_ERR_ARG,
                        "pyramidal normals: the pull-push pyramid (%d levels, %dx%d) does not "
                        "belong to the view %dx%d",
                        count, pyramid->width_px[0], pyramid->height_px[0], view->width_px,
                        view->height_px);
    }
    sta_status status = ensure_atlas(pass, pyramid, err);
    if (status != STA_OK) {
        return status;
    }
    sta_normals_pyramid_params p = params ? *params : (sta_normals_pyramid_params){ 0 };
    sta_normals_pyramid_params_defaults(&p);

    GLint offsets[2 * STA_PULLPUSH_MAX_LEVELS], sizes[2 * STA_PULLPUSH_MAX_LEVELS];
    for (int l = 0; l < count; l++) {
        offsets[2 * l] = pass->offset_x[l];
        offsets[2 * l + 1] = pass->offset_y[l];
        sizes[2 * l] = pyramid->width_px[l];
        sizes[2 * l + 1] = pyramid->height_px[l];
    }
    float jump2 = p.jump_ratio * p.jump_ratio;
    GLuint lp = pass->level_program;
    glUseProgram(lp);
    glProgramUniform1f(lp, pass->level_jump2, jump2);
    sta_gl_staging *staging = sta_gl_staging_pick(&pass->own_staging, pass->shared_staging);
    if (!pass->staged) {
        glBindImageTexture(STA_NORMALS_PYRAMID_LEVEL_IMAGE_ATLAS, pass->atlas, 0, GL_FALSE, 0,
                           GL_WRITE_ONLY, GL_RGBA32F);
    }
    for (int l = 1; l < count; l++) {
        glBindImageTexture(STA_NORMALS_PYRAMID_IMAGE_POINTS, pyramid->position[l], 0, GL_FALSE, 0,
                           GL_READ_ONLY, GL_RGBA32F);
        glProgramUniform2i(lp, pass->level_size, sizes[2 * l], sizes[2 * l + 1]);
        glProgramUniform2i(lp, pass->level_offset, offsets[2 * l], offsets[2 * l + 1]);
        glProgramUniform1f(lp, pass->level_texel_m, sta_normals_pyramid_texel_m(view, l));
        if (pass->staged) {
            status = sta_gl_staging_bind(staging, STA_NORMALS_PYRAMID_LEVEL_BUFFER_ATLAS, 1,
                                         sizes[2 * l], sizes[2 * l + 1], err);
            if (status != STA_OK) {
                return status;
            }
        }
        sta_gl_dispatch_2d(sizes[2 * l], sizes[2 * l + 1]);
        if (pass->staged) {
            sta_gl_staging_copy(staging, 0, pass->atlas, offsets[2 * l], offsets[2 * l + 1],
                                sizes[2 * l], sizes[2 * l + 1]);
        }
    }

    // Full resolution: the gather on every pixel. Half resolution: the gather on the
    // anchors into the half image, then the upsample on every pixel.
    const int i = p.half_resolution ? 1 : 0;
    const int anchor_level = sta_normals_anchor_level(view->height_px), s = 1 << anchor_level;
    const int hw = (view->width_px + s - 1) / s, hh = (view->height_px + s - 1) / s;
    GLuint gp = i ? pass->anchor_program : pass->gather_program;
    glUseProgram(gp);
    glProgramUniform2i(gp, pass->gather_size[i], view->width_px, view->height_px);
    glProgramUniform1i(gp, pass->gather_level_count[i], count);
    glProgramUniform2iv(gp, pass->gather_level_offset[i], count, offsets);
    glProgramUniform2iv(gp, pass->gather_level_size[i], count, sizes);
    glProgramUniform1f(gp, pass->gather_radius_px_m[i], sta_normals_pyramid_radius_px_m(view, &p));
    glProgramUniform1f(gp, pass->gather_near[i], view->near_m);
    glProgramUniform1f(gp, pass->gather_jump2[i], jump2);
    glProgramUniform1f(gp, pass->gather_texel_m[i], sta_normals_pyramid_texel_m(view, 0));
    glProgramUniform1f(gp, pass->gather_plane_tolerance_m[i],
                       sta_normals_pyramid_plane_tolerance_m(view, &p));
    glProgramUniform1f(gp, pass->gather_coherence[i], sta_normals_pyramid_coherence(&p));
    glProgramUniform1f(gp, pass->gather_fine_coherence[i], sta_normals_pyramid_fine_coherence(&p));
    glProgramUniform1i(gp, pass->gather_fine_min_level[i], anchor_level);
    glBindImageTexture(STA_NORMALS_PYRAMID_GATHER_IMAGE_NORMAL, i ? pass->half : out_normal_tex, 0,
                       GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    glBindImageTexture(STA_NORMALS_PYRAMID_IMAGE_POINTS, filled_position_tex, 0, GL_FALSE, 0,
                       GL_READ_ONLY, GL_RGBA32F);
    glBindImageTexture(STA_NORMALS_PYRAMID_GATHER_IMAGE_ATLAS, pass->atlas, 0, GL_FALSE, 0,
                       GL_READ_ONLY, GL_RGBA32F);
    if (i) {
        glProgramUniform1i(gp, glGetUniformLocation(gp, "u_anchor_level"), anchor_level);
        sta_gl_dispatch_2d(hw, hh);
        sta_normals_upsample_inputs in = { pass->half,
                                           hw,
                                           hh,
                                           count,
                                           anchor_level,
                                           view->near_m,
                                           sta_normals_pyramid_radius_px_m(view, &p),
                                           sta_normals_pyramid_plane_tolerance_m(view, &p) };
        if (deferred) { // the caller's shader upsamples (shade.comp STA_SHADE_UPSAMPLE)
            *deferred = in;
        } else {
            GLuint up = pass->upsample_program;
            glUseProgram(up);
            glProgramUniform2i(up, pass->upsample_size, view->width_px, view->height_px);
            sta_normals_upsample_bind(up, &pass->upsample, &in);
            glBindImageTexture(STA_NORMALS_PYRAMID_UPSAMPLE_IMAGE_NORMAL, out_normal_tex, 0,
                               GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
            sta_gl_dispatch_2d(view->width_px, view->height_px);
        }
    } else {
        sta_gl_dispatch_2d(view->width_px, view->height_px);
    }
    for (GLuint unit = 0; unit <= STA_NORMALS_PYRAMID_IMAGE_LAST; unit++) {
        glBindImageTexture(unit, 0, 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
    }
    return sta_gl_check("pyramidal normal pass", err);
}

sta_status sta_normals_pyramid_pass_run(sta_normals_pyramid_pass *pass, const sta_view_params *view,
                                        const sta_normals_pyramid_params *params,
                                        const sta_pullpush_pyramid *pyramid,
                                        GLuint filled_position_tex, GLuint out_normal_tex,
                                        sta_error *err)
{
    return run(pass, view, params, pyramid, filled_position_tex, out_normal_tex, NULL, err);
}

sta_status sta_normals_pyramid_pass_run_deferred(sta_normals_pyramid_pass *pass,
                                                 const sta_view_params *view,
                                                 const sta_normals_pyramid_params *params,
                                                 const sta_pullpush_pyramid *pyramid,
                                                 GLuint filled_position_tex,
                                                 sta_normals_upsample_inputs *out, sta_error *err)
{
    sta_normals_pyramid_params p = params ? *params : (sta_normals_pyramid_params){ 0 };
    p.half_resolution = true;
    memset(out, 0, sizeof(*out));
    return run(pass, view, &p, pyramid, filled_position_tex, 0, out, err);
}
