/* SPDX-License-Identifier: MIT
 * The screen-space normals pass of Schiffner et al. (LD, PD, PC, TI; see
 * render/ref/normals_screen_ref.h for the parameters and docs/NORMALS.md for the
 * methods) and its optional smoothing pass. Main thread (GL) only.
 */
#ifndef STA_RENDER_PASS_NORMALS_SCREEN_H
#define STA_RENDER_PASS_NORMALS_SCREEN_H

#include <epoxy/gl.h>

#include "core/status.h"
#include "render/ref/normals_screen_ref.h"
#include "render/ref/screen_space.h"

typedef struct sta_normals_screen_pass {
    GLuint programs[STA_NORMALS_SCREEN_METHOD_COUNT]; /* by method; [0] unused */
    GLint u_size[STA_NORMALS_SCREEN_METHOD_COUNT];
    GLint u_samples[STA_NORMALS_SCREEN_METHOD_COUNT];
    GLint u_max_distance2[STA_NORMALS_SCREEN_METHOD_COUNT];
    GLuint smooth_program;
    GLint smooth_u_size, smooth_u_max_distance2;
} sta_normals_screen_pass;

/* Compiles the four estimators and the smoothing program. Errors: STA_ERR_GL with the
 * compiler's log. */
sta_status sta_normals_screen_pass_init(sta_normals_screen_pass *pass, sta_error *err);

/* Frees the programs; a zeroed pass is a no-op. */
void sta_normals_screen_pass_release(sta_normals_screen_pass *pass);

/* Estimates normals over view->width_px x height_px. position_texture: RGBA32F positions,
 * level 0 read as an image (STA_NORMALS_SCREEN_IMAGE_POSITION); normal_texture: RGBA32F
 * of the same size, written (STA_NORMALS_SCREEN_IMAGE_NORMAL). Errors: STA_ERR_ARG for
 * bad parameters (sta_normals_screen_params_check). */
sta_status sta_normals_screen_pass_run(const sta_normals_screen_pass *pass,
                                       const sta_view_params *view,
                                       const sta_normals_screen_params *params,
                                       GLuint position_texture, GLuint normal_texture,
                                       sta_error *err);

/* Smooths normal_texture into out_texture (RGBA32F, same size, a different texture);
 * params supplies the maximum distance. Image units 0 (out), 1 (position), 2 (normal).
 * Errors: STA_ERR_ARG. */
sta_status sta_normals_smooth_pass_run(const sta_normals_screen_pass *pass,
                                       const sta_view_params *view,
                                       const sta_normals_screen_params *params,
                                       GLuint position_texture, GLuint normal_texture,
                                       GLuint out_texture, sta_error *err);

#endif
