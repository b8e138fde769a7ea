// SPDX-License-Identifier: MIT
// Oriented round splats (issue 12): the splat record (stream/gpu_splats.h) decoded, and
// the quad of a disk in its own plane. Shared by both splat paths (instanced quads and
// the geometry shader); render/ref/splat_ref.c is the C twin of the same rules.
uniform float u_splat_scale;   // runtime factor on the stored radius
uniform float u_default_radius; // metres, for points stored without a radius
uniform float u_min_radius_px; // a splat covers at least this many pixels (radius)
uniform float u_pixel_angle;   // 2 tan(fov_y / 2) / height: metres per pixel at 1 m
uniform uint u_hide_flags;     // points whose flags byte (14) has any of these: no splat

// Where a hidden point's corners go: outside the clip volume, so nothing is drawn.
const vec4 SPLAT_HIDDEN_POSITION = vec4(2.0, 2.0, 2.0, 1.0);

// Octahedral decode of the first word (two snorm16), as sta_octahedral_decode.
vec3 splat_normal(uint word)
{
    vec2 e = unpackSnorm2x16(word);
    vec3 n = vec3(e, 1.0 - abs(e.x) - abs(e.y));
    if (n.z < 0.0) {
        n.xy = (1.0 - abs(n.yx)) * vec2(n.x >= 0.0 ? 1.0 : -1.0, n.y >= 0.0 ? 1.0 : -1.0);
    }
    return normalize(n);
}

// World radius of the splat at camera-space centre `centre`: stored radius x scale (the
// default where none is stored), at least u_min_radius_px pixels so far splats stay
// visible as points.
float splat_radius(uint word, vec3 centre)
{
    float r = unpackHalf2x16(word).x;
    r = (r > 0.0 ? r : u_default_radius) * u_splat_scale;
    return max(r, u_min_radius_px * u_pixel_angle * max(-centre.z, 0.0));
}

// Tangent axes of the disk with normal n (camera space): a helper axis away from n.
void splat_axes(vec3 n, out vec3 t1, out vec3 t2)
{
    vec3 helper = abs(n.x) < 0.9 ? vec3(1.0, 0.0, 0.0) : vec3(0.0, 1.0, 0.0);
    t1 = normalize(cross(n, helper));
    t2 = cross(n, t1);
}

// Headlight Blinn-Phong as shaders/shade.comp, two-sided (a disk is lit from either
// face): the normal is flipped towards the eye.
vec3 splat_shade(vec3 albedo, vec3 n, vec3 position, vec4 light)
{
    vec3 to_eye = normalize(-position);
    float lambert = abs(dot(n, to_eye));
    return clamp(albedo * (light.x + light.y * lambert) + vec3(light.z * pow(lambert, light.w)),
                 0.0, 1.0);
}
