// SPDX-License-Identifier: MIT
// Volumetric classes, the overlay's tile list (issue 15, fourteenth round): one
// invocation per tile of STA_WORKGROUP_SIZE_X x STA_WORKGROUP_SIZE_Y pixels. A tile that
// a marked point's splat can reach (a marked pixel, w = STA_POSITION_W_MARKED, in the
// tile or within STA_VOLUMETRIC_SPLAT_RADIUS_PX of it) is appended to the list, and
// volumetric_overlay.comp runs one workgroup per listed tile. On llvmpipe a shader runs
// every branch for every pixel, so the overlay's 3 x 3 window costs each pixel of a pass
// it is in (~16 CPU ms of the shade pass at 1080p); on the README view only ~7 % of the
// tiles hold a splat. With VW_FLAGS the unproject pass has set a flag per tile holding a
// marked pixel (unproject.comp), and a tile is listed where it or one of its 8
// neighbours is flagged (the splat radius is at most a tile); without it (the compute
// rasteriser's resolve or the separate mark pass marked the pixels) the tile and a
// border of the radius are scanned.
layout(local_size_x = STA_WORKGROUP_SIZE_X, local_size_y = STA_WORKGROUP_SIZE_Y) in;
#ifdef VW_FLAGS
layout(binding = STA_VOLUMETRIC_TILES_IMAGE_FLAGS, r32ui) readonly uniform uimage2D u_flags;
#else
layout(binding = STA_VOLUMETRIC_WINDOW_IMAGE_POSITION,
       rgba32f) readonly uniform image2D u_position;
#endif
layout(std430, binding = STA_VOLUMETRIC_TILES_BUFFER_LIST) buffer TileList
{
    uint u_groups[3]; // the overlay's indirect dispatch: STA_VOLUMETRIC_TILE_ROW, rows, 1
    uint u_count;
    uint u_tiles[]; // x | y << 16, in tiles
};
uniform ivec2 u_size; // pixels

void main()
{
    const ivec2 tile = ivec2(STA_WORKGROUP_SIZE_X, STA_WORKGROUP_SIZE_Y);
    const int r = STA_VOLUMETRIC_SPLAT_RADIUS_PX;
    ivec2 t = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(t * tile, u_size))) {
        return;
    }
    bool found = false;
#ifdef VW_FLAGS
    ivec2 tiles = (u_size + tile - 1) / tile;
    ivec2 lo = max(t - 1, ivec2(0)), hi = min(t + 1, tiles - 1);
    for (int y = lo.y; y <= hi.y; y++) {
        for (int x = lo.x; x <= hi.x; x++) {
            found = found || imageLoad(u_flags, ivec2(x, y)).x != 0u;
        }
    }
#else
    ivec2 lo = max(t * tile - r, ivec2(0)), hi = min(t * tile + tile - 1 + r, u_size - 1);
    for (int y = lo.y; y <= hi.y && !found; y++) {
        for (int x = lo.x; x <= hi.x && !found; x++) {
            found = imageLoad(u_position, ivec2(x, y)).w == STA_POSITION_W_MARKED;
        }
    }
#endif
    if (!found) {
        return;
    }
    uint i = atomicAdd(u_count, 1u);
    u_tiles[i] = uint(t.x) | (uint(t.y) << 16);
    // The entries are 0..count-1 without gaps: the one that opens a row of the overlay's
    // dispatch raises its row count.
    if (i % uint(STA_VOLUMETRIC_TILE_ROW) == 0u) {
        atomicMax(u_groups[1], i / uint(STA_VOLUMETRIC_TILE_ROW) + 1u);
    }
}
