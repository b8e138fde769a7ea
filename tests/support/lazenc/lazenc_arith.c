/* SPDX-License-Identifier: MIT
 * Test encoder: byte buffer, range encoder and integer corrector (see lazenc.h).
 * The encoder is the classic carry-propagating range coder (Said, HPL-2004-76) with
 * the interval and model arithmetic of the LAZ decoder in src/io/laz_arith.c.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lazenc.h"

void lazenc_buf_put(lazenc_buf *buf, const void *bytes, size_t count)
{
    if (buf->size + count > buf->cap) {
        size_t cap = buf->cap ? buf->cap : 4096;
        while (cap < buf->size + count) {
            cap *= 2;
        }
        uint8_t *grown = realloc(buf->data, cap);
        if (!grown) {
            fprintf(stderr, "lazenc: out of memory (%zu bytes)\n", cap);
            abort();
        }
        buf->data = grown;
        buf->cap = cap;
    }
    memcpy(buf->data + buf->size, bytes, count);
    buf->size += count;
}

void lazenc_buf_put_u16(lazenc_buf *buf, uint16_t v)
{
    uint8_t b[2] = { (uint8_t)v, (uint8_t)(v >> 8) };
    lazenc_buf_put(buf, b, 2);
}

void lazenc_buf_put_u32(lazenc_buf *buf, uint32_t v)
{
    lazenc_buf_put_u16(buf, (uint16_t)v);
    lazenc_buf_put_u16(buf, (uint16_t)(v >> 16));
}

void lazenc_buf_put_u64(lazenc_buf *buf, uint64_t v)
{
    lazenc_buf_put_u32(buf, (uint32_t)v);
    lazenc_buf_put_u32(buf, (uint32_t)(v >> 32));
}

void lazenc_buf_free(lazenc_buf *buf)
{
    free(buf->data);
    *buf = (lazenc_buf){ 0 };
}

void *lazenc_zalloc(size_t size)
{
    void *p = calloc(1, size ? size : 1);
    if (!p) {
        fprintf(stderr, "lazenc: out of memory (%zu bytes)\n", size);
        abort();
    }
    return p;
}

sta_laz_model *lazenc_model(uint32_t symbols)
{
    sta_laz_model *m = sta_laz_model_create(symbols);
    if (!m) {
        abort();
    }
    return m;
}

void lazenc_ic_init(sta_laz_ic *ic, uint32_t bits, uint32_t contexts)
{
    if (!sta_laz_ic_init(ic, bits, contexts)) {
        abort();
    }
}

void lazenc_arith_init(lazenc_arith *enc, lazenc_buf *out)
{
    enc->out = out;
    enc->start = out->size;
    enc->base = 0;
    enc->length = 0xffffffffu;
}

// base overflowed: add one to the bytes already written (0xff bytes roll over).
static void propagate_carry(lazenc_arith *enc)
{
    size_t at = enc->out->size;
    while (at > enc->start && enc->out->data[at - 1] == 0xff) {
        enc->out->data[--at] = 0;
    }
    if (at > enc->start) {
        enc->out->data[at - 1]++;
    }
}

static void renormalise(lazenc_arith *enc)
{
    do {
        uint8_t top = (uint8_t)(enc->base >> 24);
        lazenc_buf_put(enc->out, &top, 1);
        enc->base <<= 8;
        enc->length <<= 8;
    } while (enc->length < STA_LAZ_MIN_LENGTH);
}

// Moves base by `x` (carrying into the written bytes on overflow).
static void advance(lazenc_arith *enc, uint32_t x)
{
    uint32_t before = enc->base;
    enc->base += x;
    if (enc->base < before) {
        propagate_carry(enc);
    }
}

void lazenc_encode_bit(lazenc_arith *enc, sta_laz_bit_model *m, uint32_t bit)
{
    uint32_t x = m->bit_0_prob * (enc->length >> STA_LAZ_BIT_SHIFT);
    if (bit == 0) {
        enc->length = x;
        m->bit_0_count++;
    } else {
        advance(enc, x);
        enc->length -= x;
    }
    if (enc->length < STA_LAZ_MIN_LENGTH) {
        renormalise(enc);
    }
    if (--m->bits_until_update == 0) {
        sta_laz_bit_model_update(m);
    }
}

void lazenc_encode_symbol(lazenc_arith *enc, sta_laz_model *m, uint32_t sym)
{
    uint32_t x;
    if (sym == m->last_symbol) {
        x = m->distribution[sym] * (enc->length >> STA_LAZ_SYM_SHIFT);
        advance(enc, x);
        enc->length -= x;
    } else {
        enc->length >>= STA_LAZ_SYM_SHIFT;
        x = m->distribution[sym] * enc->length;
        advance(enc, x);
        enc->length = m->distribution[sym + 1] * enc->length - x;
    }
    if (enc->length < STA_LAZ_MIN_LENGTH) {
        renormalise(enc);
    }
    m->symbol_count[sym]++;
    if (--m->symbols_until_update == 0) {
        sta_laz_model_update(m);
    }
}

void lazenc_write_bits(lazenc_arith *enc, uint32_t bits, uint32_t value)
{
    if (bits > 19) {
        lazenc_write_bits(enc, 16, value & 0xffff);
        value >>= 16;
        bits -= 16;
    }
    enc->length >>= bits;
    advance(enc, value * enc->length);
    if (enc->length < STA_LAZ_MIN_LENGTH) {
        renormalise(enc);
    }
}

void lazenc_write_u32(lazenc_arith *enc, uint32_t value)
{
    lazenc_write_bits(enc, 16, value & 0xffff);
    lazenc_write_bits(enc, 16, value >> 16);
}

void lazenc_arith_done(lazenc_arith *enc)
{
    // Pick a value inside the final interval that needs the fewest bytes: one more
    // byte when the interval is wide, two otherwise.
    bool one_byte = enc->length > 2 * STA_LAZ_MIN_LENGTH;
    if (one_byte) {
        advance(enc, STA_LAZ_MIN_LENGTH);
        enc->length = STA_LAZ_MIN_LENGTH >> 1;
    } else {
        advance(enc, STA_LAZ_MIN_LENGTH >> 1);
        enc->length = STA_LAZ_MIN_LENGTH >> 9;
    }
    renormalise(enc);
    // Zero padding as LASzip 2.x writes it (the twins in ../shared/data match): 3 bytes
    // after one final byte, 2 after two, so a stream always ends 4 bytes after the
    // last byte its decoder needed and chunks can be walked without a chunk table.
    static const uint8_t zeros[3] = { 0, 0, 0 };
    lazenc_buf_put(enc->out, zeros, one_byte ? 3 : 2);
}

// The correction `c`: its magnitude class k, then its place in the class.
static void write_corrector(sta_laz_ic *ic, lazenc_arith *enc, int32_t c, sta_laz_model *m_bits)
{
    uint32_t c1 = c <= 0 ? (uint32_t)0 - (uint32_t)c : (uint32_t)c - 1;
    uint32_t k = 0;
    while (c1) {
        c1 >>= 1;
        k++;
    }
    ic->k = k;
    lazenc_encode_symbol(enc, m_bits, k);
    if (k == 0) {
        lazenc_encode_bit(enc, &ic->corrector0, (uint32_t)c);
        return;
    }
    if (k >= 32) {
        return;
    }
    // Class k holds [-(2^k - 1), -2^(k-1)] and [2^(k-1) + 1, 2^k]: map to [0, 2^k).
    uint32_t v = c < 0 ? (uint32_t)c + ((1u << k) - 1) : (uint32_t)c - 1;
    if (k <= ic->bits_high) {
        lazenc_encode_symbol(enc, sta_laz_ic_class_model(ic, k), v);
    } else {
        uint32_t low_bits = k - ic->bits_high;
        lazenc_encode_symbol(enc, sta_laz_ic_class_model(ic, k), v >> low_bits);
        lazenc_write_bits(enc, low_bits, v & ((1u << low_bits) - 1));
    }
}

void lazenc_ic_encode(sta_laz_ic *ic, lazenc_arith *enc, int32_t pred, int32_t real,
                      uint32_t context)
{
    int32_t corr = (int32_t)((uint32_t)real - (uint32_t)pred);
    if (ic->range != 0) { // fold into [corr_min, corr_min + range - 1]
        int32_t corr_max = ic->corr_min + (int32_t)ic->range - 1;
        if (corr < ic->corr_min) {
            corr += (int32_t)ic->range;
        } else if (corr > corr_max) {
            corr -= (int32_t)ic->range;
        }
    }
    write_corrector(ic, enc, corr, sta_laz_ic_context_model(ic, context));
}
