// SPDX-License-Identifier: MIT
// Unproject: reverse-Z depth buffer -> camera-space positions (screen_space.h;
// unproject_pixel.glsl). With STA_UNPROJECT_MARK it also marks the volumetric classes
// (the mark of volumetric_mark.comp, fused: one full-screen pass fewer, issue 15 tenth
// round): a drawn pixel whose class in the geometry pass's class image is in u_classes
// gets w = STA_POSITION_W_MARKED (pull-push keeps its colour for the overlay), and its
// tile's flag is set for the overlay's tile list (volumetric_tiles.comp; issue 15,
// fourteenth round). Twins: src/render/ref/unproject_ref.c and
// sta_volumetric_mark_ref (src/render/ref/volumetric_ref.c). With STA_STAGED_STORES the
// positions go to a storage buffer, row by row, which the pass copies into the texture
// (render/gl_staged.h: llvmpipe stores an RGBA32F image texel by texel, channel by channel).
layout(local_size_x = STA_WORKGROUP_SIZE_X, local_size_y = STA_WORKGROUP_SIZE_Y) in;
// reverse-Z: near / distance, 0 = empty
layout(binding = STA_UNPROJECT_SAMPLER_DEPTH) uniform sampler2D u_depth;
#ifdef STA_STAGED_STORES
layout(std430, binding = STA_UNPROJECT_BUFFER_POSITION) writeonly restrict buffer Positions {
    vec4 u_staged_position[];
};
#else
layout(binding = STA_UNPROJECT_IMAGE_POSITION, rgba32f) writeonly uniform image2D u_position;
#endif
#ifdef STA_UNPROJECT_MARK
layout(binding = STA_UNPROJECT_IMAGE_CLASS, r8ui) readonly uniform uimage2D u_class;
uniform uint u_classes[8]; // bit c % 32 of word c / 32: class c is volumetric
// a texel per STA_WORKGROUP_SIZE_X x _Y tile, cleared by the caller
layout(binding = STA_UNPROJECT_IMAGE_TILES, r32ui) writeonly uniform uimage2D u_tile_flags;
#endif
uniform vec2 u_size;     // width, height in pixels
uniform vec2 u_tan_half; // tan(fov_y / 2) * aspect, tan(fov_y / 2)
uniform float u_near;

void main()
{
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (p.x >= int(u_size.x) || p.y >= int(u_size.y)) {
        return;
    }
    float d = texelFetch(u_depth, p, 0).r;
    vec4 position = unproject_pixel(p, d, u_size, u_tan_half, u_near);
#ifdef STA_UNPROJECT_MARK
    if (position.w > 0.0 && position.z < 0.0) {
        uint c = imageLoad(u_class, p).x & 0xFFu;
        if (((u_classes[c >> 5u] >> (c & 31u)) & 1u) != 0u) {
            position.w = STA_POSITION_W_MARKED;
            imageStore(u_tile_flags, p / ivec2(STA_WORKGROUP_SIZE_X, STA_WORKGROUP_SIZE_Y),
                       uvec4(1u));
        }
    }
#endif
#ifdef STA_STAGED_STORES
    u_staged_position[p.y * int(u_size.x) + p.x] = position;
#else
    imageStore(u_position, p, position);
#endif
}
