// SPDX-License-Identifier: MIT
// HPR, the exhaustive operator (as Pintus et al. 2011): every pixel within a fixed
// square radius at full resolution is a neighbour; sectors, occlusion value and labels
// as the pyramidal operator. Twin: sta_hpr_ref_exhaustive.
layout(local_size_x = STA_WORKGROUP_SIZE_X, local_size_y = STA_WORKGROUP_SIZE_Y) in;
// RGBA32F, screen_space.h
layout(binding = STA_HPR_EXHAUSTIVE_SAMPLER_POSITION) uniform sampler2D u_position;
layout(binding = STA_HPR_EXHAUSTIVE_IMAGE_LABEL, r16f) writeonly uniform image2D u_label;
uniform ivec2 u_size;    // width, height in pixels
uniform int u_radius;    // pixels
uniform vec2 u_tan_half; // tan(fov_y / 2) * aspect, tan(fov_y / 2)
uniform float u_far;     // depth of background pixels, metres
uniform float u_threshold;

void main()
{
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (p.x >= u_size.x || p.y >= u_size.y) {
        return;
    }
    vec4 own = texelFetch(u_position, p, 0);
    vec3 x = hpr_centre_point(own, p, u_size, u_tan_half, u_far);
    vec4 min_lo = vec4(1.0), min_hi = vec4(1.0);
    // The square clipped to the image.
    ivec2 lo = max(ivec2(-u_radius), -p);
    ivec2 hi = min(ivec2(u_radius), u_size - 1 - p);
    for (int dy = lo.y; dy <= hi.y; dy++) {
        for (int dx = lo.x; dx <= hi.x; dx++) {
            if (dx == 0 && dy == 0) {
                continue;
            }
            vec4 y = texelFetch(u_position, p + ivec2(dx, dy), 0);
            float value;
            if (y.w > 0.5 && hpr_occlusion(x, y.xyz, value)) {
                hpr_lower_sector(hpr_sector(2 * ivec2(dx, dy)), value, min_lo, min_hi);
            }
        }
    }
    int outside = hpr_reach_outside(
        p, u_size, clamp(float(u_radius), STA_HPR_MIN_REACH_PX, STA_HPR_MAX_REACH_PX));
    float mean = hpr_sector_mean(min_lo, min_hi, own.w > 0.5, outside);
    imageStore(u_label, p, vec4(hpr_label(own.w > 0.5, mean, u_threshold), 0.0, 0.0, 0.0));
}
