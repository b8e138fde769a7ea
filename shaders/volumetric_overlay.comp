// SPDX-License-Identifier: MIT
// Volumetric classes, overlay step: each marked point is drawn over the shaded picture
// as a square splat in its own colour, nearest point first, unless a visible point of
// another class in the window is as near (the filled depth is no test: pull-push
// averages depths across wide gaps). One image read per window pixel.
// Twin: src/render/ref/volumetric_ref.c (sta_volumetric_overlay_ref).
layout(local_size_x = STA_WORKGROUP_SIZE_X, local_size_y = STA_WORKGROUP_SIZE_Y) in;
layout(binding = STA_VOLUMETRIC_OVERLAY_IMAGE_POINTS, rgba32f) readonly uniform image2D u_points;
layout(binding = STA_VOLUMETRIC_OVERLAY_IMAGE_OUT, rgba8) writeonly uniform image2D u_out;
uniform ivec2 u_size;

const int R = STA_VOLUMETRIC_SPLAT_RADIUS_PX;

void main()
{
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (p.x >= u_size.x || p.y >= u_size.y) {
        return;
    }
    vec4 best = vec4(0.0); // alpha > 0: a marked point, < 0: an occluder, 0: nothing
    float occluder = 0.0; // nearest occluder's distance, 0: none
    for (int dy = -R; dy <= R; dy++) {
        for (int dx = -R; dx <= R; dx++) {
            ivec2 q = p + ivec2(dx, dy);
            vec4 v = vec4(0.0);
            if (q.x >= 0 && q.y >= 0 && q.x < u_size.x && q.y < u_size.y) {
                v = imageLoad(u_points, q);
            }
            if (v.a > 0.0 && (best.a <= 0.0 || v.a < best.a)) {
                best = v;
            } else if (v.a < 0.0 && (occluder <= 0.0 || -v.a < occluder)) {
                occluder = -v.a;
            }
        }
    }
    if (best.a <= 0.0 || (occluder > 0.0 && occluder <= best.a)) {
        return;
    }
    imageStore(u_out, p, vec4(clamp(best.rgb, 0.0, 1.0), 1.0));
}
