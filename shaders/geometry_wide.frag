// SPDX-License-Identifier: MIT
// Geometry pass (GL_POINTS) for points wider than a pixel: keeps the sprite's pixels
// inside the footprint, each with its own depth (point_footprint.glsl), so the depth
// test decides per pixel as the compute rasteriser's atomics do.
flat in vec3 v_colour;
flat in uvec2 v_id;
flat in ivec4 v_position;
flat in ivec2 v_disk;
flat in vec2 v_depth;
layout(location = STA_GEOMETRY_OUT_COLOUR) out vec4 o_colour;
layout(location = STA_GEOMETRY_OUT_ID) out uvec2 o_id;

void main()
{
    point_footprint f = point_footprint(v_position.xy, v_position.zw, v_disk.x, v_disk.y,
                                        v_depth.x, v_depth.y);
    float depth = footprint_depth(f, ivec2(gl_FragCoord.xy));
    if (depth < 0.0) {
        discard;
    }
    gl_FragDepth = depth;
    o_colour = vec4(v_colour, 1.0);
    o_id = v_id;
}
