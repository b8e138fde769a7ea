// SPDX-License-Identifier: MIT
// Volumetric classes, overlay step: each marked point is drawn over the shaded picture
// as a square splat in its own colour, nearest point first, unless a visible point of
// another class in the window is nearer (the filled depth is no test: pull-push
// averages depths across wide gaps), darkened by eye-dome lighting so that crowns show
// their depth structure even in one flat colour. Twin: src/render/ref/volumetric_ref.c (sta_volumetric_overlay_ref).
layout(local_size_x = STA_WORKGROUP_SIZE_X, local_size_y = STA_WORKGROUP_SIZE_Y) in;
layout(binding = STA_VOLUMETRIC_OVERLAY_IMAGE_POINTS, rgba32f) readonly uniform image2D u_points;
layout(binding = STA_VOLUMETRIC_OVERLAY_IMAGE_POSITION, rgba32f) readonly uniform image2D u_position;
layout(binding = STA_VOLUMETRIC_OVERLAY_IMAGE_LABEL, r32f) readonly uniform image2D u_label;
layout(binding = STA_VOLUMETRIC_OVERLAY_IMAGE_OUT, rgba8) writeonly uniform image2D u_out;
uniform ivec2 u_size;

void main()
{
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (p.x >= u_size.x || p.y >= u_size.y) {
        return;
    }
    const int r = STA_VOLUMETRIC_SPLAT_RADIUS_PX;
    vec4 best = vec4(0.0);
    for (int dy = -r; dy <= r; dy++) {
        for (int dx = -r; dx <= r; dx++) {
            ivec2 q = p + ivec2(dx, dy);
            if (q.x < 0 || q.y < 0 || q.x >= u_size.x || q.y >= u_size.y) {
                continue;
            }
            vec4 point = imageLoad(u_points, q);
            if (point.a > 0.0 && (best.a <= 0.0 || point.a < best.a)) {
                best = point;
            }
        }
    }
    if (best.a <= 0.0) {
        return;
    }
    // Hidden behind a visible point of another class in the window (a wall in front).
    for (int dy = -r; dy <= r; dy++) {
        for (int dx = -r; dx <= r; dx++) {
            ivec2 q = p + ivec2(dx, dy);
            if (q.x < 0 || q.y < 0 || q.x >= u_size.x || q.y >= u_size.y) {
                continue;
            }
            if (imageLoad(u_label, q).r == STA_LABEL_VISIBLE &&
                -imageLoad(u_position, q).z <= best.a) {
                return;
            }
        }
    }
    // Eye-dome lighting on the splat: darker where drawn points around are nearer.
    float response = 0.0;
    for (int dy = -1; dy <= 1; dy++) {
        for (int dx = -1; dx <= 1; dx++) {
            ivec2 q = p + ivec2(dx, dy);
            if ((dx == 0 && dy == 0) || q.x < 0 || q.y < 0 || q.x >= u_size.x || q.y >= u_size.y) {
                continue;
            }
            vec4 other = imageLoad(u_position, q);
            if (other.w > 0.0 && other.z < 0.0) {
                response += max(0.0, log2(best.a) - log2(-other.z));
            }
        }
    }
    float shade = exp(-STA_VOLUMETRIC_EDL_STRENGTH * response / 8.0);
    imageStore(u_out, p, vec4(clamp(best.rgb * shade, 0.0, 1.0), 1.0));
}
