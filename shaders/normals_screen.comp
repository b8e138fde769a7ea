// SPDX-License-Identifier: MIT
// Screen-space normals (Schiffner et al., WSCG 2015): position buffer -> normal buffer.
// Twin: src/render/ref/normals_screen_ref.c (same samples, order and thresholds);
// docs/NORMALS.md. Built once per method with STA_NORMALS_METHOD set to one of
// STA_NORMALS_SCREEN_LD/_PD/_PC/_TI (defines from render/pass_normals_screen.c); TI
// links eigen3.glsl.
layout(local_size_x = STA_WORKGROUP_SIZE_X, local_size_y = STA_WORKGROUP_SIZE_Y) in;
// Inputs are read as images: on llvmpipe an image load costs about half a texel fetch.
// xyz camera space, w > 0 valid
layout(binding = STA_NORMALS_SCREEN_IMAGE_POSITION, rgba32f) readonly uniform image2D u_position;
layout(binding = STA_NORMALS_SCREEN_IMAGE_NORMAL, rgba32f) writeonly uniform image2D u_normal;
uniform ivec2 u_size;          // width, height in pixels
uniform int u_samples;         // 5, 9, 17 or 25
uniform float u_max_distance2; // squared 3D distance limit (FLT_MAX = none)

#define MIN_SIN2         1e-6
#define MIN_TI_RATIO     1e-4
#define MIN_TI_DISTANCE2 1e-30

// Sample 0 is the centre, then groups of four: two opposite pairs, the second a quarter
// turn counter-clockwise from the first (diagonals then axes, radius 1, 2, 3).
const ivec2 SCHEME[25] = ivec2[25](
    ivec2(0, 0),
    ivec2(-1, -1), ivec2(1, 1), ivec2(1, -1), ivec2(-1, 1),
    ivec2(-1, 0), ivec2(1, 0), ivec2(0, -1), ivec2(0, 1),
    ivec2(-2, -2), ivec2(2, 2), ivec2(2, -2), ivec2(-2, 2),
    ivec2(-2, 0), ivec2(2, 0), ivec2(0, -2), ivec2(0, 2),
    ivec2(-3, -3), ivec2(3, 3), ivec2(3, -3), ivec2(-3, 3),
    ivec2(-3, 0), ivec2(3, 0), ivec2(0, -3), ivec2(0, 3));
// PC's counter-clockwise fans (unit directions, times the ring radius).
const ivec2 RING8[8] = ivec2[8](ivec2(1, 0), ivec2(1, 1), ivec2(0, 1), ivec2(-1, 1),
                                ivec2(-1, 0), ivec2(-1, -1), ivec2(0, -1), ivec2(1, -1));
const ivec2 RING4[4] = ivec2[4](ivec2(1, 1), ivec2(-1, 1), ivec2(-1, -1), ivec2(1, -1));

ivec2 g_pixel;
vec3 g_centre;

float dot3(vec3 a, vec3 b)
{
    return a.x * b.x + a.y * b.y + a.z * b.z;
}

vec3 cross3(vec3 a, vec3 b)
{
    return vec3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}

// The sample at the centre + offset if inside, valid and within the distance limit.
bool fetch(ivec2 offset, out vec3 s)
{
    ivec2 q = g_pixel + offset;
    s = vec3(0.0);
    if (q.x < 0 || q.y < 0 || q.x >= u_size.x || q.y >= u_size.y) {
        return false;
    }
    vec4 t = imageLoad(u_position, q);
    s = t.xyz;
    vec3 d = s - g_centre;
    return t.w > 0.0 && dot3(d, d) <= u_max_distance2;
}

// A unit normal facing the camera, or zero when |n|^2 <= limit2.
vec4 finish(vec3 n, float limit2)
{
    float n2 = dot3(n, n);
    if (!(n2 > limit2) || !(n2 <= 3.4028234664e38)) {
        return vec4(0.0);
    }
    n = n * (1.0 / sqrt(n2));
    if (dot3(n, g_centre) > 0.0) {
        n = -n;
    }
    return vec4(n, 1.0);
}

#if STA_NORMALS_METHOD == STA_NORMALS_SCREEN_LD
vec4 estimate()
{
    vec3 r, l, u, d;
    bool hr = fetch(ivec2(1, 0), r), hl = fetch(ivec2(-1, 0), l);
    bool hu = fetch(ivec2(0, 1), u), hd = fetch(ivec2(0, -1), d);
    if (!(hr || hl) || !(hu || hd)) {
        return vec4(0.0);
    }
    vec3 dx = hr ? r - g_centre : g_centre - l;
    vec3 dy = hu ? u - g_centre : g_centre - d;
    return finish(cross3(dx, dy), MIN_SIN2 * (dot3(dx, dx) * dot3(dy, dy)));
}
#elif STA_NORMALS_METHOD == STA_NORMALS_SCREEN_PD
bool diameter(int i, out vec3 dir)
{
    vec3 a, b;
    bool ha = fetch(SCHEME[i], a);
    bool hb = fetch(SCHEME[i + 1], b);
    dir = ha && hb ? a - b : (ha ? a - g_centre : g_centre - b);
    return ha || hb;
}

vec4 estimate()
{
    vec3 n = vec3(0.0);
    float s = 0.0;
    for (int g = 0; g < (u_samples - 1) / 4; g++) {
        vec3 a, b;
        bool ha = diameter(1 + 4 * g, a);
        bool hb = diameter(3 + 4 * g, b);
        if (ha && hb) {
            n = n + cross3(a, b);
            s += dot3(a, a) * dot3(b, b);
        }
    }
    return finish(n, MIN_SIN2 * s);
}
#elif STA_NORMALS_METHOD == STA_NORMALS_SCREEN_PC
ivec2 ring_direction(int i)
{
    return u_samples == 5 ? RING4[i] : RING8[i];
}

vec4 estimate()
{
    int rings = u_samples == 5 ? 1 : (u_samples - 1) / 8;
    int count = u_samples == 5 ? 4 : 8;
    vec3 n = vec3(0.0);
    float s = 0.0;
    for (int r = 1; r <= rings; r++) {
        vec3 first;
        bool has_first = fetch(ring_direction(0) * r, first);
        bool has_prev = has_first;
        vec3 prev = first;
        for (int i = 1; i <= count; i++) {
            vec3 cur = first;
            bool has_cur = has_first;
            if (i < count) {
                has_cur = fetch(ring_direction(i) * r, cur);
            }
            if (has_prev && has_cur) {
                vec3 a = prev - g_centre, b = cur - g_centre;
                n = n + cross3(a, b);
                s += dot3(a, a) * dot3(b, b);
            }
            prev = cur;
            has_prev = has_cur;
        }
    }
    return finish(n, MIN_SIN2 * s);
}
#else // TI
vec4 estimate()
{
    float m00 = 0.0, m01 = 0.0, m02 = 0.0, m11 = 0.0, m12 = 0.0, m22 = 0.0;
    int count = 0;
    for (int i = 1; i < u_samples; i++) {
        vec3 s;
        if (!fetch(SCHEME[i], s)) {
            continue;
        }
        vec3 d = g_centre - s;
        float d2 = dot3(d, d);
        if (!(d2 > MIN_TI_DISTANCE2)) {
            continue;
        }
        float inv = 1.0 / d2;
        m00 += d.x * d.x * inv;
        m01 += d.x * d.y * inv;
        m02 += d.x * d.z * inv;
        m11 += d.y * d.y * inv;
        m12 += d.y * d.z * inv;
        m22 += d.z * d.z * inv;
        count++;
    }
    if (count < 2) {
        return vec4(0.0);
    }
    vec3 w;
    mat3 v;
    eig3_sym(mat3(m00, m01, m02, m01, m11, m12, m02, m12, m22), w, v);
    if (!(w.y > MIN_TI_RATIO * w.z)) {
        return vec4(0.0);
    }
    vec3 n = v[0];
    if (dot3(n, g_centre) > 0.0) {
        n = -n;
    }
    return vec4(n, 1.0);
}
#endif

void main()
{
    g_pixel = ivec2(gl_GlobalInvocationID.xy);
    if (g_pixel.x >= u_size.x || g_pixel.y >= u_size.y) {
        return;
    }
    vec4 c = imageLoad(u_position, g_pixel);
    vec4 result = vec4(0.0);
    if (c.w > 0.0) {
        g_centre = c.xyz;
        result = estimate();
    }
    imageStore(u_normal, g_pixel, result);
}
