// SPDX-License-Identifier: MIT
// Compute rasteriser, one step per build (STA_RASTER_STEP): DEPTH keeps the largest
// reverse-Z depth per pixel; PAYLOAD then keeps, among the points at that depth, the
// first in draw order (as GL_POINTS' GL_GREATER depth test does); PACKED does both at
// once with 64-bit atomics. One workgroup per batch of STA_RASTER_BATCH_POINTS points
// of one node (the batch list is the indirect dispatch).
// Points wider than a pixel (u_point_wide) write their whole footprint
// (point_footprint.glsl) through the same atomics, the node's spacing in origin.w.
layout(local_size_x = STA_RASTER_WORKGROUP_SIZE) in;

uniform int u_point_wide; // 0: one pixel per point

// Keeps the point `index` at `bits` in `pixel` if it is nearer (or equal and earlier).
void keep(uint pixel, uint bits, uint index)
{
#if STA_RASTER_STEP == STA_RASTER_STEP_DEPTH
    if (bits > depth_bits[pixel]) { // most points lose: skip their atomic
        atomicMax(depth_bits[pixel], bits);
    }
#elif STA_RASTER_STEP == STA_RASTER_STEP_PAYLOAD
    if (bits == depth_bits[pixel]) {
        atomicMin(payload[pixel], index);
    }
#else
    uint64_t value = (uint64_t(bits) << 32) | uint64_t(~index);
    if (value > packed_pixels[pixel]) {
        atomicMax(packed_pixels[pixel], value);
    }
#endif
}

void keep_footprint(vec3 relative, float spacing, uint index)
{
    vec4 clip = u_projection * (u_view_rotation * vec4(relative, 1.0));
    point_footprint f;
    if (!footprint_of(clip, spacing, u_size, f)) {
        return;
    }
    // Only the pixels whose centres can lie in the disk, |p * 2^bits + 2^(bits-1) - s| <=
    // r per axis (arithmetic shifts floor), and the centre pixel, inside the target: the
    // same pixels as the twin's wider loop finds, fewer tested.
    const int half_pixel = 1 << (STA_RASTER_SUBPIXEL_BITS - 1);
    int r = int(sqrt(float(f.r2)) + 0.5); // f.r2 is a square: its root exactly
    ivec2 lo = -((ivec2(half_pixel + r) - f.snapped) >> STA_RASTER_SUBPIXEL_BITS);
    ivec2 hi = (f.snapped + r - half_pixel) >> STA_RASTER_SUBPIXEL_BITS;
    lo = max(min(lo, f.centre), ivec2(0));
    hi = min(max(hi, f.centre), u_size - 1);
    for (int y = lo.y; y <= hi.y; y++) {
        for (int x = lo.x; x <= hi.x; x++) {
            ivec2 p = ivec2(x, y);
            float depth = footprint_depth(f, p);
            if (depth >= 0.0) {
                keep(uint(p.y) * uint(u_size.x) + uint(p.x), floatBitsToUint(depth), index);
            }
        }
    }
}

void main()
{
    uvec2 batch = batches[gl_WorkGroupID.x];
    raster_node node = nodes[batch.x];
    uint end = min(node.info.y, batch.y + uint(STA_RASTER_BATCH_POINTS));
    for (uint i = batch.y + gl_LocalInvocationID.x; i < end; i += uint(STA_RASTER_WORKGROUP_SIZE)) {
        uvec4 t = texelFetch(u_points, int(node.info.x + i));
        if ((((t.w >> 16) & 0xFFu) & u_hide_flags) != 0u) {
            continue;
        }
        vec3 q = vec3(uvec3(t.x & 0xFFFFu, t.x >> 16, t.y & 0xFFFFu));
        vec3 relative = node.origin.xyz + q * node.step.xyz;
        if (dot(u_clip_plane.xyz, relative) + u_clip_plane.w < 0.0) {
            continue;
        }
        // Draw-order index with gaps: batch number, then the point within the batch, so
        // that the resolve finds the point through the batch list without a search.
        uint index = gl_WorkGroupID.x * uint(STA_RASTER_BATCH_POINTS) + (i - batch.y);
        if (u_point_wide != 0) {
            keep_footprint(relative, node.origin.w, index);
            continue;
        }
        uint pixel;
        float depth;
        if (!project_point(relative, pixel, depth)) {
            continue;
        }
        keep(pixel, floatBitsToUint(depth), index);
    }
}
