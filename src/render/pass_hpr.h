/* SPDX-License-Identifier: MIT
 * The HPR pass: labels each pixel of a position texture VISIBLE, HIDDEN, HOLE or
 * BACKGROUND (screen_space.h) with the pyramidal adaptive operator (Bouchiba et al.
 * 2018, section 3.1) or the exhaustive fixed-radius operator (Pintus et al. 2011). The rules
 * and their CPU twin are in render/ref/hpr_ref.h; docs/HPR.md explains every choice.
 * Main thread (GL) only.
 *
 * Pyramid texture layout: level 0 of the pyramid is the position texture itself; levels
 * l >= 1, of logical size max(1, ceil(w / 2^l)) x max(1, ceil(h / 2^l)), lie side by
 * side in one RGBA32F texture of one mip level: level 1 at (0, 0), levels 2, 3, ... in a
 * column to its right, each below the one before (sta_hpr_pyramid_level_origin). The
 * shaders read them with imageLoad, which llvmpipe runs ~2.5x cheaper than a texelFetch
 * from mip levels (issue 15, fourteenth round). Texels outside the levels are never
 * read or written.
 */
#ifndef STA_RENDER_PASS_HPR_H
#define STA_RENDER_PASS_HPR_H

#include <epoxy/gl.h>

#include "core/status.h"
#include "render/gl_staged.h"
#include "render/ref/hpr_ref.h"
#include "render/ref/screen_space.h"

typedef struct sta_hpr_pass {
    GLuint pyramid_program;    /* hpr_pyramid.comp: one level from the one below */
    GLuint exhaustive_program; /* hpr_exhaustive.comp: fixed-radius operator */
    /* The sparse operator (sta_hpr_params.sparse): hpr_sparse_classify.comp lists the
     * pixels to refine, points and empty pixels apart; hpr_occlusion.comp refines the
     * points (refine_programs, HPR_REFINE). */
    GLuint classify_program;
    /* Per see-through rule (index 0: sta_hpr_params.no_see_through, 1: the rule on, with
     * HPR_SEE_THROUGH) and per empty pixels' rule (index 0: sta_hpr_params.block_gaps, 1:
     * per pixel, the default, with HPR_SMOOTH_GAPS), the programs of hpr_occlusion.comp
     * that differ: every pixel, the anchors (HPR_ANCHORS), the listed empty pixels
     * (HPR_REFINE, HPR_EMPTY_LIST); and per see-through rule the listed points' program
     * (HPR_REFINE). Compiled when first asked for: a uniform switch cost 30 CPU ms at
     * 1080p, llvmpipe running both sides. */
    GLuint gap_programs[2][2][3];
    GLuint refine_programs[2];
    GLuint list_buffer;     /* two counts, then the pixels to refine (points from the front,
                               empty pixels from the back); grown as needed */
    int list_pixels;        /* pixels the list buffer holds */
    GLuint dispatch_buffer; /* the refinements' two indirect dispatches, sized by the copy step */
    GLint pyr_src_size, pyr_dst_size, pyr_src_origin, pyr_dst_origin;
    GLint exh_size, exh_radius, exh_tan_half, exh_far, exh_threshold;
    bool staged; /* the pyramid's levels through a staging buffer (render/gl_staged.h) */
    sta_gl_staging own_staging;
    sta_gl_staging *shared_staging; /* NULL: own_staging (the pipeline sets its own) */
} sta_hpr_pass;

/* Compiles the pyramid, exhaustive and copy-step programs (the occlusion programs are
 * compiled when first used). Needs a current GL 4.5 context. */
sta_status sta_hpr_pass_init(sta_hpr_pass *pass, sta_error *err);

/* Deletes the programs; a zeroed pass is a no-op. */
void sta_hpr_pass_release(sta_hpr_pass *pass);

/* Size of the pyramid texture for a width x height image (see the layout above); both 0
 * for sizes sta_hpr_pyramid_levels rejects. For 1920x1080: 1440x544 (12 MiB). */
void sta_hpr_pyramid_texture_size(int width_px, int height_px, int *out_width, int *out_height);

/* Texel (0, 0) of pyramid level `level` (1 .. sta_hpr_pyramid_levels - 1) in the
 * pyramid texture of a width x height image. */
void sta_hpr_pyramid_level_origin(int width_px, int height_px, int level, int out_origin[2]);

/* Creates the caller-owned pyramid texture for a width x height image (RGBA32F, the
 * size above). Reuse it for every frame of that size; delete with glDeleteTextures. */
sta_status sta_hpr_pyramid_texture_create(int width_px, int height_px, GLuint *out_texture,
                                          sta_error *err);

/* Builds pyramid levels 1 .. sta_hpr_pyramid_levels - 1 of `position_texture` (RGBA32F,
 * view's size) into `pyramid_texture` (made by sta_hpr_pyramid_texture_create for the
 * same size). Errors: STA_ERR_ARG for mismatched sizes, STA_ERR_GL. */
sta_status sta_hpr_pass_build_pyramid(sta_hpr_pass *pass, const sta_view_params *view,
                                      GLuint position_texture, GLuint pyramid_texture,
                                      sta_error *err);

/* The pyramidal operator: builds the pyramid, then writes STA_LABEL_* into
 * `label_texture` (STA_GL_LABEL_FORMAT, view's size). params may be NULL (all defaults). With
 * params->sparse: the operator on the even (x, y) anchors, the copy step, the operator
 * on the refined pixels (the list buffer is grown here; its count is read back). */
sta_status sta_hpr_pass_run_pyramid(sta_hpr_pass *pass, const sta_view_params *view,
                                    const sta_hpr_params *params, GLuint position_texture,
                                    GLuint pyramid_texture, GLuint label_texture, sta_error *err);

/* The exhaustive operator over a (2 radius_px + 1)^2 square at level 0. Uses
 * params->threshold and far_m (NULL: defaults). radius_px in [0, 1024]. */
sta_status sta_hpr_pass_run_exhaustive(const sta_hpr_pass *pass, const sta_view_params *view,
                                       const sta_hpr_params *params, int radius_px,
                                       GLuint position_texture, GLuint label_texture,
                                       sta_error *err);

#endif
