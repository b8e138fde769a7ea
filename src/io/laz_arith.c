/* SPDX-License-Identifier: MIT
 * LAZ range decoder, adaptive models and integer corrector (see laz_arith.h).
 *
 * Decisions:
 * - Corrupt input can put the code value outside the interval; the decoder then
 *   still produces symbols in range (lookup indices are clamped) and consumes bytes,
 *   so damage shows up as wrong values and an overrun, never as an invalid access.
 * - All wrapping arithmetic is done in uint32_t (the format relies on two's
 *   complement wrap of 32-bit sums).
 */
#include "io/laz_arith.h"

#include "core/alloc.h"

static uint8_t next_byte(sta_laz_dec *dec)
{
    if (dec->p < dec->end) {
        return *dec->p++;
    }
    dec->overrun++;
    return 0;
}

static void renormalise(sta_laz_dec *dec)
{
    if (dec->length == 0) { // impossible for a valid stream; keep the loop finite
        dec->length = STA_LAZ_MIN_LENGTH;
        dec->overrun += 16;
    }
    do {
        dec->value = (dec->value << 8) | next_byte(dec);
        dec->length <<= 8;
    } while (dec->length < STA_LAZ_MIN_LENGTH);
}

void sta_laz_dec_init(sta_laz_dec *dec, const uint8_t *p, const uint8_t *end)
{
    dec->p = p;
    dec->end = end;
    dec->overrun = 0;
    dec->length = 0xffffffffu;
    dec->value = 0;
    for (int i = 0; i < 4; i++) {
        dec->value = (dec->value << 8) | next_byte(dec);
    }
}

void sta_laz_bit_model_init(sta_laz_bit_model *model)
{
    model->bit_0_count = 1;
    model->bit_count = 2;
    model->bit_0_prob = 1u << (STA_LAZ_BIT_SHIFT - 1);
    model->update_cycle = 4;
    model->bits_until_update = 4;
}

void sta_laz_bit_model_update(sta_laz_bit_model *m)
{
    m->bit_count += m->update_cycle;
    if (m->bit_count > STA_LAZ_BIT_MAX_COUNT) {
        m->bit_count = (m->bit_count + 1) >> 1;
        m->bit_0_count = (m->bit_0_count + 1) >> 1;
        if (m->bit_0_count == m->bit_count) {
            m->bit_count++;
        }
    }
    uint32_t scale = 0x80000000u / m->bit_count;
    m->bit_0_prob = (m->bit_0_count * scale) >> (31 - STA_LAZ_BIT_SHIFT);
    m->update_cycle = (5 * m->update_cycle) >> 2;
    if (m->update_cycle > 64) {
        m->update_cycle = 64;
    }
    m->bits_until_update = m->update_cycle;
}

uint32_t sta_laz_decode_bit(sta_laz_dec *dec, sta_laz_bit_model *model)
{
    uint32_t x = model->bit_0_prob * (dec->length >> STA_LAZ_BIT_SHIFT);
    uint32_t bit = dec->value >= x;
    if (bit == 0) {
        dec->length = x;
        model->bit_0_count++;
    } else {
        dec->value -= x;
        dec->length -= x;
    }
    if (dec->length < STA_LAZ_MIN_LENGTH) {
        renormalise(dec);
    }
    if (--model->bits_until_update == 0) {
        sta_laz_bit_model_update(model);
    }
    return bit;
}

void sta_laz_model_update(sta_laz_model *m)
{
    m->total_count += m->update_cycle;
    if (m->total_count > STA_LAZ_SYM_MAX_COUNT) {
        m->total_count = 0;
        for (uint32_t n = 0; n < m->symbols; n++) {
            m->symbol_count[n] = (m->symbol_count[n] + 1) >> 1;
            m->total_count += m->symbol_count[n];
        }
    }
    uint32_t scale = 0x80000000u / m->total_count;
    uint32_t sum = 0;
    if (m->table_size == 0) {
        for (uint32_t k = 0; k < m->symbols; k++) {
            m->distribution[k] = (scale * sum) >> (31 - STA_LAZ_SYM_SHIFT);
            sum += m->symbol_count[k];
        }
    } else {
        uint32_t s = 0;
        for (uint32_t k = 0; k < m->symbols; k++) {
            m->distribution[k] = (scale * sum) >> (31 - STA_LAZ_SYM_SHIFT);
            sum += m->symbol_count[k];
            uint32_t w = m->distribution[k] >> m->table_shift;
            while (s < w) {
                m->decoder_table[++s] = k - 1;
            }
        }
        m->decoder_table[0] = 0;
        while (s <= m->table_size) {
            m->decoder_table[++s] = m->symbols - 1;
        }
    }
    m->update_cycle = (5 * m->update_cycle) >> 2;
    uint32_t max_cycle = (m->symbols + 6) << 3;
    if (m->update_cycle > max_cycle) {
        m->update_cycle = max_cycle;
    }
    m->symbols_until_update = m->update_cycle;
}

void sta_laz_model_reset(sta_laz_model *m)
{
    m->total_count = 0;
    m->update_cycle = m->symbols;
    for (uint32_t k = 0; k < m->symbols; k++) {
        m->symbol_count[k] = 1;
    }
    sta_laz_model_update(m);
    m->update_cycle = (m->symbols + 6) >> 1;
    m->symbols_until_update = m->update_cycle;
}

sta_laz_model *sta_laz_model_create(uint32_t symbols)
{
    if (symbols < 2 || symbols > STA_LAZ_MAX_SYMBOLS) {
        return NULL;
    }
    uint32_t table_bits = 0;
    uint32_t table_size = 0;
    if (symbols > 16) {
        table_bits = 3;
        while (symbols > (1u << (table_bits + 2))) {
            table_bits++;
        }
        table_size = 1u << table_bits;
    }
    size_t words = 2 * (size_t)symbols + (table_size ? table_size + 2 : 0);
    sta_laz_model *m = sta_malloc(sizeof(*m) + words * sizeof(uint32_t));
    if (!m) {
        return NULL;
    }
    m->symbols = symbols;
    m->last_symbol = symbols - 1;
    m->table_size = table_size;
    m->table_shift = table_size ? STA_LAZ_SYM_SHIFT - table_bits : 0;
    m->distribution = m->storage;
    m->symbol_count = m->storage + symbols;
    m->decoder_table = table_size ? m->storage + 2 * symbols : NULL;
    sta_laz_model_reset(m);
    return m;
}

void sta_laz_model_destroy(sta_laz_model *model)
{
    sta_free(model);
}

sta_laz_model *sta_laz_context_model(sta_laz_model **models, uint8_t *used, uint8_t ctx)
{
    if (!models[ctx]) {
        models[ctx] = sta_laz_model_create(256);
        if (!models[ctx]) {
            return NULL;
        }
    } else if (!(used[ctx >> 3] & (1u << (ctx & 7)))) {
        sta_laz_model_reset(models[ctx]);
    }
    used[ctx >> 3] |= (uint8_t)(1u << (ctx & 7));
    return models[ctx];
}

uint32_t sta_laz_decode_symbol(sta_laz_dec *dec, sta_laz_model *m)
{
    uint32_t sym;
    uint32_t x;
    uint32_t y = dec->length;
    if (m->decoder_table) {
        dec->length >>= STA_LAZ_SYM_SHIFT;
        uint32_t dv = dec->value / dec->length;
        uint32_t t = dv >> m->table_shift;
        if (t > m->table_size) { // only for a corrupt stream (value >= length)
            t = m->table_size;
        }
        sym = m->decoder_table[t];
        uint32_t n = m->decoder_table[t + 1] + 1;
        while (n > sym + 1) {
            uint32_t k = (sym + n) >> 1;
            if (m->distribution[k] > dv) {
                n = k;
            } else {
                sym = k;
            }
        }
        x = m->distribution[sym] * dec->length;
        if (sym != m->last_symbol) {
            y = m->distribution[sym + 1] * dec->length;
        }
    } else {
        x = 0;
        sym = 0;
        dec->length >>= STA_LAZ_SYM_SHIFT;
        uint32_t n = m->symbols;
        uint32_t k = n >> 1;
        do {
            uint32_t z = dec->length * m->distribution[k];
            if (z > dec->value) {
                n = k;
                y = z;
            } else {
                sym = k;
                x = z;
            }
            k = (sym + n) >> 1;
        } while (k != sym);
    }
    dec->value -= x;
    dec->length = y - x;
    if (dec->length < STA_LAZ_MIN_LENGTH) {
        renormalise(dec);
    }
    m->symbol_count[sym]++;
    if (--m->symbols_until_update == 0) {
        sta_laz_model_update(m);
    }
    return sym;
}

uint32_t sta_laz_read_bits(sta_laz_dec *dec, uint32_t bits)
{
    if (bits > 19) {
        uint32_t low = sta_laz_read_bits(dec, 16);
        uint32_t high = sta_laz_read_bits(dec, bits - 16);
        return (high << 16) | low;
    }
    dec->length >>= bits;
    uint32_t sym = dec->value / dec->length;
    dec->value -= dec->length * sym;
    if (dec->length < STA_LAZ_MIN_LENGTH) {
        renormalise(dec);
    }
    return sym;
}

uint32_t sta_laz_read_u32(sta_laz_dec *dec)
{
    uint32_t low = sta_laz_read_bits(dec, 16);
    uint32_t high = sta_laz_read_bits(dec, 16);
    return (high << 16) | low;
}

bool sta_laz_ic_init(sta_laz_ic *ic, uint32_t bits, uint32_t contexts)
{
    *ic = (sta_laz_ic){ 0 };
    ic->bits = bits;
    ic->contexts = contexts;
    ic->bits_high = 8;
    if (bits < 32) {
        ic->range = 1u << bits;
        ic->corr_min = -(int32_t)(ic->range / 2);
    } else {
        ic->range = 0;
        ic->corr_min = INT32_MIN;
    }
    if (bits < 1 || bits > 32 || contexts < 1 || contexts > 32) {
        return false;
    }
    ic->m_bits = sta_calloc(contexts, sizeof(*ic->m_bits));
    if (!ic->m_bits) {
        return false;
    }
    for (uint32_t i = 0; i < contexts; i++) {
        ic->m_bits[i] = sta_laz_model_create(bits + 1);
        if (!ic->m_bits[i]) {
            return false;
        }
    }
    sta_laz_bit_model_init(&ic->corrector0);
    for (uint32_t i = 1; i <= bits; i++) {
        uint32_t class_bits = i <= ic->bits_high ? i : ic->bits_high;
        ic->corrector[i] = sta_laz_model_create(1u << class_bits);
        if (!ic->corrector[i]) {
            return false;
        }
    }
    return true;
}

void sta_laz_ic_reset(sta_laz_ic *ic)
{
    // Lazy: the models reset on first use (sta_laz_ic_class_model / _context_model).
    ic->stale_contexts = ic->contexts == 32 ? UINT32_MAX : (1u << ic->contexts) - 1;
    ic->stale_classes = ((1ull << (ic->bits + 1)) - 1) & ~1ull;
    sta_laz_bit_model_init(&ic->corrector0);
    ic->k = 0;
}

void sta_laz_ic_release(sta_laz_ic *ic)
{
    if (ic->m_bits) {
        for (uint32_t i = 0; i < ic->contexts; i++) {
            sta_laz_model_destroy(ic->m_bits[i]);
        }
        sta_free(ic->m_bits);
    }
    for (uint32_t i = 1; i <= 32; i++) {
        sta_laz_model_destroy(ic->corrector[i]);
    }
    *ic = (sta_laz_ic){ 0 };
}

// The correction: its magnitude class k, then the value within the class.
static int32_t read_corrector(sta_laz_ic *ic, sta_laz_dec *dec, sta_laz_model *m_bits)
{
    uint32_t k = sta_laz_decode_symbol(dec, m_bits);
    ic->k = k;
    if (k == 0) {
        return (int32_t)sta_laz_decode_bit(dec, &ic->corrector0);
    }
    if (k >= 32) {
        return ic->corr_min;
    }
    uint32_t c;
    if (k <= ic->bits_high) {
        c = sta_laz_decode_symbol(dec, sta_laz_ic_class_model(ic, k));
    } else {
        uint32_t low_bits = k - ic->bits_high;
        c = sta_laz_decode_symbol(dec, sta_laz_ic_class_model(ic, k));
        uint32_t low = sta_laz_read_bits(dec, low_bits);
        c = (c << low_bits) | low;
    }
    // Class k holds [-(2^k - 1), -2^(k-1)] and [2^(k-1) + 1, 2^k].
    if (c >= (1u << (k - 1))) {
        c += 1;
    } else {
        c -= (1u << k) - 1;
    }
    return (int32_t)c;
}

int32_t sta_laz_ic_decode(sta_laz_ic *ic, sta_laz_dec *dec, int32_t pred, uint32_t context)
{
    if (context >= ic->contexts) { // callers pass valid contexts; stay in bounds anyway
        context = ic->contexts - 1;
    }
    uint32_t real =
        (uint32_t)pred + (uint32_t)read_corrector(ic, dec, sta_laz_ic_context_model(ic, context));
    if (ic->range != 0) {
        if ((int32_t)real < 0) {
            real += ic->range;
        } else if (real >= ic->range) {
            real -= ic->range;
        }
    }
    return (int32_t)real;
}
