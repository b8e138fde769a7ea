// SPDX-License-Identifier: MIT
// Unproject: reverse-Z depth buffer -> camera-space positions (screen_space.h;
// unproject_pixel.glsl).
layout(local_size_x = STA_WORKGROUP_SIZE_X, local_size_y = STA_WORKGROUP_SIZE_Y) in;
// reverse-Z: near / distance, 0 = empty
layout(binding = STA_UNPROJECT_SAMPLER_DEPTH) uniform sampler2D u_depth;
layout(binding = STA_UNPROJECT_IMAGE_POSITION, rgba32f) writeonly uniform image2D u_position;
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
    imageStore(u_position, p, unproject_pixel(p, d, u_size, u_tan_half, u_near));
}
