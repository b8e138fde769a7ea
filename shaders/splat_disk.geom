// SPDX-License-Identifier: MIT
// Splats, geometry-shader path: the disk's square in its own plane, from the point.
layout(points) in;
layout(triangle_strip, max_vertices = 4) out;

uniform mat4 u_projection;

in vec3 g_centre[];
in vec3 g_normal[];
in float g_radius[];
in vec3 g_colour[];
flat in uvec2 g_id[];

flat out vec3 v_colour;
flat out uvec2 v_id;
flat out vec3 v_normal;
out vec2 v_uv;
out vec3 v_position;

void main()
{
    if (g_radius[0] < 0.0) { // a hidden point (splat_point.vert): no disk
        return;
    }
    vec3 t1, t2;
    splat_axes(g_normal[0], t1, t2);
    for (int k = 0; k < 4; k++) {
        vec2 uv = vec2((k & 1) != 0 ? 1.0 : -1.0, (k & 2) != 0 ? 1.0 : -1.0);
        v_position = g_centre[0] + g_radius[0] * (uv.x * t1 + uv.y * t2);
        gl_Position = u_projection * vec4(v_position, 1.0);
        v_uv = uv;
        v_normal = g_normal[0];
        v_colour = g_colour[0];
        v_id = g_id[0];
        EmitVertex();
    }
    EndPrimitive();
}
