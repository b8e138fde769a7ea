// SPDX-License-Identifier: MIT
// Geometry pass (GL_POINTS) for points wider than a pixel: geometry.vert's position and
// colour, plus the footprint (point_footprint.glsl) the fragment stage cuts out of a
// sprite large enough to hold it.
layout(location = STA_ATTRIB_POSITION_INTENSITY) in uvec4 a_position_intensity;
layout(location = STA_ATTRIB_COLOUR_CLASS) in uvec4 a_colour_class;
layout(location = STA_ATTRIB_RETURNS) in uvec4 a_returns;

uniform vec3 u_node_origin;      // metres, camera-relative
uniform vec3 u_step;             // metres per quantisation step
uniform float u_spacing;         // metres between the node's points (adaptive size)
uniform mat4 u_view_rotation;    // world directions -> camera space
uniform mat4 u_projection;       // reverse-Z, infinite far
uniform ivec2 u_size;            // target, pixels
uniform int u_colour_mode;       // STA_COLOUR_*
uniform vec2 u_elevation;        // (camera z - min z, 1 / (max z - min z))
uniform float u_intensity_scale; // 1 / largest intensity

uniform uint u_node_slot;    // node drawn, for the id target
uniform uint u_arena_offset; // its first point in the arena (glDrawArrays' first)
uniform uint u_hide_flags;   // as geometry.vert: flagged points (byte 14) are not drawn
uniform vec4 u_clip_plane;   // as geometry.vert: the point is cut when its centre is behind

out float gl_ClipDistance[1];

flat out vec3 v_colour;
flat out uvec2 v_id;
flat out ivec4 v_position; // snapped window position, centre pixel
flat out ivec2 v_disk;     // squared radius, reach
flat out vec2 v_depth;     // depth, paraboloid factor

void main()
{
    if ((a_returns.z & u_hide_flags) != 0u) {
        gl_Position = vec4(2.0, 2.0, 2.0, 1.0); // outside the clip volume: not drawn
        return;
    }
    vec3 relative = u_node_origin + vec3(a_position_intensity.xyz) * u_step;
    vec4 clip = u_projection * (u_view_rotation * vec4(relative, 1.0));
    gl_Position = clip;
    gl_ClipDistance[0] = dot(u_clip_plane.xyz, relative) + u_clip_plane.w;
    point_footprint f;
    // Outside the clip volume GL drops the point itself.
    gl_PointSize = footprint_of(clip, u_spacing, u_size, f) ? float(2 * f.reach + 3) : 1.0;
    v_position = ivec4(f.snapped, f.centre);
    v_disk = ivec2(f.r2, f.reach);
    v_depth = vec2(f.depth, f.k);
    v_colour = point_colour(a_position_intensity, a_colour_class, a_returns, relative,
                            u_colour_mode, u_elevation, u_intensity_scale);
    v_id = uvec2(u_node_slot, uint(gl_VertexID) - u_arena_offset);
}
