// SPDX-License-Identifier: MIT
// Smoothing (correction) pass for screen-space normals (Schiffner et al., WSCG 2015):
// each pixel with a valid position gets the renormalised weighted mean of the valid
// normals in its 3x3 neighbourhood within the distance limit; weights 4 (centre),
// 2 (edge), 1 (corner). Twin: sta_normals_smooth_ref in
// src/render/ref/normals_screen_ref.c.
layout(local_size_x = STA_WORKGROUP_SIZE_X, local_size_y = STA_WORKGROUP_SIZE_Y) in;
// xyz camera space, w > 0 valid
layout(binding = STA_NORMALS_SMOOTH_IMAGE_POSITION, rgba32f) readonly uniform image2D u_position;
// xyz unit normal, w = 1 valid
layout(binding = STA_NORMALS_SMOOTH_IMAGE_NORMAL, rgba32f) readonly uniform image2D u_normal;
layout(binding = STA_NORMALS_SMOOTH_IMAGE_SMOOTHED, rgba32f) writeonly uniform image2D u_smoothed;
uniform ivec2 u_size;
uniform float u_max_distance2;

#define MIN_SMOOTH_LEN2 1e-6

void main()
{
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (p.x >= u_size.x || p.y >= u_size.y) {
        return;
    }
    vec4 c = imageLoad(u_position, p);
    vec4 result = vec4(0.0);
    if (c.w > 0.0) {
        vec3 sum = vec3(0.0);
        float weight = 0.0;
        for (int dy = -1; dy <= 1; dy++) {
            for (int dx = -1; dx <= 1; dx++) {
                ivec2 q = p + ivec2(dx, dy);
                if (q.x < 0 || q.y < 0 || q.x >= u_size.x || q.y >= u_size.y) {
                    continue;
                }
                vec4 n = imageLoad(u_normal, q);
                vec4 s = imageLoad(u_position, q);
                vec3 d = s.xyz - c.xyz;
                float d2 = d.x * d.x + d.y * d.y + d.z * d.z;
                if (s.w > 0.0 && n.w > 0.0 && d2 <= u_max_distance2) {
                    float w = float((2 - abs(dx)) * (2 - abs(dy)));
                    sum = sum + n.xyz * w;
                    weight += w;
                }
            }
        }
        float n2 = sum.x * sum.x + sum.y * sum.y + sum.z * sum.z;
        if (n2 > MIN_SMOOTH_LEN2 * (weight * weight) && n2 <= 3.4028234664e38) {
            vec3 n = sum * (1.0 / sqrt(n2));
            if (n.x * c.x + n.y * c.y + n.z * c.z > 0.0) {
                n = -n;
            }
            result = vec4(n, 1.0);
        }
    }
    imageStore(u_smoothed, p, result);
}
