/* SPDX-License-Identifier: MIT
 * Final passes into the RGBA8 display texture: deferred Blinn-Phong shading and
 * eye-dome lighting (see render/ref/shade_ref.h for the maths and parameters).
 */
#ifndef STA_RENDER_PASS_SHADE_H
#define STA_RENDER_PASS_SHADE_H

#include <epoxy/gl.h>

#include "core/status.h"
#include "render/ref/shade_ref.h"

typedef struct sta_shade_pass {
    GLuint shade_program, edl_program;
    GLint shade_size, shade_light, shade_background;
    GLint edl_size, edl_radius, edl_strength, edl_background;
} sta_shade_pass;

sta_status sta_shade_pass_init(sta_shade_pass *pass, sta_error *err);
void sta_shade_pass_release(sta_shade_pass *pass);

/* position, colour, normal: RGBA32F; out: RGBA8, all width x height. */
void sta_shade_pass_run(const sta_shade_pass *pass, const sta_shade_params *params, int width,
                        int height, GLuint position, GLuint colour, GLuint normal, GLuint out);

/* position, colour: RGBA32F; out: RGBA8. */
void sta_edl_pass_run(const sta_shade_pass *pass, const sta_edl_params *params, int width,
                      int height, GLuint position, GLuint colour, GLuint out);

#endif
