/* SPDX-License-Identifier: MIT
 * CPU twins of shaders/shade.comp (Blinn-Phong headlight) and shaders/edl.comp
 * (eye-dome lighting). Outputs are 4-channel images in 0..1 (alpha 1), the values the
 * shaders write to their RGBA8 target before 8-bit rounding.
 */
#ifndef STA_RENDER_REF_SHADE_REF_H
#define STA_RENDER_REF_SHADE_REF_H

#include "render/ref/image.h"

typedef struct sta_shade_params {
    float ambient;       /* 0: 0.25 */
    float diffuse;       /* 0: 0.75 */
    float specular;      /* 0: 0.15 */
    float shininess;     /* 0: 24 */
    float background[3]; /* RGB 0..1 */
} sta_shade_params;

typedef struct sta_edl_params {
    float radius_px; /* 0: 1.5 */
    float strength;  /* 0: 60 */
    float background[3];
} sta_edl_params;

/* Fills zero fields with the defaults above. */
void sta_shade_params_defaults(sta_shade_params *params);
void sta_edl_params_defaults(sta_edl_params *params);

void sta_shade_ref(const sta_shade_params *params, const sta_image *position,
                   const sta_image *colour, const sta_image *normal, sta_image *out);

void sta_edl_ref(const sta_edl_params *params, const sta_image *position, const sta_image *colour,
                 sta_image *out);

#endif
