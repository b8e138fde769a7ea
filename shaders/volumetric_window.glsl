// SPDX-License-Identifier: MIT
// Volumetric classes, the overlay's window (shared by volumetric_overlay.comp and the
// shade pass's overlay variant, shade.comp with STA_SHADE_OVERLAY, which draws the
// marked points while shading and so saves a full-screen pass): the colour a pixel
// takes from the marked points of the points image (volumetric_mark.comp) in its
// window, nearest first, unless a visible point of another class in the window is as
// near. Twin: src/render/ref/volumetric_ref.c (sta_volumetric_overlay_ref).
layout(binding = STA_VOLUMETRIC_WINDOW_IMAGE_POINTS, rgba32f) readonly uniform image2D u_points;

const int VW_R = STA_VOLUMETRIC_SPLAT_RADIUS_PX;

// True where a marked point covers p (its colour in `colour`, not clamped).
bool vw_overlay_colour(ivec2 p, ivec2 size, out vec3 colour)
{
    vec4 best = vec4(0.0); // alpha > 0: a marked point, < 0: an occluder, 0: nothing
    float occluder = 0.0;  // nearest occluder's distance, 0: none
    for (int dy = -VW_R; dy <= VW_R; dy++) {
        for (int dx = -VW_R; dx <= VW_R; dx++) {
            ivec2 q = p + ivec2(dx, dy);
            vec4 v = vec4(0.0);
            if (q.x >= 0 && q.y >= 0 && q.x < size.x && q.y < size.y) {
                v = imageLoad(u_points, q);
            }
            if (v.a > 0.0 && (best.a <= 0.0 || v.a < best.a)) {
                best = v;
            } else if (v.a < 0.0 && (occluder <= 0.0 || -v.a < occluder)) {
                occluder = -v.a;
            }
        }
    }
    colour = best.rgb;
    return best.a > 0.0 && !(occluder > 0.0 && occluder <= best.a);
}
