// SPDX-License-Identifier: MIT
// Pyramidal normals at half resolution, step 3, as a function (shared by
// normals_pyramid_upsample.comp, which writes the normal image, and shade.comp with
// STA_SHADE_UPSAMPLE, which shades from it directly in the shaded pipeline: one
// full-screen pass fewer). The normal of the pixel q with filled point p (w > 0): bilinear
// interpolation of the normals of the anchors (normals_pyramid_gather.comp with
// NP_ANCHORS; anchor (i, j) sits at pixel (i, j) * 2^u_anchor_level, so the weights are
// k / 2^u_anchor_level per axis), counting only anchors whose tangent plane passes within
// the gather's plane tolerance of p at the finer of the two levels the gather would use
// here, at least level u_anchor_level (the anchors' spacing): no mixing across depth discontinuities,
// and a noisy point still finds its surface's anchors. Where no anchor qualifies (a
// surface seen only between anchors), the normal of the anchor whose plane passes nearest
// (the pixel's own level-0 normal there measured as good, but computing it costs every
// pixel on llvmpipe, which runs both sides of a branch: +25 % of the pass). An anchor
// reads back its own normal. Returns xyz facing the camera, w = 1, or zero where none.
// Twin: src/render/ref/normals_pyramid_ref.c.
layout(binding = STA_NORMALS_UPSAMPLE_IMAGE_HALF, rgba32f) readonly uniform image2D u_half;
uniform ivec2 u_half_size;
uniform int u_anchor_level; // anchor (i, j) sits at pixel (i, j) * 2^u_anchor_level
uniform float u_upsample_near;
uniform int u_level_count;
uniform float u_radius_px_m;       // as the gather's
uniform float u_plane_tolerance_m; // as the gather's: a level-l texel's is this * 2^l * depth

vec4 np_upsample(ivec2 q, vec4 p)
{
    vec4 result = vec4(0.0);
    if (p.w > 0.0) {
        float depth = max(-p.z, u_upsample_near);
        float t;
        int level = max(np_level_of_detail(u_radius_px_m / depth, u_level_count, t), u_anchor_level);
        float tolerance = u_plane_tolerance_m * float(1 << level) * depth;
        // Shifts, not divisions (q >= 0): llvmpipe runs an integer division lane by lane.
        ivec2 i0 = q >> u_anchor_level;
        vec2 f = vec2(q - (i0 << u_anchor_level)) * (1.0 / float(1 << u_anchor_level));
        precise vec3 acc = vec3(0.0);
        vec3 nearest = vec3(0.0);
        float nearest_off = 1e30;
        for (int b = 0; b < 2; b++) {
            for (int a = 0; a < 2; a++) {
                ivec2 t = min(i0 + ivec2(a, b), u_half_size - 1);
                vec4 m = imageLoad(u_half, t);
                float bw = (a == 1 ? f.x : 1.0 - f.x) * (b == 1 ? f.y : 1.0 - f.y);
                float off = abs(np_dot(m.xyz, p.xyz) - m.w);
                bool valid = np_dot(m.xyz, m.xyz) > 0.5;
                if (valid && off <= tolerance) {
                    acc += bw * m.xyz;
                }
                if (valid && bw > 0.0 && off < nearest_off) {
                    nearest_off = off;
                    nearest = m.xyz;
                }
            }
        }
        vec3 n = np_dot(acc, acc) > 1e-12 ? acc : nearest;
        float n2 = np_dot(n, n);
        if (n2 > 1e-12) {
            float len = sqrt(n2);
            float s = np_facing_sign(n, p.xyz);
            result = vec4(s * (n / len), 1.0);
        }
    }
    return result;
}
