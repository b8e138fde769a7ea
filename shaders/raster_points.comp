// SPDX-License-Identifier: MIT
// Compute rasteriser, one step per build (STA_RASTER_STEP): DEPTH keeps the largest
// reverse-Z depth per pixel; PAYLOAD then keeps, among the points at that depth, the
// first in draw order (as GL_POINTS' GL_GREATER depth test does); PACKED does both at
// once with 64-bit atomics. One workgroup per batch of STA_RASTER_BATCH_POINTS points
// of one node (the batch list is the indirect dispatch).
layout(local_size_x = STA_RASTER_WORKGROUP_SIZE) in;

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
        uint pixel;
        float depth;
        if (!project_point(relative, pixel, depth)) {
            continue;
        }
        uint bits = floatBitsToUint(depth);
        // Draw-order index with gaps: batch number, then the point within the batch, so
        // that the resolve finds the point through the batch list without a search.
        uint index = gl_WorkGroupID.x * uint(STA_RASTER_BATCH_POINTS) + (i - batch.y);
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
}
