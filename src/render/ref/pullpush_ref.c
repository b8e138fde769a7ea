/* SPDX-License-Identifier: MIT
 * CPU twin of the pull-push pass: the same loops, weights, clamps and order of float
 * operations as shaders/pullpush_pull.comp and shaders/pullpush_push.comp.
 *
 * Based on: M. Kraus, "The pull-push algorithm revisited", GRAPP 2009; H. Bouchiba et
 * al., Eurographics 2018, section 3.2.
 */
#include "render/ref/pullpush_ref.h"

#include <math.h>
#include <stdbool.h>
#include <string.h>

/* 1D taps of the 4x4 pull (analysis) filter, fine texels 2i-1 .. 2i+2; their 2D
 * products sum to 4, the weight of a fully covered 2x2 block. */
static const float pull_taps[4] = { 0.25f, 0.75f, 0.75f, 0.25f };

/* One texel of a level: point, colour, weight. */
typedef struct texel {
    float p[3];
    float c[3];
    float w;
    float s; /* see-through share of the value (STA_PULLPUSH_GLASS_SHARE) */
} texel;

/* Where the texels of one level come from: level 0 reads the inputs (weight from the
 * label), levels >= 1 read the pyramid images. */
typedef struct level_source {
    const sta_image *position, *colour, *label;     /* level 0 (label may be NULL) */
    const sta_image *level_position, *level_colour; /* levels >= 1 */
} level_source;

static bool is_label(float label, float value)
{
    return fabsf(label - value) < 0.5f;
}

static texel fetch(const level_source *s, int x, int y)
{
    texel t;
    const float *p, *c;
    if (s->level_position) {
        p = sta_image_at(s->level_position, x, y);
        c = sta_image_at(s->level_colour, x, y);
        t.w = p[3];
        t.s = c[3];
    } else {
        p = sta_image_at(s->position, x, y);
        c = sta_image_at(s->colour, x, y);
        bool visible = !s->label || is_label(*sta_image_at(s->label, x, y), STA_LABEL_VISIBLE);
        t.w = p[3] > 0.0f && p[3] != STA_POSITION_W_MARKED && visible ? 1.0f : 0.0f;
        t.s = sta_position_see_through(p[3]) ? 1.0f : 0.0f;
    }
    for (int k = 0; k < 3; k++) {
        t.p[k] = p[k];
        t.c[k] = c[k];
    }
    return t;
}

static bool is_glass(const texel *t)
{
    return t->s >= STA_PULLPUSH_GLASS_SHARE;
}

/* The farthest depth of the solid taps with weight, or 0. */
static float solid_depth(const texel *t, float solid_d)
{
    float d = -t->p[2];
    return t->w > 0.0f && !is_glass(t) && d > solid_d ? d : solid_d;
}

/* A glass tap in front of the farthest solid tap by more than STA_PULLPUSH_GLASS_GAP (the
 * window in front of its room) gives no value. */
static bool glass_over_solid(const texel *t, float solid_d)
{
    return is_glass(t) && solid_d > -t->p[2] * (1.0f + STA_PULLPUSH_GLASS_GAP);
}

/* Stores a pyramid texel: the colour's alpha holds the see-through share s. */
static void store(const sta_image *position, const sta_image *colour, int x, int y,
                  const float p[3], const float c[3], float w, float s)
{
    float *op = sta_image_at(position, x, y);
    float *oc = sta_image_at(colour, x, y);
    for (int k = 0; k < 3; k++) {
        op[k] = p[k];
        oc[k] = c[k];
    }
    op[3] = w;
    oc[3] = s;
}

static const float zero3[3] = { 0.0f, 0.0f, 0.0f };

/* The push's and the pull's depth factor 1 + x + x^2/2 + x^3/6 (exp(x) to third order),
 * x = ((d - d_near) / (tau d_near))^2; a tap's weight is divided by it. */
static float depth_factor(float d, float near_d, float tau)
{
    float dz = (d - near_d) / (tau * near_d);
    float x = dz * dz;
    return 1.0f + x * (1.0f + x * (0.5f + x * (1.0f / 6.0f)));
}

/* Pull: coarse texel (i, j) is the 4x4 filter of the fine level; its weight is the
 * filtered weight sum clamped to 1, its values the filter normalised with each tap's
 * weight divided by the depth factor (STA_PULLPUSH_PULL_DEPTH_TAU) against the nearest
 * tap: a coarse texel over a depth edge keeps the near surface (issue 15, sixth round). */
static void pull_level(const level_source *fine, int fine_w, int fine_h, bool box,
                       const sta_image *out_p, const sta_image *out_c)
{
    /* The 2x2 box: the inner taps with weight 1 (sta_pullpush_box_first_pull). */
    static const float box_taps[4] = { 0.0f, 1.0f, 1.0f, 0.0f };
    const float *taps_1d = box ? box_taps : pull_taps;
    for (int j = 0; j < out_p->height; j++) {
        for (int i = 0; i < out_p->width; i++) {
            texel taps[16];
            /* The depth reference: the nearest depth among the inner 2x2 taps with weight
             * (the coarse texel's own footprint), else among all 16. */
            float solid_d = 0.0f; /* farthest solid tap */
            for (int b = 0; b < 4; b++) {
                for (int a = 0; a < 4; a++) {
                    int fx = 2 * i - 1 + a, fy = 2 * j - 1 + b;
                    texel *t = &taps[4 * b + a];
                    bool outer = a == 0 || a == 3 || b == 0 || b == 3;
                    if (fx < 0 || fy < 0 || fx >= fine_w || fy >= fine_h || (box && outer)) {
                        t->w = 0.0f;
                        continue;
                    }
                    *t = fetch(fine, fx, fy);
                    solid_d = solid_depth(t, solid_d);
                }
            }
            /* Glass taps in front of a solid one give no value (they keep their
             * coverage) and take no part in the reference. */
            float near_d = 0.0f, near_inner = 0.0f;
            for (int b = 0; b < 4; b++) {
                for (int a = 0; a < 4; a++) {
                    const texel *t = &taps[4 * b + a];
                    if (!(t->w > 0.0f) || glass_over_solid(t, solid_d)) {
                        continue;
                    }
                    if (near_d <= 0.0f || -t->p[2] < near_d) {
                        near_d = -t->p[2];
                    }
                    bool inner = (a == 1 || a == 2) && (b == 1 || b == 2);
                    if (inner && (near_inner <= 0.0f || -t->p[2] < near_inner)) {
                        near_inner = -t->p[2];
                    }
                }
            }
            if (near_inner > 0.0f) {
                near_d = near_inner;
            }
            float sw = 0.0f, sv = 0.0f, ss = 0.0f;
            float sp[3] = { 0.0f, 0.0f, 0.0f }, sc[3] = { 0.0f, 0.0f, 0.0f };
            for (int b = 0; b < 4; b++) {
                for (int a = 0; a < 4; a++) {
                    const texel *t = &taps[4 * b + a];
                    if (!(t->w > 0.0f)) {
                        continue;
                    }
                    float kw = taps_1d[a] * taps_1d[b] * t->w;
                    sw += kw;
                    if (glass_over_solid(t, solid_d)) {
                        continue;
                    }
                    if (near_d > 0.0f) {
                        kw = kw / depth_factor(-t->p[2], near_d, STA_PULLPUSH_PULL_DEPTH_TAU);
                    }
                    sv += kw;
                    ss += kw * t->s;
                    for (int k = 0; k < 3; k++) {
                        sp[k] += kw * t->p[k];
                        sc[k] += kw * t->c[k];
                    }
                }
            }
            if (sw > 0.0f) {
                float inv = 1.0f / sv;
                float p[3], c[3];
                for (int k = 0; k < 3; k++) {
                    p[k] = sp[k] * inv;
                    c[k] = sc[k] * inv;
                }
                store(out_p, out_c, i, j, p, c, fminf(1.0f, sw), ss * inv);
            } else {
                store(out_p, out_c, i, j, zero3, zero3, 0.0f, 0.0f);
            }
        }
    }
}

static int clamp_int(int v, int lo, int hi)
{
    return v < lo ? lo : (v > hi ? hi : v);
}

/* Push of one fine texel: bilinear 2x2 interpolation of the (already pushed) coarse
 * level, taps 3/4 and 1/4 per axis, clamped to the coarse level's edge; empty coarse
 * texels do not contribute. Then "over" compositing: w' = w + (1 - w) sw, value
 * (w v + (1 - w) sv) / w'. With glass_rule (levels >= 1), glass taps in front of
 * a solid tap (glass_over_solid) are skipped and a glass fine texel in front of them takes
 * their value. Returns w'; *out_s receives the see-through share. */
static float push_texel(const texel *fine, const level_source *coarse, int coarse_w, int coarse_h,
                        int i, int j, bool glass_rule, float out_p[3], float out_c[3], float *out_s)
{
    float sw = 0.0f, ss = 0.0f, sp[3] = { 0.0f, 0.0f, 0.0f }, sc[3] = { 0.0f, 0.0f, 0.0f };
    float w = fine->w;
    if (coarse) {
        int cx0 = ((i + 1) >> 1) - 1, cy0 = ((j + 1) >> 1) - 1;
        float wx[2], wy[2];
        wx[0] = (i & 1) ? 0.75f : 0.25f;
        wx[1] = 1.0f - wx[0];
        wy[0] = (j & 1) ? 0.75f : 0.25f;
        wy[1] = 1.0f - wy[0];
        texel taps[4];
        float solid_d = 0.0f;
        for (int k = 0; k < 4; k++) {
            int a = k & 1, b = k >> 1;
            taps[k] = fetch(coarse, clamp_int(cx0 + a, 0, coarse_w - 1),
                            clamp_int(cy0 + b, 0, coarse_h - 1));
            solid_d = solid_depth(&taps[k], solid_d);
        }
        /* Glass taps in front of a solid one are dropped (weight 0 from here on). */
        float near_d = 0.0f; /* nearest depth among the non-empty taps (the fallback) */
        for (int k = 0; k < 4; k++) {
            if (glass_rule && glass_over_solid(&taps[k], solid_d)) {
                taps[k].w = 0.0f;
            }
            float d = -taps[k].p[2];
            if (taps[k].w > 0.0f && (near_d <= 0.0f || d < near_d)) {
                near_d = d;
            }
        }
        /* A glass texel in front of them takes the coarse value (level 0 then interpolates
         * no glass beside the room, without this test per pixel). */
        if (glass_rule && glass_over_solid(fine, solid_d)) {
            w = 0.0f;
        }
        /* The reference: the depth of the 9/16 tap (the coarse texel holding the fine
         * one) where its footprint is fully covered (w = 1), else the nearest: a sparse
         * near surface leaves partly covered coarse texels around its own holes, and those
         * holes then stay on it rather than take the denser surface behind (issue 15,
         * eighteenth round). */
        int own = ((i & 1) ? 0 : 1) + ((j & 1) ? 0 : 2);
        if (taps[own].w >= 1.0f) {
            near_d = -taps[own].p[2];
        }
        for (int k = 0; k < 4; k++) {
            const texel *t = &taps[k];
            if (t->w > 0.0f) {
                float kw = wx[k & 1] * wy[k >> 1] * t->w;
                if (near_d > 0.0f) {
                    kw = kw / depth_factor(-t->p[2], near_d, STA_PULLPUSH_DEPTH_TAU);
                }
                sw += kw;
                ss += kw * t->s;
                for (int c = 0; c < 3; c++) {
                    sp[c] += kw * t->p[c];
                    sc[c] += kw * t->c[c];
                }
            }
        }
    }
    float nw = fminf(1.0f, w + (1.0f - w) * sw);
    if (!(nw > 0.0f)) {
        memcpy(out_p, zero3, sizeof(zero3));
        memcpy(out_c, zero3, sizeof(zero3));
        *out_s = 0.0f;
        return 0.0f;
    }
    float inv = 1.0f / nw;
    float ns = (1.0f - w) * ss;
    if (w > 0.0f) {
        ns = w * fine->s + ns;
    }
    *out_s = ns * inv;
    for (int k = 0; k < 3; k++) {
        float np = (1.0f - w) * sp[k], nc = (1.0f - w) * sc[k];
        if (w > 0.0f) {
            np = w * fine->p[k] + np;
            nc = w * fine->c[k] + nc;
        }
        out_p[k] = np * inv;
        out_c[k] = nc * inv;
    }
    return nw;
}

int sta_pullpush_level_count(int width_px, int height_px)
{
    int size = width_px > height_px ? width_px : height_px;
    if (size < 1 || size > (1 << (STA_PULLPUSH_MAX_LEVELS - 1))) {
        return 0;
    }
    int count = 1;
    while ((1 << (count - 1)) < size) {
        count++;
    }
    return count;
}

void sta_pullpush_levels_release(sta_pullpush_levels *levels)
{
    for (int l = 0; l < STA_PULLPUSH_MAX_LEVELS; l++) {
        sta_image_release(&levels->position[l]);
        sta_image_release(&levels->colour[l]);
    }
    levels->count = 0;
}

static bool same_size(const sta_image *a, int w, int h, int min_channels)
{
    return a && a->width == w && a->height == h && a->channels >= min_channels;
}

sta_status sta_pullpush_ref(const sta_view_params *view, const sta_image *position,
                            const sta_image *colour, const sta_image *label,
                            sta_image *out_position, sta_image *out_colour,
                            sta_pullpush_levels *out_levels, sta_error *err)
{
    int w = view->width_px, h = view->height_px;
    int count = sta_pullpush_level_count(w, h);
    if (count == 0) {
        return sta_fail(err, STA_ERR_ARG, "pull-push: view %dx%d is out of range (1..32768)", w, h);
    }
    if (!same_size(position, w, h, 4) || !same_size(colour, w, h, 3) ||
        (label && !same_size(label, w, h, 1)) || !same_size(out_position, w, h, 4) ||
        !same_size(out_colour, w, h, 4)) {
        return sta_fail(err, STA_ERR_ARG,
                        "pull-push: an image does not match the view %dx%d (position and outputs "
                        "need 4 channels, colour 3 or 4, label 1)",
                        w, h);
    }
    sta_pullpush_levels local = { 0 };
    sta_pullpush_levels *levels = out_levels ? out_levels : &local;
    sta_pullpush_levels_release(levels);
    sta_status status = STA_OK;
    for (int l = 1; l < count && status == STA_OK; l++) {
        int lw = sta_pullpush_level_size(w, l), lh = sta_pullpush_level_size(h, l);
        status = sta_image_init(&levels->position[l], lw, lh, 4, err);
        if (status == STA_OK) {
            status = sta_image_init(&levels->colour[l], lw, lh, 4, err);
        }
    }
    if (status != STA_OK) {
        sta_pullpush_levels_release(levels);
        return status;
    }
    levels->count = count;

    level_source input = { position, colour, label, NULL, NULL };
    // Pull: level l from level l - 1 (level 0 = the inputs).
    for (int l = 1; l < count; l++) {
        level_source fine = input;
        if (l > 1) {
            fine = (level_source){ NULL, NULL, NULL, &levels->position[l - 1],
                                   &levels->colour[l - 1] };
        }
        pull_level(&fine, sta_pullpush_level_size(w, l - 1), sta_pullpush_level_size(h, l - 1),
                   l == 1 && sta_pullpush_box_first_pull(h), &levels->position[l],
                   &levels->colour[l]);
    }
    // Push: level l from level l + 1, in place, down to level 1.
    for (int l = count - 2; l >= 1; l--) {
        const sta_image *lp = &levels->position[l], *lc = &levels->colour[l];
        level_source self = { NULL, NULL, NULL, lp, lc };
        level_source coarse = { NULL, NULL, NULL, &levels->position[l + 1],
                                &levels->colour[l + 1] };
        for (int j = 0; j < lp->height; j++) {
            for (int i = 0; i < lp->width; i++) {
                texel t = fetch(&self, i, j);
                float p[3], c[3], ts;
                float nw = push_texel(&t, &coarse, levels->position[l + 1].width,
                                      levels->position[l + 1].height, i, j, true, p, c, &ts);
                store(lp, lc, i, j, p, c, nw, ts);
            }
        }
    }
    // Level 0: the inputs over the pushed level 1, then the HPR background restored.
    level_source coarse1 = { 0 };
    if (count > 1) {
        coarse1 = (level_source){ NULL, NULL, NULL, &levels->position[1], &levels->colour[1] };
    }
    for (int j = 0; j < h; j++) {
        for (int i = 0; i < w; i++) {
            texel t = fetch(&input, i, j);
            float p[3], c[3], ts;
            float nw = push_texel(
                &t, count > 1 ? &coarse1 : NULL, count > 1 ? levels->position[1].width : 0,
                count > 1 ? levels->position[1].height : 0, i, j, false, p, c, &ts);
            if (label && is_label(*sta_image_at(label, i, j), STA_LABEL_BACKGROUND)) {
                store(out_position, out_colour, i, j, zero3, zero3, 0.0f, 0.0f);
            } else {
                store(out_position, out_colour, i, j, p, c, nw, 0.0f);
            }
            float *oc = sta_image_at(out_colour, i, j); // RGBA8 (screen_space.h)
            for (int k = 0; k < 3; k++) {
                oc[k] = sta_unorm8(oc[k]);
            }
            oc[3] = 0.0f;
        }
    }
    sta_pullpush_levels_release(&local);
    return STA_OK;
}
