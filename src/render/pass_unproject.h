/* SPDX-License-Identifier: MIT
 * The unproject pass: depth buffer -> camera-space position texture (RGBA32F).
 */
#ifndef STA_RENDER_PASS_UNPROJECT_H
#define STA_RENDER_PASS_UNPROJECT_H

#include <epoxy/gl.h>
#include <stdint.h>

#include "core/status.h"
#include "render/gl_staged.h"
#include "render/ref/screen_space.h"

/* Words of a class set (= STA_VOLUMETRIC_CLASS_WORDS): bit c of word c / 32 is class c. */
#define STA_UNPROJECT_CLASS_WORDS 8

typedef struct sta_unproject_pass {
    GLuint programs[2]; /* 0: plain, 1: with the volumetric mark (STA_UNPROJECT_MARK) */
    GLint u_size[2], u_tan_half[2], u_near[2];
    GLint u_classes; /* of programs[1] */
    bool staged;     /* stores through a staging buffer (render/gl_staged.h), decided at init */
    sta_gl_staging own_staging;
    sta_gl_staging *shared_staging; /* NULL: own_staging (the pipeline sets its own) */
} sta_unproject_pass;

sta_status sta_unproject_pass_init(sta_unproject_pass *pass, sta_error *err);
void sta_unproject_pass_release(sta_unproject_pass *pass);

/* depth_texture: GL_DEPTH_COMPONENT32F (or R32F) reverse-Z depth; position_texture:
 * RGBA32F of the same size, written. Fails only when a staging buffer cannot be had. */
sta_status sta_unproject_pass_run(sta_unproject_pass *pass, const sta_view_params *view,
                                  GLuint depth_texture, GLuint position_texture, sta_error *err);

/* The volumetric mark's inputs for sta_unproject_pass_run_marked. */
typedef struct sta_unproject_mark {
    GLuint class_texture;      /* R8UI: the class of each pixel's point (the geometry pass's) */
    const uint32_t *class_set; /* STA_UNPROJECT_CLASS_WORDS words: bit c % 32 of word c / 32 */
    GLuint tile_flags;         /* R32UI, a texel per STA_WORKGROUP_SIZE_X x _Y tile: set to 1 where
                                  a pixel is marked (cleared by the caller; the overlay's tile list,
                                  render/pass_volumetric.h) */
} sta_unproject_mark;

/* The same, and the volumetric mark fused into it (issue 15, tenth round): a drawn pixel
 * whose class is in the set gets w = STA_POSITION_W_MARKED, as sta_volumetric_mark_ref
 * marks it. mark NULL: the plain pass. */
sta_status sta_unproject_pass_run_marked(sta_unproject_pass *pass, const sta_view_params *view,
                                         GLuint depth_texture, const sta_unproject_mark *mark,
                                         GLuint position_texture, sta_error *err);

/* The floats unproject_pixel.glsl takes for `view` (u_size, u_tan_half; u_near is
 * view->near_m): the compute rasteriser's resolve passes the same ones, so that its
 * positions are the pass's bit for bit. */
void sta_unproject_uniforms(const sta_view_params *view, float size[2], float tan_half[2]);

#endif
