// SPDX-License-Identifier: MIT
// Splats, geometry-shader path: one vertex per point (GL_POINTS) carrying the disk's
// centre, normal and radius in camera space to shaders/splat_disk.geom.
layout(location = STA_ATTRIB_POSITION_INTENSITY) in uvec4 a_position_intensity;
layout(location = STA_ATTRIB_COLOUR_CLASS) in uvec4 a_colour_class;
layout(location = STA_ATTRIB_RETURNS) in uvec4 a_returns;
layout(location = STA_ATTRIB_SPLAT) in uvec2 a_splat;

uniform vec3 u_node_origin;
uniform vec3 u_step;
uniform mat4 u_view_rotation;
uniform int u_colour_mode;
uniform vec2 u_elevation;
uniform float u_intensity_scale;
uniform uint u_node_slot;
uniform uint u_arena_offset; // the node's first point in the arena (glDrawArrays' first)

out vec3 g_centre;
out vec3 g_normal;
out float g_radius;
out vec3 g_colour;
flat out uvec2 g_id;

void main()
{
    vec3 relative = u_node_origin + vec3(a_position_intensity.xyz) * u_step;
    g_centre = (u_view_rotation * vec4(relative, 1.0)).xyz;
    g_normal = normalize(mat3(u_view_rotation) * splat_normal(a_splat.x));
    g_radius = (a_returns.z & u_hide_flags) != 0u ? -1.0 : splat_radius(a_splat.y, g_centre);
    g_colour = point_colour(a_position_intensity, a_colour_class, a_returns, relative,
                            u_colour_mode, u_elevation, u_intensity_scale);
    g_id = uvec2(u_node_slot, uint(gl_VertexID) - u_arena_offset);
}
