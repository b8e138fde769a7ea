/* SPDX-License-Identifier: MIT
 * Test encoder: point14 family, layered chunks (compressor 3), item versions 3 and 4:
 * POINT14, RGB14, RGBNIR14, WAVEPACKET14, BYTE14 (see lazenc.h).
 *
 * Design: written from the LASzip writer's behaviour (what it codes, in which layer,
 * with which model), independently of the decoder in src/io/laz_point14.c, so the
 * two check each other. Every layer is its own range-coded stream in its own buffer;
 * at the chunk's end the writer emits the point count, the byte count of each layer
 * (0 for a layer whose values never changed in the chunk, although its symbols were
 * coded) and the layers. Each item keeps four scanner-channel contexts; the POINT14
 * item decides the channel and the other items follow it. Version 3 and 4 differ
 * only in the other items: on a switch to a context already used in the chunk,
 * version 3 keeps predicting from (and overwriting) the previous context's last
 * record, version 4 uses the new context's own last record.
 * All models are created up front (test code: memory is not a concern); a model that
 * LASzip creates on first use starts in the same state as one reset at context start.
 *
 * Based on: the LASzip writer's published behaviour (LAS 1.4 layered compressor,
 * point14 items versions 3 and 4, including the 2017 context-switch fix of version 4).
 */
#include <stdlib.h>
#include <string.h>

#include "io/laz_predict.h"
#include "lazenc.h"

enum {
    N_CTX = 4,
    P14_SIZE = 30,
    WP_SIZE = 29,
    P14_NLAYERS = 9,
    GT_MULTI = 500,
    GT_MINUS = -10,
    GT_FULL = GT_MULTI - GT_MINUS + 1, // 511: a new sequence starts
    GT_TOTAL = GT_MULTI - GT_MINUS + 5,
};

// Return class of (n, r) (LASzip's 6-context map).
static const uint8_t class_of[16][16] = {
    { 0, 1, 2, 3, 4, 5, 3, 4, 4, 5, 5, 5, 5, 5, 5, 5 },
    { 1, 0, 1, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3 },
    { 2, 1, 2, 4, 4, 4, 4, 4, 4, 4, 4, 3, 3, 3, 3, 3 },
    { 3, 3, 4, 5, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4 },
    { 4, 3, 4, 4, 5, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4 },
    { 5, 3, 4, 4, 4, 5, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4 },
    { 3, 3, 4, 4, 4, 4, 5, 4, 4, 4, 4, 4, 4, 4, 4, 4 },
    { 4, 3, 4, 4, 4, 4, 4, 5, 4, 4, 4, 4, 4, 4, 4, 4 },
    { 4, 3, 4, 4, 4, 4, 4, 4, 5, 4, 4, 4, 4, 4, 4, 4 },
    { 5, 3, 4, 4, 4, 4, 4, 4, 4, 5, 4, 4, 4, 4, 4, 4 },
    { 5, 3, 4, 4, 4, 4, 4, 4, 4, 4, 5, 4, 4, 4, 4, 4 },
    { 5, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 5, 5, 4, 4, 4 },
    { 5, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 5, 5, 5, 4, 4 },
    { 5, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 4, 5, 5, 5, 4 },
    { 5, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 5, 5, 5 },
    { 5, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 5, 5 },
};

static uint16_t ld16(const uint8_t *p)
{
    return (uint16_t)(p[0] | (p[1] << 8));
}

static uint32_t ld32(const uint8_t *p)
{
    return (uint32_t)p[0] | ((uint32_t)p[1] << 8) | ((uint32_t)p[2] << 16) | ((uint32_t)p[3] << 24);
}

static uint64_t ld64(const uint8_t *p)
{
    return (uint64_t)ld32(p) | ((uint64_t)ld32(p + 4) << 32);
}

static double ld_f64(const uint8_t *p)
{
    uint64_t bits = ld64(p);
    double v;
    memcpy(&v, &bits, sizeof(v));
    return v;
}

static uint32_t fold8(int32_t diff)
{
    return (uint32_t)diff & 255u;
}

static int32_t clamp8(int32_t v)
{
    return v < 0 ? 0 : v > 255 ? 255 : v;
}

// One output layer.
typedef struct out_layer {
    lazenc_buf buf;
    lazenc_arith ac;
    bool changed; // some value differed from its prediction source in this chunk
} out_layer;

// ---- POINT14 ----

typedef struct pt_ctx {
    bool unused;
    uint8_t last[P14_SIZE]; // raw POINT14 bytes of the context's last record
    bool last_gps_change;
    uint16_t last_intensity[8];
    int32_t last_z[8];
    median5 dx[12], dy[12];
    uint32_t gt_last, gt_next;
    uint64_t gt[4];
    int32_t gt_diff[4];
    int32_t gt_extreme[4];
    sta_laz_model *changed[8], *channel, *n_model[16], *r_model[16], *r_same;
    sta_laz_model *cls[64], *flags[64], *user[64], *gt_multi, *gt_0diff;
    sta_laz_ic ic_dx, ic_dy, ic_z, ic_int, ic_angle, ic_source, ic_gt;
} pt_ctx;

typedef struct pt_enc {
    uint32_t current;
    pt_ctx ctx[N_CTX];
    out_layer *L; // P14_NLAYERS layers
} pt_enc;

static void pt_create(pt_ctx *c)
{
    for (int i = 0; i < 8; i++) {
        c->changed[i] = lazenc_model(128);
    }
    c->channel = lazenc_model(3);
    for (int i = 0; i < 16; i++) {
        c->n_model[i] = lazenc_model(16);
        c->r_model[i] = lazenc_model(16);
    }
    c->r_same = lazenc_model(13);
    for (int i = 0; i < 64; i++) {
        c->cls[i] = lazenc_model(256);
        c->flags[i] = lazenc_model(64);
        c->user[i] = lazenc_model(256);
    }
    c->gt_multi = lazenc_model(GT_TOTAL);
    c->gt_0diff = lazenc_model(5);
    lazenc_ic_init(&c->ic_dx, 32, 2);
    lazenc_ic_init(&c->ic_dy, 32, 22);
    lazenc_ic_init(&c->ic_z, 32, 20);
    lazenc_ic_init(&c->ic_int, 16, 4);
    lazenc_ic_init(&c->ic_angle, 16, 2);
    lazenc_ic_init(&c->ic_source, 16, 1);
    lazenc_ic_init(&c->ic_gt, 32, 9);
}

static void pt_destroy(pt_ctx *c)
{
    for (int i = 0; i < 8; i++) {
        sta_laz_model_destroy(c->changed[i]);
    }
    sta_laz_model_destroy(c->channel);
    for (int i = 0; i < 16; i++) {
        sta_laz_model_destroy(c->n_model[i]);
        sta_laz_model_destroy(c->r_model[i]);
    }
    sta_laz_model_destroy(c->r_same);
    for (int i = 0; i < 64; i++) {
        sta_laz_model_destroy(c->cls[i]);
        sta_laz_model_destroy(c->flags[i]);
        sta_laz_model_destroy(c->user[i]);
    }
    sta_laz_model_destroy(c->gt_multi);
    sta_laz_model_destroy(c->gt_0diff);
    sta_laz_ic *ics[] = { &c->ic_dx,    &c->ic_dy,     &c->ic_z, &c->ic_int,
                          &c->ic_angle, &c->ic_source, &c->ic_gt };
    for (size_t i = 0; i < sizeof(ics) / sizeof(ics[0]); i++) {
        sta_laz_ic_release(ics[i]);
    }
}

// First use of context `c` in the chunk: fresh models, predictors from `rec`.
static void pt_start(pt_ctx *c, const uint8_t *rec)
{
    for (int i = 0; i < 8; i++) {
        sta_laz_model_reset(c->changed[i]);
    }
    sta_laz_model_reset(c->channel);
    for (int i = 0; i < 16; i++) {
        sta_laz_model_reset(c->n_model[i]);
        sta_laz_model_reset(c->r_model[i]);
    }
    sta_laz_model_reset(c->r_same);
    for (int i = 0; i < 64; i++) {
        sta_laz_model_reset(c->cls[i]);
        sta_laz_model_reset(c->flags[i]);
        sta_laz_model_reset(c->user[i]);
    }
    sta_laz_model_reset(c->gt_multi);
    sta_laz_model_reset(c->gt_0diff);
    sta_laz_ic_reset(&c->ic_dx);
    sta_laz_ic_reset(&c->ic_dy);
    sta_laz_ic_reset(&c->ic_z);
    sta_laz_ic_reset(&c->ic_int);
    sta_laz_ic_reset(&c->ic_angle);
    sta_laz_ic_reset(&c->ic_source);
    sta_laz_ic_reset(&c->ic_gt);
    for (int i = 0; i < 12; i++) {
        sta_laz_median_init(&c->dx[i]);
        sta_laz_median_init(&c->dy[i]);
    }
    for (int i = 0; i < 8; i++) {
        c->last_z[i] = (int32_t)ld32(rec + 8);
        c->last_intensity[i] = ld16(rec + 12);
    }
    c->gt_last = c->gt_next = 0;
    memset(c->gt_diff, 0, sizeof(c->gt_diff));
    memset(c->gt_extreme, 0, sizeof(c->gt_extreme));
    c->gt[0] = ld64(rec + 22);
    c->gt[1] = c->gt[2] = c->gt[3] = 0;
    memcpy(c->last, rec, P14_SIZE);
    c->last_gps_change = false;
    c->unused = false;
}

// Whether `bits` - `from` fits in an int32 (as a 64-bit integer difference).
static bool diff_fits(uint64_t bits, uint64_t from, int32_t *out)
{
    int64_t d = (int64_t)(bits - from);
    *out = (int32_t)d;
    return d == (int64_t)*out;
}

static void gt_multiple(pt_ctx *c, lazenc_arith *a, uint32_t sym, int32_t multi, int32_t diff,
                        uint32_t ic_ctx, bool extreme)
{
    uint32_t s = c->gt_last;
    lazenc_encode_symbol(a, c->gt_multi, sym);
    lazenc_ic_encode(&c->ic_gt, a, (int32_t)((uint32_t)multi * (uint32_t)c->gt_diff[s]), diff,
                     ic_ctx);
    if (extreme) {
        if (++c->gt_extreme[s] > 3) {
            c->gt_diff[s] = diff;
            c->gt_extreme[s] = 0;
        }
    }
}

static void gt_write(pt_ctx *c, lazenc_arith *a, uint64_t t)
{
    for (;;) {
        uint32_t s = c->gt_last;
        int32_t diff;
        bool fits = diff_fits(t, c->gt[s], &diff);
        if (fits && c->gt_diff[s] == 0) {
            lazenc_encode_symbol(a, c->gt_0diff, 0);
            lazenc_ic_encode(&c->ic_gt, a, 0, diff, 0);
            c->gt_diff[s] = diff;
            c->gt_extreme[s] = 0;
            c->gt[s] = t;
            return;
        }
        if (fits) {
            float f = (float)diff / (float)c->gt_diff[s];
            if (f > 1e6f) {
                f = 1e6f; // beyond any multiplier coded directly
            } else if (f < -1e6f) {
                f = -1e6f;
            }
            int32_t multi = f >= 0 ? (int32_t)(f + 0.5f) : (int32_t)(f - 0.5f);
            if (multi == 1) {
                lazenc_encode_symbol(a, c->gt_multi, 1);
                lazenc_ic_encode(&c->ic_gt, a, c->gt_diff[s], diff, 1);
                c->gt_extreme[s] = 0;
            } else if (multi > 0 && multi < GT_MULTI) {
                gt_multiple(c, a, (uint32_t)multi, multi, diff, multi < 10 ? 2 : 3, false);
            } else if (multi >= GT_MULTI) {
                gt_multiple(c, a, GT_MULTI, GT_MULTI, diff, 4, true);
            } else if (multi < 0 && multi > GT_MINUS) {
                gt_multiple(c, a, (uint32_t)(GT_MULTI - multi), multi, diff, 5, false);
            } else if (multi < 0) {
                gt_multiple(c, a, GT_MULTI - GT_MINUS, GT_MINUS, diff, 6, true);
            } else {
                gt_multiple(c, a, 0, 0, diff, 7, true);
            }
            c->gt[s] = t;
            return;
        }
        // A jump: another of the four sequences, or a new one.
        uint32_t other = 0;
        for (uint32_t i = 1; i < 4 && !other; i++) {
            int32_t unused;
            if (diff_fits(t, c->gt[(s + i) & 3], &unused)) {
                other = i;
            }
        }
        sta_laz_model *m = c->gt_diff[s] == 0 ? c->gt_0diff : c->gt_multi;
        uint32_t base = c->gt_diff[s] == 0 ? 1 : GT_FULL;
        if (other) {
            lazenc_encode_symbol(a, m, base + other);
            c->gt_last = (s + other) & 3;
            continue;
        }
        lazenc_encode_symbol(a, m, base);
        lazenc_ic_encode(&c->ic_gt, a, (int32_t)(uint32_t)(c->gt[s] >> 32),
                         (int32_t)(uint32_t)(t >> 32), 8);
        lazenc_write_u32(a, (uint32_t)t);
        c->gt_next = (c->gt_next + 1) & 3;
        c->gt_last = c->gt_next;
        c->gt_diff[c->gt_last] = 0;
        c->gt_extreme[c->gt_last] = 0;
        c->gt[c->gt_last] = t;
        return;
    }
}

static void pt_encode(pt_enc *e, const uint8_t *rec)
{
    out_layer *L = e->L;
    pt_ctx *cur = &e->ctx[e->current];
    const uint8_t *last = cur->last;
    uint32_t last_r0 = last[14] & 15;
    uint32_t last_n0 = last[14] >> 4;
    uint32_t lpr = (last_r0 == 1 ? 1u : 0u) + (last_r0 >= last_n0 ? 2u : 0u) +
                   (cur->last_gps_change ? 4u : 0u);
    uint32_t channel = (rec[15] >> 4) & 3;
    if (channel != e->current && !e->ctx[channel].unused) {
        last = e->ctx[channel].last;
    }
    bool source_change = ld16(rec + 20) != ld16(last + 20);
    bool gps_change = ld_f64(rec + 22) != ld_f64(last + 22); // compared as doubles
    bool angle_change = ld16(rec + 18) != ld16(last + 18);
    uint32_t last_n = last[14] >> 4;
    uint32_t last_r = last[14] & 15;
    uint32_t n = rec[14] >> 4;
    uint32_t r = rec[14] & 15;
    uint32_t changed = (channel != e->current ? 64u : 0u) | (source_change ? 32u : 0u) |
                       (gps_change ? 16u : 0u) | (angle_change ? 8u : 0u) | (n != last_n ? 4u : 0u);
    if (r != last_r) {
        changed |= r == ((last_r + 1) & 15) ? 1u : r == ((last_r + 15) & 15) ? 2u : 3u;
    }
    lazenc_arith *xy = &L[0].ac;
    lazenc_encode_symbol(xy, cur->changed[lpr], changed);
    if (changed & 64) {
        lazenc_encode_symbol(xy, cur->channel, (channel + N_CTX - e->current - 1) % N_CTX);
        if (e->ctx[channel].unused) {
            pt_start(&e->ctx[channel], cur->last);
            last = e->ctx[channel].last;
        }
        e->current = channel;
    }
    pt_ctx *c = &e->ctx[e->current];
    if (changed & 4) {
        lazenc_encode_symbol(xy, c->n_model[last_n], n);
    }
    if ((changed & 3) == 3) {
        if (gps_change) {
            lazenc_encode_symbol(xy, c->r_model[last_r], r);
        } else {
            lazenc_encode_symbol(xy, c->r_same, (r + 16 - last_r - 2) & 15);
        }
    }
    uint32_t m = class_of[n][r];
    uint32_t level = n > r ? n - r : r - n;
    level = level > 7 ? 7 : level;
    uint32_t cpr = (r == 1 ? 1u : 0u) + (r >= n ? 2u : 0u);
    uint32_t single = n == 1 ? 1u : 0u;
    uint32_t at = (m << 1) | (gps_change ? 1u : 0u);

    int32_t dx = (int32_t)(ld32(rec) - ld32(last));
    lazenc_ic_encode(&c->ic_dx, xy, c->dx[at].v[2], dx, single);
    sta_laz_median_add(&c->dx[at], dx);
    uint32_t k = c->ic_dx.k;
    int32_t dy = (int32_t)(ld32(rec + 4) - ld32(last + 4));
    lazenc_ic_encode(&c->ic_dy, xy, c->dy[at].v[2], dy, single + (k < 20 ? (k & ~1u) : 20));
    sta_laz_median_add(&c->dy[at], dy);

    k = (c->ic_dx.k + c->ic_dy.k) / 2;
    int32_t z = (int32_t)ld32(rec + 8);
    lazenc_ic_encode(&c->ic_z, &L[1].ac, c->last_z[level], z, single + (k < 18 ? (k & ~1u) : 18));
    c->last_z[level] = z;

    uint32_t cls = rec[16];
    L[2].changed |= cls != last[16];
    lazenc_encode_symbol(&L[2].ac, c->cls[((last[16] & 31u) << 1) + (cpr == 3 ? 1u : 0u)], cls);

    // Flags: edge (bit 5), scan direction (bit 4), classification flags (bits 0-3).
    uint32_t flags = (uint32_t)((rec[15] >> 7) << 5 | ((rec[15] >> 6) & 1) << 4 | (rec[15] & 15));
    uint32_t last_flags =
        (uint32_t)((last[15] >> 7) << 5 | ((last[15] >> 6) & 1) << 4 | (last[15] & 15));
    L[3].changed |= flags != last_flags;
    lazenc_encode_symbol(&L[3].ac, c->flags[last_flags], flags);

    uint16_t intensity = ld16(rec + 12);
    L[4].changed |= intensity != ld16(last + 12);
    uint32_t ia = (cpr << 1) | (gps_change ? 1u : 0u);
    lazenc_ic_encode(&c->ic_int, &L[4].ac, c->last_intensity[ia], intensity, cpr);
    c->last_intensity[ia] = intensity;

    if (angle_change) {
        L[5].changed = true;
        lazenc_ic_encode(&c->ic_angle, &L[5].ac, (int16_t)ld16(last + 18), (int16_t)ld16(rec + 18),
                         gps_change ? 1u : 0u);
    }
    L[6].changed |= rec[17] != last[17];
    lazenc_encode_symbol(&L[6].ac, c->user[last[17] / 4], rec[17]);
    if (source_change) {
        L[7].changed = true;
        lazenc_ic_encode(&c->ic_source, &L[7].ac, ld16(last + 20), ld16(rec + 20), 0);
    }
    if (gps_change) {
        L[8].changed = true;
        gt_write(c, &L[8].ac, ld64(rec + 22));
    }
    // After any switch `last` is the new context's own record: it becomes this one.
    memcpy(c->last, rec, P14_SIZE);
    c->last_gps_change = gps_change;
}

// ---- RGB14, RGBNIR14, WAVEPACKET14, BYTE14 ----

typedef struct ex_ctx {
    bool unused;
    uint8_t *last; // item size bytes
    sta_laz_model *used, *diff[6], *nir_used, *nir_diff[2];
    sta_laz_model **bytes; // BYTE14
    // WAVEPACKET14
    sta_laz_model *wp_index, *wp_offset[4];
    sta_laz_ic ic_offset, ic_size, ic_return, ic_xyz;
    int32_t wp_last_diff;
    uint32_t wp_last_sym;
} ex_ctx;

typedef struct ex_enc {
    uint16_t type;
    size_t size;
    bool v4;
    uint32_t current;
    ex_ctx ctx[N_CTX];
    out_layer *L;
} ex_enc;

static size_t ex_layers(uint16_t type, size_t size)
{
    return type == STA_LAZ_ITEM_BYTE14 ? size : type == STA_LAZ_ITEM_RGBNIR14 ? 2 : 1;
}

static void ex_create(ex_enc *e)
{
    for (int i = 0; i < N_CTX; i++) {
        ex_ctx *x = &e->ctx[i];
        x->last = calloc(e->size, 1);
        if (!x->last) {
            abort();
        }
        if (e->type == STA_LAZ_ITEM_BYTE14) {
            x->bytes = calloc(e->size, sizeof(*x->bytes));
            if (!x->bytes) {
                abort();
            }
            for (size_t b = 0; b < e->size; b++) {
                x->bytes[b] = lazenc_model(256);
            }
        } else if (e->type == STA_LAZ_ITEM_WAVEPACKET14) {
            x->wp_index = lazenc_model(256);
            for (int j = 0; j < 4; j++) {
                x->wp_offset[j] = lazenc_model(4);
            }
            lazenc_ic_init(&x->ic_offset, 32, 1);
            lazenc_ic_init(&x->ic_size, 32, 1);
            lazenc_ic_init(&x->ic_return, 32, 1);
            lazenc_ic_init(&x->ic_xyz, 32, 3);
        } else {
            x->used = lazenc_model(128);
            for (int j = 0; j < 6; j++) {
                x->diff[j] = lazenc_model(256);
            }
            if (e->type == STA_LAZ_ITEM_RGBNIR14) {
                x->nir_used = lazenc_model(4);
                x->nir_diff[0] = lazenc_model(256);
                x->nir_diff[1] = lazenc_model(256);
            }
        }
    }
}

static void ex_destroy(ex_enc *e)
{
    for (int i = 0; i < N_CTX; i++) {
        ex_ctx *x = &e->ctx[i];
        if (x->bytes) {
            for (size_t b = 0; b < e->size; b++) {
                sta_laz_model_destroy(x->bytes[b]);
            }
            free(x->bytes);
        }
        free(x->last);
        sta_laz_model_destroy(x->used);
        for (int j = 0; j < 6; j++) {
            sta_laz_model_destroy(x->diff[j]);
        }
        sta_laz_model_destroy(x->nir_used);
        sta_laz_model_destroy(x->nir_diff[0]);
        sta_laz_model_destroy(x->nir_diff[1]);
        sta_laz_model_destroy(x->wp_index);
        for (int j = 0; j < 4; j++) {
            sta_laz_model_destroy(x->wp_offset[j]);
        }
        sta_laz_ic_release(&x->ic_offset);
        sta_laz_ic_release(&x->ic_size);
        sta_laz_ic_release(&x->ic_return);
        sta_laz_ic_release(&x->ic_xyz);
    }
}

static void ex_start(ex_enc *e, uint32_t ctx, const uint8_t *from)
{
    ex_ctx *x = &e->ctx[ctx];
    sta_laz_model *all[] = { x->used,         x->diff[0],      x->diff[1],     x->diff[2],
                             x->diff[3],      x->diff[4],      x->diff[5],     x->nir_used,
                             x->nir_diff[0],  x->nir_diff[1],  x->wp_index,    x->wp_offset[0],
                             x->wp_offset[1], x->wp_offset[2], x->wp_offset[3] };
    for (size_t i = 0; i < sizeof(all) / sizeof(all[0]); i++) {
        if (all[i]) {
            sta_laz_model_reset(all[i]);
        }
    }
    if (x->bytes) {
        for (size_t b = 0; b < e->size; b++) {
            sta_laz_model_reset(x->bytes[b]);
        }
    }
    if (e->type == STA_LAZ_ITEM_WAVEPACKET14) {
        sta_laz_ic_reset(&x->ic_offset);
        sta_laz_ic_reset(&x->ic_size);
        sta_laz_ic_reset(&x->ic_return);
        sta_laz_ic_reset(&x->ic_xyz);
        x->wp_last_diff = 0;
        x->wp_last_sym = 0;
    }
    memmove(x->last, from, e->size);
    x->unused = false;
}

// RGB of `item` against `last` (three u16), into layer `a`; true when something differs.
static bool rgb_write(ex_ctx *x, lazenc_arith *a, const uint8_t *last, const uint8_t *item)
{
    uint32_t l[3] = { ld16(last), ld16(last + 2), ld16(last + 4) };
    uint32_t v[3] = { ld16(item), ld16(item + 2), ld16(item + 4) };
    uint32_t sym = 0;
    for (int i = 0; i < 3; i++) {
        sym |= ((l[i] & 255) != (v[i] & 255) ? 1u : 0u) << (2 * i);
        sym |= ((l[i] >> 8) != (v[i] >> 8) ? 1u : 0u) << (2 * i + 1);
    }
    bool colour = (v[0] & 255) != (v[1] & 255) || (v[0] & 255) != (v[2] & 255) ||
                  (v[0] >> 8) != (v[1] >> 8) || (v[0] >> 8) != (v[2] >> 8);
    sym |= colour ? 64u : 0u;
    lazenc_encode_symbol(a, x->used, sym);
    int32_t dl = 0;
    int32_t dh = 0;
    if (sym & 1) {
        dl = (int32_t)(v[0] & 255) - (int32_t)(l[0] & 255);
        lazenc_encode_symbol(a, x->diff[0], fold8(dl));
    }
    if (sym & 2) {
        dh = (int32_t)(v[0] >> 8) - (int32_t)(l[0] >> 8);
        lazenc_encode_symbol(a, x->diff[1], fold8(dh));
    }
    if (sym & 64) {
        if (sym & 4) {
            int32_t corr = (int32_t)(v[1] & 255) - clamp8(dl + (int32_t)(l[1] & 255));
            lazenc_encode_symbol(a, x->diff[2], fold8(corr));
        }
        if (sym & 16) {
            dl = (dl + (int32_t)(v[1] & 255) - (int32_t)(l[1] & 255)) / 2;
            int32_t corr = (int32_t)(v[2] & 255) - clamp8(dl + (int32_t)(l[2] & 255));
            lazenc_encode_symbol(a, x->diff[4], fold8(corr));
        }
        if (sym & 8) {
            int32_t corr = (int32_t)(v[1] >> 8) - clamp8(dh + (int32_t)(l[1] >> 8));
            lazenc_encode_symbol(a, x->diff[3], fold8(corr));
        }
        if (sym & 32) {
            dh = (dh + (int32_t)(v[1] >> 8) - (int32_t)(l[1] >> 8)) / 2;
            int32_t corr = (int32_t)(v[2] >> 8) - clamp8(dh + (int32_t)(l[2] >> 8));
            lazenc_encode_symbol(a, x->diff[5], fold8(corr));
        }
    }
    return sym != 0;
}

static bool nir_write(ex_ctx *x, lazenc_arith *a, const uint8_t *last, const uint8_t *item)
{
    uint32_t l = ld16(last + 6);
    uint32_t v = ld16(item + 6);
    uint32_t sym = ((l & 255) != (v & 255) ? 1u : 0u) | ((l >> 8) != (v >> 8) ? 2u : 0u);
    lazenc_encode_symbol(a, x->nir_used, sym);
    if (sym & 1) {
        lazenc_encode_symbol(a, x->nir_diff[0], fold8((int32_t)(v & 255) - (int32_t)(l & 255)));
    }
    if (sym & 2) {
        lazenc_encode_symbol(a, x->nir_diff[1], fold8((int32_t)(v >> 8) - (int32_t)(l >> 8)));
    }
    return sym != 0;
}

// Wave packet: descriptor index u8, offset u64, size u32, return point f32, x/y/z f32.
static void wp_write(ex_ctx *x, lazenc_arith *a, const uint8_t *last, const uint8_t *item)
{
    lazenc_encode_symbol(a, x->wp_index, item[0]);
    int32_t diff;
    if (diff_fits(ld64(item + 1), ld64(last + 1), &diff)) {
        uint32_t sym = diff == 0 ? 0 : diff == (int32_t)ld32(last + 9) ? 1 : 2;
        lazenc_encode_symbol(a, x->wp_offset[x->wp_last_sym], sym);
        x->wp_last_sym = sym;
        if (sym == 2) {
            lazenc_ic_encode(&x->ic_offset, a, x->wp_last_diff, diff, 0);
            x->wp_last_diff = diff;
        }
    } else {
        lazenc_encode_symbol(a, x->wp_offset[x->wp_last_sym], 3);
        x->wp_last_sym = 3;
        uint64_t offset = ld64(item + 1);
        lazenc_write_u32(a, (uint32_t)offset);
        lazenc_write_u32(a, (uint32_t)(offset >> 32));
    }
    lazenc_ic_encode(&x->ic_size, a, (int32_t)ld32(last + 9), (int32_t)ld32(item + 9), 0);
    lazenc_ic_encode(&x->ic_return, a, (int32_t)ld32(last + 13), (int32_t)ld32(item + 13), 0);
    for (uint32_t i = 0; i < 3; i++) {
        lazenc_ic_encode(&x->ic_xyz, a, (int32_t)ld32(last + 17 + 4 * i),
                         (int32_t)ld32(item + 17 + 4 * i), i);
    }
}

static void ex_encode(ex_enc *e, uint32_t channel, const uint8_t *item)
{
    uint8_t *last = e->ctx[e->current].last;
    if (channel != e->current) {
        e->current = channel;
        if (e->ctx[channel].unused) {
            ex_start(e, channel, last);
            last = e->ctx[channel].last;
        } else if (e->v4) {
            last = e->ctx[channel].last; // version 4: the context's own last record
        }
        // version 3: still the previous context's last record (LASzip's behaviour)
    }
    ex_ctx *x = &e->ctx[e->current];
    out_layer *L = e->L;
    switch (e->type) {
    case STA_LAZ_ITEM_BYTE14:
        for (size_t i = 0; i < e->size; i++) {
            int32_t diff = (int32_t)item[i] - (int32_t)last[i];
            lazenc_encode_symbol(&L[i].ac, x->bytes[i], fold8(diff));
            if (diff) {
                L[i].changed = true;
                last[i] = item[i];
            }
        }
        return;
    case STA_LAZ_ITEM_WAVEPACKET14:
        L[0].changed |= memcmp(item, last, WP_SIZE) != 0;
        wp_write(x, &L[0].ac, last, item);
        break;
    default:
        L[0].changed |= rgb_write(x, &L[0].ac, last, item);
        if (e->type == STA_LAZ_ITEM_RGBNIR14) {
            L[1].changed |= nir_write(x, &L[1].ac, last, item);
        }
        break;
    }
    memcpy(last, item, e->size);
}

// ---- the chunk ----

bool lazenc_point14_chunk(const sta_laz_vlr *vlr, const uint8_t *records, size_t count,
                          size_t record_length, lazenc_buf *out)
{
    if (count == 0 || vlr->item_count == 0 || vlr->item_count > STA_LAZ_MAX_ITEMS ||
        vlr->items[0].type != STA_LAZ_ITEM_POINT14 || vlr->items[0].size != P14_SIZE) {
        return false;
    }
    uint16_t version = vlr->items[0].version;
    if (version != 3 && version != 4) {
        return false;
    }
    size_t layer_count = P14_NLAYERS;
    size_t at[STA_LAZ_MAX_ITEMS];
    size_t offset = 0;
    for (size_t i = 0; i < vlr->item_count; i++) {
        const sta_laz_item *it = &vlr->items[i];
        bool known = (it->type == STA_LAZ_ITEM_POINT14 && i == 0) ||
                     (it->type == STA_LAZ_ITEM_RGB14 && it->size == 6) ||
                     (it->type == STA_LAZ_ITEM_RGBNIR14 && it->size == 8) ||
                     (it->type == STA_LAZ_ITEM_WAVEPACKET14 && it->size == WP_SIZE) ||
                     (it->type == STA_LAZ_ITEM_BYTE14 && it->size > 0);
        if (!known || it->version != version) {
            return false;
        }
        at[i] = offset;
        offset += it->size;
        if (i > 0) {
            layer_count += ex_layers(it->type, it->size);
        }
    }
    if (offset != record_length) {
        return false;
    }

    out_layer *layers = calloc(layer_count, sizeof(*layers));
    pt_enc *pt = calloc(1, sizeof(*pt));
    ex_enc *ex = calloc(vlr->item_count, sizeof(*ex));
    if (!layers || !pt || !ex) {
        abort();
    }
    for (size_t l = 0; l < layer_count; l++) {
        lazenc_arith_init(&layers[l].ac, &layers[l].buf);
    }
    const uint8_t *first = records;
    pt->L = layers;
    pt->current = (first[15] >> 4) & 3;
    for (int c = 0; c < N_CTX; c++) {
        pt_create(&pt->ctx[c]);
        pt->ctx[c].unused = true;
    }
    pt_start(&pt->ctx[pt->current], first);
    size_t next_layer = P14_NLAYERS;
    for (size_t i = 1; i < vlr->item_count; i++) {
        ex_enc *e = &ex[i];
        e->type = vlr->items[i].type;
        e->size = vlr->items[i].size;
        e->v4 = version == 4;
        e->L = layers + next_layer;
        next_layer += ex_layers(e->type, e->size);
        ex_create(e);
        for (int c = 0; c < N_CTX; c++) {
            e->ctx[c].unused = true;
        }
        e->current = pt->current;
        ex_start(e, e->current, first + at[i]);
    }

    for (size_t p = 1; p < count; p++) {
        const uint8_t *rec = records + p * record_length;
        pt_encode(pt, rec);
        for (size_t i = 1; i < vlr->item_count; i++) {
            ex_encode(&ex[i], pt->current, rec + at[i]);
        }
    }

    // The first record raw, the point count, the layer sizes, the layers. The
    // channel/returns/XY and Z layers are always kept, the others only when changed.
    lazenc_buf_put(out, first, record_length);
    lazenc_buf_put_u32(out, (uint32_t)count);
    for (size_t l = 0; l < layer_count; l++) {
        lazenc_arith_done(&layers[l].ac);
        if (l < 2) {
            layers[l].changed = true;
        }
        lazenc_buf_put_u32(out, layers[l].changed ? (uint32_t)layers[l].buf.size : 0);
    }
    for (size_t l = 0; l < layer_count; l++) {
        if (layers[l].changed) {
            lazenc_buf_put(out, layers[l].buf.data, layers[l].buf.size);
        }
        lazenc_buf_free(&layers[l].buf);
    }
    for (int c = 0; c < N_CTX; c++) {
        pt_destroy(&pt->ctx[c]);
    }
    for (size_t i = 1; i < vlr->item_count; i++) {
        ex_destroy(&ex[i]);
    }
    free(ex);
    free(pt);
    free(layers);
    return true;
}
