/* SPDX-License-Identifier: MIT
 * Final passes into the RGBA8 display texture: deferred Blinn-Phong shading and
 * eye-dome lighting (see render/ref/shade_ref.h for the maths and parameters).
 */
#ifndef STA_RENDER_PASS_SHADE_H
#define STA_RENDER_PASS_SHADE_H

#include <epoxy/gl.h>

#include "core/status.h"
#include "render/pass_normals_pyramid.h"
#include "render/ref/shade_ref.h"

/* Programs of the shade pass: 0 plain, 1 with the upsample. (Until issue 15's fourteenth
 * cost round a variant drew the volumetric overlay too; it runs on the tiles a splat
 * reaches now, render/pass_volumetric.h.) */
#define STA_SHADE_VARIANTS 2

typedef struct sta_shade_pass {
    GLuint programs[STA_SHADE_VARIANTS]; /* shade.comp, [1] with STA_SHADE_UPSAMPLE */
    GLuint edl_program;
    GLint shade_size[STA_SHADE_VARIANTS], shade_light[STA_SHADE_VARIANTS];
    GLint shade_background[STA_SHADE_VARIANTS];
    sta_normals_upsample_uniforms upsample[STA_SHADE_VARIANTS];
    GLint edl_size, edl_radius, edl_strength, edl_background;
} sta_shade_pass;

sta_status sta_shade_pass_init(sta_shade_pass *pass, sta_error *err);
void sta_shade_pass_release(sta_shade_pass *pass);

/* position, colour, normal: RGBA32F; out: RGBA8, all width x height. upsample: NULL, or
 * the anchors of half-resolution pyramidal normals (sta_normals_pyramid_pass_run_deferred),
 * upsampled here instead of read from `normal` (the same normals; one full-screen pass
 * fewer). */
void sta_shade_pass_run(const sta_shade_pass *pass, const sta_shade_params *params, int width,
                        int height, GLuint position, GLuint colour, GLuint normal,
                        const sta_normals_upsample_inputs *upsample, GLuint out);

/* position, colour: RGBA32F; out: RGBA8. */
void sta_edl_pass_run(const sta_shade_pass *pass, const sta_edl_params *params, int width,
                      int height, GLuint position, GLuint colour, GLuint out);

#endif
