// SPDX-License-Identifier: MIT
// Volumetric classes, mark step (before HPR): a drawn pixel whose point, looked up
// through the point-id target in the arena, has a class in u_classes gets
// w = STA_POSITION_W_MARKED in the position image (screen_space.h): HPR still sees it as
// a point, pull-push takes no seed from it, and the overlay draws it
// (volumetric_window.glsl) in its colour, which pull-push keeps in the filled colour's
// alpha. With STA_VOLUMETRIC_CLASS_IMAGE the class comes from a
// per-pixel class image (the rasterisers write it with the point) instead of the id and
// arena lookup: the same marks, without two dependent buffer reads a pixel. The GL_POINTS
// pipeline marks inside the unproject pass instead (unproject.comp, STA_UNPROJECT_MARK).
// Twin: src/render/ref/volumetric_ref.c (sta_volumetric_mark_ref).
layout(local_size_x = STA_WORKGROUP_SIZE_X, local_size_y = STA_WORKGROUP_SIZE_Y) in;
#ifdef STA_VOLUMETRIC_CLASS_IMAGE
layout(binding = STA_VOLUMETRIC_MARK_IMAGE_CLASS, r8ui) readonly uniform uimage2D u_class;
#else
layout(binding = STA_VOLUMETRIC_MARK_IMAGE_ID, rg32ui) readonly uniform uimage2D u_id;
#endif
layout(binding = STA_VOLUMETRIC_MARK_IMAGE_POSITION, rgba32f) uniform image2D u_position;
#ifndef STA_VOLUMETRIC_CLASS_IMAGE
// The arena: 16-byte points (stream/gpu_points.h); classification is byte 11.
layout(std430, binding = STA_VOLUMETRIC_MARK_BUFFER_ARENA) readonly buffer Arena
{
    uvec4 arena[];
};
// Per node slot: first arena point, point count (0: not resident).
layout(std430, binding = STA_VOLUMETRIC_MARK_BUFFER_NODES) readonly buffer Nodes
{
    uvec2 nodes[];
};
#endif
uniform ivec2 u_size;
uniform uint u_classes[8]; // bit c % 32 of word c / 32: class c is volumetric

void main()
{
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (p.x >= u_size.x || p.y >= u_size.y) {
        return;
    }
    vec4 position = imageLoad(u_position, p);
    if (!(position.w > 0.0 && position.z < 0.0)) {
        return; // no point drawn here
    }
    bool marked = false;
#ifdef STA_VOLUMETRIC_CLASS_IMAGE
    uint c = imageLoad(u_class, p).x & 0xFFu;
    marked = ((u_classes[c >> 5u] >> (c & 31u)) & 1u) != 0u;
#else
    uvec2 id = imageLoad(u_id, p).xy;
    if (id.x < uint(nodes.length())) {
        uvec2 node = nodes[id.x];
        uint total = uint(arena.length());
        if (id.y < node.y && node.x < total && id.y < total - node.x) {
            uint c = (arena[node.x + id.y].z >> 24u) & 0xFFu;
            marked = ((u_classes[c >> 5u] >> (c & 31u)) & 1u) != 0u;
        }
    }
#endif
    if (marked) {
        imageStore(u_position, p, vec4(position.xyz, STA_POSITION_W_MARKED));
    }
}
