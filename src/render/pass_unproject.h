/* SPDX-License-Identifier: MIT
 * The unproject pass: depth buffer -> camera-space position texture (RGBA32F).
 */
#ifndef STA_RENDER_PASS_UNPROJECT_H
#define STA_RENDER_PASS_UNPROJECT_H

#include <epoxy/gl.h>

#include "core/status.h"
#include "render/ref/screen_space.h"

typedef struct sta_unproject_pass {
    GLuint program;
    GLint u_size, u_tan_half, u_near;
} sta_unproject_pass;

sta_status sta_unproject_pass_init(sta_unproject_pass *pass, sta_error *err);
void sta_unproject_pass_release(sta_unproject_pass *pass);

/* depth_texture: GL_DEPTH_COMPONENT32F (or R32F) reverse-Z depth; position_texture:
 * RGBA32F of the same size, written. */
void sta_unproject_pass_run(const sta_unproject_pass *pass, const sta_view_params *view,
                            GLuint depth_texture, GLuint position_texture);

/* The floats unproject_pixel.glsl takes for `view` (u_size, u_tan_half; u_near is
 * view->near_m): the compute rasteriser's resolve passes the same ones, so that its
 * positions are the pass's bit for bit. */
void sta_unproject_uniforms(const sta_view_params *view, float size[2], float tan_half[2]);

#endif
