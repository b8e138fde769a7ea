// SPDX-License-Identifier: MIT
// The compute rasteriser's shared part (render/raster_compute.h): the frame's node
// table, the arena of points (a texture buffer of 16-byte texels, stream/gpu_points.h),
// the per-pixel buffers and the projection of a point to its pixel as the GL_POINTS
// rasteriser does it.
//
// Based on: Schütz, Kerbl, Wimmer, "Rendering Point Clouds with Compute Shaders and
// Vertex Order Optimization", CGF 40(4), 2021: atomicMin/Max of depth (and payload)
// per pixel, then a resolve pass.

struct raster_node {
    vec4 origin; // xyz: node corner minus camera position, metres
    vec4 step;   // xyz: metres per quantisation step
    uvec4 info;  // arena offset, point count, first batch, node slot
};

layout(std430, binding = STA_RASTER_BUFFER_NODES) readonly buffer raster_nodes {
    raster_node nodes[];
};

layout(std430, binding = STA_RASTER_BUFFER_BATCHES) readonly buffer raster_batches {
    uvec2 batches[]; // node table index, first point of the batch in the node
};

#if STA_RASTER_PACKED
layout(std430, binding = STA_RASTER_BUFFER_DEPTH) coherent buffer raster_packed {
    uint64_t packed_pixels[]; // depth bits << 32 | ~draw-order index; 0: empty
};
#else
layout(std430, binding = STA_RASTER_BUFFER_DEPTH) coherent buffer raster_depth {
    uint depth_bits[]; // floatBitsToUint(reverse-Z depth); 0: empty
};
layout(std430, binding = STA_RASTER_BUFFER_PAYLOAD) coherent buffer raster_payload {
    uint payload[]; // smallest draw-order index at that depth; STA_RASTER_NO_POINT: none
};
layout(std430, binding = STA_RASTER_BUFFER_CANDIDATES) buffer raster_candidates {
    uint candidates[]; // per invocation: bit k set when its k-th point may win (DEPTH step)
};
#endif

layout(binding = STA_RASTER_SAMPLER_POINTS) uniform usamplerBuffer u_points;
uniform mat4 u_view_rotation; // world directions -> camera space
uniform mat4 u_projection;    // reverse-Z, infinite far
uniform ivec2 u_size;         // target, pixels
uniform uint u_hide_flags;    // points with any of these flags (byte 14) are not drawn
uniform vec4 u_clip_plane;    // camera-relative plane; points with a negative distance are not drawn

// The point's attributes as the vertex stage reads them (geometry.vert).
void unpack_point(uvec4 t, out uvec4 position_intensity, out uvec4 colour_class,
                  out uvec4 returns)
{
    position_intensity = uvec4(t.x & 0xFFFFu, t.x >> 16, t.y & 0xFFFFu, t.y >> 16);
    colour_class = uvec4(t.z & 0xFFu, (t.z >> 8) & 0xFFu, (t.z >> 16) & 0xFFu, t.z >> 24);
    returns = uvec4(t.w & 0xFFu, (t.w >> 8) & 0xFFu, (t.w >> 16) & 0xFFu, t.w >> 24);
}

// Pixel (row-major from the bottom) and reverse-Z depth of a point, or false when the
// GL_POINTS path would not draw it. The rule is the rasteriser's: clip volume test on
// the point's centre, ndc = clip * (1 / w), window = ndc * size / 2 + size / 2 fused,
// snapped to 1 / 2^STA_RASTER_SUBPIXEL_BITS pixel (half up), and a one-pixel point
// covers the pixel whose centre lies in [x - 0.5, x + 0.5) on the snapped grid, that is
// pixel ceil(x) - 1 on each axis.
bool project_point(vec3 relative, out uint pixel, out float depth)
{
    vec4 clip = u_projection * (u_view_rotation * vec4(relative, 1.0));
    if (!(clip.w > 0.0) || abs(clip.x) > clip.w || abs(clip.y) > clip.w || clip.z < 0.0 ||
        clip.z > clip.w) {
        return false;
    }
    vec3 ndc = clip.xyz * (1.0 / clip.w);
    // llvmpipe's viewport transform is one fused multiply-add, but its shaders split
    // fma() into two roundings: in double the product is exact and the sum rounds once
    // before the float (a second rounding that differs from a fused one only when the
    // double lands exactly halfway between two floats).
    vec2 half_size = vec2(u_size) * 0.5;
    vec2 window = vec2(dvec2(ndc.xy) * dvec2(half_size) + dvec2(half_size));
    ivec2 snapped = ivec2(floor(window * float(1 << STA_RASTER_SUBPIXEL_BITS) + 0.5));
    ivec2 p = (snapped - 1) >> STA_RASTER_SUBPIXEL_BITS;
    if (p.x < 0 || p.y < 0 || p.x >= u_size.x || p.y >= u_size.y) {
        return false;
    }
    pixel = uint(p.y) * uint(u_size.x) + uint(p.x);
    depth = ndc.z;
    return true;
}
