// SPDX-License-Identifier: MIT
// Splats, instanced path: one instance per point, four vertices (a triangle strip) per
// instance spanning the disk's square in its own plane. Point and splat attributes
// advance per instance (divisor 1; base instance = the node's first arena slot).
layout(location = STA_ATTRIB_POSITION_INTENSITY) in uvec4 a_position_intensity;
layout(location = STA_ATTRIB_COLOUR_CLASS) in uvec4 a_colour_class;
layout(location = STA_ATTRIB_RETURNS) in uvec4 a_returns;
layout(location = STA_ATTRIB_SPLAT) in uvec2 a_splat;

uniform vec3 u_node_origin;    // metres, camera-relative
uniform vec3 u_step;           // metres per quantisation step
uniform mat4 u_view_rotation;  // world directions -> camera space
uniform mat4 u_projection;     // reverse-Z, infinite far
uniform int u_colour_mode;     // STA_COLOUR_*
uniform vec2 u_elevation;      // (camera z - min z, 1 / (max z - min z))
uniform float u_intensity_scale; // 1 / largest intensity
uniform uint u_node_slot;      // node drawn, for the id target

flat out vec3 v_colour;
flat out uvec2 v_id;
flat out vec3 v_normal; // camera space
out vec2 v_uv;          // position on the disk, radii (unit circle = its edge)
out vec3 v_position;    // camera space

void main()
{
    vec3 relative = u_node_origin + vec3(a_position_intensity.xyz) * u_step;
    vec3 centre = (u_view_rotation * vec4(relative, 1.0)).xyz;
    vec3 n = normalize(mat3(u_view_rotation) * splat_normal(a_splat.x));
    float r = splat_radius(a_splat.y, centre);
    vec3 t1, t2;
    splat_axes(n, t1, t2);
    vec2 uv = vec2((gl_VertexID & 1) != 0 ? 1.0 : -1.0, (gl_VertexID & 2) != 0 ? 1.0 : -1.0);
    v_position = centre + r * (uv.x * t1 + uv.y * t2);
    gl_Position = u_projection * vec4(v_position, 1.0);
    v_uv = uv;
    v_normal = n;
    v_colour = point_colour(a_position_intensity, a_colour_class, a_returns, relative,
                            u_colour_mode, u_elevation, u_intensity_scale);
    v_id = uvec2(u_node_slot, uint(gl_InstanceID));
    if ((a_returns.z & u_hide_flags) != 0u) {
        gl_Position = SPLAT_HIDDEN_POSITION;
    }
}
