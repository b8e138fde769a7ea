// SPDX-License-Identifier: MIT
// Push (Kraus 2009): fine texel q of level l takes the bilinear interpolation of the
// pushed level l + 1 (taps 3/4 and 1/4 per axis, 9/16 3/16 3/16 1/16 in 2D, coordinates
// clamped to the coarse level, empty coarse texels skipped) under its own value by
// "over" compositing: w' = w + (1 - w) sw, value (w v + (1 - w) sv) / w'. Each tap's
// weight is divided by 1 + x + x^2/2 + x^3/6 (exp(x) to third order; GLSL's exp differs
// from the twin's expf), x = ((d - d_near) / (PP_DEPTH_TAU d_near))^2, d_near the depth
// of the 9/16 tap where its coverage is full (w = 1), else the nearest tap depth: a hole
// at an outline takes one surface, not a depth between both.
// Glass (issue 15, part 2), levels >= 1 only: glass taps in front of a solid coarse tap
// (pp_glass_over_solid; the see-through share is the colour's alpha) are skipped, and a glass
// fine texel in front of them takes their value; the level-0 push has no test (it cost 5-6
// CPU ms at 1080p, docs/PULLPUSH.md).
// Twin: src/render/ref/pullpush_ref.c (push_texel). Built twice: with PP_LEVEL0 the
// fine level is the input, the result goes to the output textures and the background
// found by HPR is restored and the colour goes to the RGBA8 filled colour with alpha 0
// (screen_space.h); without it a pyramid level is updated in place. With STA_STAGED_STORES
// the RGBA32F results go to the staging buffers (pullpush_common.glsl), which the pass
// copies into the level (or the output position) after the dispatch.
layout(local_size_x = STA_WORKGROUP_SIZE_X, local_size_y = STA_WORKGROUP_SIZE_Y) in;
#ifdef PP_LEVEL0
// Level 0: the outputs.
#ifndef STA_STAGED_STORES
layout(binding = STA_PULLPUSH_IMAGE_OUT_POSITION, rgba32f) writeonly uniform image2D u_position;
#endif
layout(binding = STA_PULLPUSH_IMAGE_OUT_COLOUR, rgba8) writeonly uniform image2D u_colour;
layout(binding = STA_PULLPUSH_IMAGE_FINE_POSITION, rgba32f)
    readonly uniform image2D u_input_position;
// The input colour, RGBA32F or RGBA8.
layout(binding = STA_PULLPUSH_SAMPLER_INPUT_COLOUR) uniform sampler2D u_input_colour;
layout(binding = STA_PULLPUSH_IMAGE_LABEL, r16f) readonly uniform image2D u_label;
uniform bool u_has_label;
#else
// Level l, updated in place.
layout(binding = STA_PULLPUSH_IMAGE_OUT_POSITION, rgba32f) uniform image2D u_position;
layout(binding = STA_PULLPUSH_IMAGE_OUT_COLOUR, rgba32f) uniform image2D u_colour;
#endif
// The pushed level l + 1.
layout(binding = STA_PULLPUSH_IMAGE_COARSE_POSITION, rgba32f)
    readonly uniform image2D u_coarse_position;
layout(binding = STA_PULLPUSH_IMAGE_COARSE_COLOUR, rgba32f)
    readonly uniform image2D u_coarse_colour;
uniform ivec2 u_size;
uniform ivec2 u_coarse_size;
uniform bool u_has_coarse; // false only for a 1 x 1 view

void main()
{
    ivec2 q = ivec2(gl_GlobalInvocationID.xy);
    if (q.x >= u_size.x || q.y >= u_size.y) {
        return;
    }
#ifdef PP_LEVEL0
    vec4 t0 = imageLoad(u_input_position, q);
    float label = imageLoad(u_label, q).r;
    float fw = pp_input_weight(t0, label, u_has_label);
    vec3 fc = texelFetch(u_input_colour, q, 0).rgb;
    float fs = 0.0; // not stored at level 0
#else
    vec4 t0 = imageLoad(u_position, q);
    float fw = t0.w;
    vec4 fc4 = imageLoad(u_colour, q);
    vec3 fc = fc4.rgb;
    float fs = fc4.a;
#endif
    vec3 fp = t0.xyz;
    float sw = 0.0, ss = 0.0;
    vec3 sp = vec3(0.0), sc = vec3(0.0);
    if (u_has_coarse) {
        ivec2 c0 = ((q + 1) >> 1) - 1;
        vec2 wx, wy;
        wx[0] = (q.x & 1) != 0 ? 0.75 : 0.25;
        wx[1] = 1.0 - wx[0];
        wy[0] = (q.y & 1) != 0 ? 0.75 : 0.25;
        wy[1] = 1.0 - wy[0];
        vec4 tp[4];
        for (int k = 0; k < 4; k++) {
            ivec2 cq = clamp(c0 + ivec2(k & 1, k >> 1), ivec2(0), u_coarse_size - 1);
            tp[k] = imageLoad(u_coarse_position, cq);
        }
#ifndef PP_LEVEL0
        vec4 tc[4]; // the coarse colours, alpha the see-through share
        float solid_d = 0.0; // farthest solid tap with weight
        for (int k = 0; k < 4; k++) {
            ivec2 cq = clamp(c0 + ivec2(k & 1, k >> 1), ivec2(0), u_coarse_size - 1);
            tc[k] = imageLoad(u_coarse_colour, cq);
            if (tp[k].w > 0.0 && tc[k].a < PP_GLASS_SHARE) {
                solid_d = max(solid_d, -tp[k].z);
            }
        }
        for (int k = 0; k < 4; k++) {
            if (pp_glass_over_solid(-tp[k].z, tc[k].a, solid_d)) {
                tp[k].w = 0.0; // glass in front of a solid tap
            }
        }
        // A glass texel in front of them takes the coarse value (level 0 then
        // interpolates no glass beside the room, without this test per pixel).
        if (pp_glass_over_solid(-fp.z, fs, solid_d)) {
            fw = 0.0;
        }
#endif
        float near_d = 0.0; // nearest depth among the non-empty taps (the fallback)
        for (int k = 0; k < 4; k++) {
            float d = -tp[k].z;
            if (tp[k].w > 0.0 && (near_d <= 0.0 || d < near_d)) {
                near_d = d;
            }
        }
        // The reference is the depth of the tap of weight 9/16, the coarse texel that
        // holds q, where its footprint is fully covered (w = 1; issue 15, eighth and
        // eighteenth rounds): a hole beside a wall stays on the wall even where a
        // neighbouring coarse texel holds a nearer tree, and a partly covered coarse texel
        // (around the holes of a sparse near surface) takes the nearest tap, so those holes
        // stay on the near surface rather than take the denser one behind it.
        // (Selected with constant indices: a per-pixel index into tp costs llvmpipe a
        // trip through memory, +13 % of the pass.)
        bool odd_x = (q.x & 1) != 0;
        vec4 own = (q.y & 1) != 0 ? (odd_x ? tp[0] : tp[1]) : (odd_x ? tp[2] : tp[3]);
        if (own.w >= 1.0) {
            near_d = -own.z;
        }
        for (int k = 0; k < 4; k++) {
            if (tp[k].w > 0.0) {
                float kw = wx[k & 1] * wy[k >> 1] * tp[k].w;
                if (near_d > 0.0) {
                    precise float dz = (-tp[k].z - near_d) / (PP_DEPTH_TAU * near_d);
                    precise float x = dz * dz;
                    precise float e = 1.0 + x * (1.0 + x * (0.5 + x * (1.0 / 6.0)));
                    kw = kw / e;
                }
                sw += kw;
                sp += kw * tp[k].xyz;
#ifdef PP_LEVEL0
                // Level 0: the colour of the taps with weight only (the share is not stored).
                ivec2 cq = clamp(c0 + ivec2(k & 1, k >> 1), ivec2(0), u_coarse_size - 1);
                sc += kw * imageLoad(u_coarse_colour, cq).rgb;
#else
                ss += kw * tc[k].a;
                sc += kw * tc[k].rgb;
#endif
            }
        }
    }
    float nw = min(1.0, fw + (1.0 - fw) * sw);
    vec4 out_p = vec4(0.0), out_c = vec4(0.0);
    if (nw > 0.0) {
        float inv = 1.0 / nw;
        vec3 np = (1.0 - fw) * sp, nc = (1.0 - fw) * sc;
        float ns = (1.0 - fw) * ss;
        if (fw > 0.0) {
            np = fw * fp + np;
            nc = fw * fc + nc;
            ns = fw * fs + ns;
        }
        out_p = vec4(np * inv, nw);
        out_c = vec4(nc * inv, ns * inv);
    }
#ifdef PP_LEVEL0
    if (u_has_label && pp_is_label(label, PP_LABEL_BACKGROUND)) {
        out_p = vec4(0.0);
        out_c = vec4(0.0);
    }
    // A marked (volumetric) point keeps its own colour in the alpha for the overlay
    // (screen_space.h; the input colour is fetched here anyway).
    out_c.a = 0.0; // 1 only where the overlay draws a marked point (volumetric_window.glsl)
#endif
#ifdef STA_STAGED_STORES
    int i = q.y * u_size.x + q.x;
    u_staged_position[i] = out_p;
#ifdef PP_LEVEL0
    imageStore(u_colour, q, out_c); // RGBA8: stored as fast as a float (gl_staged.h)
#else
    u_staged_colour[i] = out_c;
#endif
#else
    imageStore(u_position, q, out_p);
    imageStore(u_colour, q, out_c);
#endif
}
