/* SPDX-License-Identifier: MIT
 * LAZ point10 family item decoders, version 1 (files written by LASzip 1.x):
 * POINT10, GPSTIME11, RGB12, WAVEPACKET13 (formats 4 and 5) and BYTE (extra bytes).
 * WAVEPACKET13 exists only as version 1, so it also appears next to version 2 items.
 *
 * Design: like version 2, each item predicts the next record from the last one of the
 * chunk, but with simpler predictors and more integer correctors:
 * - POINT10: x, y, z come first, x and y as the median of the last three differences
 *   (one history, no return classes), z as the last z; y's corrector context is the
 *   magnitude class k of x's correction (capped at 19), z's the mean of both k. Then a
 *   6-bit mask (32 intensity, 16 flag byte, 8 classification, 4 scan angle, 2 user
 *   data, 1 point source) and the changed fields: intensity, scan angle and point
 *   source through correctors from their last value, the other bytes through a
 *   256-symbol model chosen by their last value (lazily allocated, reset per chunk).
 * - GPSTIME11: one time sequence; the difference of the raw 64-bit patterns is
 *   predicted as a multiple (0..509, 0 meaning a quarter) of the last difference;
 *   symbol 510 sends the time in full, 511 means unchanged.
 * - RGB12: a mask of the six bytes that changed, each coded from its last value.
 * - WAVEPACKET13: the descriptor index as a symbol; the offset as unchanged, last
 *   offset plus last packet size, last plus a coded 32-bit difference, or in full
 *   (a 4-symbol model per previous choice); size, return point location and the x, y,
 *   z(t) float bit patterns from their last values.
 * - BYTE: every byte from its last value, one corrector context per byte.
 *
 * Based on: M. Isenburg, "LASzip: lossless compression of LiDAR data", PE&RS 79(2),
 * 2013; the item layouts, model sizes and contexts of LASzip's version 1 items
 * (LASzip 1.x, 2011) as the format fixes them.
 */
#include <string.h>

#include "core/alloc.h"
#include "core/bytes.h"
#include "io/laz_internal.h"
#include "io/laz_predict.h"

enum {
    GPS_MULTI_MAX = 512,                   // symbols of the multiplier model
    GPS_MULTI_EXTREME = GPS_MULTI_MAX - 3, // 509: the largest multiplier
    GPS_MULTI_FULL = GPS_MULTI_MAX - 2,    // 510: time sent in full
    WAVE_INDEX = 0,                        // byte offsets in the 29-byte item
    WAVE_OFFSET = 1,
    WAVE_SIZE = 9,
    WAVE_RETURN_POINT = 13,
    WAVE_X = 17,
    WAVE_BYTES = 29,
};

typedef struct point10_v1 {
    uint8_t last[20];
    int32_t last_dx[3]; // the last three x differences (ring)
    int32_t last_dy[3];
    uint32_t ring; // next slot of last_dx / last_dy
    sta_laz_model *m_changed;
    sta_laz_model *m_flags[256]; // by previous flag byte; lazily allocated
    sta_laz_model *m_class[256];
    sta_laz_model *m_user_data[256];
    uint8_t used_flags[32]; // bit set: model reset in this chunk
    uint8_t used_class[32];
    uint8_t used_user_data[32];
    sta_laz_ic ic_dx;
    sta_laz_ic ic_dy;
    sta_laz_ic ic_z;
    sta_laz_ic ic_intensity;
    sta_laz_ic ic_scan_angle;
    sta_laz_ic ic_source;
} point10_v1;

typedef struct gpstime_v1 {
    uint64_t last;     // raw bit pattern of the last time
    int32_t last_diff; // difference the multiples refer to
    uint32_t extreme;  // extreme multipliers in a row
    sta_laz_model *m_multi;
    sta_laz_model *m_zero_diff;
    sta_laz_ic ic;
} gpstime_v1;

typedef struct rgb_v1 {
    uint8_t last[6];
    sta_laz_model *m_used;
    sta_laz_ic ic;
} rgb_v1;

typedef struct wave_v1 {
    uint8_t last[WAVE_BYTES]; // byte 0 (the index) is not predicted
    int32_t last_diff;        // last coded offset difference
    uint32_t last_choice;     // previous offset choice (0..3)
    sta_laz_model *m_index;
    sta_laz_model *m_offset[4];
    sta_laz_ic ic_offset;
    sta_laz_ic ic_size;
    sta_laz_ic ic_return_point;
    sta_laz_ic ic_xyz;
} wave_v1;

typedef struct byte_v1 {
    size_t count;
    uint8_t *last;
    sta_laz_ic ic;
} byte_v1;

struct sta_laz_v1_item {
    uint16_t type;
    union {
        point10_v1 point;
        gpstime_v1 gps;
        rgb_v1 rgb;
        wave_v1 wave;
        byte_v1 bytes;
    } u;
};

static int32_t median3(const int32_t *v)
{
    int32_t lo = v[0] < v[1] ? v[0] : v[1];
    int32_t hi = v[0] < v[1] ? v[1] : v[0];
    return v[2] < lo ? lo : (v[2] > hi ? hi : v[2]);
}

// ---- POINT10 ----

static bool point10_create(point10_v1 *s)
{
    s->m_changed = sta_laz_model_create(64);
    return s->m_changed && sta_laz_ic_init(&s->ic_dx, 32, 1) &&
           sta_laz_ic_init(&s->ic_dy, 32, 20) && sta_laz_ic_init(&s->ic_z, 32, 20) &&
           sta_laz_ic_init(&s->ic_intensity, 16, 1) && sta_laz_ic_init(&s->ic_scan_angle, 8, 2) &&
           sta_laz_ic_init(&s->ic_source, 16, 1);
}

static void point10_release(point10_v1 *s)
{
    sta_laz_model_destroy(s->m_changed);
    for (int i = 0; i < 256; i++) {
        sta_laz_model_destroy(s->m_flags[i]);
        sta_laz_model_destroy(s->m_class[i]);
        sta_laz_model_destroy(s->m_user_data[i]);
    }
    sta_laz_ic_release(&s->ic_dx);
    sta_laz_ic_release(&s->ic_dy);
    sta_laz_ic_release(&s->ic_z);
    sta_laz_ic_release(&s->ic_intensity);
    sta_laz_ic_release(&s->ic_scan_angle);
    sta_laz_ic_release(&s->ic_source);
}

static void point10_begin(point10_v1 *s, const uint8_t *first)
{
    memcpy(s->last, first, 20);
    memset(s->last_dx, 0, sizeof(s->last_dx));
    memset(s->last_dy, 0, sizeof(s->last_dy));
    s->ring = 0;
    sta_laz_model_reset(s->m_changed);
    memset(s->used_flags, 0, sizeof(s->used_flags));
    memset(s->used_class, 0, sizeof(s->used_class));
    memset(s->used_user_data, 0, sizeof(s->used_user_data));
    sta_laz_ic_reset(&s->ic_dx);
    sta_laz_ic_reset(&s->ic_dy);
    sta_laz_ic_reset(&s->ic_z);
    sta_laz_ic_reset(&s->ic_intensity);
    sta_laz_ic_reset(&s->ic_scan_angle);
    sta_laz_ic_reset(&s->ic_source);
}

// A byte coded by the model of its previous value; false when out of memory.
static bool context_byte(sta_laz_dec *dec, sta_laz_model **models, uint8_t *used, uint8_t *value)
{
    sta_laz_model *m = sta_laz_context_model(models, used, *value);
    if (!m) {
        return false;
    }
    *value = (uint8_t)sta_laz_decode_symbol(dec, m);
    return true;
}

static bool point10_decode(point10_v1 *s, sta_laz_dec *dec, uint8_t *out)
{
    uint8_t *last = s->last;
    int32_t dx = sta_laz_ic_decode(&s->ic_dx, dec, median3(s->last_dx), 0);
    sta_store_u32le(last + 0, sta_load_u32le(last + 0) + (uint32_t)dx);
    uint32_t k = s->ic_dx.k;
    int32_t dy = sta_laz_ic_decode(&s->ic_dy, dec, median3(s->last_dy), k < 19 ? k : 19);
    sta_store_u32le(last + 4, sta_load_u32le(last + 4) + (uint32_t)dy);
    k = (k + s->ic_dy.k) / 2;
    int32_t z = sta_laz_ic_decode(&s->ic_z, dec, sta_load_i32le(last + 8), k < 19 ? k : 19);
    sta_store_i32le(last + 8, z);

    uint32_t changed = sta_laz_decode_symbol(dec, s->m_changed);
    if (changed & 32) {
        int32_t v = sta_laz_ic_decode(&s->ic_intensity, dec, sta_load_u16le(last + 12), 0);
        sta_store_u16le(last + 12, (uint16_t)v);
    }
    if ((changed & 16) && !context_byte(dec, s->m_flags, s->used_flags, &last[14])) {
        return false;
    }
    if ((changed & 8) && !context_byte(dec, s->m_class, s->used_class, &last[15])) {
        return false;
    }
    if (changed & 4) {
        last[16] = (uint8_t)sta_laz_ic_decode(&s->ic_scan_angle, dec, last[16], k < 3);
    }
    if ((changed & 2) && !context_byte(dec, s->m_user_data, s->used_user_data, &last[17])) {
        return false;
    }
    if (changed & 1) {
        int32_t v = sta_laz_ic_decode(&s->ic_source, dec, sta_load_u16le(last + 18), 0);
        sta_store_u16le(last + 18, (uint16_t)v);
    }
    s->last_dx[s->ring] = dx;
    s->last_dy[s->ring] = dy;
    s->ring = s->ring == 2 ? 0 : s->ring + 1;
    memcpy(out, last, 20);
    return true;
}

// ---- GPSTIME11 ----

static bool gpstime_create(gpstime_v1 *s)
{
    s->m_multi = sta_laz_model_create(GPS_MULTI_MAX);
    s->m_zero_diff = sta_laz_model_create(3);
    return s->m_multi && s->m_zero_diff && sta_laz_ic_init(&s->ic, 32, 6);
}

static void gpstime_release(gpstime_v1 *s)
{
    sta_laz_model_destroy(s->m_multi);
    sta_laz_model_destroy(s->m_zero_diff);
    sta_laz_ic_release(&s->ic);
}

static void gpstime_begin(gpstime_v1 *s, const uint8_t *first)
{
    s->last = sta_load_u64le(first);
    s->last_diff = 0;
    s->extreme = 0;
    sta_laz_model_reset(s->m_multi);
    sta_laz_model_reset(s->m_zero_diff);
    sta_laz_ic_reset(&s->ic);
}

static uint64_t read_u64(sta_laz_dec *dec)
{
    uint64_t low = sta_laz_read_u32(dec);
    uint64_t high = sta_laz_read_u32(dec);
    return (high << 32) | low;
}

// Counts an extreme multiplier; after more than three in a row `diff` becomes the base.
static void gpstime_extreme(gpstime_v1 *s, int32_t diff)
{
    if (++s->extreme > 3) {
        s->last_diff = diff;
        s->extreme = 0;
    }
}

static void gpstime_decode(gpstime_v1 *s, sta_laz_dec *dec, uint8_t *out)
{
    if (s->last_diff == 0) {
        uint32_t sym = sta_laz_decode_symbol(dec, s->m_zero_diff);
        if (sym == 1) {
            s->last_diff = sta_laz_ic_decode(&s->ic, dec, 0, 0);
            s->last += (uint64_t)(int64_t)s->last_diff;
        } else if (sym == 2) {
            s->last = read_u64(dec);
        }
    } else {
        uint32_t multi = sta_laz_decode_symbol(dec, s->m_multi);
        if (multi < GPS_MULTI_FULL) {
            // Multiples wrap in 32 bits, as the writer computed them.
            uint32_t pred = multi * (uint32_t)s->last_diff;
            int32_t diff;
            if (multi == 1) {
                diff = sta_laz_ic_decode(&s->ic, dec, s->last_diff, 1);
                s->last_diff = diff;
                s->extreme = 0;
            } else if (multi == 0) {
                diff = sta_laz_ic_decode(&s->ic, dec, s->last_diff / 4, 2);
                gpstime_extreme(s, diff);
            } else {
                uint32_t context = multi < 10 ? 3 : (multi < 50 ? 4 : 5);
                diff = sta_laz_ic_decode(&s->ic, dec, (int32_t)pred, context);
                if (multi == GPS_MULTI_EXTREME) {
                    gpstime_extreme(s, diff);
                }
            }
            s->last += (uint64_t)(int64_t)diff;
        } else if (multi == GPS_MULTI_FULL) {
            s->last = read_u64(dec);
        }
        // GPS_MULTI_MAX - 1: unchanged.
    }
    sta_store_u64le(out, s->last);
}

// ---- RGB12 ----

static bool rgb_create(rgb_v1 *s)
{
    s->m_used = sta_laz_model_create(64);
    return s->m_used && sta_laz_ic_init(&s->ic, 8, 6);
}

static void rgb_release(rgb_v1 *s)
{
    sta_laz_model_destroy(s->m_used);
    sta_laz_ic_release(&s->ic);
}

static void rgb_begin(rgb_v1 *s, const uint8_t *first)
{
    memcpy(s->last, first, 6);
    sta_laz_model_reset(s->m_used);
    sta_laz_ic_reset(&s->ic);
}

static void rgb_decode(rgb_v1 *s, sta_laz_dec *dec, uint8_t *out)
{
    uint32_t used = sta_laz_decode_symbol(dec, s->m_used);
    // Bit i: byte i of the record (red low, red high, green low, ...).
    for (uint32_t i = 0; i < 6; i++) {
        if (used & (1u << i)) {
            s->last[i] = (uint8_t)sta_laz_ic_decode(&s->ic, dec, s->last[i], i);
        }
    }
    memcpy(out, s->last, 6);
}

// ---- WAVEPACKET13 ----

static bool wave_create(wave_v1 *s)
{
    bool ok = (s->m_index = sta_laz_model_create(256)) != NULL;
    for (int i = 0; i < 4; i++) {
        ok = ok && (s->m_offset[i] = sta_laz_model_create(4)) != NULL;
    }
    return ok && sta_laz_ic_init(&s->ic_offset, 32, 1) && sta_laz_ic_init(&s->ic_size, 32, 1) &&
           sta_laz_ic_init(&s->ic_return_point, 32, 1) && sta_laz_ic_init(&s->ic_xyz, 32, 3);
}

static void wave_release(wave_v1 *s)
{
    sta_laz_model_destroy(s->m_index);
    for (int i = 0; i < 4; i++) {
        sta_laz_model_destroy(s->m_offset[i]);
    }
    sta_laz_ic_release(&s->ic_offset);
    sta_laz_ic_release(&s->ic_size);
    sta_laz_ic_release(&s->ic_return_point);
    sta_laz_ic_release(&s->ic_xyz);
}

static void wave_begin(wave_v1 *s, const uint8_t *first)
{
    memcpy(s->last, first, WAVE_BYTES);
    s->last_diff = 0;
    s->last_choice = 0;
    sta_laz_model_reset(s->m_index);
    for (int i = 0; i < 4; i++) {
        sta_laz_model_reset(s->m_offset[i]);
    }
    sta_laz_ic_reset(&s->ic_offset);
    sta_laz_ic_reset(&s->ic_size);
    sta_laz_ic_reset(&s->ic_return_point);
    sta_laz_ic_reset(&s->ic_xyz);
}

static void wave_decode(wave_v1 *s, sta_laz_dec *dec, uint8_t *out)
{
    uint8_t *last = s->last;
    last[WAVE_INDEX] = (uint8_t)sta_laz_decode_symbol(dec, s->m_index);
    s->last_choice = sta_laz_decode_symbol(dec, s->m_offset[s->last_choice & 3]) & 3;
    uint64_t offset = sta_load_u64le(last + WAVE_OFFSET);
    uint32_t size = sta_load_u32le(last + WAVE_SIZE);
    if (s->last_choice == 1) {
        offset += size;
    } else if (s->last_choice == 2) {
        s->last_diff = sta_laz_ic_decode(&s->ic_offset, dec, s->last_diff, 0);
        offset += (uint64_t)(int64_t)s->last_diff;
    } else if (s->last_choice == 3) {
        offset = read_u64(dec);
    }
    sta_store_u64le(last + WAVE_OFFSET, offset);
    size = (uint32_t)sta_laz_ic_decode(&s->ic_size, dec, (int32_t)size, 0);
    sta_store_u32le(last + WAVE_SIZE, size);
    int32_t v = sta_load_i32le(last + WAVE_RETURN_POINT);
    sta_store_i32le(last + WAVE_RETURN_POINT, sta_laz_ic_decode(&s->ic_return_point, dec, v, 0));
    for (uint32_t i = 0; i < 3; i++) {
        uint8_t *p = last + WAVE_X + 4 * i;
        sta_store_i32le(p, sta_laz_ic_decode(&s->ic_xyz, dec, sta_load_i32le(p), i));
    }
    memcpy(out, last, WAVE_BYTES);
}

// ---- BYTE ----

static bool bytes_create(byte_v1 *s, size_t count)
{
    s->count = count;
    s->last = sta_malloc(count);
    return s->last && sta_laz_ic_init(&s->ic, 8, (uint32_t)count);
}

static void bytes_release(byte_v1 *s)
{
    sta_free(s->last);
    sta_laz_ic_release(&s->ic);
}

static void bytes_begin(byte_v1 *s, const uint8_t *first)
{
    memcpy(s->last, first, s->count);
    sta_laz_ic_reset(&s->ic);
}

static void bytes_decode(byte_v1 *s, sta_laz_dec *dec, uint8_t *out)
{
    for (size_t i = 0; i < s->count; i++) {
        s->last[i] = (uint8_t)sta_laz_ic_decode(&s->ic, dec, s->last[i], (uint32_t)i);
    }
    memcpy(out, s->last, s->count);
}

// ---- the item ----

sta_laz_v1_item *sta_laz_v1_item_create(const sta_laz_item *item)
{
    sta_laz_v1_item *s = sta_calloc(1, sizeof(*s));
    if (!s) {
        return NULL;
    }
    s->type = item->type;
    bool ok = false;
    switch (item->type) {
    case STA_LAZ_ITEM_POINT10:
        ok = point10_create(&s->u.point);
        break;
    case STA_LAZ_ITEM_GPSTIME11:
        ok = gpstime_create(&s->u.gps);
        break;
    case STA_LAZ_ITEM_RGB12:
        ok = rgb_create(&s->u.rgb);
        break;
    case STA_LAZ_ITEM_WAVEPACKET13:
        ok = wave_create(&s->u.wave);
        break;
    default: // BYTE (sta_laz_parse_vlr admits nothing else)
        s->type = STA_LAZ_ITEM_BYTE;
        ok = item->size > 0 && bytes_create(&s->u.bytes, item->size);
        break;
    }
    if (!ok) {
        sta_laz_v1_item_destroy(s);
        return NULL;
    }
    return s;
}

void sta_laz_v1_item_destroy(sta_laz_v1_item *s)
{
    if (!s) {
        return;
    }
    switch (s->type) {
    case STA_LAZ_ITEM_POINT10:
        point10_release(&s->u.point);
        break;
    case STA_LAZ_ITEM_GPSTIME11:
        gpstime_release(&s->u.gps);
        break;
    case STA_LAZ_ITEM_RGB12:
        rgb_release(&s->u.rgb);
        break;
    case STA_LAZ_ITEM_WAVEPACKET13:
        wave_release(&s->u.wave);
        break;
    default:
        bytes_release(&s->u.bytes);
        break;
    }
    sta_free(s);
}

void sta_laz_v1_item_begin(sta_laz_v1_item *s, const uint8_t *first)
{
    switch (s->type) {
    case STA_LAZ_ITEM_POINT10:
        point10_begin(&s->u.point, first);
        break;
    case STA_LAZ_ITEM_GPSTIME11:
        gpstime_begin(&s->u.gps, first);
        break;
    case STA_LAZ_ITEM_RGB12:
        rgb_begin(&s->u.rgb, first);
        break;
    case STA_LAZ_ITEM_WAVEPACKET13:
        wave_begin(&s->u.wave, first);
        break;
    default:
        bytes_begin(&s->u.bytes, first);
        break;
    }
}

bool sta_laz_v1_item_decode(sta_laz_v1_item *s, sta_laz_dec *dec, uint8_t *out)
{
    switch (s->type) {
    case STA_LAZ_ITEM_POINT10:
        return point10_decode(&s->u.point, dec, out);
    case STA_LAZ_ITEM_GPSTIME11:
        gpstime_decode(&s->u.gps, dec, out);
        return true;
    case STA_LAZ_ITEM_RGB12:
        rgb_decode(&s->u.rgb, dec, out);
        return true;
    case STA_LAZ_ITEM_WAVEPACKET13:
        wave_decode(&s->u.wave, dec, out);
        return true;
    default:
        bytes_decode(&s->u.bytes, dec, out);
        return true;
    }
}
