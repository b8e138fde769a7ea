/* SPDX-License-Identifier: MIT
 * What the geometry pass's colour modes need to know about the scene (both rasterisers
 * colour points alike: shaders/geometry_colour.glsl).
 */
#ifndef STA_RENDER_GEOMETRY_COLOURS_H
#define STA_RENDER_GEOMETRY_COLOURS_H

#include "render/ground_texture.h"

typedef struct sta_geometry_colours {
    int mode;                         /* STA_COLOUR_* of render/bindings.h */
    double elevation_min;             /* metres: bottom of the elevation ramp */
    double elevation_span;            /* metres: height of the elevation ramp (> 0) */
    float intensity_scale;            /* 1 / largest intensity */
    const sta_ground_texture *ground; /* for STA_COLOUR_HEIGHT; NULL: none yet */
    unsigned hide_flags;              /* points with any of these STA_GPU_FLAG_* are not drawn */
    float clip_plane[4]; /* camera-relative a x + b y + c z + d >= 0 kept; zero: no clipping
                            (the mirror pass's reflected view, render/pass_mirror.h) */
} sta_geometry_colours;

#endif
