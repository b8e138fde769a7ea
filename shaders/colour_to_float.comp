// SPDX-License-Identifier: MIT
// The geometry pass's RGBA8 colour as RGBA32F for the screen-space passes.
layout(local_size_x = STA_WORKGROUP_SIZE_X, local_size_y = STA_WORKGROUP_SIZE_Y) in;
layout(binding = STA_COLOUR_TO_FLOAT_SAMPLER_COLOUR8) uniform sampler2D u_colour8;
layout(binding = STA_COLOUR_TO_FLOAT_IMAGE_COLOUR, rgba32f) writeonly uniform image2D u_colour;
uniform vec2 u_size;

void main()
{
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (p.x >= int(u_size.x) || p.y >= int(u_size.y)) {
        return;
    }
    imageStore(u_colour, p, vec4(texelFetch(u_colour8, p, 0).rgb, 1.0));
}
