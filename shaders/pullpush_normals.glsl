// SPDX-License-Identifier: MIT
// The normal of one texel of a pyramid level (Bouchiba et al. 2018, 3.3), shared by
// normals_pyramid_level.comp and normals_pyramid_gather.comp (which uses it for level
// 0, where bilinear interpolation at pixel centres reads a single texel). Twin:
// sta_normals_pyramid_level_ref in src/render/ref/normals_pyramid_ref.c.
// xyz, w > 0 where a point is
layout(binding = STA_NORMALS_PYRAMID_IMAGE_POINTS, rgba32f) readonly uniform image2D u_points;

// The point at q, w = 0 outside the level.
vec4 pn_point_at(ivec2 q, ivec2 size)
{
    bool inside = q.x >= 0 && q.y >= 0 && q.x < size.x && q.y < size.y;
    return inside ? imageLoad(u_points, q) : vec4(0.0);
}

// The difference along one axis: central where both neighbours exist, one-sided
// where one does, none otherwise. A neighbour more than sqrt(jump2) times as far from p
// as the other one and as the texel's footprint (floor2 = its square) lies across a
// depth discontinuity: then the near side alone.
bool pn_difference(vec4 next, vec4 prev, vec3 p, float jump2, float floor2, out precise vec3 d)
{
    d = vec3(0.0);
    bool has_next = next.w > 0.0, has_prev = prev.w > 0.0;
    if (has_next && has_prev) {
        precise vec3 fa = next.xyz - p, fb = p - prev.xyz;
        float la = np_dot(fa, fa), lb = np_dot(fb, fb);
        has_next = !(la > jump2 * max(lb, floor2));
        has_prev = !(lb > jump2 * max(la, floor2));
    }
    if (has_next && has_prev) {
        d = next.xyz - prev.xyz;
    } else if (has_next) {
        d = next.xyz - p;
    } else if (has_prev) {
        d = p - prev.xyz;
    } else {
        return false;
    }
    return true;
}

// cross(dx, dy) normalised and turned towards the camera; false where the texel has
// no point or the differences give no reliable normal (pn_difference; texel_m: the
// texel's footprint per metre of depth).
bool pn_point_normal(ivec2 q, ivec2 size, float jump2, float texel_m, out vec3 n)
{
    n = vec3(0.0);
    vec4 p = imageLoad(u_points, q);
    vec3 dx, dy;
    precise float footprint = texel_m * -p.z;
    precise float floor2 = footprint * footprint;
    if (!(p.w > 0.0) ||
        !pn_difference(pn_point_at(q + ivec2(1, 0), size), pn_point_at(q - ivec2(1, 0), size),
                       p.xyz, jump2, floor2, dx) ||
        !pn_difference(pn_point_at(q + ivec2(0, 1), size), pn_point_at(q - ivec2(0, 1), size),
                       p.xyz, jump2, floor2, dy)) {
        return false;
    }
    precise vec3 c = vec3(dx.y * dy.z - dy.y * dx.z, dx.z * dy.x - dy.z * dx.x, dx.x * dy.y - dy.x * dx.y);
    float n2 = np_dot(c, c), dx2 = np_dot(dx, dx), dy2 = np_dot(dy, dy);
    // No normal from differences that are float noise (below ~3e-6 of the point's
    // distance: copies of one sample) or parallel (sin^2 below 1e-12).
    float min_d2 = 1e-11 * np_dot(p.xyz, p.xyz);
    if (!(dx2 > min_d2 && dy2 > min_d2 && n2 > 1e-12 * dx2 * dy2)) {
        return false;
    }
    float len = sqrt(n2);
    float s = np_facing_sign(c, p.xyz);
    n = s * (c / len);
    return true;
}
