/* SPDX-License-Identifier: MIT
 * LAZ point14 family item decoders, versions 3 and 4 (layered chunks): POINT14 (the 30
 * bytes every format 6-10 record starts with), RGB14, RGBNIR14, WAVEPACKET14 (formats
 * 9 and 10) and BYTE14 (extra bytes).
 *
 * Design: a layered chunk holds the first record raw, the chunk's point count, the
 * byte count of every layer, then the layers: each an arithmetic-coded stream of one
 * group of fields, so a field that never changes in the chunk costs an empty layer.
 * POINT14 has nine layers (scanner channel + returns + X/Y, Z, classification, flags,
 * intensity, scan angle, user data, point source, GPS time); RGB14 one, RGBNIR14 two
 * (RGB, NIR), BYTE14 one per extra byte. Every item keeps four contexts, one per
 * scanner channel, each with its own last record, predictors and models; a context
 * is initialised from the record of the previous context on its first use in a chunk.
 * Predictions follow point10: medians of the last five X/Y differences per return
 * class, last Z per return level, last intensity per return kind, GPS time as up to
 * four interleaved sequences predicted by multiples of their last difference (the
 * GPSTIME11 predictor, shared: laz_gpstime.c).
 * The symbol models whose context is a previous value are allocated on first use and
 * kept (reset when their context is initialised in a later chunk).
 * Versions 3 and 4 differ only in the items after POINT14: on a switch to a context
 * already used in the chunk, version 3 keeps predicting from (and updating) the last
 * record of the context left (the LASzip 3.x writer's behaviour, which its reader
 * mirrors), version 4 predicts from the new context's own last record (LASzip's
 * "context switch" fix of December 2017). One flag per item selects this.
 *
 * Based on: M. Isenburg, "LASzip: lossless compression of LiDAR data", PE&RS 79(2),
 * 2013; the LAZ specification's description of the LAS 1.4 "layered chunked"
 * compressor and its version 3 and 4 items (layers, contexts, context tables).
 */
#include <string.h>

#include "core/alloc.h"
#include "core/bytes.h"
#include "io/laz_gpstime.h"
#include "io/laz_internal.h"
#include "io/laz_predict.h"

enum {
    P14_LAYERS = 9,
    L_XY = 0,
    L_Z,
    L_CLASS,
    L_FLAGS,
    L_INTENSITY,
    L_SCAN_ANGLE,
    L_USER_DATA,
    L_SOURCE,
    L_GPS,
    CONTEXTS = 4,
    GPS_MAX_SWITCHES = 8, // a valid stream switches sequence at most once per point
};

// Return class (6 values) of (number of returns n, return number r), 16 x 16.
static const uint8_t return_map[16][16] = {
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

typedef struct layer {
    const uint8_t *p;
    uint32_t size;
    sta_laz_dec dec;
} layer;

// The last record of a context, as fields.
typedef struct p14_item {
    int32_t x, y, z;
    uint16_t intensity;
    uint8_t r, n;
    uint8_t class_flags, scan_dir, edge;
    uint8_t classification, user_data;
    int16_t scan_angle;
    uint16_t source;
    uint64_t gps; // bits of the double
    bool gps_change;
} p14_item;

typedef struct p14_context {
    bool unused;
    bool created;
    p14_item last;
    uint16_t last_intensity[8];
    median5 dx[12];
    median5 dy[12];
    int32_t last_z[8];
    sta_laz_gpstime gps; // the GPS time layer's predictor and models
    sta_laz_model *m_changed[8];
    sta_laz_model *m_channel;
    sta_laz_model *m_n[16];
    sta_laz_model *m_r[16];
    sta_laz_model *m_r_same;
    sta_laz_model *m_class[64];
    sta_laz_model *m_flags[64];
    sta_laz_model *m_user[64];
    sta_laz_ic ic_dx, ic_dy, ic_z, ic_intensity, ic_scan_angle, ic_source;
} p14_context;

// RGB14 / RGBNIR14 / WAVEPACKET14 / BYTE14: `size` bytes predicted per context.
typedef struct extra_context {
    bool unused;
    uint8_t last[8]; // RGB: 3 u16 (+ NIR); BYTE14: up to 8 here, more in `wide`
    uint8_t *wide;   // items of more than 8 bytes (wave packets, wide BYTE14)
    sta_laz_model *m_used;
    sta_laz_model *m_diff[6];
    sta_laz_model *m_nir_used;
    sta_laz_model *m_nir_diff[2];
    sta_laz_model **m_bytes; // BYTE14: one per byte
    // WAVEPACKET14: descriptor index, offset kind (by the last kind), correctors
    sta_laz_model *m_wp_index;
    sta_laz_model *m_wp_offset[4];
    sta_laz_ic ic_wp_offset, ic_wp_size, ic_wp_return, ic_wp_xyz;
    int32_t wp_last_diff;  // last offset difference coded by the corrector
    uint32_t wp_last_kind; // 0 same offset, 1 + last size, 2 coded difference, 3 raw
} extra_context;

typedef struct extra_item {
    uint16_t type;
    size_t at;   // offset in the record
    size_t size; // bytes
    size_t first_layer;
    uint32_t current;
    bool own_last; // version 4: a switch predicts from the new context's last record
    extra_context ctx[CONTEXTS];
} extra_item;

struct sta_laz_p14 {
    size_t layer_count;
    layer *layers;
    uint32_t current;
    bool bad; // corrupt stream detected (besides overruns)
    p14_context ctx[CONTEXTS];
    size_t extra_count;
    extra_item extras[STA_LAZ_MAX_ITEMS];
};

// A lazily created model: created on first use, reset when its context is initialised.
static sta_laz_model *lazy_model(sta_laz_model **slot, uint32_t symbols)
{
    if (!*slot) {
        *slot = sta_laz_model_create(symbols);
    }
    return *slot;
}

static void reset_if(sta_laz_model *m)
{
    if (m) {
        sta_laz_model_reset(m);
    }
}

// ---- POINT14 ----

static void item_from_record(p14_item *it, const uint8_t *rec)
{
    it->x = sta_load_i32le(rec);
    it->y = sta_load_i32le(rec + 4);
    it->z = sta_load_i32le(rec + 8);
    it->intensity = sta_load_u16le(rec + 12);
    it->r = rec[14] & 15;
    it->n = rec[14] >> 4;
    it->class_flags = rec[15] & 15;
    it->scan_dir = (rec[15] >> 6) & 1;
    it->edge = rec[15] >> 7;
    it->classification = rec[16];
    it->user_data = rec[17];
    it->scan_angle = sta_load_i16le(rec + 18);
    it->source = sta_load_u16le(rec + 20);
    it->gps = sta_load_u64le(rec + 22);
    it->gps_change = false;
}

static void item_to_record(const p14_item *it, uint32_t channel, uint8_t *rec)
{
    sta_store_i32le(rec, it->x);
    sta_store_i32le(rec + 4, it->y);
    sta_store_i32le(rec + 8, it->z);
    sta_store_u16le(rec + 12, it->intensity);
    rec[14] = (uint8_t)(it->r | (it->n << 4));
    rec[15] = (uint8_t)(it->class_flags | (channel << 4) | (it->scan_dir << 6) | (it->edge << 7));
    rec[16] = it->classification;
    rec[17] = it->user_data;
    sta_store_i16le(rec + 18, it->scan_angle);
    sta_store_u16le(rec + 20, it->source);
    sta_store_u64le(rec + 22, it->gps);
}

static bool context_create(p14_context *c)
{
    for (int i = 0; i < 8; i++) {
        if (!(c->m_changed[i] = sta_laz_model_create(128))) {
            return false;
        }
    }
    c->m_channel = sta_laz_model_create(3);
    c->m_r_same = sta_laz_model_create(13);
    if (!c->m_channel || !c->m_r_same || !sta_laz_gpstime_init(&c->gps, false)) {
        return false;
    }
    c->created = sta_laz_ic_init(&c->ic_dx, 32, 2) && sta_laz_ic_init(&c->ic_dy, 32, 22) &&
                 sta_laz_ic_init(&c->ic_z, 32, 20) && sta_laz_ic_init(&c->ic_intensity, 16, 4) &&
                 sta_laz_ic_init(&c->ic_scan_angle, 16, 2) && sta_laz_ic_init(&c->ic_source, 16, 1);
    return c->created;
}

static void context_release(p14_context *c)
{
    sta_laz_model **all[] = { c->m_changed, &c->m_channel, c->m_n,     c->m_r,
                              &c->m_r_same, c->m_class,    c->m_flags, c->m_user };
    static const size_t counts[] = { 8, 1, 16, 16, 1, 64, 64, 64 };
    for (size_t a = 0; a < sizeof(counts) / sizeof(counts[0]); a++) {
        for (size_t i = 0; i < counts[a]; i++) {
            sta_laz_model_destroy(all[a][i]);
        }
    }
    sta_laz_ic *ics[] = { &c->ic_dx,        &c->ic_dy,         &c->ic_z,
                          &c->ic_intensity, &c->ic_scan_angle, &c->ic_source };
    for (size_t i = 0; i < sizeof(ics) / sizeof(ics[0]); i++) {
        sta_laz_ic_release(ics[i]);
    }
    sta_laz_gpstime_release(&c->gps);
    *c = (p14_context){ .unused = true };
}

// Initialises context `c` (first use in a chunk) from the record `from`.
static bool context_init(p14_context *c, const p14_item *from)
{
    if (!c->created && !context_create(c)) {
        context_release(c); // partly created: start over next time
        return false;
    }
    for (int i = 0; i < 8; i++) {
        sta_laz_model_reset(c->m_changed[i]);
    }
    sta_laz_model_reset(c->m_channel);
    for (int i = 0; i < 16; i++) {
        reset_if(c->m_n[i]);
        reset_if(c->m_r[i]);
    }
    sta_laz_model_reset(c->m_r_same);
    for (int i = 0; i < 64; i++) {
        reset_if(c->m_class[i]);
        reset_if(c->m_flags[i]);
        reset_if(c->m_user[i]);
    }
    sta_laz_ic_reset(&c->ic_dx);
    sta_laz_ic_reset(&c->ic_dy);
    sta_laz_ic_reset(&c->ic_z);
    sta_laz_ic_reset(&c->ic_intensity);
    sta_laz_ic_reset(&c->ic_scan_angle);
    sta_laz_ic_reset(&c->ic_source);
    for (int i = 0; i < 12; i++) {
        sta_laz_median_init(&c->dx[i]);
        sta_laz_median_init(&c->dy[i]);
    }
    for (int i = 0; i < 8; i++) {
        c->last_z[i] = from->z;
        c->last_intensity[i] = from->intensity;
    }
    sta_laz_gpstime_begin(&c->gps, from->gps);
    c->last = *from;
    c->last.gps_change = false;
    c->unused = false;
    return true;
}

static bool point14_decode(sta_laz_p14 *s, uint8_t *out)
{
    layer *L = s->layers;
    if (L[L_XY].size == 0) { // points after the first need this layer
        s->bad = true;
        return true;
    }
    p14_context *c = &s->ctx[s->current];
    p14_item *last = &c->last;
    sta_laz_dec *dxy = &L[L_XY].dec;

    uint32_t lpr =
        (last->r == 1 ? 1u : 0u) + (last->r >= last->n ? 2u : 0u) + (last->gps_change ? 4u : 0u);
    uint32_t changed = sta_laz_decode_symbol(dxy, c->m_changed[lpr]);
    if (changed & (1u << 6)) {
        uint32_t diff = sta_laz_decode_symbol(dxy, c->m_channel);
        uint32_t channel = (s->current + diff + 1) % CONTEXTS;
        if (s->ctx[channel].unused && !context_init(&s->ctx[channel], last)) {
            return false;
        }
        s->current = channel;
        c = &s->ctx[channel];
        last = &c->last;
    }
    bool source_change = (changed & (1u << 5)) != 0;
    bool gps_change = (changed & (1u << 4)) != 0;
    bool scan_angle_change = (changed & (1u << 3)) != 0;

    uint32_t n = last->n;
    uint32_t last_r = last->r;
    if (changed & (1u << 2)) {
        sta_laz_model *m = lazy_model(&c->m_n[n], 16);
        if (!m) {
            return false;
        }
        n = sta_laz_decode_symbol(dxy, m);
        last->n = (uint8_t)n;
    }
    uint32_t r;
    switch (changed & 3) {
    case 0:
        r = last_r;
        break;
    case 1:
        r = (last_r + 1) % 16;
        break;
    case 2:
        r = (last_r + 15) % 16;
        break;
    default:
        if (gps_change) {
            sta_laz_model *m = lazy_model(&c->m_r[last_r], 16);
            if (!m) {
                return false;
            }
            r = sta_laz_decode_symbol(dxy, m);
        } else {
            r = (last_r + sta_laz_decode_symbol(dxy, c->m_r_same) + 2) % 16;
        }
        break;
    }
    last->r = (uint8_t)r;

    uint32_t m = return_map[n][r];
    uint32_t level = n > r ? n - r : r - n;
    if (level > 7) {
        level = 7;
    }
    uint32_t cpr = (r == 1 ? 2u : 0u) + (r >= n ? 1u : 0u);
    uint32_t single = n == 1 ? 1u : 0u;

    uint32_t idx = (m << 1) | (gps_change ? 1u : 0u);
    int32_t diff = sta_laz_ic_decode(&c->ic_dx, dxy, c->dx[idx].v[2], single);
    last->x = (int32_t)((uint32_t)last->x + (uint32_t)diff);
    sta_laz_median_add(&c->dx[idx], diff);
    uint32_t k = c->ic_dx.k;
    diff = sta_laz_ic_decode(&c->ic_dy, dxy, c->dy[idx].v[2], single + (k < 20 ? (k & ~1u) : 20));
    last->y = (int32_t)((uint32_t)last->y + (uint32_t)diff);
    sta_laz_median_add(&c->dy[idx], diff);

    if (L[L_Z].size) {
        k = (c->ic_dx.k + c->ic_dy.k) / 2;
        last->z = sta_laz_ic_decode(&c->ic_z, &L[L_Z].dec, c->last_z[level],
                                    single + (k < 18 ? (k & ~1u) : 18));
        c->last_z[level] = last->z;
    }
    if (L[L_CLASS].size) {
        uint32_t ccc = ((last->classification & 0x1fu) << 1) + (cpr == 3 ? 1u : 0u);
        sta_laz_model *mc = lazy_model(&c->m_class[ccc], 256);
        if (!mc) {
            return false;
        }
        last->classification = (uint8_t)sta_laz_decode_symbol(&L[L_CLASS].dec, mc);
    }
    if (L[L_FLAGS].size) {
        uint32_t prev =
            ((uint32_t)last->edge << 5) | ((uint32_t)last->scan_dir << 4) | last->class_flags;
        sta_laz_model *mf = lazy_model(&c->m_flags[prev], 64);
        if (!mf) {
            return false;
        }
        uint32_t flags = sta_laz_decode_symbol(&L[L_FLAGS].dec, mf);
        last->edge = (uint8_t)((flags >> 5) & 1);
        last->scan_dir = (uint8_t)((flags >> 4) & 1);
        last->class_flags = (uint8_t)(flags & 15);
    }
    if (L[L_INTENSITY].size) {
        uint32_t at = (cpr << 1) | (gps_change ? 1u : 0u);
        uint16_t v = (uint16_t)sta_laz_ic_decode(&c->ic_intensity, &L[L_INTENSITY].dec,
                                                 c->last_intensity[at], cpr);
        c->last_intensity[at] = v;
        last->intensity = v;
    }
    if (L[L_SCAN_ANGLE].size && scan_angle_change) {
        last->scan_angle = (int16_t)sta_laz_ic_decode(&c->ic_scan_angle, &L[L_SCAN_ANGLE].dec,
                                                      last->scan_angle, gps_change ? 1u : 0u);
    }
    if (L[L_USER_DATA].size) {
        sta_laz_model *mu = lazy_model(&c->m_user[last->user_data / 4], 256);
        if (!mu) {
            return false;
        }
        last->user_data = (uint8_t)sta_laz_decode_symbol(&L[L_USER_DATA].dec, mu);
    }
    if (L[L_SOURCE].size && source_change) {
        last->source =
            (uint16_t)sta_laz_ic_decode(&c->ic_source, &L[L_SOURCE].dec, last->source, 0);
    }
    if (L[L_GPS].size && gps_change) {
        if (!sta_laz_gpstime_decode(&c->gps, &L[L_GPS].dec, GPS_MAX_SWITCHES)) {
            s->bad = true;
        }
        last->gps = sta_laz_gpstime_last(&c->gps);
    }
    item_to_record(last, s->current, out);
    last->gps_change = gps_change;
    return true;
}

// ---- RGB14, RGBNIR14, BYTE14 ----

static uint8_t *extra_last(extra_item *e, uint32_t ctx)
{
    return e->ctx[ctx].wide ? e->ctx[ctx].wide : e->ctx[ctx].last;
}

static bool extra_create(extra_item *e)
{
    for (int c = 0; c < CONTEXTS; c++) {
        extra_context *x = &e->ctx[c];
        if (e->size > sizeof(x->last) && !(x->wide = sta_malloc(e->size))) {
            return false;
        }
        if (e->type == STA_LAZ_ITEM_WAVEPACKET14) {
            if (!(x->m_wp_index = sta_laz_model_create(256))) {
                return false;
            }
            for (int i = 0; i < 4; i++) {
                if (!(x->m_wp_offset[i] = sta_laz_model_create(4))) {
                    return false;
                }
            }
            if (!sta_laz_ic_init(&x->ic_wp_offset, 32, 1) ||
                !sta_laz_ic_init(&x->ic_wp_size, 32, 1) ||
                !sta_laz_ic_init(&x->ic_wp_return, 32, 1) ||
                !sta_laz_ic_init(&x->ic_wp_xyz, 32, 3)) {
                return false;
            }
            continue;
        }
        if (e->type == STA_LAZ_ITEM_BYTE14) {
            x->m_bytes = sta_calloc(e->size, sizeof(*x->m_bytes));
            if (!x->m_bytes) {
                return false;
            }
            for (size_t i = 0; i < e->size; i++) {
                if (!(x->m_bytes[i] = sta_laz_model_create(256))) {
                    return false;
                }
            }
            continue;
        }
        if (!(x->m_used = sta_laz_model_create(128))) {
            return false;
        }
        for (int i = 0; i < 6; i++) {
            if (!(x->m_diff[i] = sta_laz_model_create(256))) {
                return false;
            }
        }
        if (e->type == STA_LAZ_ITEM_RGBNIR14) {
            x->m_nir_used = sta_laz_model_create(4);
            x->m_nir_diff[0] = sta_laz_model_create(256);
            x->m_nir_diff[1] = sta_laz_model_create(256);
            if (!x->m_nir_used || !x->m_nir_diff[0] || !x->m_nir_diff[1]) {
                return false;
            }
        }
    }
    return true;
}

static void extra_release(extra_item *e)
{
    for (int c = 0; c < CONTEXTS; c++) {
        extra_context *x = &e->ctx[c];
        if (x->m_bytes) {
            for (size_t i = 0; i < e->size; i++) {
                sta_laz_model_destroy(x->m_bytes[i]);
            }
            sta_free(x->m_bytes);
        }
        sta_free(x->wide);
        sta_laz_model_destroy(x->m_used);
        for (int i = 0; i < 6; i++) {
            sta_laz_model_destroy(x->m_diff[i]);
        }
        sta_laz_model_destroy(x->m_nir_used);
        sta_laz_model_destroy(x->m_nir_diff[0]);
        sta_laz_model_destroy(x->m_nir_diff[1]);
        sta_laz_model_destroy(x->m_wp_index);
        for (int i = 0; i < 4; i++) {
            sta_laz_model_destroy(x->m_wp_offset[i]);
        }
        sta_laz_ic_release(&x->ic_wp_offset);
        sta_laz_ic_release(&x->ic_wp_size);
        sta_laz_ic_release(&x->ic_wp_return);
        sta_laz_ic_release(&x->ic_wp_xyz);
    }
}

static void extra_init(extra_item *e, uint32_t ctx, const uint8_t *from)
{
    extra_context *x = &e->ctx[ctx];
    if (x->m_bytes) {
        for (size_t i = 0; i < e->size; i++) {
            sta_laz_model_reset(x->m_bytes[i]);
        }
    }
    if (x->m_used) {
        sta_laz_model_reset(x->m_used);
        for (int i = 0; i < 6; i++) {
            sta_laz_model_reset(x->m_diff[i]);
        }
    }
    if (x->m_nir_used) {
        sta_laz_model_reset(x->m_nir_used);
        sta_laz_model_reset(x->m_nir_diff[0]);
        sta_laz_model_reset(x->m_nir_diff[1]);
    }
    if (x->m_wp_index) {
        sta_laz_model_reset(x->m_wp_index);
        for (int i = 0; i < 4; i++) {
            sta_laz_model_reset(x->m_wp_offset[i]);
        }
        sta_laz_ic_reset(&x->ic_wp_offset);
        sta_laz_ic_reset(&x->ic_wp_size);
        sta_laz_ic_reset(&x->ic_wp_return);
        sta_laz_ic_reset(&x->ic_wp_xyz);
        x->wp_last_diff = 0;
        x->wp_last_kind = 0;
    }
    memmove(extra_last(e, ctx), from, e->size);
    x->unused = false;
}

// One byte: the last value plus a coded difference, or the last value.
static uint32_t rgb_byte(sta_laz_dec *dec, sta_laz_model *m, int32_t pred)
{
    return sta_laz_fold_u8((int32_t)sta_laz_decode_symbol(dec, m) + pred);
}

static void rgb_decode(extra_context *x, sta_laz_dec *dec, uint8_t *last)
{
    uint32_t l[3] = { sta_load_u16le(last), sta_load_u16le(last + 2), sta_load_u16le(last + 4) };
    uint32_t sym = sta_laz_decode_symbol(dec, x->m_used);
    uint32_t r = (sym & 1) ? rgb_byte(dec, x->m_diff[0], (int32_t)(l[0] & 255)) : (l[0] & 255);
    r |= ((sym & 2) ? rgb_byte(dec, x->m_diff[1], (int32_t)(l[0] >> 8)) : (l[0] >> 8)) << 8;
    uint32_t g;
    uint32_t b;
    if (sym & (1u << 6)) {
        int32_t diff = (int32_t)(r & 255) - (int32_t)(l[0] & 255);
        g = (sym & 4) ? rgb_byte(dec, x->m_diff[2], sta_laz_clamp_u8(diff + (int32_t)(l[1] & 255)))
                      : (l[1] & 255);
        if (sym & 16) {
            diff = (diff + ((int32_t)(g & 255) - (int32_t)(l[1] & 255))) / 2;
            b = rgb_byte(dec, x->m_diff[4], sta_laz_clamp_u8(diff + (int32_t)(l[2] & 255)));
        } else {
            b = l[2] & 255;
        }
        diff = (int32_t)(r >> 8) - (int32_t)(l[0] >> 8);
        if (sym & 8) {
            g |= rgb_byte(dec, x->m_diff[3], sta_laz_clamp_u8(diff + (int32_t)(l[1] >> 8))) << 8;
        } else {
            g |= l[1] & 0xff00;
        }
        if (sym & 32) {
            diff = (diff + ((int32_t)(g >> 8) - (int32_t)(l[1] >> 8))) / 2;
            b |= rgb_byte(dec, x->m_diff[5], sta_laz_clamp_u8(diff + (int32_t)(l[2] >> 8))) << 8;
        } else {
            b |= l[2] & 0xff00;
        }
    } else {
        g = r;
        b = r;
    }
    sta_store_u16le(last, (uint16_t)r);
    sta_store_u16le(last + 2, (uint16_t)g);
    sta_store_u16le(last + 4, (uint16_t)b);
}

static void nir_decode(extra_context *x, sta_laz_dec *dec, uint8_t *last)
{
    uint32_t l = sta_load_u16le(last + 6);
    uint32_t sym = sta_laz_decode_symbol(dec, x->m_nir_used);
    uint32_t v = (sym & 1) ? rgb_byte(dec, x->m_nir_diff[0], (int32_t)(l & 255)) : (l & 255);
    v |= ((sym & 2) ? rgb_byte(dec, x->m_nir_diff[1], (int32_t)(l >> 8)) : (l >> 8)) << 8;
    sta_store_u16le(last + 6, (uint16_t)v);
}

// Wave packet (29 bytes): u8 descriptor index, u64 offset of the waveform data, u32
// packet size, f32 return point location, f32 x(t), y(t), z(t) (corrected as bits).
static void wavepacket_decode(extra_context *x, sta_laz_dec *dec, uint8_t *last)
{
    last[0] = (uint8_t)sta_laz_decode_symbol(dec, x->m_wp_index);
    uint32_t kind = sta_laz_decode_symbol(dec, x->m_wp_offset[x->wp_last_kind]);
    x->wp_last_kind = kind;
    uint64_t offset = sta_load_u64le(last + 1);
    uint32_t size = sta_load_u32le(last + 9);
    if (kind == 1) {
        offset += size;
    } else if (kind == 2) {
        x->wp_last_diff = sta_laz_ic_decode(&x->ic_wp_offset, dec, x->wp_last_diff, 0);
        offset += (uint64_t)(int64_t)x->wp_last_diff;
    } else if (kind == 3) {
        uint64_t low = sta_laz_read_u32(dec);
        offset = low | (uint64_t)sta_laz_read_u32(dec) << 32;
    }
    sta_store_u64le(last + 1, offset);
    sta_store_u32le(last + 9, (uint32_t)sta_laz_ic_decode(&x->ic_wp_size, dec, (int32_t)size, 0));
    sta_store_u32le(last + 13, (uint32_t)sta_laz_ic_decode(&x->ic_wp_return, dec,
                                                           (int32_t)sta_load_u32le(last + 13), 0));
    for (uint32_t i = 0; i < 3; i++) {
        uint8_t *v = last + 17 + 4 * i;
        sta_store_u32le(
            v, (uint32_t)sta_laz_ic_decode(&x->ic_wp_xyz, dec, (int32_t)sta_load_u32le(v), i));
    }
}

static void extra_decode(sta_laz_p14 *s, extra_item *e, uint8_t *out)
{
    // Version 3 (as the LASzip writer does): a switch to an already used context still
    // predicts this record from the previous context's last record (and updates that
    // one). Version 4 uses the new context's own last record.
    uint8_t *last = extra_last(e, e->current);
    if (e->current != s->current) {
        e->current = s->current;
        if (e->ctx[e->current].unused) {
            extra_init(e, e->current, last);
            last = extra_last(e, e->current);
        } else if (e->own_last) {
            last = extra_last(e, e->current);
        }
    }
    extra_context *x = &e->ctx[e->current];
    layer *L = &s->layers[e->first_layer];
    if (e->type == STA_LAZ_ITEM_BYTE14) {
        for (size_t i = 0; i < e->size; i++) {
            if (L[i].size) {
                last[i] = sta_laz_fold_u8((int32_t)last[i] +
                                          (int32_t)sta_laz_decode_symbol(&L[i].dec, x->m_bytes[i]));
            }
        }
    } else if (e->type == STA_LAZ_ITEM_WAVEPACKET14) {
        if (L[0].size) {
            wavepacket_decode(x, &L[0].dec, last);
        }
    } else {
        if (L[0].size) {
            rgb_decode(x, &L[0].dec, last);
        }
        if (e->type == STA_LAZ_ITEM_RGBNIR14 && L[1].size) {
            nir_decode(x, &L[1].dec, last);
        }
    }
    memcpy(out, last, e->size);
}

// ---- the family ----

sta_laz_p14 *sta_laz_p14_create(const sta_laz_vlr *vlr)
{
    sta_laz_p14 *s = sta_calloc(1, sizeof(*s));
    if (!s) {
        return NULL;
    }
    size_t at = 0;
    size_t layers = 0;
    bool ok = true;
    for (size_t i = 0; i < vlr->item_count && ok; i++) {
        const sta_laz_item *item = &vlr->items[i];
        if (item->type == STA_LAZ_ITEM_POINT14) {
            layers += P14_LAYERS;
        } else {
            extra_item *e = &s->extras[s->extra_count++];
            e->type = item->type;
            e->at = at;
            e->size = item->size;
            e->first_layer = layers;
            e->own_last = item->version >= 4;
            layers += item->type == STA_LAZ_ITEM_BYTE14     ? item->size
                      : item->type == STA_LAZ_ITEM_RGBNIR14 ? 2
                                                            : 1;
            ok = extra_create(e);
        }
        at += item->size;
    }
    s->layer_count = layers;
    s->layers = ok ? sta_calloc(layers, sizeof(*s->layers)) : NULL;
    if (!s->layers) {
        sta_laz_p14_destroy(s);
        return NULL;
    }
    return s;
}

void sta_laz_p14_destroy(sta_laz_p14 *state)
{
    if (!state) {
        return;
    }
    for (int c = 0; c < CONTEXTS; c++) {
        context_release(&state->ctx[c]);
    }
    for (size_t i = 0; i < state->extra_count; i++) {
        extra_release(&state->extras[i]);
    }
    sta_free(state->layers);
    sta_free(state);
}

bool sta_laz_p14_begin(sta_laz_p14 *state, const uint8_t *first, const uint8_t *p,
                       const uint8_t *end, uint32_t *out_count, const uint8_t **out_end)
{
    sta_laz_p14 *s = state;
    *out_count = 0;
    *out_end = NULL;
    size_t header = 4 * (s->layer_count + 1);
    if (p > end || (size_t)(end - p) < header) {
        return false;
    }
    *out_count = sta_load_u32le(p);
    const uint8_t *data = p + header;
    for (size_t i = 0; i < s->layer_count; i++) {
        uint32_t size = sta_load_u32le(p + 4 * (i + 1));
        if ((size_t)(end - data) < size) {
            return false;
        }
        layer *l = &s->layers[i];
        l->p = data;
        l->size = size;
        if (size) {
            sta_laz_dec_init(&l->dec, data, data + size);
        }
        data += size;
    }
    *out_end = data;
    s->bad = false;
    s->current = (first[15] >> 4) & 3;
    for (int c = 0; c < CONTEXTS; c++) {
        s->ctx[c].unused = true;
    }
    p14_item item;
    item_from_record(&item, first);
    if (!context_init(&s->ctx[s->current], &item)) {
        return false;
    }
    for (size_t i = 0; i < s->extra_count; i++) {
        extra_item *e = &s->extras[i];
        for (int c = 0; c < CONTEXTS; c++) {
            e->ctx[c].unused = true;
        }
        e->current = s->current;
        extra_init(e, e->current, first + e->at);
    }
    return true;
}

bool sta_laz_p14_decode(sta_laz_p14 *state, uint8_t *record)
{
    sta_laz_p14 *s = state;
    if (!point14_decode(s, record)) {
        return false;
    }
    for (size_t i = 0; i < s->extra_count; i++) {
        extra_decode(s, &s->extras[i], record + s->extras[i].at);
    }
    if (s->bad) {
        return false;
    }
    for (size_t i = 0; i < s->layer_count; i++) {
        if (s->layers[i].size && s->layers[i].dec.overrun) {
            return false;
        }
    }
    return true;
}
