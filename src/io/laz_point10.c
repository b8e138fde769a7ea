/* SPDX-License-Identifier: MIT
 * LAZ point10 family item decoders, version 2: POINT10 (the 20 bytes every format
 * 0-5 record starts with), GPSTIME11, RGB12 and BYTE (extra bytes); and the family's
 * record decoder, which runs the items in record order (version 1 items and
 * WAVEPACKET13 live in laz_point10_v1.c).
 *
 * Design: each item keeps the last decoded record of its chunk and predicts the next
 * from it. POINT10: a 6-bit mask says which of the flag byte, intensity,
 * classification, scan angle, user data and point source ID changed; x and y are
 * predicted by the median of the last five differences of the same return class, z
 * by the last z of the same return level. GPSTIME11: up to four interleaved time
 * sequences, each predicted as a multiple of its last difference (the predictor it
 * shares with POINT14, laz_gpstime.c). RGB12: per-byte changes predicted from the red
 * channel's change. BYTE: per-byte differences.
 * The models of flag byte, classification and user data depend on the previous value
 * (256 possible models each) and are allocated on first use, then kept for the next
 * chunks (reset at each chunk start; sta_laz_context_model in laz_arith.c, which the
 * version 1 items use too).
 *
 * Based on: M. Isenburg, "LASzip: lossless compression of LiDAR data", PE&RS 79(2),
 * 2013, sections on the point, GPS time and RGB predictors; the LAZ specification's
 * description of the version 2 items.
 */
#include <string.h>

#include "core/alloc.h"
#include "core/bytes.h"
#include "io/laz_gpstime.h"
#include "io/laz_internal.h"
#include "io/laz_predict.h"

enum {
    GPS_MAX_SWITCHES = 4, // a valid stream switches sequence at most once per point
};

// Return class m of (number of returns n, return number r): single returns, first
// and last of many, intermediate ones... each has its own x/y/intensity history.
static const uint8_t return_map[8][8] = {
    { 15, 14, 13, 12, 11, 10, 9, 8 },  { 14, 0, 1, 3, 6, 10, 10, 9 },
    { 13, 1, 2, 4, 7, 11, 11, 10 },    { 12, 3, 4, 5, 8, 12, 12, 11 },
    { 11, 6, 7, 8, 9, 13, 13, 12 },    { 10, 10, 11, 12, 13, 14, 14, 13 },
    { 9, 10, 11, 12, 13, 14, 15, 14 }, { 8, 9, 10, 11, 12, 13, 14, 15 },
};

typedef struct point10_state {
    uint8_t last[20];
    uint16_t last_intensity[16];
    median5 dx[16];
    median5 dy[16];
    int32_t last_height[8];
    sta_laz_model *m_changed;
    sta_laz_model *m_scan_angle[2];
    sta_laz_model *m_flags[256];     // by previous flag byte; lazily allocated
    sta_laz_model *m_class[256];     // by previous classification
    sta_laz_model *m_user_data[256]; // by previous user data
    uint8_t used_flags[32];          // bit set: model reset in this chunk
    uint8_t used_class[32];
    uint8_t used_user_data[32];
    sta_laz_ic ic_intensity;
    sta_laz_ic ic_source;
    sta_laz_ic ic_dx;
    sta_laz_ic ic_dy;
    sta_laz_ic ic_z;
} point10_state;

typedef struct rgb_state {
    uint16_t last[3];
    sta_laz_model *m_used;
    sta_laz_model *m_diff[6];
} rgb_state;

typedef struct byte_state {
    size_t count;
    uint8_t *last;
    sta_laz_model **m;
} byte_state;

// One item of the record, in record order.
typedef struct item_slot {
    uint16_t type;
    size_t at;           // byte offset in the record
    sta_laz_v1_item *v1; // version 1 item (laz_point10_v1.c), else NULL
} item_slot;

struct sta_laz_p10 {
    point10_state point;  // models allocated only when POINT10 is version 2
    sta_laz_gpstime *gps; // version 2 items; NULL when absent
    rgb_state *rgb;
    byte_state *bytes;
    size_t item_count;
    item_slot items[STA_LAZ_MAX_ITEMS];
};

// ---- POINT10 ----

static bool point10_create(point10_state *s)
{
    s->m_changed = sta_laz_model_create(64);
    s->m_scan_angle[0] = sta_laz_model_create(256);
    s->m_scan_angle[1] = sta_laz_model_create(256);
    return s->m_changed && s->m_scan_angle[0] && s->m_scan_angle[1] &&
           sta_laz_ic_init(&s->ic_intensity, 16, 4) && sta_laz_ic_init(&s->ic_source, 16, 1) &&
           sta_laz_ic_init(&s->ic_dx, 32, 2) && sta_laz_ic_init(&s->ic_dy, 32, 22) &&
           sta_laz_ic_init(&s->ic_z, 32, 20);
}

static void point10_release(point10_state *s)
{
    sta_laz_model_destroy(s->m_changed);
    sta_laz_model_destroy(s->m_scan_angle[0]);
    sta_laz_model_destroy(s->m_scan_angle[1]);
    for (int i = 0; i < 256; i++) {
        sta_laz_model_destroy(s->m_flags[i]);
        sta_laz_model_destroy(s->m_class[i]);
        sta_laz_model_destroy(s->m_user_data[i]);
    }
    sta_laz_ic_release(&s->ic_intensity);
    sta_laz_ic_release(&s->ic_source);
    sta_laz_ic_release(&s->ic_dx);
    sta_laz_ic_release(&s->ic_dy);
    sta_laz_ic_release(&s->ic_z);
}

static void point10_begin(point10_state *s, const uint8_t *first)
{
    for (int i = 0; i < 16; i++) {
        sta_laz_median_init(&s->dx[i]);
        sta_laz_median_init(&s->dy[i]);
        s->last_intensity[i] = 0;
    }
    memset(s->last_height, 0, sizeof(s->last_height));
    sta_laz_model_reset(s->m_changed);
    sta_laz_model_reset(s->m_scan_angle[0]);
    sta_laz_model_reset(s->m_scan_angle[1]);
    memset(s->used_flags, 0, sizeof(s->used_flags));
    memset(s->used_class, 0, sizeof(s->used_class));
    memset(s->used_user_data, 0, sizeof(s->used_user_data));
    sta_laz_ic_reset(&s->ic_intensity);
    sta_laz_ic_reset(&s->ic_source);
    sta_laz_ic_reset(&s->ic_dx);
    sta_laz_ic_reset(&s->ic_dy);
    sta_laz_ic_reset(&s->ic_z);
    memcpy(s->last, first, 20);
    // The intensity is predicted from last_intensity[], which starts at zero; so does
    // the intensity carried over when nothing changed.
    s->last[12] = 0;
    s->last[13] = 0;
}

static bool point10_decode(point10_state *s, sta_laz_dec *dec, uint8_t *out)
{
    uint8_t *last = s->last;
    uint32_t changed = sta_laz_decode_symbol(dec, s->m_changed);
    uint32_t r;
    uint32_t n;
    if (changed) {
        if (changed & 32) {
            sta_laz_model *m = sta_laz_context_model(s->m_flags, s->used_flags, last[14]);
            if (!m) {
                return false;
            }
            last[14] = (uint8_t)sta_laz_decode_symbol(dec, m);
        }
        r = last[14] & 7;
        n = (last[14] >> 3) & 7;
        uint32_t m = return_map[n][r];
        if (changed & 16) {
            uint16_t intensity = (uint16_t)sta_laz_ic_decode(&s->ic_intensity, dec,
                                                             s->last_intensity[m], m < 3 ? m : 3);
            s->last_intensity[m] = intensity;
        }
        sta_store_u16le(last + 12, s->last_intensity[m]);
        if (changed & 8) {
            sta_laz_model *model = sta_laz_context_model(s->m_class, s->used_class, last[15]);
            if (!model) {
                return false;
            }
            last[15] = (uint8_t)sta_laz_decode_symbol(dec, model);
        }
        if (changed & 4) {
            uint32_t direction = (last[14] >> 6) & 1;
            uint32_t delta = sta_laz_decode_symbol(dec, s->m_scan_angle[direction]);
            last[16] = sta_laz_fold_u8((int32_t)(delta + last[16]));
        }
        if (changed & 2) {
            sta_laz_model *model =
                sta_laz_context_model(s->m_user_data, s->used_user_data, last[17]);
            if (!model) {
                return false;
            }
            last[17] = (uint8_t)sta_laz_decode_symbol(dec, model);
        }
        if (changed & 1) {
            uint16_t source =
                (uint16_t)sta_laz_ic_decode(&s->ic_source, dec, sta_load_u16le(last + 18), 0);
            sta_store_u16le(last + 18, source);
        }
    } else {
        r = last[14] & 7;
        n = (last[14] >> 3) & 7;
    }
    uint32_t m = return_map[n][r];
    uint32_t l = n > r ? n - r : r - n; // return level |n - r|

    int32_t diff = sta_laz_ic_decode(&s->ic_dx, dec, s->dx[m].v[2], n == 1);
    sta_store_u32le(last + 0, sta_load_u32le(last + 0) + (uint32_t)diff);
    sta_laz_median_add(&s->dx[m], diff);

    uint32_t k_bits = s->ic_dx.k;
    diff = sta_laz_ic_decode(&s->ic_dy, dec, s->dy[m].v[2],
                             (n == 1) + (k_bits < 20 ? (k_bits & ~1u) : 20));
    sta_store_u32le(last + 4, sta_load_u32le(last + 4) + (uint32_t)diff);
    sta_laz_median_add(&s->dy[m], diff);

    k_bits = (s->ic_dx.k + s->ic_dy.k) / 2;
    int32_t z = sta_laz_ic_decode(&s->ic_z, dec, s->last_height[l],
                                  (n == 1) + (k_bits < 18 ? (k_bits & ~1u) : 18));
    sta_store_i32le(last + 8, z);
    s->last_height[l] = z;

    memcpy(out, last, 20);
    return true;
}

// ---- RGB12 ----

static bool rgb_create(rgb_state *s)
{
    s->m_used = sta_laz_model_create(128);
    bool ok = s->m_used != NULL;
    for (int i = 0; i < 6; i++) {
        s->m_diff[i] = sta_laz_model_create(256);
        ok = ok && s->m_diff[i];
    }
    return ok;
}

static void rgb_release(rgb_state *s)
{
    sta_laz_model_destroy(s->m_used);
    for (int i = 0; i < 6; i++) {
        sta_laz_model_destroy(s->m_diff[i]);
    }
}

static void rgb_begin(rgb_state *s, const uint8_t *first)
{
    sta_laz_model_reset(s->m_used);
    for (int i = 0; i < 6; i++) {
        sta_laz_model_reset(s->m_diff[i]);
    }
    for (int i = 0; i < 3; i++) {
        s->last[i] = sta_load_u16le(first + 2 * i);
    }
}

// One byte of a channel: the last value's byte plus a prediction, corrected.
static uint32_t rgb_byte(rgb_state *s, sta_laz_dec *dec, uint32_t model, int32_t predicted)
{
    uint32_t corr = sta_laz_decode_symbol(dec, s->m_diff[model]);
    return sta_laz_fold_u8((int32_t)corr + predicted);
}

static void rgb_decode(rgb_state *s, sta_laz_dec *dec, uint8_t *out)
{
    const uint16_t *last = s->last;
    uint16_t c[3];
    uint32_t used = sta_laz_decode_symbol(dec, s->m_used);
    uint32_t lo = (used & 1) ? rgb_byte(s, dec, 0, last[0] & 0xff) : (last[0] & 0xffu);
    uint32_t hi = (used & 2) ? rgb_byte(s, dec, 1, last[0] >> 8) : (last[0] >> 8);
    c[0] = (uint16_t)(lo | (hi << 8));
    if (used & 64) {
        int32_t diff = (int32_t)(c[0] & 0xff) - (int32_t)(last[0] & 0xff);
        uint32_t g_lo = (used & 4) ? rgb_byte(s, dec, 2, sta_laz_clamp_u8(diff + (last[1] & 0xff)))
                                   : (last[1] & 0xffu);
        uint32_t b_lo = last[2] & 0xffu;
        if (used & 16) {
            int32_t d = (diff + ((int32_t)g_lo - (int32_t)(last[1] & 0xff))) / 2;
            b_lo = rgb_byte(s, dec, 4, sta_laz_clamp_u8(d + (last[2] & 0xff)));
        }
        diff = (int32_t)(c[0] >> 8) - (int32_t)(last[0] >> 8);
        uint32_t g_hi = (used & 8) ? rgb_byte(s, dec, 3, sta_laz_clamp_u8(diff + (last[1] >> 8)))
                                   : (last[1] >> 8);
        uint32_t b_hi = last[2] >> 8;
        if (used & 32) {
            int32_t d = (diff + ((int32_t)g_hi - (int32_t)(last[1] >> 8))) / 2;
            b_hi = rgb_byte(s, dec, 5, sta_laz_clamp_u8(d + (last[2] >> 8)));
        }
        c[1] = (uint16_t)(g_lo | (g_hi << 8));
        c[2] = (uint16_t)(b_lo | (b_hi << 8));
    } else {
        c[1] = c[0];
        c[2] = c[0];
    }
    for (int i = 0; i < 3; i++) {
        s->last[i] = c[i];
        sta_store_u16le(out + 2 * i, c[i]);
    }
}

// ---- BYTE ----

static bool bytes_create(byte_state *s, size_t count)
{
    s->count = count;
    s->last = sta_malloc(count);
    s->m = sta_calloc(count, sizeof(*s->m));
    if (!s->last || !s->m) {
        return false;
    }
    for (size_t i = 0; i < count; i++) {
        s->m[i] = sta_laz_model_create(256);
        if (!s->m[i]) {
            return false;
        }
    }
    return true;
}

static void bytes_release(byte_state *s)
{
    if (s->m) {
        for (size_t i = 0; i < s->count; i++) {
            sta_laz_model_destroy(s->m[i]);
        }
    }
    sta_free(s->m);
    sta_free(s->last);
}

static void bytes_begin(byte_state *s, const uint8_t *first)
{
    for (size_t i = 0; i < s->count; i++) {
        sta_laz_model_reset(s->m[i]);
    }
    memcpy(s->last, first, s->count);
}

static void bytes_decode(byte_state *s, sta_laz_dec *dec, uint8_t *out)
{
    for (size_t i = 0; i < s->count; i++) {
        uint32_t delta = sta_laz_decode_symbol(dec, s->m[i]);
        s->last[i] = sta_laz_fold_u8((int32_t)(delta + s->last[i]));
    }
    memcpy(out, s->last, s->count);
}

// ---- the family ----

sta_laz_p10 *sta_laz_p10_create(const sta_laz_vlr *vlr)
{
    sta_laz_p10 *state = sta_calloc(1, sizeof(*state));
    if (!state) {
        return NULL;
    }
    bool ok = true;
    size_t at = 0;
    for (size_t i = 0; i < vlr->item_count && ok; i++) {
        const sta_laz_item *item = &vlr->items[i];
        item_slot *slot = &state->items[i];
        slot->type = item->type;
        slot->at = at;
        state->item_count = i + 1;
        at += item->size;
        if (item->version == 1) { // checked by sta_laz_parse_vlr, as the types are
            slot->v1 = sta_laz_v1_item_create(item);
            ok = slot->v1 != NULL;
            continue;
        }
        switch (item->type) {
        case STA_LAZ_ITEM_POINT10:
            ok = point10_create(&state->point);
            break;
        case STA_LAZ_ITEM_GPSTIME11:
            state->gps = sta_calloc(1, sizeof(*state->gps));
            ok = state->gps && sta_laz_gpstime_init(state->gps, true);
            break;
        case STA_LAZ_ITEM_RGB12:
            state->rgb = sta_calloc(1, sizeof(*state->rgb));
            ok = state->rgb && rgb_create(state->rgb);
            break;
        default: // BYTE
            state->bytes = sta_calloc(1, sizeof(*state->bytes));
            ok = state->bytes && bytes_create(state->bytes, item->size);
            break;
        }
    }
    if (!ok) {
        sta_laz_p10_destroy(state);
        return NULL;
    }
    return state;
}

void sta_laz_p10_destroy(sta_laz_p10 *state)
{
    if (!state) {
        return;
    }
    point10_release(&state->point);
    for (size_t i = 0; i < state->item_count; i++) {
        sta_laz_v1_item_destroy(state->items[i].v1);
    }
    if (state->gps) {
        sta_laz_gpstime_release(state->gps);
        sta_free(state->gps);
    }
    if (state->rgb) {
        rgb_release(state->rgb);
        sta_free(state->rgb);
    }
    if (state->bytes) {
        bytes_release(state->bytes);
        sta_free(state->bytes);
    }
    sta_free(state);
}

void sta_laz_p10_begin(sta_laz_p10 *state, const uint8_t *first)
{
    for (size_t i = 0; i < state->item_count; i++) {
        const item_slot *slot = &state->items[i];
        const uint8_t *p = first + slot->at;
        if (slot->v1) {
            sta_laz_v1_item_begin(slot->v1, p);
            continue;
        }
        switch (slot->type) {
        case STA_LAZ_ITEM_POINT10:
            point10_begin(&state->point, p);
            break;
        case STA_LAZ_ITEM_GPSTIME11:
            sta_laz_gpstime_begin(state->gps, sta_load_u64le(p));
            break;
        case STA_LAZ_ITEM_RGB12:
            rgb_begin(state->rgb, p);
            break;
        default:
            bytes_begin(state->bytes, p);
            break;
        }
    }
}

bool sta_laz_p10_decode(sta_laz_p10 *state, sta_laz_dec *dec, uint8_t *record)
{
    // Every item reads the same stream, in record order.
    for (size_t i = 0; i < state->item_count; i++) {
        const item_slot *slot = &state->items[i];
        uint8_t *p = record + slot->at;
        if (slot->v1) {
            if (!sta_laz_v1_item_decode(slot->v1, dec, p)) {
                return false;
            }
            continue;
        }
        switch (slot->type) {
        case STA_LAZ_ITEM_POINT10:
            if (!point10_decode(&state->point, dec, p)) {
                return false;
            }
            break;
        case STA_LAZ_ITEM_GPSTIME11:
            // GPSTIME11 does not treat endless sequence switching (corrupt) as an
            // error: the point keeps the time of the sequence switched to.
            (void)sta_laz_gpstime_decode(state->gps, dec, GPS_MAX_SWITCHES);
            sta_store_u64le(p, sta_laz_gpstime_last(state->gps));
            break;
        case STA_LAZ_ITEM_RGB12:
            rgb_decode(state->rgb, dec, p);
            break;
        default:
            bytes_decode(state->bytes, dec, p);
            break;
        }
    }
    return true;
}
