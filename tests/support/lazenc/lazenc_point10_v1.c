/* SPDX-License-Identifier: MIT
 * Test encoder: point10 family items, version 1 (LASzip 1.x): POINT10, GPSTIME11,
 * RGB12, WAVEPACKET13 and BYTE, as the LASzip writer of those items decides what to
 * send. Written from the writer's rules, separately from src/io/laz_point10_v1.c, so
 * the tests cross-check the two.
 *
 * Writer rules reproduced:
 * - POINT10: x and y differences against the median of the last three differences
 *   (32-bit correctors; y's context min(k_x, 19)), z against the last z (context
 *   min((k_x + k_y) / 2, 19)); then the mask of changed fields (intensity 32, flag
 *   byte 16, classification 8, scan angle 4, user data 2, point source 1), always sent;
 *   flag byte, classification and user data as symbols of a model per previous value
 *   (created on first use, reset at every chunk start), intensity (16 bits), scan angle
 *   (8 bits, context (k_x + k_y) / 2 < 3) and point source (16 bits) as corrections.
 * - GPSTIME11: 64-bit integer difference of the raw patterns. After a zero difference:
 *   symbol 0 unchanged, 1 a 32-bit difference, 2 the full pattern. Otherwise the
 *   multiplier round(diff / last_diff) in float, clamped to 0..509 (0 predicts a
 *   quarter), 510 the full pattern, 511 unchanged.
 * - RGB12: mask of the six bytes that differ, each sent as an 8-bit correction.
 * - WAVEPACKET13: the index byte as a symbol; the offset choice 0 (same), 1 (last
 *   offset + last size, compared as the writer does: the 32-bit difference equals the
 *   size read as signed), 2 (coded 32-bit difference) or 3 (full), with a model per
 *   previous choice; the other fields as 32-bit corrections from their last value.
 * - BYTE: each byte an 8-bit correction from its last value, context = byte index.
 */
#include <stdlib.h>
#include <string.h>

#include "lazenc.h"

static uint16_t get16(const uint8_t *p)
{
    return (uint16_t)(p[0] | p[1] << 8);
}

static uint32_t get32(const uint8_t *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

static uint64_t get64(const uint8_t *p)
{
    return (uint64_t)get32(p) | (uint64_t)get32(p + 4) << 32;
}

static void write_u64(lazenc_arith *enc, uint64_t v)
{
    lazenc_write_u32(enc, (uint32_t)v);
    lazenc_write_u32(enc, (uint32_t)(v >> 32));
}

// ---- POINT10 ----

typedef struct enc_point {
    uint8_t last[20];
    int32_t hist_x[3];
    int32_t hist_y[3];
    int slot;
    sta_laz_model *changed;
    sta_laz_model *by_prev[3][256]; // flag byte, classification, user data
    sta_laz_ic dx, dy, z, intensity, angle, source;
} enc_point;

static int32_t mid_of_three(const int32_t *h)
{
    int32_t a = h[0], b = h[1], c = h[2], t;
    if (a > b) {
        t = a;
        a = b;
        b = t;
    }
    if (b > c) {
        b = c;
    }
    return a > b ? a : b;
}

static void point_begin(void *state, const uint8_t *first)
{
    enc_point *s = state;
    memcpy(s->last, first, 20);
    memset(s->hist_x, 0, sizeof(s->hist_x));
    memset(s->hist_y, 0, sizeof(s->hist_y));
    s->slot = 0;
    sta_laz_model_reset(s->changed);
    for (int f = 0; f < 3; f++) {
        for (int v = 0; v < 256; v++) {
            if (s->by_prev[f][v]) {
                sta_laz_model_reset(s->by_prev[f][v]);
            }
        }
    }
    sta_laz_ic_reset(&s->dx);
    sta_laz_ic_reset(&s->dy);
    sta_laz_ic_reset(&s->z);
    sta_laz_ic_reset(&s->intensity);
    sta_laz_ic_reset(&s->angle);
    sta_laz_ic_reset(&s->source);
}

static void send_by_prev(enc_point *s, lazenc_arith *enc, int field, uint8_t prev, uint8_t now)
{
    if (!s->by_prev[field][prev]) {
        s->by_prev[field][prev] = lazenc_model(256);
    }
    lazenc_encode_symbol(enc, s->by_prev[field][prev], now);
}

static void point_encode(void *state, lazenc_arith *enc, const uint8_t *item)
{
    enc_point *s = state;
    const uint8_t *last = s->last;
    int32_t x_diff = (int32_t)(get32(item) - get32(last));
    int32_t y_diff = (int32_t)(get32(item + 4) - get32(last + 4));
    lazenc_ic_encode(&s->dx, enc, mid_of_three(s->hist_x), x_diff, 0);
    uint32_t k = s->dx.k;
    lazenc_ic_encode(&s->dy, enc, mid_of_three(s->hist_y), y_diff, k < 19 ? k : 19);
    k = (k + s->dy.k) / 2;
    lazenc_ic_encode(&s->z, enc, (int32_t)get32(last + 8), (int32_t)get32(item + 8),
                     k < 19 ? k : 19);
    uint32_t changed =
        (uint32_t)(get16(last + 12) != get16(item + 12)) << 5 |
        (uint32_t)(last[14] != item[14]) << 4 | (uint32_t)(last[15] != item[15]) << 3 |
        (uint32_t)(last[16] != item[16]) << 2 | (uint32_t)(last[17] != item[17]) << 1 |
        (uint32_t)(get16(last + 18) != get16(item + 18));
    lazenc_encode_symbol(enc, s->changed, changed);
    if (changed & 32) {
        lazenc_ic_encode(&s->intensity, enc, get16(last + 12), get16(item + 12), 0);
    }
    if (changed & 16) {
        send_by_prev(s, enc, 0, last[14], item[14]);
    }
    if (changed & 8) {
        send_by_prev(s, enc, 1, last[15], item[15]);
    }
    if (changed & 4) {
        lazenc_ic_encode(&s->angle, enc, last[16], item[16], k < 3 ? 1 : 0);
    }
    if (changed & 2) {
        send_by_prev(s, enc, 2, last[17], item[17]);
    }
    if (changed & 1) {
        lazenc_ic_encode(&s->source, enc, get16(last + 18), get16(item + 18), 0);
    }
    s->hist_x[s->slot] = x_diff;
    s->hist_y[s->slot] = y_diff;
    s->slot = (s->slot + 1) % 3;
    memcpy(s->last, item, 20);
}

static void point_destroy(void *state)
{
    enc_point *s = state;
    sta_laz_model_destroy(s->changed);
    for (int f = 0; f < 3; f++) {
        for (int v = 0; v < 256; v++) {
            sta_laz_model_destroy(s->by_prev[f][v]);
        }
    }
    sta_laz_ic_release(&s->dx);
    sta_laz_ic_release(&s->dy);
    sta_laz_ic_release(&s->z);
    sta_laz_ic_release(&s->intensity);
    sta_laz_ic_release(&s->angle);
    sta_laz_ic_release(&s->source);
    free(s);
}

static void *point_create(void)
{
    enc_point *s = lazenc_zalloc(sizeof(*s));
    s->changed = lazenc_model(64);
    lazenc_ic_init(&s->dx, 32, 1);
    lazenc_ic_init(&s->dy, 32, 20);
    lazenc_ic_init(&s->z, 32, 20);
    lazenc_ic_init(&s->intensity, 16, 1);
    lazenc_ic_init(&s->angle, 8, 2);
    lazenc_ic_init(&s->source, 16, 1);
    return s;
}

// ---- GPSTIME11 ----

enum {
    MULTI_SYMBOLS = 512
};

typedef struct enc_gps {
    int64_t last;
    int32_t last_diff;
    int extreme_run;
    sta_laz_model *multi;
    sta_laz_model *after_zero;
    sta_laz_ic ic;
} enc_gps;

static void gps_begin(void *state, const uint8_t *first)
{
    enc_gps *s = state;
    s->last = (int64_t)get64(first);
    s->last_diff = 0;
    s->extreme_run = 0;
    sta_laz_model_reset(s->multi);
    sta_laz_model_reset(s->after_zero);
    sta_laz_ic_reset(&s->ic);
}

static void gps_extreme(enc_gps *s, int32_t diff)
{
    s->extreme_run++;
    if (s->extreme_run > 3) {
        s->last_diff = diff;
        s->extreme_run = 0;
    }
}

static void gps_encode(void *state, lazenc_arith *enc, const uint8_t *item)
{
    enc_gps *s = state;
    int64_t now = (int64_t)get64(item);
    uint64_t wide = (uint64_t)now - (uint64_t)s->last;
    int32_t diff = (int32_t)(uint32_t)wide;
    bool fits = (uint64_t)(int64_t)diff == wide;
    if (s->last_diff == 0) {
        if (now == s->last) {
            lazenc_encode_symbol(enc, s->after_zero, 0);
            return;
        }
        if (fits) {
            lazenc_encode_symbol(enc, s->after_zero, 1);
            lazenc_ic_encode(&s->ic, enc, 0, diff, 0);
            s->last_diff = diff;
        } else {
            lazenc_encode_symbol(enc, s->after_zero, 2);
            write_u64(enc, (uint64_t)now);
        }
        s->last = now;
        return;
    }
    if (now == s->last) {
        lazenc_encode_symbol(enc, s->multi, MULTI_SYMBOLS - 1);
        return;
    }
    if (!fits) {
        lazenc_encode_symbol(enc, s->multi, MULTI_SYMBOLS - 2);
        write_u64(enc, (uint64_t)now);
        s->last = now;
        return;
    }
    // The writer rounds the ratio in single precision; clamp before converting.
    float ratio = (float)diff / (float)s->last_diff + 0.5f;
    int32_t multi;
    if (ratio >= (float)(MULTI_SYMBOLS - 3)) {
        multi = MULTI_SYMBOLS - 3;
    } else if (ratio < 1.0f) {
        multi = 0;
    } else {
        multi = (int32_t)ratio;
    }
    lazenc_encode_symbol(enc, s->multi, (uint32_t)multi);
    if (multi == 1) {
        lazenc_ic_encode(&s->ic, enc, s->last_diff, diff, 1);
        s->last_diff = diff;
        s->extreme_run = 0;
    } else if (multi == 0) {
        lazenc_ic_encode(&s->ic, enc, s->last_diff / 4, diff, 2);
        gps_extreme(s, diff);
    } else {
        int32_t pred = (int32_t)((uint32_t)multi * (uint32_t)s->last_diff);
        uint32_t context = multi < 10 ? 3 : multi < 50 ? 4 : 5;
        lazenc_ic_encode(&s->ic, enc, pred, diff, context);
        if (multi == MULTI_SYMBOLS - 3) {
            gps_extreme(s, diff);
        }
    }
    s->last = now;
}

static void gps_destroy(void *state)
{
    enc_gps *s = state;
    sta_laz_model_destroy(s->multi);
    sta_laz_model_destroy(s->after_zero);
    sta_laz_ic_release(&s->ic);
    free(s);
}

static void *gps_create(void)
{
    enc_gps *s = lazenc_zalloc(sizeof(*s));
    s->multi = lazenc_model(MULTI_SYMBOLS);
    s->after_zero = lazenc_model(3);
    lazenc_ic_init(&s->ic, 32, 6);
    return s;
}

// ---- RGB12 ----

typedef struct enc_rgb {
    uint8_t last[6];
    sta_laz_model *mask;
    sta_laz_ic ic;
} enc_rgb;

static void rgb_begin(void *state, const uint8_t *first)
{
    enc_rgb *s = state;
    memcpy(s->last, first, 6);
    sta_laz_model_reset(s->mask);
    sta_laz_ic_reset(&s->ic);
}

static void rgb_encode(void *state, lazenc_arith *enc, const uint8_t *item)
{
    enc_rgb *s = state;
    uint32_t mask = 0;
    for (uint32_t b = 0; b < 6; b++) {
        mask |= (uint32_t)(item[b] != s->last[b]) << b;
    }
    lazenc_encode_symbol(enc, s->mask, mask);
    for (uint32_t b = 0; b < 6; b++) {
        if (mask >> b & 1) {
            lazenc_ic_encode(&s->ic, enc, s->last[b], item[b], b);
        }
    }
    memcpy(s->last, item, 6);
}

static void rgb_destroy(void *state)
{
    enc_rgb *s = state;
    sta_laz_model_destroy(s->mask);
    sta_laz_ic_release(&s->ic);
    free(s);
}

static void *rgb_create(void)
{
    enc_rgb *s = lazenc_zalloc(sizeof(*s));
    s->mask = lazenc_model(64);
    lazenc_ic_init(&s->ic, 8, 6);
    return s;
}

// ---- WAVEPACKET13 ----

typedef struct enc_wave {
    uint8_t last[29]; // byte 0 unused (the index is not predicted)
    int32_t last_diff;
    uint32_t choice;
    sta_laz_model *index;
    sta_laz_model *offset_choice[4];
    sta_laz_ic offset, size, return_point, xyz;
} enc_wave;

static void wave_begin(void *state, const uint8_t *first)
{
    enc_wave *s = state;
    memcpy(s->last, first, 29);
    s->last_diff = 0;
    s->choice = 0;
    sta_laz_model_reset(s->index);
    for (int i = 0; i < 4; i++) {
        sta_laz_model_reset(s->offset_choice[i]);
    }
    sta_laz_ic_reset(&s->offset);
    sta_laz_ic_reset(&s->size);
    sta_laz_ic_reset(&s->return_point);
    sta_laz_ic_reset(&s->xyz);
}

static void wave_encode(void *state, lazenc_arith *enc, const uint8_t *item)
{
    enc_wave *s = state;
    const uint8_t *last = s->last;
    lazenc_encode_symbol(enc, s->index, item[0]);
    uint64_t wide = get64(item + 1) - get64(last + 1);
    int32_t diff = (int32_t)(uint32_t)wide;
    uint32_t choice;
    if ((uint64_t)(int64_t)diff != wide) {
        choice = 3;
    } else if (diff == 0) {
        choice = 0;
    } else if (diff == (int32_t)get32(last + 9)) {
        choice = 1;
    } else {
        choice = 2;
    }
    lazenc_encode_symbol(enc, s->offset_choice[s->choice], choice);
    s->choice = choice;
    if (choice == 2) {
        lazenc_ic_encode(&s->offset, enc, s->last_diff, diff, 0);
        s->last_diff = diff;
    } else if (choice == 3) {
        write_u64(enc, get64(item + 1));
    }
    lazenc_ic_encode(&s->size, enc, (int32_t)get32(last + 9), (int32_t)get32(item + 9), 0);
    lazenc_ic_encode(&s->return_point, enc, (int32_t)get32(last + 13), (int32_t)get32(item + 13),
                     0);
    for (uint32_t c = 0; c < 3; c++) {
        uint32_t at = 17 + 4 * c;
        lazenc_ic_encode(&s->xyz, enc, (int32_t)get32(last + at), (int32_t)get32(item + at), c);
    }
    memcpy(s->last, item, 29);
}

static void wave_destroy(void *state)
{
    enc_wave *s = state;
    sta_laz_model_destroy(s->index);
    for (int i = 0; i < 4; i++) {
        sta_laz_model_destroy(s->offset_choice[i]);
    }
    sta_laz_ic_release(&s->offset);
    sta_laz_ic_release(&s->size);
    sta_laz_ic_release(&s->return_point);
    sta_laz_ic_release(&s->xyz);
    free(s);
}

static void *wave_create(void)
{
    enc_wave *s = lazenc_zalloc(sizeof(*s));
    s->index = lazenc_model(256);
    for (int i = 0; i < 4; i++) {
        s->offset_choice[i] = lazenc_model(4);
    }
    lazenc_ic_init(&s->offset, 32, 1);
    lazenc_ic_init(&s->size, 32, 1);
    lazenc_ic_init(&s->return_point, 32, 1);
    lazenc_ic_init(&s->xyz, 32, 3);
    return s;
}

// ---- BYTE ----

typedef struct enc_bytes {
    size_t count;
    uint8_t *last;
    sta_laz_ic ic;
} enc_bytes;

static void bytes_begin(void *state, const uint8_t *first)
{
    enc_bytes *s = state;
    memcpy(s->last, first, s->count);
    sta_laz_ic_reset(&s->ic);
}

static void bytes_encode(void *state, lazenc_arith *enc, const uint8_t *item)
{
    enc_bytes *s = state;
    for (size_t i = 0; i < s->count; i++) {
        lazenc_ic_encode(&s->ic, enc, s->last[i], item[i], (uint32_t)i);
    }
    memcpy(s->last, item, s->count);
}

static void bytes_destroy(void *state)
{
    enc_bytes *s = state;
    sta_laz_ic_release(&s->ic);
    free(s->last);
    free(s);
}

static void *bytes_create(size_t count)
{
    enc_bytes *s = lazenc_zalloc(sizeof(*s));
    s->count = count;
    s->last = lazenc_zalloc(count);
    lazenc_ic_init(&s->ic, 8, (uint32_t)count);
    return s;
}

bool lazenc_point10_v1_item(const sta_laz_item *item, lazenc_seq_item *out)
{
    if (item->version != 1) {
        return false;
    }
    switch (item->type) {
    case STA_LAZ_ITEM_POINT10:
        if (item->size != 20) {
            return false;
        }
        *out = (lazenc_seq_item){ point_create(), point_begin, point_encode, point_destroy };
        return true;
    case STA_LAZ_ITEM_GPSTIME11:
        if (item->size != 8) {
            return false;
        }
        *out = (lazenc_seq_item){ gps_create(), gps_begin, gps_encode, gps_destroy };
        return true;
    case STA_LAZ_ITEM_RGB12:
        if (item->size != 6) {
            return false;
        }
        *out = (lazenc_seq_item){ rgb_create(), rgb_begin, rgb_encode, rgb_destroy };
        return true;
    case STA_LAZ_ITEM_WAVEPACKET13:
        if (item->size != 29) {
            return false;
        }
        *out = (lazenc_seq_item){ wave_create(), wave_begin, wave_encode, wave_destroy };
        return true;
    case STA_LAZ_ITEM_BYTE:
        if (item->size == 0) {
            return false;
        }
        *out =
            (lazenc_seq_item){ bytes_create(item->size), bytes_begin, bytes_encode, bytes_destroy };
        return true;
    default:
        return false;
    }
}
