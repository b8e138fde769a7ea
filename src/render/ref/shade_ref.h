/* SPDX-License-Identifier: MIT
 * CPU twins of shaders/shade.comp (Blinn-Phong headlight) and shaders/edl.comp
 * (eye-dome lighting). Outputs are 4-channel images in 0..1 (alpha 1), the values the
 * shaders write to their RGBA8 target before 8-bit rounding.
 */
#ifndef STA_RENDER_REF_SHADE_REF_H
#define STA_RENDER_REF_SHADE_REF_H

#include "render/ref/image.h"

/* Defaults of the Blinn-Phong headlight (sta_shade_params_defaults). */
#define STA_SHADE_DEFAULT_AMBIENT   0.25f
#define STA_SHADE_DEFAULT_DIFFUSE   0.75f
#define STA_SHADE_DEFAULT_SPECULAR  0.15f
#define STA_SHADE_DEFAULT_SHININESS 24.0f

/* Defaults of eye-dome lighting (sta_edl_params_defaults). */
#define STA_EDL_DEFAULT_RADIUS_PX 1.5f
#define STA_EDL_DEFAULT_STRENGTH  60.0f

/* Blinn-Phong shading. Zero (or negative) light fields mean their defaults. */
typedef struct sta_shade_params {
    float ambient;       /* ambient term; <= 0: STA_SHADE_DEFAULT_AMBIENT */
    float diffuse;       /* diffuse weight; <= 0: STA_SHADE_DEFAULT_DIFFUSE */
    float specular;      /* specular weight; <= 0: STA_SHADE_DEFAULT_SPECULAR */
    float shininess;     /* Blinn-Phong exponent; <= 0: STA_SHADE_DEFAULT_SHININESS */
    float background[3]; /* RGB 0..1 of pixels without a point; zero is black */
} sta_shade_params;

/* Eye-dome lighting. Zero (or negative) fields mean their defaults. */
typedef struct sta_edl_params {
    float radius_px;     /* neighbour distance, pixels; <= 0: STA_EDL_DEFAULT_RADIUS_PX */
    float strength;      /* response scale; <= 0: STA_EDL_DEFAULT_STRENGTH */
    float background[3]; /* RGB 0..1 of pixels without a point; zero is black */
} sta_edl_params;

/* Fills the zero (or negative) fields of `config` with the defaults above, in place;
 * other fields stay as they are. */
void sta_shade_params_defaults(sta_shade_params *config);

/* Fills the zero (or negative) fields of `config` with the defaults above, in place;
 * other fields stay as they are. */
void sta_edl_params_defaults(sta_edl_params *config);

void sta_shade_ref(const sta_shade_params *params, const sta_image *position,
                   const sta_image *colour, const sta_image *normal, sta_image *out);

void sta_edl_ref(const sta_edl_params *params, const sta_image *position, const sta_image *colour,
                 sta_image *out);

#endif
