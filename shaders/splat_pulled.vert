// SPDX-License-Identifier: MIT
// Splats, pulled path: one draw of 6 vertices (two triangles) per point, no instancing
// and no vertex attributes; each vertex reads its point and splat record from the
// arenas through texture buffers (gl_VertexID / 6 is the arena slot).
layout(binding = STA_SPLAT_SAMPLER_POINTS) uniform usamplerBuffer u_points; // RGBA32UI
layout(binding = STA_SPLAT_SAMPLER_SPLATS) uniform usamplerBuffer u_splats; // RG32UI

uniform vec3 u_node_origin;
uniform vec3 u_step;
uniform mat4 u_view_rotation;
uniform mat4 u_projection;
uniform int u_colour_mode;
uniform vec2 u_elevation;
uniform float u_intensity_scale;
uniform uint u_node_slot;
uniform uint u_arena_offset;

flat out vec3 v_colour;
flat out uvec2 v_id;
flat out vec3 v_normal;
out vec2 v_uv;
out vec3 v_position;

void main()
{
    int slot = gl_VertexID / 6, corner = gl_VertexID % 6;
    uvec4 t = texelFetch(u_points, slot);
    uvec2 splat = texelFetch(u_splats, slot).xy;
    // The 16-byte point (stream/gpu_points.h) as the attribute path reads it.
    uvec4 position_intensity = uvec4(t.x & 0xFFFFu, t.x >> 16, t.y & 0xFFFFu, t.y >> 16);
    uvec4 colour_class = uvec4(t.z & 0xFFu, (t.z >> 8) & 0xFFu, (t.z >> 16) & 0xFFu, t.z >> 24);
    uvec4 returns = uvec4(t.w & 0xFFu, (t.w >> 8) & 0xFFu, (t.w >> 16) & 0xFFu, t.w >> 24);
    vec3 relative = u_node_origin + vec3(position_intensity.xyz) * u_step;
    vec3 centre = (u_view_rotation * vec4(relative, 1.0)).xyz;
    vec3 n = normalize(mat3(u_view_rotation) * splat_normal(splat.x));
    float r = splat_radius(splat.y, centre);
    vec3 t1, t2;
    splat_axes(n, t1, t2);
    // Triangles (0, 1, 2) and (2, 1, 3) of the strip's corners.
    const int strip[6] = int[6](0, 1, 2, 2, 1, 3);
    int k = strip[corner];
    vec2 uv = vec2((k & 1) != 0 ? 1.0 : -1.0, (k & 2) != 0 ? 1.0 : -1.0);
    v_position = centre + r * (uv.x * t1 + uv.y * t2);
    gl_Position = (returns.z & u_hide_flags) != 0u ? SPLAT_HIDDEN_POSITION
                                                  : u_projection * vec4(v_position, 1.0);
    v_uv = uv;
    v_normal = n;
    v_colour = point_colour(position_intensity, colour_class, returns, relative, u_colour_mode,
                            u_elevation, u_intensity_scale);
    v_id = uvec2(u_node_slot, uint(slot) - u_arena_offset);
}
