// SPDX-License-Identifier: MIT
// Pyramidal normals (Bouchiba et al. 2018, 3.3), step 2: per filled pixel, a level
// from its depth (lambda = log2 of the metric radius r_n in pixels), bilinear
// interpolation inside the two nearest levels and linear interpolation between them.
// Levels >= 1 come from the normal atlas; level 0 is computed here from the filled
// points (u_points, the pull-push output), since bilinear interpolation at a pixel
// centre of level 0 reads that one texel. A texel of level >= 1 counts only where its
// tangent plane passes within u_plane_tolerance_m * 2^l * depth of the pixel's point
// (no mixing across depth discontinuities); where neither level has one, the next finer
// level that does. Two levels whose normals disagree (dot below u_coherence: a crease
// or a second surface inside the coarser level's radius) are mixed less, down to the
// finer one alone at 1 - 2 spread (issue 15, fifteenth round); the finer level itself
// fades the same way into the level below it where those two disagree (u_fine_coherence;
// issue 15, sixteenth round). Twin: src/render/ref/normals_pyramid_ref.c.
// With NP_ANCHORS (half resolution, sta_normals_pyramid_params.half_resolution) it runs
// on the anchors (i, j) * 2^u_anchor_level only (every even pixel below 1080 px of view
// height, every 4th from 1080: sta_normals_anchor_level) and writes texel (i, j) of the image
// that normals_pyramid_upsample.comp reads: xyz the normal (zero where none), w its
// tangent plane's offset dot(n, p).
layout(local_size_x = STA_WORKGROUP_SIZE_X, local_size_y = STA_WORKGROUP_SIZE_Y) in;
layout(binding = STA_NORMALS_PYRAMID_GATHER_IMAGE_NORMAL, rgba32f)
    writeonly uniform image2D u_normal;
// normals of levels >= 1 (xyz, zero where none) and their plane offsets dot(n, p) (w)
layout(binding = STA_NORMALS_PYRAMID_GATHER_IMAGE_ATLAS, rgba32f) readonly uniform image2D u_atlas;
uniform ivec2 u_size;
uniform int u_level_count;
uniform ivec2 u_level_offset[16]; // STA_PULLPUSH_MAX_LEVELS
uniform ivec2 u_level_size[16];
uniform float u_radius_px_m; // r_n * H / (2 tan(fov_y / 2)): r_px = u_radius_px_m / depth
uniform float u_near;
uniform float u_plane_tolerance_m; // per texel footprint at unit depth
uniform int u_anchor_level;        // NP_ANCHORS: anchors every 2^u_anchor_level pixels
uniform float u_jump2;             // squared jump ratio (pn_difference)
uniform float u_texel_m;           // a level-0 texel's footprint per metre of depth
uniform float u_coherence;         // 1 - spread (sta_normals_pyramid_coherence)
uniform float u_fine_coherence;    // 1 - fine_spread (sta_normals_pyramid_fine_coherence)
uniform int u_fine_min_level;      // the finest level it falls back to (the anchor level)

// The pixel's level-0 normal, computed once in main: level_normal reads it for l = 0.
// Computed inside level_normal, llvmpipe ran its five loads and jump tests in every
// call whose lanes split between level 0 and the atlas (up to three a pixel): the
// gather took 24.8-25.2 CPU ms at 1080p on the README view, 20.4-20.7 this way.
bool g_has_n0;
vec3 g_n0;

// How much of the coarser level two levels' normals may mix in, from their dot d: 1 where
// d >= u_coherence (1 - spread), falling linearly to 0 at 1 - 2 spread; 1 everywhere
// when the test is off (coherence <= -1). Twin: coherence_weight in normals_pyramid_ref.c.
float coherence_weight(float coherence, float d)
{
    if (coherence <= -1.0) {
        return 1.0;
    }
    float spread = 1.0 - coherence;
    return clamp((d - (coherence - spread)) / spread, 0.0, 1.0);
}

bool level_normal(int l, ivec2 q, vec3 p, float tolerance_m, out vec3 n)
{
    precise vec3 acc = vec3(0.0);
    if (l == 0) {
        if (g_has_n0) {
            acc += 1.0 * g_n0; // the twin's bilinear weights at a level-0 centre: 1, 0, 0, 0
        }
    } else {
        float s = float(1 << l);
        vec2 u = (vec2(q) + 0.5) / s - 0.5;
        vec2 u0 = floor(u);
        vec2 f = u - u0;
        ivec2 i0 = ivec2(u0);
        for (int b = 0; b < 2; b++) {
            for (int a = 0; a < 2; a++) {
                ivec2 t = clamp(i0 + ivec2(a, b), ivec2(0), u_level_size[l] - 1);
                vec4 m = imageLoad(u_atlas, u_level_offset[l] + t);
                if (np_dot(m.xyz, m.xyz) > 0.5 && abs(np_dot(m.xyz, p) - m.w) <= tolerance_m) {
                    float bw = (a == 1 ? f.x : 1.0 - f.x) * (b == 1 ? f.y : 1.0 - f.y);
                    acc += bw * m.xyz;
                }
            }
        }
    }
    float a2 = np_dot(acc, acc);
    n = vec3(0.0);
    if (!(a2 > 1e-12)) {
        return false;
    }
    n = acc / sqrt(a2);
    return true;
}

void main()
{
#ifdef NP_ANCHORS
    ivec2 q = ivec2(gl_GlobalInvocationID.xy) << u_anchor_level;
#else
    ivec2 q = ivec2(gl_GlobalInvocationID.xy);
#endif
    if (q.x >= u_size.x || q.y >= u_size.y) {
        return;
    }
    vec4 p = imageLoad(u_points, q);
    vec4 result = vec4(0.0);
    g_has_n0 = pn_point_normal(q, u_size, u_jump2, u_texel_m, g_n0);
    if (p.w > 0.0) {
        float depth = max(-p.z, u_near);
        float r_px = u_radius_px_m / depth;
        float t;
        int la = np_level_of_detail(r_px, u_level_count, t);
        int lb = min(la + 1, u_level_count - 1);
        vec3 na, nb;
        precise vec3 n = vec3(0.0);
        float ta = u_plane_tolerance_m * float(1 << la) * depth;
        float tb = u_plane_tolerance_m * float(1 << lb) * depth;
        bool va = level_normal(la, q, p.xyz, ta, na);
        bool vb = level_normal(lb, q, p.xyz, tb, nb);
        int lf = la - 1;
        if (va && lf >= u_fine_min_level && u_fine_coherence > -1.0) {
            // The finer level against the one below: where they disagree, la's texels
            // reached a crease or another surface that lf's do not, and la fades into lf.
            vec3 nf;
            float tf = u_plane_tolerance_m * float(1 << lf) * depth;
            if (level_normal(lf, q, p.xyz, tf, nf)) {
                float w = coherence_weight(u_fine_coherence, np_dot(na, nf));
                precise vec3 m = w * na + (1.0 - w) * nf;
                float m2 = np_dot(m, m);
                if (m2 > 1e-12) { // opposite unit normals halfway: keep la's
                    na = m / sqrt(m2);
                }
            }
        }
        bool ok = true;
        if (va && vb) {
            // The coarser level's share fades out as the two disagree, so the switch to
            // the finer level leaves no seam (coherence_weight: 1 where they agree).
            float tw = t * coherence_weight(u_coherence, np_dot(na, nb));
            n = (1.0 - tw) * na + tw * nb;
        } else if (va) {
            n = na; // the finer one where the two disagree
        } else if (vb) {
            n = nb;
        } else {
            // Both levels straddle a discontinuity here: the next finer level that has
            // a texel on the pixel's side.
            ok = false;
            for (int l = la - 1; l >= 0 && !ok; l--) {
                float tl = u_plane_tolerance_m * float(1 << l) * depth;
                ok = level_normal(l, q, p.xyz, tl, n);
            }
        }
        float n2 = np_dot(n, n);
        if (ok && n2 > 1e-12) {
            float len = sqrt(n2);
            float s = np_facing_sign(n, p.xyz);
            result = vec4(s * (n / len), 1.0);
        }
    }
#ifdef NP_ANCHORS
    imageStore(u_normal, q >> u_anchor_level,
               result.w > 0.0 ? vec4(result.xyz, np_dot(result.xyz, p.xyz)) : vec4(0.0));
#else
    imageStore(u_normal, q, result);
#endif
}
