/* SPDX-License-Identifier: MIT
 * The pyramidal normal estimator (Bouchiba et al. 2018, section 3.3) on the filled
 * pull-push pyramid. Twin: render/ref/normals_pyramid_ref.h; docs/PULLPUSH.md.
 *
 * Design: the normals of levels >= 1 go into one RGBA32F atlas texture owned by the
 * pass (level 1 at the origin, levels 2.. stacked in a column to its right, about 3/8
 * of the view's texels), so that the gather shader can pick a level per pixel; it is
 * (re)allocated when the view size changes. Level-0 normals are computed by the
 * gather shader itself where a pixel uses level 0. At half resolution
 * (params->half_resolution) the gather runs on the anchors only (every even pixel, every
 * 4th from 1080 px of view height: sta_normals_anchor_level), into a smaller image, and
 * an upsample pass interpolates every pixel from it (the twin's
 * steps 4-5). Main thread (GL) only.
 */
#ifndef STA_RENDER_PASS_NORMALS_PYRAMID_H
#define STA_RENDER_PASS_NORMALS_PYRAMID_H

#include <epoxy/gl.h>

#include "core/status.h"
#include "render/gl_staged.h"
#include "render/pass_pullpush.h"
#include "render/ref/normals_pyramid_ref.h"
#include "render/ref/screen_space.h"

/* What step 3 of the half-resolution normals (shaders/normals_upsample.glsl) reads: the
 * anchors' normals and the floats of the view. */
typedef struct sta_normals_upsample_inputs {
    GLuint half; /* RGBA32F, half_width_px x half_height_px: normal, plane offset */
    int half_width_px, half_height_px, level_count;
    int anchor_level; /* sta_normals_anchor_level: anchors every 2^anchor_level pixels */
    float near_m, radius_px_m, plane_tolerance_m;
} sta_normals_upsample_inputs;

/* The uniforms of normals_upsample.glsl in one program. */
typedef struct sta_normals_upsample_uniforms {
    GLint half_size, near, level_count, radius_px_m, plane_tolerance_m, anchor_level;
} sta_normals_upsample_uniforms;

/* Finds them in `program` (linked with normals_upsample.glsl). */
void sta_normals_upsample_locate(GLuint program, sta_normals_upsample_uniforms *uniforms);

/* Sets them for `in` and binds its half image (before a dispatch of `program`). */
void sta_normals_upsample_bind(GLuint program, const sta_normals_upsample_uniforms *uniforms,
                               const sta_normals_upsample_inputs *in);

typedef struct sta_normals_pyramid_pass {
    GLuint level_program, gather_program;
    GLuint anchor_program;   /* the gather on the even pixels (half resolution) */
    GLuint upsample_program; /* half resolution, step 3 */
    GLint level_size, level_offset, level_jump2, level_texel_m;
    /* [0] the gather program, [1] the anchor program */
    GLint gather_size[2], gather_level_count[2], gather_level_offset[2], gather_level_size[2];
    GLint gather_radius_px_m[2], gather_near[2], gather_plane_tolerance_m[2], gather_jump2[2];
    GLint gather_coherence[2], gather_fine_coherence[2], gather_fine_min_level[2];
    GLint gather_texel_m[2];
    GLint upsample_size;
    sta_normals_upsample_uniforms upsample;
    GLuint atlas; /* owned, RGBA32F */
    GLuint half;  /* owned, RGBA32F, ceil(w / 2) x ceil(h / 2): the anchors' normals */
    int atlas_width_px, atlas_height_px;
    int view_width_px, view_height_px;     /* the size the atlas was made for */
    int offset_x[STA_PULLPUSH_MAX_LEVELS]; /* level origins in the atlas */
    int offset_y[STA_PULLPUSH_MAX_LEVELS];
    bool staged; /* the levels' normals through a staging buffer (render/gl_staged.h) */
    sta_gl_staging own_staging;
    sta_gl_staging *shared_staging; /* NULL: own_staging (the pipeline sets its own) */
} sta_normals_pyramid_pass;

/* Compiles the shaders. Errors: STA_ERR_GL with the compiler's log. */
sta_status sta_normals_pyramid_pass_init(sta_normals_pyramid_pass *pass, sta_error *err);

/* Frees programs and atlas; a zeroed pass is a no-op. */
void sta_normals_pyramid_pass_release(sta_normals_pyramid_pass *pass);

/* params: NULL for the defaults. pyramid: the pull-push pyramid of the same view (from
 * sta_pullpush_pass_pyramid after a run); filled_position_tex: that run's output
 * position (level 0); out_normal_tex: RGBA32F of the view size, written per
 * screen_space.h (xyz unit normal facing the camera, w = 1 valid / 0 none). Errors:
 * STA_ERR_ARG when the pyramid does not belong to this view size, STA_ERR_GL. */
sta_status sta_normals_pyramid_pass_run(sta_normals_pyramid_pass *pass, const sta_view_params *view,
                                        const sta_normals_pyramid_params *params,
                                        const sta_pullpush_pyramid *pyramid,
                                        GLuint filled_position_tex, GLuint out_normal_tex,
                                        sta_error *err);

/* The half-resolution estimator without its last step: the anchors' normals into the
 * pass's half image, described in `out` for a shader that upsamples them itself where it
 * reads a normal (shade.comp with STA_SHADE_UPSAMPLE: one full-screen pass fewer; the
 * same normals as sta_normals_pyramid_pass_run with half_resolution). */
sta_status sta_normals_pyramid_pass_run_deferred(sta_normals_pyramid_pass *pass,
                                                 const sta_view_params *view,
                                                 const sta_normals_pyramid_params *params,
                                                 const sta_pullpush_pyramid *pyramid,
                                                 GLuint filled_position_tex,
                                                 sta_normals_upsample_inputs *out, sta_error *err);

#endif
