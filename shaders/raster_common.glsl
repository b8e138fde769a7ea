// SPDX-License-Identifier: MIT
// The compute rasteriser's shared part (render/raster_compute.h): the frame's node
// table, the arena of points (a texture buffer of 16-byte texels, stream/gpu_points.h),
// the per-pixel buffers and the projection of a one-pixel point to its pixel by the
// node's precomputed rows (wider points: point_footprint.glsl, as GL_POINTS does).
//
// Based on: Schütz, Kerbl, Wimmer, "Rendering Point Clouds with Compute Shaders and
// Vertex Order Optimization", CGF 40(4), 2021: atomicMin/Max of depth (and payload)
// per pixel, then a resolve pass.

struct raster_node {
    vec4 origin; // xyz: node corner minus camera position, metres
    vec4 step;   // xyz: metres per quantisation step
    uvec4 info;  // arena offset, point count, first batch, node slot
    // One-pixel points: the node's rows from quantised position to snapped window x, y
    // (times w), w and the clip plane; clip_z.x: clip.z (render/ref/raster_ref.h).
    vec4 row_x, row_y, row_w, plane, clip_z;
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

// One of a node's rows at quantised position q, summed as the C twin does.
float row_at(vec4 r, vec3 q)
{
    return ((r.x * q.x + r.y * q.y) + r.z * q.z) + r.w;
}

// Pixel and depth of the point at quantised position q of `node` by the node's rows (the
// compute rasteriser's one-pixel rule, render/ref/raster_ref.h: one product per row and
// one division instead of two matrix products, the viewport and snapping folded in), or
// false when it is not drawn (clip plane included).
bool project_rows(raster_node node, vec3 q, out uint pixel, out float depth)
{
#ifndef STA_RASTER_NO_PLANE
    if (row_at(node.plane, q) < 0.0) {
        return false;
    }
#endif
    float w = row_at(node.row_w, q);
    if (!(w > 0.0)) {
        return false;
    }
    float inverse = 1.0 / w;
    depth = node.clip_z.x * inverse;
    vec2 s = vec2(row_at(node.row_x, q), row_at(node.row_y, q)) * inverse;
    vec2 limit = vec2(u_size * (1 << STA_RASTER_SUBPIXEL_BITS)) + 1.0;
    if (!(depth >= 0.0 && depth <= 1.0 && s.x >= 1.0 && s.y >= 1.0 && s.x < limit.x &&
          s.y < limit.y)) {
        return false;
    }
    ivec2 p = (ivec2(s) - 1) >> STA_RASTER_SUBPIXEL_BITS;
    pixel = uint(p.y) * uint(u_size.x) + uint(p.x);
    return true;
}
