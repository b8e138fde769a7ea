// SPDX-License-Identifier: MIT
// Compute rasteriser's resolve: the point kept in each pixel gives its colour (as the
// GL_POINTS path colours it), its depth and its id to the render target. One program per
// colour mode (STA_RASTER_COLOUR_MODE), so that only that mode's branch runs. With
// STA_RASTER_POSITION also its camera-space position (what the unproject pass would make
// of the depth written here: unproject_pixel.glsl), so the screen-space pipeline can skip
// that pass, and its class; a drawn pixel whose class is in u_mark_classes gets
// w = STA_POSITION_W_MARKED, the volumetric mark (render/ref/volumetric_ref.h) done here
// (issue 15, tenth round: the mark pass is skipped; all zero: nothing marked); any other
// drawn pixel whose point is not the last return of its pulse and has a class from
// STA_SEE_THROUGH_MIN_CLASS on gets w = STA_POSITION_W_SEE_THROUGH
// (render/ref/screen_space.h; issue 15, sixteenth round).
uniform vec2 u_elevation;        // (camera z - min z, 1 / (max z - min z))
uniform float u_intensity_scale; // 1 / largest intensity
uniform vec3 u_background;       // colour of empty pixels
#if STA_RASTER_POSITION
layout(location = STA_GEOMETRY_OUT_POSITION) out vec4 o_position;
layout(location = STA_GEOMETRY_OUT_CLASS) out uint o_class; // for the volumetric mark
uniform vec2 u_unproject_size; // as the unproject pass's u_size, u_tan_half, u_near
uniform vec2 u_tan_half;
uniform float u_near;
uniform uint u_mark_classes[8]; // bit c % 32 of word c / 32: class c is volumetric
#endif

layout(location = STA_GEOMETRY_OUT_COLOUR) out vec4 o_colour;
layout(location = STA_GEOMETRY_OUT_ID) out uvec2 o_id;

void main()
{
    ivec2 p = ivec2(gl_FragCoord.xy);
    uint pixel = uint(p.y) * uint(u_size.x) + uint(p.x);
#if STA_RASTER_PACKED
    uint64_t value = packed_pixels[pixel];
    uint bits = uint(value >> 32);
    uint index = ~uint(value & 0xFFFFFFFFul);
#else
    uint bits = depth_bits[pixel];
    uint index = payload[pixel];
#endif
    // Every pixel is written, so the target needs no clear first.
    if (bits == 0u || index == STA_RASTER_NO_POINT) {
        o_colour = vec4(u_background, 1.0);
        o_id = uvec2(STA_RASTER_NO_POINT);
        gl_FragDepth = 0.0;
#if STA_RASTER_POSITION
        o_position = vec4(0.0);
        o_class = 0u;
#endif
        return;
    }
    // The draw-order index is batch * STA_RASTER_BATCH_POINTS + point within the batch.
    uvec2 batch = batches[index / uint(STA_RASTER_BATCH_POINTS)];
    raster_node node = nodes[batch.x];
    uint i = batch.y + index % uint(STA_RASTER_BATCH_POINTS);
    uvec4 position_intensity, colour_class, returns;
    unpack_point(texelFetch(u_points, int(node.info.x + i)), position_intensity, colour_class,
                 returns);
    vec3 relative = node.origin.xyz + vec3(position_intensity.xyz) * node.step.xyz;
    o_colour = vec4(point_colour(position_intensity, colour_class, returns, relative,
                                 STA_RASTER_COLOUR_MODE, u_elevation, u_intensity_scale),
                    1.0);
    o_id = uvec2(node.info.w, i);
    gl_FragDepth = uintBitsToFloat(bits);
#if STA_RASTER_POSITION
    o_position = unproject_pixel(p, uintBitsToFloat(bits), u_unproject_size, u_tan_half, u_near);
    o_class = colour_class.w;
    uint c = colour_class.w & 0xFFu;
    if (o_position.w > 0.0 && o_position.z < 0.0 &&
        ((u_mark_classes[c >> 5u] >> (c & 31u)) & 1u) != 0u) {
        o_position.w = STA_POSITION_W_MARKED;
    } else if (o_position.w > 0.0 && o_position.z < 0.0 && returns.x < returns.y &&
               c >= uint(STA_SEE_THROUGH_MIN_CLASS)) {
        o_position.w = STA_POSITION_W_SEE_THROUGH; // returns.xy: return number, of returns
    }
#endif
}
