/* SPDX-License-Identifier: MIT
 * The uniforms of shaders/point_footprint.glsl, located once per program and set from a
 * frame's footprint (render/point_size.h), for the compute rasteriser and the GL_POINTS
 * wide program alike. Main thread (GL) only.
 */
#ifndef STA_RENDER_FOOTPRINT_UNIFORMS_H
#define STA_RENDER_FOOTPRINT_UNIFORMS_H

#include <epoxy/gl.h>

#include "render/ref/raster_ref.h"

typedef struct sta_footprint_uniforms {
    GLint adaptive, radius_px, spacing_to_px, radius_range, depth_per_px;
} sta_footprint_uniforms;

void sta_footprint_uniforms_locate(sta_footprint_uniforms *uniforms, GLuint program);

/* Sets them on the program in use (the one they were located in). */
void sta_footprint_uniforms_set(const sta_footprint_uniforms *uniforms,
                                const sta_raster_ref_footprint *footprint);

#endif
