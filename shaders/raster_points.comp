// SPDX-License-Identifier: MIT
// Compute rasteriser, one step per build (STA_RASTER_STEP): DEPTH keeps the largest
// reverse-Z depth per pixel; PAYLOAD then keeps, among the points at that depth, the
// first in draw order (as GL_POINTS' GL_GREATER depth test does); PACKED does both at
// once with 64-bit atomics. One workgroup per batch of STA_RASTER_BATCH_POINTS points
// of one node (the batch list is the indirect dispatch). The DEPTH step marks, per
// invocation, the points that were not behind the pixel's depth when they came (bit k:
// its k-th point); only those can be nearest at the end (depths only grow), so the
// PAYLOAD step projects only them.
// Built with STA_RASTER_WIDE, points wider than a pixel write their whole footprint
// (point_footprint.glsl) through the same atomics, the node's spacing in origin.w.
layout(local_size_x = STA_RASTER_WORKGROUP_SIZE) in;

// Keeps the point `index` at `bits` in `pixel` if it is nearer (or equal and earlier).
// DEPTH step: true when the point may still be the pixel's nearest (a candidate).
bool keep(uint pixel, uint bits, uint index)
{
#if STA_RASTER_STEP == STA_RASTER_STEP_DEPTH
    uint kept = depth_bits[pixel];
    if (bits > kept) { // most points lose: skip their atomic
        atomicMax(depth_bits[pixel], bits);
    }
    return bits >= kept;
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
    return false;
}

#if STA_RASTER_WIDE
bool keep_footprint(vec3 relative, float spacing, uint index)
{
    vec4 clip = u_projection * (u_view_rotation * vec4(relative, 1.0));
    point_footprint f;
    if (!footprint_of(clip, spacing, u_size, f)) {
        return false;
    }
    bool candidate = false;
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
                candidate = keep(uint(p.y) * uint(u_size.x) + uint(p.x), floatBitsToUint(depth),
                                 index) ||
                            candidate;
            }
        }
    }
    return candidate;
}
#endif

// Point `i` of node `node` (in the workgroup's batch); true when it
// is a candidate (DEPTH step).
bool raster_point(raster_node node, uint i)
{
    uvec4 t = texelFetch(u_points, int(node.info.x + i));
    if ((((t.w >> 16) & 0xFFu) & u_hide_flags) != 0u) {
        return false;
    }
    vec3 q = vec3(uvec3(t.x & 0xFFFFu, t.x >> 16, t.y & 0xFFFFu));
    // Draw-order index with gaps: the batch's number in draw order (the node's first,
    // node.info.z, plus i's batch within the node), then the point within the batch, so
    // that the resolve finds the point through the draw-order batch list without a
    // search. The workgroups themselves run nearest node first (raster_compute.c).
    uint index = node.info.z * uint(STA_RASTER_BATCH_POINTS) + i;
#if STA_RASTER_WIDE
    vec3 relative = node.origin.xyz + q * node.step.xyz;
    if (dot(u_clip_plane.xyz, relative) + u_clip_plane.w < 0.0) {
        return false;
    }
    return keep_footprint(relative, node.origin.w, index);
#else
    uint pixel;
    float depth;
    return project_rows(node, q, pixel, depth) && keep(pixel, floatBitsToUint(depth), index);
#endif
}

void main()
{
    uvec2 batch = batches[gl_WorkGroupID.x];
    raster_node node = nodes[batch.x];
    uint invocation = gl_WorkGroupID.x * uint(STA_RASTER_WORKGROUP_SIZE) + gl_LocalInvocationID.x;
    uint first = batch.y + gl_LocalInvocationID.x;
#if STA_RASTER_STEP == STA_RASTER_STEP_PAYLOAD
    // Only the depth step's candidates: bit k of the mask is point first + k * size.
    uint mask = candidates[invocation];
    while (mask != 0u) {
        int k = findLSB(mask);
        mask &= mask - 1u;
        raster_point(node, first + uint(k) * uint(STA_RASTER_WORKGROUP_SIZE));
    }
#else
    uint end = min(node.info.y, batch.y + uint(STA_RASTER_BATCH_POINTS));
    uint mask = 0u;
    for (uint k = 0u, i = first; i < end; k++, i += uint(STA_RASTER_WORKGROUP_SIZE)) {
        if (raster_point(node, i)) {
            mask |= 1u << k;
        }
    }
#if STA_RASTER_STEP == STA_RASTER_STEP_DEPTH
    candidates[invocation] = mask;
#endif
#endif
}
