// SPDX-License-Identifier: MIT
// Points wider than one pixel (render/point_size.h): a round footprint with a depth per
// fragment, shared by the compute rasteriser (raster_points.comp) and the GL_POINTS
// wide program (geometry_wide.*). The rule, and its C twin, are in
// render/ref/raster_ref.h: the same clip test and snapped window position as the
// one-pixel rule, a disk of radius R pixels around it (integers in 1/2^bits pixel), and
// a paraboloid depth: the eye distance shortened by the radius in metres at the centre,
// by nothing at the rim. Every operation mirrors the twin, so small cases match exactly.
uniform int u_point_adaptive;         // radius from the node's spacing, else u_point_radius_px
uniform float u_point_radius_px;      // fixed radius
uniform float u_point_spacing_to_px;  // adaptive: radius = spacing * this * (1 / w)
uniform vec2 u_point_radius_range;    // adaptive clamp: min, max radius
uniform float u_point_depth_per_px;   // relative eye-distance offset per pixel of radius

struct point_footprint {
    ivec2 snapped; // window position, 1/2^bits pixel
    ivec2 centre;  // the one-pixel rule's pixel (may lie outside the target)
    int r2;        // squared radius, (1/2^bits pixel)^2
    int reach;     // pixels tested on each side of the centre
    float depth;   // reverse-Z depth of the point
    float k;       // radius * u_point_depth_per_px
};

// The footprint of a point at clip position `clip` in a target of `size`, or false when
// the centre is outside the clip volume (as GL clips points).
bool footprint_of(vec4 clip, float spacing, ivec2 size, out point_footprint f)
{
    f = point_footprint(ivec2(0), ivec2(0), 0, 0, 0.0, 0.0);
    if (!(clip.w > 0.0) || abs(clip.x) > clip.w || abs(clip.y) > clip.w || clip.z < 0.0 ||
        clip.z > clip.w) {
        return false;
    }
    float inverse = 1.0 / clip.w;
    vec3 ndc = clip.xyz * inverse;
    // GL_POINTS' window position: llvmpipe's viewport transform is one fused
    // multiply-add, but its shaders split fma() into two roundings: in double the
    // product is exact and the sum rounds once before the float.
    vec2 half_size = vec2(size) * 0.5;
    vec2 window = vec2(dvec2(ndc.xy) * dvec2(half_size) + dvec2(half_size));
    f.snapped = ivec2(floor(window * float(1 << STA_RASTER_SUBPIXEL_BITS) + 0.5));
    f.centre = (f.snapped - 1) >> STA_RASTER_SUBPIXEL_BITS;
    f.depth = ndc.z;
    float radius = u_point_radius_px;
    if (u_point_adaptive != 0) {
        radius = min(max(spacing * u_point_spacing_to_px * inverse, u_point_radius_range.x),
                     u_point_radius_range.y);
    }
    int r = int(radius * float(1 << STA_RASTER_SUBPIXEL_BITS));
    f.r2 = r * r;
    f.reach = int(radius) + 1;
    f.k = radius * u_point_depth_per_px;
    return true;
}

// Reverse-Z depth of the footprint in pixel `p`, or -1 where it does not cover `p`.
float footprint_depth(point_footprint f, ivec2 p)
{
    ivec2 o = p - f.centre;
    if (abs(o.x) > f.reach || abs(o.y) > f.reach) {
        return -1.0;
    }
    ivec2 d = p * (1 << STA_RASTER_SUBPIXEL_BITS) + (1 << (STA_RASTER_SUBPIXEL_BITS - 1)) -
              f.snapped;
    int d2 = d.x * d.x + d.y * d.y;
    if (d2 > f.r2 && (o.x != 0 || o.y != 0)) {
        return -1.0;
    }
    float t = f.r2 > 0 ? 1.0 - min(float(d2) * (1.0 / float(f.r2)), 1.0) : 0.0;
    return f.depth * (1.0 / (1.0 - f.k * t));
}
