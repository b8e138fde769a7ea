/* SPDX-License-Identifier: MIT
 * Final passes into the RGBA8 display texture: deferred Blinn-Phong shading and
 * eye-dome lighting (see render/ref/shade_ref.h for the maths and parameters).
 */
#ifndef STA_RENDER_PASS_SHADE_H
#define STA_RENDER_PASS_SHADE_H

#include <epoxy/gl.h>

#include "core/status.h"
#include "render/pass_normals_pyramid.h"
#include "render/pass_volumetric.h"
#include "render/ref/shade_ref.h"

/* Programs of the shade pass: bit 0 the volumetric overlay, bit 1 the upsample. */
#define STA_SHADE_VARIANTS 4

typedef struct sta_shade_pass {
    GLuint programs[STA_SHADE_VARIANTS]; /* shade.comp, STA_SHADE_OVERLAY | _UPSAMPLE */
    GLuint edl_program;
    GLint shade_size[STA_SHADE_VARIANTS], shade_light[STA_SHADE_VARIANTS];
    GLint shade_background[STA_SHADE_VARIANTS];
    sta_normals_upsample_uniforms upsample[STA_SHADE_VARIANTS];
    GLint edl_size, edl_radius, edl_strength, edl_background;
} sta_shade_pass;

sta_status sta_shade_pass_init(sta_shade_pass *pass, sta_error *err);
void sta_shade_pass_release(sta_shade_pass *pass);

/* position, colour, normal: RGBA32F; out: RGBA8, all width x height. overlay: NULL, or
 * the frame whose marked volumetric points (render/pass_volumetric.h) are then drawn over
 * the shading in the same pass, as sta_volumetric_pass_overlay would after it (the same
 * picture, one full-screen pass fewer). upsample: NULL, or the anchors of
 * half-resolution pyramidal normals (sta_normals_pyramid_pass_run_deferred), upsampled
 * here instead of read from `normal` (the same normals; one full-screen pass fewer). */
void sta_shade_pass_run(const sta_shade_pass *pass, const sta_shade_params *params, int width,
                        int height, GLuint position, GLuint colour, GLuint normal,
                        const sta_normals_upsample_inputs *upsample,
                        const sta_volumetric_frame *overlay, GLuint out);

/* position, colour: RGBA32F; out: RGBA8. */
void sta_edl_pass_run(const sta_shade_pass *pass, const sta_edl_params *params, int width,
                      int height, GLuint position, GLuint colour, GLuint out);

#endif
