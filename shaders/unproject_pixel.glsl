// SPDX-License-Identifier: MIT
// The camera-space position of one pixel from its reverse-Z depth (screen_space.h),
// shared by unproject.comp and the compute rasteriser's resolve (raster_resolve.frag
// with STA_RASTER_POSITION, which writes the positions itself so that the unproject pass
// can be skipped): one function, so both give the same bits.
// size: width, height in pixels; tan_half: tan(fov_y / 2) * aspect, tan(fov_y / 2).
vec4 unproject_pixel(ivec2 p, float d, vec2 size, vec2 tan_half, float near)
{
    vec4 result = vec4(0.0);
    if (d > 0.0) {
        float distance = near / d;
        vec2 ndc = (vec2(p) + 0.5) / size * 2.0 - 1.0;
        result = vec4(ndc * tan_half * distance, -distance, 1.0);
    }
    return result;
}
