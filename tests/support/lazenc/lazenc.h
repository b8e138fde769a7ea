/* SPDX-License-Identifier: MIT
 * A LAZ encoder for the test suite only: it writes LAZ files from raw LAS records so
 * the decoder can be tested on item types, versions and layouts that no file in
 * ../shared/data has (compressor version 1, point14 version 4, several scanner
 * channels, RGB14 / RGBNIR14 / BYTE14, wave packets, variable chunks, COPC-like
 * files). It is not part of the product (the product only reads LAZ).
 *
 * Why it can be trusted as a reference: it is written from the LASzip writer's
 * published behaviour, separately from the decoder in src/io, and the tests first
 * check that it re-encodes the LAS twins of ../shared/data/laz into exactly the
 * chunk bytes LASzip wrote (tests/test_lazenc.c). An encoder and a decoder that only
 * agree with each other would not pass that.
 *
 * Memory: output buffers grow as needed; allocation failure aborts (test code).
 */
#ifndef STA_TESTS_LAZENC_H
#define STA_TESTS_LAZENC_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "io/laz_arith.h"
#include "io/laz_internal.h"

/* A growing byte buffer. */
typedef struct lazenc_buf {
    uint8_t *data;
    size_t size;
    size_t cap;
} lazenc_buf;

void lazenc_buf_put(lazenc_buf *buf, const void *bytes, size_t count);
void lazenc_buf_put_u16(lazenc_buf *buf, uint16_t v);
void lazenc_buf_put_u32(lazenc_buf *buf, uint32_t v);
void lazenc_buf_put_u64(lazenc_buf *buf, uint64_t v);
void lazenc_buf_free(lazenc_buf *buf);

/* Allocation helpers of the item encoders: zeroed memory, a model, a corrector;
 * each aborts when out of memory (test code). */
void *lazenc_zalloc(size_t size);
sta_laz_model *lazenc_model(uint32_t symbols);
void lazenc_ic_init(sta_laz_ic *ic, uint32_t bits, uint32_t contexts);

/* The range encoder, appending to a buffer (the mirror of sta_laz_dec). */
typedef struct lazenc_arith {
    lazenc_buf *out;
    size_t start; /* where this stream's bytes begin in out */
    uint32_t base;
    uint32_t length;
} lazenc_arith;

void lazenc_arith_init(lazenc_arith *enc, lazenc_buf *out);
void lazenc_encode_bit(lazenc_arith *enc, sta_laz_bit_model *model, uint32_t bit);
void lazenc_encode_symbol(lazenc_arith *enc, sta_laz_model *model, uint32_t symbol);
/* `bits` (1..32) raw bits of `value` (the mirror of sta_laz_read_bits). */
void lazenc_write_bits(lazenc_arith *enc, uint32_t bits, uint32_t value);
void lazenc_write_u32(lazenc_arith *enc, uint32_t value);
/* Ends the stream: final bytes, then LASzip's zero padding. */
void lazenc_arith_done(lazenc_arith *enc);

/* Encodes `real` as `pred` + correction (the mirror of sta_laz_ic_decode; the
 * corrector's models come from sta_laz_ic_init / sta_laz_ic_reset). */
void lazenc_ic_encode(sta_laz_ic *ic, lazenc_arith *enc, int32_t pred, int32_t real,
                      uint32_t context);

/* An item encoder of the point10 family (sequential: all items share one stream). */
typedef struct lazenc_seq_item {
    void *state;
    /* Chunk start: `first` is this item's bytes of the chunk's first (raw) record. */
    void (*begin)(void *state, const uint8_t *first);
    /* Encodes this item's bytes of the next record. */
    void (*encode)(void *state, lazenc_arith *enc, const uint8_t *item_bytes);
    void (*destroy)(void *state);
} lazenc_seq_item;

/* Sets *out for a version 2 item (POINT10, GPSTIME11, RGB12, BYTE); false otherwise. */
bool lazenc_point10_v2_item(const sta_laz_item *item, lazenc_seq_item *out);
/* Sets *out for a version 1 item (POINT10, GPSTIME11, RGB12, BYTE, WAVEPACKET13). */
bool lazenc_point10_v1_item(const sta_laz_item *item, lazenc_seq_item *out);

/* Appends one layered (point14 family) chunk of `count` >= 1 records: the first
 * record raw, the count, the layer sizes, the layers. False for items it lacks. */
bool lazenc_point14_chunk(const sta_laz_vlr *vlr, const uint8_t *records, size_t count,
                          size_t record_length, lazenc_buf *out);

/* How to lay the point data out. */
typedef struct lazenc_options {
    uint16_t compressor;          /* STA_LAZ_COMPRESSOR_* (1 pointwise, 2, 3 layered) */
    uint16_t version;             /* item version: 1 or 2 (point10), 3 or 4 (point14) */
    uint32_t chunk_size;          /* points per chunk; UINT32_MAX: variable (chunk_points) */
    const uint32_t *chunk_points; /* variable chunks: points of each chunk */
    size_t chunk_count;
    bool no_chunk_table; /* write -1 as the table offset and no table */
} lazenc_options;

/* The LASzip VLR for records of `point_format` (0-10) and `record_length` bytes
 * (extra bytes become a BYTE / BYTE14 item). False for an impossible combination. */
bool lazenc_make_vlr(int point_format, size_t record_length, const lazenc_options *options,
                     sta_laz_vlr *vlr);
/* The VLR's payload bytes as LASzip writes them. */
void lazenc_vlr_payload(const sta_laz_vlr *vlr, lazenc_buf *out);

/* Appends the point data (chunk table offset, chunks, chunk table) of `count`
 * records; `data_offset` is the file offset the point data will start at. */
bool lazenc_point_data(const lazenc_options *options, const sta_laz_vlr *vlr,
                       const uint8_t *records, uint64_t count, size_t record_length,
                       uint64_t data_offset, lazenc_buf *out);

/* A whole LAZ file from a whole LAS file (header, VLRs, records, EVLRs): the point
 * format gets LAZ's compression bit, the LASzip VLR is appended to the VLRs, the
 * EVLRs move behind the point data. False (and `why`) on a LAS file it cannot use. */
bool lazenc_from_las(const uint8_t *las, size_t las_size, const lazenc_options *options,
                     lazenc_buf *out, char *why, size_t why_size);

#endif
