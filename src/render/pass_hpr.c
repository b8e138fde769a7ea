/* SPDX-License-Identifier: MIT
 * The HPR pass (pyramid, pyramidal occlusion, exhaustive occlusion).
 *
 * Based on: Bouchiba, Deschaud, Goulette 2018, section 3.1; Pintus, Gobbetti, Agus 2011.
 */
#include "render/pass_hpr.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "render/bindings.h"
#include "render/gl.h"
#include "render/gl_image.h"

// The constants of hpr_ref.h and screen_space.h the shaders use, as #defines.
static void shader_defines(char *out, size_t size)
{
    snprintf(out, size,
             "#define STA_HPR_MAX_LEVELS %d\n"
             "#define STA_HPR_SECTOR_TAN_NUM %d\n"
             "#define STA_HPR_SECTOR_TAN_DEN %d\n"
             "#define STA_HPR_MIN_LENGTH2_M2 %.9e\n"
             "#define STA_LABEL_BACKGROUND %.1f\n"
             "#define STA_LABEL_VISIBLE %.1f\n"
             "#define STA_LABEL_HIDDEN %.1f\n"
             "#define STA_LABEL_HOLE %.1f\n"
             "#define STA_HPR_SQRT_HALF %.9e\n"
             "#define STA_HPR_MIN_REACH_PX %.9e\n"
             "#define STA_HPR_MAX_REACH_PX %.9e\n"
             "#define STA_HPR_CUT_FACTOR %.9e\n",
             STA_HPR_MAX_LEVELS, STA_HPR_SECTOR_TAN_NUM, STA_HPR_SECTOR_TAN_DEN,
             (double)STA_HPR_MIN_LENGTH2_M2, (double)STA_LABEL_BACKGROUND,
             (double)STA_LABEL_VISIBLE, (double)STA_LABEL_HIDDEN, (double)STA_LABEL_HOLE,
             (double)STA_HPR_SQRT_HALF, (double)STA_HPR_MIN_REACH_PX, (double)STA_HPR_MAX_REACH_PX,
             (double)STA_HPR_CUT_FACTOR);
}

sta_status sta_hpr_pass_init(sta_hpr_pass *pass, sta_error *err)
{
    memset(pass, 0, sizeof(*pass));
    char defines[1024];
    shader_defines(defines, sizeof(defines));
    const char *pyramid[] = { "hpr_pyramid.comp" };
    const char *occlusion[] = { "hpr_common.glsl", "hpr_occlusion.comp" };
    const char *exhaustive[] = { "hpr_common.glsl", "hpr_exhaustive.comp" };
    sta_status status = sta_gl_program_create(pyramid, 1, defines, &pass->pyramid_program, err);
    if (status == STA_OK) {
        status = sta_gl_program_create(occlusion, 2, defines, &pass->occlusion_program, err);
    }
    if (status == STA_OK) {
        status = sta_gl_program_create(exhaustive, 2, defines, &pass->exhaustive_program, err);
    }
    if (status != STA_OK) {
        sta_hpr_pass_release(pass);
        return status;
    }
    GLuint p = pass->pyramid_program;
    pass->pyr_src_size = glGetUniformLocation(p, "u_src_size");
    pass->pyr_dst_size = glGetUniformLocation(p, "u_dst_size");
    p = pass->occlusion_program;
    pass->occ_size = glGetUniformLocation(p, "u_size");
    pass->occ_level_count = glGetUniformLocation(p, "u_level_count");
    pass->occ_coarse_level = glGetUniformLocation(p, "u_coarse_level");
    pass->occ_level_depth = glGetUniformLocation(p, "u_level_depth");
    pass->occ_tan_half = glGetUniformLocation(p, "u_tan_half");
    pass->occ_far = glGetUniformLocation(p, "u_far");
    pass->occ_threshold = glGetUniformLocation(p, "u_threshold");
    pass->occ_radius_k = glGetUniformLocation(p, "u_radius_k");
    pass->occ_scale = glGetUniformLocation(p, "u_scale");
    p = pass->exhaustive_program;
    pass->exh_size = glGetUniformLocation(p, "u_size");
    pass->exh_radius = glGetUniformLocation(p, "u_radius");
    pass->exh_tan_half = glGetUniformLocation(p, "u_tan_half");
    pass->exh_far = glGetUniformLocation(p, "u_far");
    pass->exh_threshold = glGetUniformLocation(p, "u_threshold");
    return STA_OK;
}

void sta_hpr_pass_release(sta_hpr_pass *pass)
{
    GLuint programs[] = { pass->pyramid_program, pass->occlusion_program,
                          pass->exhaustive_program };
    for (size_t i = 0; i < sizeof(programs) / sizeof(programs[0]); i++) {
        if (programs[i]) {
            glDeleteProgram(programs[i]);
        }
    }
    memset(pass, 0, sizeof(*pass));
}

// Smallest mip-0 extent along one axis such that mip g (floor halving, at least 1)
// holds pyramid level g + 1 for every mip g < mip_levels.
static int padded_extent(int size_px, int mip_levels)
{
    int extent = 1;
    for (int g = 0; g < mip_levels; g++) {
        int need = sta_hpr_level_size(size_px, g + 1);
        if (need >= 2 && (need << g) > extent) {
            extent = need << g;
        }
    }
    return extent;
}

void sta_hpr_pyramid_texture_size(int width_px, int height_px, int *out_width, int *out_height,
                                  int *out_mip_levels)
{
    int levels = sta_hpr_pyramid_levels(width_px, height_px);
    if (levels == 0) {
        *out_width = *out_height = *out_mip_levels = 0;
        return;
    }
    *out_mip_levels = levels - 1;
    *out_width = padded_extent(width_px, levels - 1);
    *out_height = padded_extent(height_px, levels - 1);
}

sta_status sta_hpr_pyramid_texture_create(int width_px, int height_px, GLuint *out_texture,
                                          sta_error *err)
{
    *out_texture = 0;
    int w, h, mips;
    sta_hpr_pyramid_texture_size(width_px, height_px, &w, &h, &mips);
    if (mips == 0) {
        return sta_fail(err, STA_ERR_ARG, "hpr: no pyramid for a %dx%d image (1..%d px a side)",
                        width_px, height_px, 1 << (STA_HPR_MAX_LEVELS - 1));
    }
    return sta_gl_texture_create(w, h, 4, mips, out_texture, err);
}

// STA_ERR_ARG unless `texture` level `level` is at least width x height.
static sta_status check_size(GLuint texture, int level, int width, int height, const char *what,
                             sta_error *err)
{
    GLint w = 0, h = 0;
    glGetTextureLevelParameteriv(texture, level, GL_TEXTURE_WIDTH, &w);
    glGetTextureLevelParameteriv(texture, level, GL_TEXTURE_HEIGHT, &h);
    if (w < width || h < height) {
        return sta_fail(err, STA_ERR_ARG, "hpr: %s texture %u level %d is %dx%d, needs %dx%d", what,
                        texture, level, w, h, width, height);
    }
    return STA_OK;
}

sta_status sta_hpr_pass_build_pyramid(const sta_hpr_pass *pass, const sta_view_params *view,
                                      GLuint position_texture, GLuint pyramid_texture,
                                      sta_error *err)
{
    int w = view->width_px, h = view->height_px;
    int levels = sta_hpr_pyramid_levels(w, h);
    if (levels == 0) {
        return sta_fail(err, STA_ERR_ARG, "hpr: view %dx%d has no pyramid", w, h);
    }
    sta_status status = check_size(position_texture, 0, w, h, "position", err);
    for (int l = 1; l < levels && status == STA_OK; l++) {
        status = check_size(pyramid_texture, l - 1, sta_hpr_level_size(w, l),
                            sta_hpr_level_size(h, l), "pyramid", err);
    }
    if (status != STA_OK) {
        return status;
    }
    glUseProgram(pass->pyramid_program);
    for (int l = 1; l < levels; l++) {
        GLuint src = l == 1 ? position_texture : pyramid_texture;
        GLint src_mip = l == 1 ? 0 : l - 2;
        int dst_w = sta_hpr_level_size(w, l), dst_h = sta_hpr_level_size(h, l);
        glUniform2i(pass->pyr_src_size, sta_hpr_level_size(w, l - 1), sta_hpr_level_size(h, l - 1));
        glUniform2i(pass->pyr_dst_size, dst_w, dst_h);
        glBindImageTexture(STA_HPR_PYRAMID_IMAGE_SRC, src, src_mip, GL_FALSE, 0, GL_READ_ONLY,
                           GL_RGBA32F);
        glBindImageTexture(STA_HPR_PYRAMID_IMAGE_DST, pyramid_texture, l - 1, GL_FALSE, 0,
                           GL_WRITE_ONLY, GL_RGBA32F);
        sta_gl_dispatch_2d(dst_w, dst_h);
    }
    return sta_gl_check("hpr pyramid", err);
}

static void tan_half(const sta_view_params *view, float out[2])
{
    // As the twin (hpr_ref.c frame_of) computes them.
    out[1] = tanf(0.5f * view->fov_y);
    out[0] = out[1] * (float)view->width_px / (float)view->height_px;
}

sta_status sta_hpr_pass_run_pyramid(const sta_hpr_pass *pass, const sta_view_params *view,
                                    const sta_hpr_params *params, GLuint position_texture,
                                    GLuint pyramid_texture, GLuint label_texture, sta_error *err)
{
    sta_status status =
        sta_hpr_pass_build_pyramid(pass, view, position_texture, pyramid_texture, err);
    if (status == STA_OK) {
        status = check_size(label_texture, 0, view->width_px, view->height_px, "label", err);
    }
    if (status != STA_OK) {
        return status;
    }
    sta_hpr_params p = params ? *params : (sta_hpr_params){ 0 };
    sta_hpr_params_defaults(&p);
    int levels = sta_hpr_pyramid_levels(view->width_px, view->height_px);
    float level_depth[STA_HPR_MAX_LEVELS];
    sta_hpr_level_depths(view, &p, levels, level_depth);
    int coarse = p.coarse_level < levels - 1 ? p.coarse_level : levels - 1; // >= 1
    float th[2];
    tan_half(view, th);
    glUseProgram(pass->occlusion_program);
    glUniform2i(pass->occ_size, view->width_px, view->height_px);
    glUniform1i(pass->occ_level_count, levels);
    glUniform1i(pass->occ_coarse_level, coarse);
    glUniform1fv(pass->occ_level_depth, levels, level_depth);
    glUniform2f(pass->occ_tan_half, th[0], th[1]);
    glUniform1f(pass->occ_far, p.far_m);
    glUniform1f(pass->occ_threshold, p.threshold);
    glUniform1f(pass->occ_radius_k, sta_hpr_radius_k(view, &p));
    // As the twin (hpr_ref.c frame_of): pixels per unit of x / d and y / d.
    glUniform2f(pass->occ_scale, 0.5f * (float)view->width_px / th[0],
                0.5f * (float)view->height_px / th[1]);
    glBindTextureUnit(STA_HPR_OCCLUSION_SAMPLER_POSITION, position_texture);
    glBindTextureUnit(STA_HPR_OCCLUSION_SAMPLER_PYRAMID, pyramid_texture);
    glBindImageTexture(STA_HPR_OCCLUSION_IMAGE_LABEL, label_texture, 0, GL_FALSE, 0, GL_WRITE_ONLY,
                       GL_R32F);
    sta_gl_dispatch_2d(view->width_px, view->height_px);
    return sta_gl_check("hpr pyramidal occlusion", err);
}

sta_status sta_hpr_pass_run_exhaustive(const sta_hpr_pass *pass, const sta_view_params *view,
                                       const sta_hpr_params *params, int radius_px,
                                       GLuint position_texture, GLuint label_texture,
                                       sta_error *err)
{
    if (radius_px < 0 || radius_px > 1024 || view->width_px < 1 || view->height_px < 1) {
        return sta_fail(err, STA_ERR_ARG, "hpr: exhaustive radius %d px on a %dx%d view is invalid",
                        radius_px, view->width_px, view->height_px);
    }
    sta_status status =
        check_size(position_texture, 0, view->width_px, view->height_px, "position", err);
    if (status == STA_OK) {
        status = check_size(label_texture, 0, view->width_px, view->height_px, "label", err);
    }
    if (status != STA_OK) {
        return status;
    }
    sta_hpr_params p = params ? *params : (sta_hpr_params){ 0 };
    sta_hpr_params_defaults(&p);
    float th[2];
    tan_half(view, th);
    glUseProgram(pass->exhaustive_program);
    glUniform2i(pass->exh_size, view->width_px, view->height_px);
    glUniform1i(pass->exh_radius, radius_px);
    glUniform2f(pass->exh_tan_half, th[0], th[1]);
    glUniform1f(pass->exh_far, p.far_m);
    glUniform1f(pass->exh_threshold, p.threshold);
    glBindTextureUnit(STA_HPR_EXHAUSTIVE_SAMPLER_POSITION, position_texture);
    glBindImageTexture(STA_HPR_EXHAUSTIVE_IMAGE_LABEL, label_texture, 0, GL_FALSE, 0, GL_WRITE_ONLY,
                       GL_R32F);
    sta_gl_dispatch_2d(view->width_px, view->height_px);
    return sta_gl_check("hpr exhaustive occlusion", err);
}
