// SPDX-License-Identifier: MIT
// Pull (Kraus 2009): coarse texel (i, j) of level l is the weight-normalised 4x4
// filter (taps 1/4, 3/4, 3/4, 1/4 per axis over fine texels 2i-1 .. 2i+2) of level
// l - 1; its weight is the filtered weight sum clamped to 1. Fine texels outside the
// fine level have weight 0. In the values (not the weight) each tap's weight is divided
// by the push's depth factor with PP_PULL_TAU against the nearest of the inner 2x2 taps,
// or of all 16 where those are empty (issue 15). Each texel's colour alpha holds the share
// of its value from see-through returns; glass taps in front of a solid tap
// (pp_glass_over_solid: the room behind a window) give no value and no reference, only
// coverage (issue 15, part 2).
// Twin: src/render/ref/pullpush_ref.c (pull_level).
// Built three times: with PP_FROM_INPUT the fine level is level 0 (the inputs, weights
// from the HPR labels), and with PP_BOX too for views from STA_PULLPUSH_BOX_PULL_HEIGHT_PX
// high (the 2x2 box); without them a pyramid level. With STA_STAGED_STORES the coarse
// level goes to the staging buffers (pullpush_common.glsl).
layout(local_size_x = STA_WORKGROUP_SIZE_X, local_size_y = STA_WORKGROUP_SIZE_Y) in;
#ifndef STA_STAGED_STORES
layout(binding = STA_PULLPUSH_IMAGE_OUT_POSITION, rgba32f)
    writeonly uniform image2D u_coarse_position;
layout(binding = STA_PULLPUSH_IMAGE_OUT_COLOUR, rgba32f) writeonly uniform image2D u_coarse_colour;
#endif
layout(binding = STA_PULLPUSH_IMAGE_FINE_POSITION, rgba32f)
    readonly uniform image2D u_fine_position;
#ifdef PP_FROM_INPUT
// The input colour, RGBA32F or RGBA8.
layout(binding = STA_PULLPUSH_SAMPLER_INPUT_COLOUR) uniform sampler2D u_input_colour;
layout(binding = STA_PULLPUSH_IMAGE_LABEL, r16f) readonly uniform image2D u_label;
uniform bool u_has_label;
#else
layout(binding = STA_PULLPUSH_IMAGE_FINE_COLOUR, rgba32f) readonly uniform image2D u_fine_colour;
#endif
uniform ivec2 u_fine_size;
uniform ivec2 u_coarse_size;

#ifdef PP_BOX
// Level 1 of a view from STA_PULLPUSH_BOX_PULL_HEIGHT_PX high: Kraus' 2x2 box, the inner
// taps only (pullpush_ref.h, sta_pullpush_box_first_pull).
const float PULL_TAPS[4] = float[4](0.0, 1.0, 1.0, 0.0);
#define PP_TAP_FIRST 1
#define PP_TAP_END   3
#else
const float PULL_TAPS[4] = float[4](0.25, 0.75, 0.75, 0.25);
#define PP_TAP_FIRST 0
#define PP_TAP_END   4
#endif

void main()
{
    ivec2 q = ivec2(gl_GlobalInvocationID.xy);
    if (q.x >= u_coarse_size.x || q.y >= u_coarse_size.y) {
        return;
    }
    // The 16 fine texels and their weights (0 outside the fine level), then the depth
    // reference: the nearest depth among the inner 2x2 texels with weight (the coarse
    // texel's own footprint), else among all 16 (issue 15, eighth round).
    vec4 t[16];
    float w[16], s[16];
#ifndef PP_FROM_INPUT
    vec4 c[16]; // the fine colours, loaded once (alpha: the see-through share)
#endif
    // Coverage: the plain filtered weight sum, glass taps included.
    float sw = 0.0;
    float solid_d = 0.0; // farthest solid tap with weight
    for (int b = PP_TAP_FIRST; b < PP_TAP_END; b++) {
        for (int a = PP_TAP_FIRST; a < PP_TAP_END; a++) {
            ivec2 f = 2 * q - 1 + ivec2(a, b);
            bool inside = f.x >= 0 && f.y >= 0 && f.x < u_fine_size.x && f.y < u_fine_size.y;
            int k = 4 * b + a;
            t[k] = imageLoad(u_fine_position, f);
#ifdef PP_FROM_INPUT
            w[k] = inside ? pp_input_weight(t[k], imageLoad(u_label, f).r, u_has_label) : 0.0;
            s[k] = pp_input_share(t[k]);
#else
            w[k] = inside ? t[k].w : 0.0;
            c[k] = imageLoad(u_fine_colour, f);
            s[k] = c[k].a;
#endif
            if (w[k] > 0.0) {
                sw += PULL_TAPS[a] * PULL_TAPS[b] * w[k];
            }
            if (w[k] > 0.0 && s[k] < PP_GLASS_SHARE) {
                solid_d = max(solid_d, -t[k].z);
            }
        }
    }
    // Glass taps in front of a solid one: no value (their coverage is in sw).
    float near_d = 0.0, near_inner = 0.0;
    for (int b = PP_TAP_FIRST; b < PP_TAP_END; b++) {
        for (int a = PP_TAP_FIRST; a < PP_TAP_END; a++) {
            int k = 4 * b + a;
            if (pp_glass_over_solid(-t[k].z, s[k], solid_d)) {
                w[k] = 0.0;
            }
            if (w[k] > 0.0 && (near_d <= 0.0 || -t[k].z < near_d)) {
                near_d = -t[k].z;
            }
            bool inner = (a == 1 || a == 2) && (b == 1 || b == 2);
            if (inner && w[k] > 0.0 && (near_inner <= 0.0 || -t[k].z < near_inner)) {
                near_inner = -t[k].z;
            }
        }
    }
    if (near_inner > 0.0) {
        near_d = near_inner;
    }
    // Values: each tap's weight divided by the depth factor, so a coarse texel over a
    // depth edge keeps the near surface rather than a depth between both.
    float sv = 0.0, ss = 0.0;
    vec3 sp = vec3(0.0), sc = vec3(0.0);
    for (int b = PP_TAP_FIRST; b < PP_TAP_END; b++) {
        for (int a = PP_TAP_FIRST; a < PP_TAP_END; a++) {
            int k = 4 * b + a;
            if (w[k] > 0.0) {
                float kw = PULL_TAPS[a] * PULL_TAPS[b] * w[k];
                if (near_d > 0.0) {
                    precise float dz = (-t[k].z - near_d) / (PP_PULL_TAU * near_d);
                    precise float x = dz * dz;
                    precise float e = 1.0 + x * (1.0 + x * (0.5 + x * (1.0 / 6.0)));
                    kw = kw / e;
                }
                sv += kw;
                ss += kw * s[k];
                sp += kw * t[k].xyz;
#ifdef PP_FROM_INPUT
                sc += kw * texelFetch(u_input_colour, 2 * q - 1 + ivec2(a, b), 0).rgb;
#else
                sc += kw * c[k].rgb;
#endif
            }
        }
    }
    vec4 out_p = vec4(0.0), out_c = vec4(0.0);
    if (sw > 0.0) {
        float inv = 1.0 / sv;
        float cover = min(1.0, sw);
        out_p = vec4(sp * inv, cover);
        out_c = vec4(sc * inv, ss * inv);
    }
#ifdef STA_STAGED_STORES
    int i = q.y * u_coarse_size.x + q.x;
    u_staged_position[i] = out_p;
    u_staged_colour[i] = out_c;
#else
    imageStore(u_coarse_position, q, out_p);
    imageStore(u_coarse_colour, q, out_c);
#endif
}
