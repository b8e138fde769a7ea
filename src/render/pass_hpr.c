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
#include "render/gl_staged.h"

/* Entries of the refinement list per dispatch row. */
#define STA_HPR_LIST_WIDTH           1024
/* 2x2 blocks per side of a copy step's tile (hpr_sparse_classify.comp): 8 x 8 grid pixels. */
#define STA_HPR_CLASSIFY_TILE        4
/* Tiles per workgroup of the copy step: a row of them. */
#define STA_HPR_CLASSIFY_GROUP_TILES (STA_WORKGROUP_SIZE_X * STA_WORKGROUP_SIZE_Y)
/* Room for the shader defines (shader_defines) and a variant's own. */
#define STA_HPR_DEFINES_SIZE         2048

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
             "#define STA_HPR_CUT_FACTOR %.9e\n"
             "#define STA_HPR_EMPTY_CUT_BLOCKS %.9e\n"
             "#define STA_HPR_AXIS_TOL %.9e\n"
             "#define STA_HPR_SPARSE_DEPTH_TAU %.9e\n"
             "#define STA_HPR_LIST_WIDTH %d\n"
             "#define STA_HPR_ANCHOR_STRIDE %d\n"
             "#define STA_POSITION_W_OCCLUDER_MAX %.9e\n"
             "#define STA_HPR_SURFACE_MIN_POINTS %d\n"
             "#define STA_HPR_SURFACE_MIN_DET %.9e\n"
             "#define STA_HPR_SURFACE_FRONT_SHARE %.9e\n"
             "#define STA_HPR_CLASSIFY_TILE %d\n"
             "#define STA_HPR_CLASSIFY_GROUP_TILES %d\n"
             "#define STA_POSITION_W_SEE_THROUGH_MIN %.9e\n"
             "#define STA_HPR_SOLID_LEVELS %d\n"
             "#define STA_HPR_SOLID_VALUE %.9e\n"
             "#define STA_HPR_EMPTY_WIDEN_OPEN %d\n"
             "#define STA_HPR_EMPTY_NEAR_RADII %.9e\n"
             "#define STA_HPR_EMPTY_NEAR_MIN_PX %.9e\n",
             STA_HPR_MAX_LEVELS, STA_HPR_SECTOR_TAN_NUM, STA_HPR_SECTOR_TAN_DEN,
             (double)STA_HPR_MIN_LENGTH2_M2, (double)STA_LABEL_BACKGROUND,
             (double)STA_LABEL_VISIBLE, (double)STA_LABEL_HIDDEN, (double)STA_LABEL_HOLE,
             (double)STA_HPR_SQRT_HALF, (double)STA_HPR_MIN_REACH_PX, (double)STA_HPR_MAX_REACH_PX,
             (double)STA_HPR_CUT_FACTOR, (double)STA_HPR_EMPTY_CUT_BLOCKS, (double)STA_HPR_AXIS_TOL,
             (double)STA_HPR_SPARSE_DEPTH_TAU, STA_HPR_LIST_WIDTH, STA_HPR_ANCHOR_STRIDE,
             (double)STA_POSITION_W_OCCLUDER_MAX, STA_HPR_SURFACE_MIN_POINTS,
             (double)STA_HPR_SURFACE_MIN_DET, (double)STA_HPR_SURFACE_FRONT_SHARE,
             STA_HPR_CLASSIFY_TILE, STA_HPR_CLASSIFY_GROUP_TILES,
             (double)STA_POSITION_W_SEE_THROUGH_MIN, STA_HPR_SOLID_LEVELS,
             (double)STA_HPR_SOLID_VALUE, STA_HPR_EMPTY_WIDEN_OPEN,
             (double)STA_HPR_EMPTY_NEAR_RADII, (double)STA_HPR_EMPTY_NEAR_MIN_PX);
}

sta_status sta_hpr_pass_init(sta_hpr_pass *pass, sta_error *err)
{
    memset(pass, 0, sizeof(*pass));
    char defines[STA_HPR_DEFINES_SIZE];
    shader_defines(defines, sizeof(defines));
    const char *pyramid[] = { "hpr_pyramid.comp" };
    const char *exhaustive[] = { "hpr_common.glsl", "hpr_exhaustive.comp" };
    const char *classify[] = { "hpr_sparse_classify.comp" };
    pass->staged = sta_gl_staged_stores();
    char pyramid_defines[STA_HPR_DEFINES_SIZE + 64];
    snprintf(pyramid_defines, sizeof(pyramid_defines), "%s%s", defines,
             sta_gl_staged_define(pass->staged));
    sta_status status =
        sta_gl_program_create(pyramid, 1, pyramid_defines, &pass->pyramid_program, err);
    if (status == STA_OK) {
        status = sta_gl_program_create(exhaustive, 2, defines, &pass->exhaustive_program, err);
    }
    if (status == STA_OK) {
        status = sta_gl_program_create(classify, 1, defines, &pass->classify_program, err);
    }
    if (status != STA_OK) {
        sta_hpr_pass_release(pass);
        return status;
    }
    GLuint p = pass->pyramid_program;
    pass->pyr_src_size = glGetUniformLocation(p, "u_src_size");
    pass->pyr_dst_size = glGetUniformLocation(p, "u_dst_size");
    pass->pyr_src_origin = glGetUniformLocation(p, "u_src_origin");
    pass->pyr_dst_origin = glGetUniformLocation(p, "u_dst_origin");
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
    GLuint programs[] = { pass->pyramid_program, pass->exhaustive_program, pass->classify_program,
                          pass->refine_programs[0], pass->refine_programs[1] };
    for (size_t i = 0; i < sizeof(programs) / sizeof(programs[0]); i++) {
        if (programs[i]) {
            glDeleteProgram(programs[i]);
        }
    }
    for (int see = 0; see < 2; see++) {
        for (int m = 0; m < 2; m++) {
            for (int i = 0; i < 3; i++) {
                if (pass->gap_programs[see][m][i]) {
                    glDeleteProgram(pass->gap_programs[see][m][i]);
                }
            }
        }
    }
    if (pass->list_buffer) {
        glDeleteBuffers(1, &pass->list_buffer);
    }
    if (pass->dispatch_buffer) {
        glDeleteBuffers(1, &pass->dispatch_buffer);
    }
    sta_gl_staging_release(&pass->own_staging);
    memset(pass, 0, sizeof(*pass));
}

void sta_hpr_pyramid_level_origin(int width_px, int height_px, int level, int out_origin[2])
{
    out_origin[0] = out_origin[1] = 0;
    if (level >= 2) {
        out_origin[0] = sta_hpr_level_size(width_px, 1);
        for (int l = 2; l < level; l++) {
            out_origin[1] += sta_hpr_level_size(height_px, l);
        }
    }
}

void sta_hpr_pyramid_texture_size(int width_px, int height_px, int *out_width, int *out_height)
{
    int levels = sta_hpr_pyramid_levels(width_px, height_px);
    *out_width = *out_height = 0;
    if (levels == 0) {
        return;
    }
    int column_h = 0; // levels >= 2, one below the other
    for (int l = 2; l < levels; l++) {
        column_h += sta_hpr_level_size(height_px, l);
    }
    int level1_h = sta_hpr_level_size(height_px, 1);
    *out_width =
        sta_hpr_level_size(width_px, 1) + (levels > 2 ? sta_hpr_level_size(width_px, 2) : 0);
    *out_height = column_h > level1_h ? column_h : level1_h;
}

sta_status sta_hpr_pyramid_texture_create(int width_px, int height_px, GLuint *out_texture,
                                          sta_error *err)
{
    *out_texture = 0;
    int w, h;
    sta_hpr_pyramid_texture_size(width_px, height_px, &w, &h);
    if (w == 0) {
        return sta_fail(err, STA_ERR_ARG, "hpr: no pyramid for a %dx%d image (1..%d px a side)",
                        width_px, height_px, 1 << (STA_HPR_MAX_LEVELS - 1));
    }
    return sta_gl_texture_create(w, h, 4, 1, out_texture, err);
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

sta_status sta_hpr_pass_build_pyramid(sta_hpr_pass *pass, const sta_view_params *view,
                                      GLuint position_texture, GLuint pyramid_texture,
                                      sta_error *err)
{
    int w = view->width_px, h = view->height_px;
    int levels = sta_hpr_pyramid_levels(w, h);
    if (levels == 0) {
        return sta_fail(err, STA_ERR_ARG, "hpr: view %dx%d has no pyramid", w, h);
    }
    int atlas_w, atlas_h;
    sta_hpr_pyramid_texture_size(w, h, &atlas_w, &atlas_h);
    sta_status status = check_size(position_texture, 0, w, h, "position", err);
    if (status == STA_OK) {
        status = check_size(pyramid_texture, 0, atlas_w, atlas_h, "pyramid", err);
    }
    if (status != STA_OK) {
        return status;
    }
    glUseProgram(pass->pyramid_program);
    sta_gl_staging *staging = sta_gl_staging_pick(&pass->own_staging, pass->shared_staging);
    if (!pass->staged) {
        glBindImageTexture(STA_HPR_PYRAMID_IMAGE_DST, pyramid_texture, 0, GL_FALSE, 0,
                           GL_WRITE_ONLY, GL_RGBA32F);
    }
    int src_origin[2] = { 0, 0 }, dst_origin[2];
    for (int l = 1; l < levels; l++) {
        // Level 1 from the positions, level l from level l - 1 of the same texture (the
        // regions do not overlap).
        GLuint src = l == 1 ? position_texture : pyramid_texture;
        int dst_w = sta_hpr_level_size(w, l), dst_h = sta_hpr_level_size(h, l);
        sta_hpr_pyramid_level_origin(w, h, l, dst_origin);
        glUniform2i(pass->pyr_src_size, sta_hpr_level_size(w, l - 1), sta_hpr_level_size(h, l - 1));
        glUniform2i(pass->pyr_dst_size, dst_w, dst_h);
        glUniform2i(pass->pyr_src_origin, src_origin[0], src_origin[1]);
        glUniform2i(pass->pyr_dst_origin, dst_origin[0], dst_origin[1]);
        glBindImageTexture(STA_HPR_PYRAMID_IMAGE_SRC, src, 0, GL_FALSE, 0, GL_READ_ONLY,
                           GL_RGBA32F);
        if (pass->staged) {
            status = sta_gl_staging_bind(staging, STA_HPR_PYRAMID_BUFFER_DST, 1, dst_w, dst_h, err);
            if (status != STA_OK) {
                return status;
            }
        }
        sta_gl_dispatch_2d(dst_w, dst_h);
        if (pass->staged) {
            sta_gl_staging_copy(staging, 0, pyramid_texture, dst_origin[0], dst_origin[1], dst_w,
                                dst_h);
        }
        src_origin[0] = dst_origin[0];
        src_origin[1] = dst_origin[1];
    }
    return sta_gl_check("hpr pyramid", err);
}

static void tan_half(const sta_view_params *view, float out[2])
{
    // As the twin (hpr_ref.c frame_of) computes them.
    out[1] = tanf(0.5f * view->fov_y);
    out[0] = out[1] * (float)view->width_px / (float)view->height_px;
}

// The occlusion uniforms of one variant of hpr_occlusion.comp.
static void set_occlusion_uniforms(GLuint program, const sta_view_params *view,
                                   const sta_hpr_params *p, int levels, const float *level_depth)
{
    int coarse = p->coarse_level < levels - 1 ? p->coarse_level : levels - 1; // >= 1
    float th[2];
    tan_half(view, th);
    glUseProgram(program);
    glUniform2i(glGetUniformLocation(program, "u_size"), view->width_px, view->height_px);
    glUniform1i(glGetUniformLocation(program, "u_level_count"), levels);
    glUniform1i(glGetUniformLocation(program, "u_coarse_level"), coarse);
    glUniform1fv(glGetUniformLocation(program, "u_level_depth"), levels, level_depth);
    GLint origins[2 * STA_HPR_MAX_LEVELS] = { 0 };
    for (int l = 1; l < levels; l++) {
        sta_hpr_pyramid_level_origin(view->width_px, view->height_px, l, origins + 2 * l);
    }
    glUniform2iv(glGetUniformLocation(program, "u_level_origin"), levels, origins);
    glUniform2f(glGetUniformLocation(program, "u_tan_half"), th[0], th[1]);
    glUniform1f(glGetUniformLocation(program, "u_far"), p->far_m);
    glUniform1f(glGetUniformLocation(program, "u_threshold"), p->threshold);
    glUniform1f(glGetUniformLocation(program, "u_radius_k"), sta_hpr_radius_k(view, p));
    glUniform1f(glGetUniformLocation(program, "u_gap"), sta_hpr_occluder_gap_m(view, p));
    glUniform1f(glGetUniformLocation(program, "u_marked_reach"),
                sta_hpr_marked_reach_px_m(view, p));
    glUniform1f(glGetUniformLocation(program, "u_surface_tol"), sta_hpr_surface_tol_m(view, p));
    glUniform1f(glGetUniformLocation(program, "u_empty_border"),
                sta_hpr_empty_border_px(view->height_px));
    // As the twin (hpr_ref.c frame_of): pixels per unit of x / d and y / d.
    glUniform2f(glGetUniformLocation(program, "u_scale"), 0.5f * (float)view->width_px / th[0],
                0.5f * (float)view->height_px / th[1]);
}

// Grows the refinement list to hold `pixels` entries after its count.
static sta_status ensure_list(sta_hpr_pass *pass, int pixels, sta_error *err)
{
    if (pass->list_buffer && pass->list_pixels >= pixels) {
        return STA_OK;
    }
    if (pass->list_buffer) {
        glDeleteBuffers(1, &pass->list_buffer);
    }
    if (!pass->dispatch_buffer) {
        glCreateBuffers(1, &pass->dispatch_buffer);
        glNamedBufferStorage(pass->dispatch_buffer, 6 * sizeof(GLuint), NULL,
                             GL_DYNAMIC_STORAGE_BIT);
    }
    glCreateBuffers(1, &pass->list_buffer);
    // Two counts, then the pixels: the shaders take the lists' room from its length.
    glNamedBufferStorage(pass->list_buffer, ((GLsizeiptr)pixels + 2) * (GLsizeiptr)sizeof(GLuint),
                         NULL, GL_DYNAMIC_STORAGE_BIT);
    pass->list_pixels = pixels;
    return sta_gl_check("hpr refinement list", err);
}

// One copy step of the sparse operator on the grid of pixels whose x and y are
// multiples of `stride`, then the refinement of the points and of the empty pixels it
// listed (`refine`: the two programs; one indirect dispatch each, sized by the copy step:
// no count read back, so a GPU does not stall).
static void copy_and_refine(sta_hpr_pass *pass, const sta_view_params *view,
                            const sta_hpr_params *p, int levels, const float *level_depth,
                            const GLuint refine[2], int stride)
{
    int w = view->width_px, h = view->height_px;
    const GLuint zero[2] = { 0, 0 };
    // The refinements' workgroups: a row of STA_HPR_LIST_WIDTH pixels across, rows
    // added by the classify step as each list grows (none when it stays empty).
    const GLuint groups[6] = { STA_HPR_LIST_WIDTH / STA_WORKGROUP_SIZE_X, 0, 1,
                               STA_HPR_LIST_WIDTH / STA_WORKGROUP_SIZE_X, 0, 1 };
    glNamedBufferSubData(pass->list_buffer, 0, sizeof(zero), zero);
    glNamedBufferSubData(pass->dispatch_buffer, 0, sizeof(groups), groups);
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    glUseProgram(pass->classify_program);
    glUniform2i(glGetUniformLocation(pass->classify_program, "u_size"), w, h);
    glUniform1i(glGetUniformLocation(pass->classify_program, "u_stride"), stride);
    int grid_w = (w + stride - 1) / stride, grid_h = (h + stride - 1) / stride;
    // One invocation per tile of STA_HPR_CLASSIFY_TILE x STA_HPR_CLASSIFY_TILE 2x2 blocks,
    // a workgroup per row of STA_HPR_CLASSIFY_GROUP_TILES tiles.
    const int tile = 2 * STA_HPR_CLASSIFY_TILE;
    const int tiles_w = (grid_w + tile - 1) / tile, tiles_h = (grid_h + tile - 1) / tile;
    glDispatchCompute(
        (GLuint)((tiles_w + STA_HPR_CLASSIFY_GROUP_TILES - 1) / STA_HPR_CLASSIFY_GROUP_TILES),
        (GLuint)tiles_h, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT |
                    GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, pass->dispatch_buffer);
    for (int kind = 0; kind < 2; kind++) { // the points, then the empty pixels
        set_occlusion_uniforms(refine[kind], view, p, levels, level_depth);
        glDispatchComputeIndirect((GLintptr)(3 * sizeof(GLuint) * (size_t)kind));
    }
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, 0);
}

// The sparse operator (docs/HPR.md, "Sparse operator"): the operator on the anchors
// (x and y multiples of sta_hpr_anchor_stride), then copy steps with their refinements
// on ever finer grids, down to every pixel from the even ones. programs: the empty
// pixels' rule's (every pixel, anchors, listed empty pixels); refine_points: the listed
// points'.
static sta_status run_sparse(sta_hpr_pass *pass, const sta_view_params *view,
                             const sta_hpr_params *p, int levels, const float *level_depth,
                             const GLuint programs[3], GLuint refine_points, GLuint label_texture,
                             sta_error *err)
{
    int w = view->width_px, h = view->height_px;
    sta_status status = ensure_list(pass, w * h, err);
    if (status != STA_OK) {
        return status;
    }
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, STA_HPR_OCCLUSION_BUFFER_LIST, pass->list_buffer);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, STA_HPR_SPARSE_CLASSIFY_BUFFER_DISPATCH,
                     pass->dispatch_buffer);
    glBindImageTexture(STA_HPR_OCCLUSION_IMAGE_LABEL, label_texture, 0, GL_FALSE, 0, GL_READ_WRITE,
                       STA_GL_LABEL_FORMAT);
    set_occlusion_uniforms(programs[1], view, p, levels, level_depth);
    const int stride = sta_hpr_anchor_stride(h);
    glUniform1i(glGetUniformLocation(programs[1], "u_anchor_stride"), stride);
    sta_gl_dispatch_2d((w + stride - 1) / stride, (h + stride - 1) / stride);
    const GLuint refine[2] = { refine_points, programs[2] };
    for (int step = stride / 2; step >= 1; step /= 2) {
        copy_and_refine(pass, view, p, levels, level_depth, refine, step);
    }
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT |
                    GL_TEXTURE_UPDATE_BARRIER_BIT);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, STA_HPR_OCCLUSION_BUFFER_LIST, 0);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, STA_HPR_SPARSE_CLASSIFY_BUFFER_DISPATCH, 0);
    return sta_gl_check("hpr sparse occlusion", err);
}

// The programs of the see-through rule `see` and the empty pixels' rule `smooth` (every
// pixel, anchors, listed empty pixels) and the see-through rule's listed points' program,
// compiled on first use; each rule's programs hold no code of the other. Without the
// see-through rule (positions from depth, which hold no see-through returns) HPR saves
// its minima and solid test (issue 15, sixteenth round: cost margin).
static sta_status occlusion_programs(sta_hpr_pass *pass, bool see, bool smooth, sta_error *err)
{
    GLuint *out = pass->gap_programs[see ? 1 : 0][smooth ? 1 : 0];
    GLuint *refine = &pass->refine_programs[see ? 1 : 0];
    if (out[0] && *refine) {
        return STA_OK;
    }
    const char *occlusion[] = { "hpr_common.glsl", "hpr_occlusion.comp" };
    const char *variants[4] = { "", "#define HPR_ANCHORS 1\n",
                                "#define HPR_REFINE 1\n#define HPR_EMPTY_LIST 1\n",
                                "#define HPR_REFINE 1\n" };
    GLuint *targets[4] = { &out[0], &out[1], &out[2], refine };
    char defines[STA_HPR_DEFINES_SIZE];
    shader_defines(defines, sizeof(defines));
    size_t n = strlen(defines);
    sta_status status = STA_OK;
    for (int i = 0; i < 4 && status == STA_OK; i++) {
        if (*targets[i]) {
            continue; // the points' program, shared by both empty pixels' rules
        }
        // The points' program has no empty pixels' code: no smooth variant.
        snprintf(defines + n, sizeof(defines) - n, "%s%s%s",
                 see ? "#define HPR_SEE_THROUGH 1\n" : "",
                 smooth && i < 3 ? "#define HPR_SMOOTH_GAPS 1\n" : "", variants[i]);
        status = sta_gl_program_create(occlusion, 2, defines, targets[i], err);
    }
    if (status != STA_OK) {
        for (int i = 0; i < 3; i++) {
            if (out[i]) {
                glDeleteProgram(out[i]);
            }
            out[i] = 0;
        }
    }
    return status;
}

sta_status sta_hpr_pass_run_pyramid(sta_hpr_pass *pass, const sta_view_params *view,
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
    glBindImageTexture(STA_HPR_OCCLUSION_IMAGE_POSITION, position_texture, 0, GL_FALSE, 0,
                       GL_READ_ONLY, GL_RGBA32F);
    glBindImageTexture(STA_HPR_OCCLUSION_IMAGE_PYRAMID, pyramid_texture, 0, GL_FALSE, 0,
                       GL_READ_ONLY, GL_RGBA32F);
    // every pixel, anchors, listed empty pixels: the rules' own
    const int see = p.no_see_through ? 0 : 1, smooth = p.block_gaps ? 0 : 1;
    status = occlusion_programs(pass, see, smooth, err);
    if (status != STA_OK) {
        return status;
    }
    const GLuint *programs = pass->gap_programs[see][smooth];
    if (p.sparse) {
        return run_sparse(pass, view, &p, levels, level_depth, programs, pass->refine_programs[see],
                          label_texture, err);
    }
    set_occlusion_uniforms(programs[0], view, &p, levels, level_depth);
    glBindImageTexture(STA_HPR_OCCLUSION_IMAGE_LABEL, label_texture, 0, GL_FALSE, 0, GL_WRITE_ONLY,
                       STA_GL_LABEL_FORMAT);
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
                       STA_GL_LABEL_FORMAT);
    sta_gl_dispatch_2d(view->width_px, view->height_px);
    return sta_gl_check("hpr exhaustive occlusion", err);
}
