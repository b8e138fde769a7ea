// SPDX-License-Identifier: MIT
// Geometry pass (GL_POINTS): one pixel per point, coloured by geometry_colour.glsl.
// Positions arrive node-relative and quantized (stream/gpu_points.h); u_node_origin is the node corner minus the camera position,
// computed in double on the CPU, so the scene's distance from the origin costs no
// precision here.
layout(location = STA_ATTRIB_POSITION_INTENSITY) in uvec4 a_position_intensity;
layout(location = STA_ATTRIB_COLOUR_CLASS) in uvec4 a_colour_class;
layout(location = STA_ATTRIB_RETURNS) in uvec4 a_returns;

uniform vec3 u_node_origin;    // metres, camera-relative
uniform vec3 u_step;           // metres per quantisation step
uniform mat4 u_view_rotation;  // world directions -> camera space
uniform mat4 u_projection;     // reverse-Z, infinite far
uniform int u_colour_mode;     // STA_COLOUR_*
uniform vec2 u_elevation;      // (camera z - min z, 1 / (max z - min z))
uniform float u_intensity_scale; // 1 / largest intensity

uniform uint u_node_slot;       // node drawn, for the id target
uniform uint u_arena_offset;    // its first point in the arena (glDrawArrays' first)
uniform uint u_hide_flags;      // points with any of these flags (byte 14) are not drawn
uniform vec4 u_clip_plane;      // camera-relative; GL_CLIP_DISTANCE0 on only when set

out float gl_ClipDistance[1];

flat out vec3 v_colour;
flat out uvec2 v_id;
flat out uint v_class; // for the volumetric mark (written when a class texture is attached)

void main()
{
    if ((a_returns.z & u_hide_flags) != 0u) {
        gl_Position = vec4(2.0, 2.0, 2.0, 1.0); // outside the clip volume: not drawn
        return;
    }
    vec3 relative = u_node_origin + vec3(a_position_intensity.xyz) * u_step;
    gl_Position = u_projection * (u_view_rotation * vec4(relative, 1.0));
    gl_ClipDistance[0] = dot(u_clip_plane.xyz, relative) + u_clip_plane.w;
    gl_PointSize = 1.0;
    v_colour = point_colour(a_position_intensity, a_colour_class, a_returns, relative,
                            u_colour_mode, u_elevation, u_intensity_scale);
    v_id = uvec2(u_node_slot, uint(gl_VertexID) - u_arena_offset);
    v_class = a_colour_class.w;
}
