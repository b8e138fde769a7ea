/* SPDX-License-Identifier: MIT
 * Test encoder: point10 family items, version 2 (POINT10, GPSTIME11, RGB12, BYTE),
 * written from the LASzip writer's behaviour: which fields changed, median-of-five
 * x/y predictors per return class, z per return level, GPS time as multiples of the
 * last difference in up to four sequences, RGB bytes predicted from red's change.
 */
#include <stdlib.h>
#include <string.h>

#include "core/bytes.h"
#include "io/laz_predict.h"
#include "lazenc.h"

enum {
    GPS_MULTI = 500,
    GPS_MULTI_MINUS = -10,
    GPS_UNCHANGED = 511, // symbol: same time as the last
    GPS_CODE_FULL = 512, // symbol: a new sequence, time sent in full
};

// ---- POINT10 ----

// Return class of (number of returns, return number); level is |n - r|.
static const uint8_t return_class[8][8] = {
    { 15, 14, 13, 12, 11, 10, 9, 8 },  { 14, 0, 1, 3, 6, 10, 10, 9 },
    { 13, 1, 2, 4, 7, 11, 11, 10 },    { 12, 3, 4, 5, 8, 12, 12, 11 },
    { 11, 6, 7, 8, 9, 13, 13, 12 },    { 10, 10, 11, 12, 13, 14, 14, 13 },
    { 9, 10, 11, 12, 13, 14, 15, 14 }, { 8, 9, 10, 11, 12, 13, 14, 15 },
};

typedef struct p10 {
    uint8_t last[20];
    uint16_t last_intensity[16];
    int32_t last_z[8];
    median5 dx[16];
    median5 dy[16];
    sta_laz_model *m_changed;
    sta_laz_model *m_angle[2];
    sta_laz_model *m_flags[256];
    sta_laz_model *m_class[256];
    sta_laz_model *m_user[256];
    sta_laz_ic ic_intensity;
    sta_laz_ic ic_source;
    sta_laz_ic ic_dx;
    sta_laz_ic ic_dy;
    sta_laz_ic ic_z;
} p10;

// Models selected by the previous byte: fresh for each chunk.
static sta_laz_model *by_previous(sta_laz_model **family, uint8_t previous)
{
    if (!family[previous]) {
        family[previous] = lazenc_model(256);
    }
    return family[previous];
}

static void p10_begin(void *state, const uint8_t *first)
{
    p10 *s = state;
    for (int i = 0; i < 256; i++) {
        sta_laz_model_destroy(s->m_flags[i]);
        sta_laz_model_destroy(s->m_class[i]);
        sta_laz_model_destroy(s->m_user[i]);
        s->m_flags[i] = s->m_class[i] = s->m_user[i] = NULL;
    }
    sta_laz_model_reset(s->m_changed);
    sta_laz_model_reset(s->m_angle[0]);
    sta_laz_model_reset(s->m_angle[1]);
    sta_laz_ic_reset(&s->ic_intensity);
    sta_laz_ic_reset(&s->ic_source);
    sta_laz_ic_reset(&s->ic_dx);
    sta_laz_ic_reset(&s->ic_dy);
    sta_laz_ic_reset(&s->ic_z);
    for (int i = 0; i < 16; i++) {
        sta_laz_median_init(&s->dx[i]);
        sta_laz_median_init(&s->dy[i]);
    }
    memset(s->last_intensity, 0, sizeof(s->last_intensity));
    memset(s->last_z, 0, sizeof(s->last_z));
    memcpy(s->last, first, 20);
}

static void p10_encode(void *state, lazenc_arith *enc, const uint8_t *item)
{
    p10 *s = state;
    uint8_t *last = s->last;
    uint32_t r = item[14] & 7;
    uint32_t n = (item[14] >> 3) & 7;
    uint32_t m = return_class[n][r];
    uint32_t l = n > r ? n - r : r - n;
    uint16_t intensity = sta_load_u16le(item + 12);
    uint16_t source = sta_load_u16le(item + 18);
    uint32_t changed =
        ((uint32_t)(last[14] != item[14]) << 5) |
        ((uint32_t)(s->last_intensity[m] != intensity) << 4) |
        ((uint32_t)(last[15] != item[15]) << 3) | ((uint32_t)(last[16] != item[16]) << 2) |
        ((uint32_t)(last[17] != item[17]) << 1) | (uint32_t)(sta_load_u16le(last + 18) != source);
    lazenc_encode_symbol(enc, s->m_changed, changed);
    if (changed & 32) {
        lazenc_encode_symbol(enc, by_previous(s->m_flags, last[14]), item[14]);
    }
    if (changed & 16) {
        lazenc_ic_encode(&s->ic_intensity, enc, s->last_intensity[m], intensity, m < 3 ? m : 3);
        s->last_intensity[m] = intensity;
    }
    if (changed & 8) {
        lazenc_encode_symbol(enc, by_previous(s->m_class, last[15]), item[15]);
    }
    if (changed & 4) {
        lazenc_encode_symbol(enc, s->m_angle[(item[14] >> 6) & 1],
                             sta_laz_fold_u8((int32_t)item[16] - (int32_t)last[16]));
    }
    if (changed & 2) {
        lazenc_encode_symbol(enc, by_previous(s->m_user, last[17]), item[17]);
    }
    if (changed & 1) {
        lazenc_ic_encode(&s->ic_source, enc, sta_load_u16le(last + 18), source, 0);
    }
    int32_t dx = (int32_t)(sta_load_u32le(item) - sta_load_u32le(last));
    lazenc_ic_encode(&s->ic_dx, enc, s->dx[m].v[2], dx, n == 1);
    sta_laz_median_add(&s->dx[m], dx);
    uint32_t k = s->ic_dx.k;
    int32_t dy = (int32_t)(sta_load_u32le(item + 4) - sta_load_u32le(last + 4));
    lazenc_ic_encode(&s->ic_dy, enc, s->dy[m].v[2], dy, (n == 1) + (k < 20 ? (k & ~1u) : 20));
    sta_laz_median_add(&s->dy[m], dy);
    k = (s->ic_dx.k + s->ic_dy.k) / 2;
    int32_t z = (int32_t)sta_load_u32le(item + 8);
    lazenc_ic_encode(&s->ic_z, enc, s->last_z[l], z, (n == 1) + (k < 18 ? (k & ~1u) : 18));
    s->last_z[l] = z;
    memcpy(last, item, 20);
}

static void p10_destroy(void *state)
{
    p10 *s = state;
    sta_laz_model_destroy(s->m_changed);
    sta_laz_model_destroy(s->m_angle[0]);
    sta_laz_model_destroy(s->m_angle[1]);
    for (int i = 0; i < 256; i++) {
        sta_laz_model_destroy(s->m_flags[i]);
        sta_laz_model_destroy(s->m_class[i]);
        sta_laz_model_destroy(s->m_user[i]);
    }
    sta_laz_ic_release(&s->ic_intensity);
    sta_laz_ic_release(&s->ic_source);
    sta_laz_ic_release(&s->ic_dx);
    sta_laz_ic_release(&s->ic_dy);
    sta_laz_ic_release(&s->ic_z);
    free(s);
}

static void *p10_create(void)
{
    p10 *s = lazenc_zalloc(sizeof(*s));
    s->m_changed = lazenc_model(64);
    s->m_angle[0] = lazenc_model(256);
    s->m_angle[1] = lazenc_model(256);
    lazenc_ic_init(&s->ic_intensity, 16, 4);
    lazenc_ic_init(&s->ic_source, 16, 1);
    lazenc_ic_init(&s->ic_dx, 32, 2);
    lazenc_ic_init(&s->ic_dy, 32, 22);
    lazenc_ic_init(&s->ic_z, 32, 20);
    return s;
}

// ---- GPSTIME11 ----

typedef struct gps {
    uint32_t last;
    uint32_t next;
    int64_t time[4];
    int32_t diff[4];
    int32_t extreme[4];
    sta_laz_model *m_multi;
    sta_laz_model *m_zero;
    sta_laz_ic ic;
} gps;

static void gps_begin(void *state, const uint8_t *first)
{
    gps *s = state;
    s->last = s->next = 0;
    memset(s->diff, 0, sizeof(s->diff));
    memset(s->extreme, 0, sizeof(s->extreme));
    s->time[0] = (int64_t)sta_load_u64le(first);
    s->time[1] = s->time[2] = s->time[3] = 0;
    sta_laz_model_reset(s->m_multi);
    sta_laz_model_reset(s->m_zero);
    sta_laz_ic_reset(&s->ic);
}

static bool fits_32(int64_t v)
{
    return v == (int64_t)(int32_t)v;
}

// Another sequence within 32 bits of `t`: 1..3 steps ahead of `last`, or 0.
static uint32_t other_sequence(const gps *s, int64_t t)
{
    for (uint32_t i = 1; i < 4; i++) {
        if (fits_32((int64_t)((uint64_t)t - (uint64_t)s->time[(s->last + i) & 3]))) {
            return i;
        }
    }
    return 0;
}

static void gps_full(gps *s, lazenc_arith *enc, int64_t t)
{
    lazenc_ic_encode(&s->ic, enc, (int32_t)(uint32_t)((uint64_t)s->time[s->last] >> 32),
                     (int32_t)(uint32_t)((uint64_t)t >> 32), 8);
    lazenc_write_u32(enc, (uint32_t)(uint64_t)t);
    s->next = (s->next + 1) & 3;
    s->last = s->next;
    s->diff[s->last] = 0;
    s->extreme[s->last] = 0;
}

// After more than three extreme multipliers in a row the difference becomes the base.
static void count_extreme(gps *s, int32_t diff)
{
    if (++s->extreme[s->last] > 3) {
        s->diff[s->last] = diff;
        s->extreme[s->last] = 0;
    }
}

static void gps_encode_time(gps *s, lazenc_arith *enc, int64_t t)
{
    uint32_t last = s->last;
    bool zero_base = s->diff[last] == 0;
    sta_laz_model *m = zero_base ? s->m_zero : s->m_multi;
    if (t == s->time[last]) {
        lazenc_encode_symbol(enc, m, zero_base ? 0 : GPS_UNCHANGED);
        return;
    }
    int64_t d64 = (int64_t)((uint64_t)t - (uint64_t)s->time[last]);
    if (!fits_32(d64)) {
        uint32_t i = other_sequence(s, t);
        if (i) {
            lazenc_encode_symbol(enc, m, zero_base ? i + 2 : GPS_CODE_FULL + i);
            s->last = (last + i) & 3;
            gps_encode_time(s, enc, t);
            return;
        }
        lazenc_encode_symbol(enc, m, zero_base ? 2 : GPS_CODE_FULL);
        gps_full(s, enc, t);
        s->time[s->last] = t;
        return;
    }
    int32_t d = (int32_t)d64;
    if (zero_base) {
        lazenc_encode_symbol(enc, m, 1);
        lazenc_ic_encode(&s->ic, enc, 0, d, 0);
        s->diff[last] = d;
        s->extreme[last] = 0;
        s->time[last] = t;
        return;
    }
    float ratio = (float)d / (float)s->diff[last];
    int32_t multi = ratio >= 0 ? (int32_t)(ratio + 0.5f) : (int32_t)(ratio - 0.5f);
    int32_t base = s->diff[last];
    if (multi == 1) {
        lazenc_encode_symbol(enc, m, 1);
        lazenc_ic_encode(&s->ic, enc, base, d, 1);
        s->extreme[last] = 0;
    } else if (multi > 0 && multi < GPS_MULTI) {
        lazenc_encode_symbol(enc, m, (uint32_t)multi);
        lazenc_ic_encode(&s->ic, enc, (int32_t)((uint32_t)multi * (uint32_t)base), d,
                         multi < 10 ? 2 : 3);
    } else if (multi >= GPS_MULTI) {
        lazenc_encode_symbol(enc, m, GPS_MULTI);
        lazenc_ic_encode(&s->ic, enc, (int32_t)((uint32_t)GPS_MULTI * (uint32_t)base), d, 4);
        count_extreme(s, d);
    } else if (multi < 0 && multi > GPS_MULTI_MINUS) {
        lazenc_encode_symbol(enc, m, (uint32_t)(GPS_MULTI - multi));
        lazenc_ic_encode(&s->ic, enc, (int32_t)((uint32_t)multi * (uint32_t)base), d, 5);
    } else if (multi < 0) {
        lazenc_encode_symbol(enc, m, GPS_MULTI - GPS_MULTI_MINUS);
        lazenc_ic_encode(&s->ic, enc, (int32_t)((uint32_t)GPS_MULTI_MINUS * (uint32_t)base), d, 6);
        count_extreme(s, d);
    } else {
        lazenc_encode_symbol(enc, m, 0);
        lazenc_ic_encode(&s->ic, enc, 0, d, 7);
        count_extreme(s, d);
    }
    s->time[last] = t;
}

static void gps_encode(void *state, lazenc_arith *enc, const uint8_t *item)
{
    gps_encode_time(state, enc, (int64_t)sta_load_u64le(item));
}

static void gps_destroy(void *state)
{
    gps *s = state;
    sta_laz_model_destroy(s->m_multi);
    sta_laz_model_destroy(s->m_zero);
    sta_laz_ic_release(&s->ic);
    free(s);
}

static void *gps_create(void)
{
    gps *s = lazenc_zalloc(sizeof(*s));
    s->m_multi = lazenc_model(GPS_MULTI - GPS_MULTI_MINUS + 6);
    s->m_zero = lazenc_model(6);
    lazenc_ic_init(&s->ic, 32, 9);
    return s;
}

// ---- RGB12 ----

typedef struct rgb {
    uint16_t last[3];
    sta_laz_model *m_used;
    sta_laz_model *m_diff[6];
} rgb;

static void rgb_begin(void *state, const uint8_t *first)
{
    rgb *s = state;
    sta_laz_model_reset(s->m_used);
    for (int i = 0; i < 6; i++) {
        sta_laz_model_reset(s->m_diff[i]);
    }
    for (int i = 0; i < 3; i++) {
        s->last[i] = sta_load_u16le(first + 2 * i);
    }
}

static void rgb_put(rgb *s, lazenc_arith *enc, int i, int32_t value, int32_t predicted)
{
    lazenc_encode_symbol(enc, s->m_diff[i], sta_laz_fold_u8(value - predicted));
}

static void rgb_encode(void *state, lazenc_arith *enc, const uint8_t *item)
{
    rgb *s = state;
    const uint16_t *p = s->last;
    int32_t lo[3];
    int32_t hi[3];
    int32_t plo[3];
    int32_t phi[3];
    for (int i = 0; i < 3; i++) {
        uint16_t c = sta_load_u16le(item + 2 * i);
        lo[i] = c & 0xff;
        hi[i] = c >> 8;
        plo[i] = p[i] & 0xff;
        phi[i] = p[i] >> 8;
    }
    uint32_t used = (uint32_t)(lo[0] != plo[0]) | ((uint32_t)(hi[0] != phi[0]) << 1) |
                    ((uint32_t)(lo[1] != plo[1]) << 2) | ((uint32_t)(hi[1] != phi[1]) << 3) |
                    ((uint32_t)(lo[2] != plo[2]) << 4) | ((uint32_t)(hi[2] != phi[2]) << 5);
    bool grey = lo[0] == lo[1] && lo[0] == lo[2] && hi[0] == hi[1] && hi[0] == hi[2];
    used |= (uint32_t)!grey << 6;
    lazenc_encode_symbol(enc, s->m_used, used);
    int32_t dlo = 0;
    int32_t dhi = 0;
    if (used & 1) {
        dlo = lo[0] - plo[0];
        rgb_put(s, enc, 0, lo[0], plo[0]);
    }
    if (used & 2) {
        dhi = hi[0] - phi[0];
        rgb_put(s, enc, 1, hi[0], phi[0]);
    }
    if (used & 64) {
        if (used & 4) {
            rgb_put(s, enc, 2, lo[1], sta_laz_clamp_u8(dlo + plo[1]));
        }
        if (used & 16) {
            int32_t d = (dlo + lo[1] - plo[1]) / 2;
            rgb_put(s, enc, 4, lo[2], sta_laz_clamp_u8(d + plo[2]));
        }
        if (used & 8) {
            rgb_put(s, enc, 3, hi[1], sta_laz_clamp_u8(dhi + phi[1]));
        }
        if (used & 32) {
            int32_t d = (dhi + hi[1] - phi[1]) / 2;
            rgb_put(s, enc, 5, hi[2], sta_laz_clamp_u8(d + phi[2]));
        }
    }
    for (int i = 0; i < 3; i++) {
        s->last[i] = sta_load_u16le(item + 2 * i);
    }
}

static void rgb_destroy(void *state)
{
    rgb *s = state;
    sta_laz_model_destroy(s->m_used);
    for (int i = 0; i < 6; i++) {
        sta_laz_model_destroy(s->m_diff[i]);
    }
    free(s);
}

static void *rgb_create(void)
{
    rgb *s = lazenc_zalloc(sizeof(*s));
    s->m_used = lazenc_model(128);
    for (int i = 0; i < 6; i++) {
        s->m_diff[i] = lazenc_model(256);
    }
    return s;
}

// ---- BYTE ----

typedef struct bytes {
    size_t count;
    uint8_t *last;
    sta_laz_model **m;
} bytes;

static void bytes_begin(void *state, const uint8_t *first)
{
    bytes *s = state;
    for (size_t i = 0; i < s->count; i++) {
        sta_laz_model_reset(s->m[i]);
    }
    memcpy(s->last, first, s->count);
}

static void bytes_encode(void *state, lazenc_arith *enc, const uint8_t *item)
{
    bytes *s = state;
    for (size_t i = 0; i < s->count; i++) {
        lazenc_encode_symbol(enc, s->m[i], sta_laz_fold_u8((int32_t)item[i] - (int32_t)s->last[i]));
    }
    memcpy(s->last, item, s->count);
}

static void bytes_destroy(void *state)
{
    bytes *s = state;
    for (size_t i = 0; i < s->count; i++) {
        sta_laz_model_destroy(s->m[i]);
    }
    free(s->m);
    free(s->last);
    free(s);
}

static void *bytes_create(size_t count)
{
    bytes *s = lazenc_zalloc(sizeof(*s));
    s->count = count;
    s->last = lazenc_zalloc(count);
    s->m = lazenc_zalloc(count * sizeof(*s->m));
    for (size_t i = 0; i < count; i++) {
        s->m[i] = lazenc_model(256);
    }
    return s;
}

bool lazenc_point10_v2_item(const sta_laz_item *item, lazenc_seq_item *out)
{
    if (item->version != 2) {
        return false;
    }
    switch (item->type) {
    case STA_LAZ_ITEM_POINT10:
        *out = (lazenc_seq_item){ p10_create(), p10_begin, p10_encode, p10_destroy };
        return true;
    case STA_LAZ_ITEM_GPSTIME11:
        *out = (lazenc_seq_item){ gps_create(), gps_begin, gps_encode, gps_destroy };
        return true;
    case STA_LAZ_ITEM_RGB12:
        *out = (lazenc_seq_item){ rgb_create(), rgb_begin, rgb_encode, rgb_destroy };
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
