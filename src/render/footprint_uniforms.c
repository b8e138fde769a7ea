/* SPDX-License-Identifier: MIT
 * The uniforms of shaders/point_footprint.glsl. */
#include "render/footprint_uniforms.h"

void sta_footprint_uniforms_locate(sta_footprint_uniforms *u, GLuint program)
{
    u->adaptive = glGetUniformLocation(program, "u_point_adaptive");
    u->radius_px = glGetUniformLocation(program, "u_point_radius_px");
    u->spacing_to_px = glGetUniformLocation(program, "u_point_spacing_to_px");
    u->radius_range = glGetUniformLocation(program, "u_point_radius_range");
    u->depth_per_px = glGetUniformLocation(program, "u_point_depth_per_px");
}

void sta_footprint_uniforms_set(const sta_footprint_uniforms *u, const sta_raster_ref_footprint *f)
{
    glUniform1i(u->adaptive, f->adaptive);
    glUniform1f(u->radius_px, f->radius_px);
    glUniform1f(u->spacing_to_px, f->spacing_to_px);
    glUniform2f(u->radius_range, f->min_radius_px, f->max_radius_px);
    glUniform1f(u->depth_per_px, f->depth_per_px);
}
