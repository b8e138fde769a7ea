// SPDX-License-Identifier: MIT
// Volumetric classes, the overlay's window (volumetric_overlay.comp; the tile list,
// volumetric_tiles.comp, reads the same positions): the colour a pixel
// takes from the marked points (position w = STA_POSITION_W_MARKED) in its window,
// nearest first, unless a drawn point of another class is in the window and as near
// (HPR's labels play no part: a nearer point of another class is a surface in front,
// kept by HPR or not). Read from the positions and, for the nearest marked point, its
// colour from the geometry pass's colour target (the overlay runs before the shade pass
// overwrites it; issue 15, fourteenth round), rounded to 8 bits (sta_unorm8).
// Twin: src/render/ref/volumetric_ref.c (sta_volumetric_overlay_ref).
layout(binding = STA_VOLUMETRIC_WINDOW_IMAGE_POSITION,
       rgba32f) readonly uniform image2D u_vw_position;
// The point colours of the geometry pass (RGBA8 or float).
layout(binding = STA_VOLUMETRIC_WINDOW_SAMPLER_COLOUR) uniform sampler2D u_vw_colour;

const int VW_R = STA_VOLUMETRIC_SPLAT_RADIUS_PX;

// True where a marked point covers p (its colour in `colour`, not clamped).
bool vw_overlay_colour(ivec2 p, ivec2 size, out vec3 colour)
{
    float best = 0.0; // nearest marked point's distance, 0: none
    ivec2 best_q = p;
    float occluder = 0.0; // nearest occluder's distance, 0: none
    for (int dy = -VW_R; dy <= VW_R; dy++) {
        for (int dx = -VW_R; dx <= VW_R; dx++) {
            ivec2 q = p + ivec2(dx, dy);
            bool inside = q.x >= 0 && q.y >= 0 && q.x < size.x && q.y < size.y;
            vec4 v = imageLoad(u_vw_position, q);
            float d = -v.z;
            bool drawn = inside && v.w > 0.0 && d > 0.0;
            bool marked = drawn && v.w == STA_POSITION_W_MARKED;
            if (marked && (best <= 0.0 || d < best)) {
                best = d;
                best_q = q;
            } else if (drawn && !marked && (occluder <= 0.0 || d < occluder)) {
                occluder = d;
            }
        }
    }
    vec3 c = texelFetch(u_vw_colour, best_q, 0).rgb;
    colour = round(clamp(c, 0.0, 1.0) * 255.0) / 255.0;
    return best > 0.0 && !(occluder > 0.0 && occluder <= best);
}
