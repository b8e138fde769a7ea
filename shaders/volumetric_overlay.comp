// SPDX-License-Identifier: MIT
// Volumetric classes, overlay step: each marked point is drawn into the RGBA8 filled
// colour with alpha 1 (the shade pass and the fill display show it unlit, as if drawn
// over their picture; screen_space.h) as a square splat in its own colour, nearest point first, unless a visible point of
// another class in the window is as near (the filled depth is no test: pull-push
// averages depths across wide gaps). One image read per window pixel
// (volumetric_window.glsl). One workgroup per tile that volumetric_tiles.comp listed (an
// indirect dispatch, rows of STA_VOLUMETRIC_TILE_ROW tiles): the pixels no splat reaches
// are not run at all (issue 15, fourteenth round).
// Twin: src/render/ref/volumetric_ref.c (sta_volumetric_overlay_ref).
layout(local_size_x = STA_WORKGROUP_SIZE_X, local_size_y = STA_WORKGROUP_SIZE_Y) in;
layout(binding = STA_VOLUMETRIC_OVERLAY_IMAGE_OUT, rgba8) writeonly uniform image2D u_out;
layout(std430, binding = STA_VOLUMETRIC_OVERLAY_BUFFER_TILES) readonly buffer TileList
{
    uint u_groups[3];
    uint u_count;
    uint u_tiles[]; // x | y << 16, in tiles
};
uniform ivec2 u_size;

void main()
{
    uint g = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
    if (g >= u_count) {
        return;
    }
    uint t = u_tiles[g];
    ivec2 p = ivec2(int(t & 0xffffu), int(t >> 16)) * ivec2(gl_WorkGroupSize.xy) +
              ivec2(gl_LocalInvocationID.xy);
    if (p.x >= u_size.x || p.y >= u_size.y) {
        return;
    }
    vec3 colour;
    if (vw_overlay_colour(p, u_size, colour)) {
        imageStore(u_out, p, vec4(clamp(colour, 0.0, 1.0), 1.0));
    }
}
