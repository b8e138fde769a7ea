// SPDX-License-Identifier: MIT
// Compute rasteriser's resolve: the point kept in each pixel gives its colour (as the
// GL_POINTS path colours it), its depth and its id to the render target.
uniform int u_colour_mode;       // STA_COLOUR_*
uniform vec2 u_elevation;        // (camera z - min z, 1 / (max z - min z))
uniform float u_intensity_scale; // 1 / largest intensity
uniform uint u_node_count;       // entries of the node table

layout(location = STA_GEOMETRY_OUT_COLOUR) out vec4 o_colour;
layout(location = STA_GEOMETRY_OUT_ID) out uvec2 o_id;

void main()
{
    ivec2 p = ivec2(gl_FragCoord.xy);
    uint pixel = uint(p.y) * uint(u_size.x) + uint(p.x);
#if STA_RASTER_PACKED
    uint64_t value = packed[pixel];
    uint bits = uint(value >> 32);
    uint index = ~uint(value & 0xFFFFFFFFul);
#else
    uint bits = depth_bits[pixel];
    uint index = payload[pixel];
#endif
    if (bits == 0u || index == STA_RASTER_NO_POINT || u_node_count == 0u) {
        discard;
    }
    // The node holding draw-order index `index`: the last whose first index is <= it
    // (an empty node shares its first index with the next one, so it is never chosen).
    uint lo = 0u, hi = u_node_count;
    while (hi - lo > 1u) {
        uint mid = (lo + hi) / 2u;
        if (nodes[mid].info.z <= index) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    raster_node node = nodes[lo];
    uint i = index - node.info.z;
    uvec4 position_intensity, colour_class, returns;
    unpack_point(texelFetch(u_points, int(node.info.x + i)), position_intensity, colour_class,
                 returns);
    vec3 relative = node.origin.xyz + vec3(position_intensity.xyz) * node.step.xyz;
    o_colour = vec4(point_colour(position_intensity, colour_class, returns, relative.z,
                                 u_colour_mode, u_elevation, u_intensity_scale),
                    1.0);
    o_id = uvec2(node.info.w, i);
    gl_FragDepth = uintBitsToFloat(bits);
}
