/* SPDX-License-Identifier: MIT
 * Internal to the LAZ decoder (laz_*.c) and its hook in the LAS reader: the LASzip
 * VLR, the chunk layout, the per-item decoders and the decoder object that turns the
 * compressed point data back into the raw LAS point records.
 *
 * Design: the LAS reader opens a LAZ file like a LAS file (header, VLRs, EVLRs, extra
 * bytes), then hands the point data to sta_laz_open, which parses the LASzip VLR and
 * the chunk table. Reading decodes the next records into a small buffer of raw LAS
 * records (at most STA_LAZ_BATCH_RECORDS at a time) which the LAS reader's own
 * per-format decoder turns into points, so all field conversions stay in las_points.c.
 * State kept across reads: the chunk being decoded, its arithmetic decoder and the
 * item models (memory: the models plus one small record buffer, never a whole chunk).
 */
#ifndef STA_IO_LAZ_INTERNAL_H
#define STA_IO_LAZ_INTERNAL_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "core/status.h"
#include "io/laz_arith.h"

/* LASzip item types (LAZ specification, "items"). */
typedef enum sta_laz_item_type {
    STA_LAZ_ITEM_BYTE = 0,
    STA_LAZ_ITEM_SHORT = 1,
    STA_LAZ_ITEM_INT = 2,
    STA_LAZ_ITEM_LONG = 3,
    STA_LAZ_ITEM_FLOAT = 4,
    STA_LAZ_ITEM_DOUBLE = 5,
    STA_LAZ_ITEM_POINT10 = 6,
    STA_LAZ_ITEM_GPSTIME11 = 7,
    STA_LAZ_ITEM_RGB12 = 8,
    STA_LAZ_ITEM_WAVEPACKET13 = 9,
    STA_LAZ_ITEM_POINT14 = 10,
    STA_LAZ_ITEM_RGB14 = 11,
    STA_LAZ_ITEM_RGBNIR14 = 12,
    STA_LAZ_ITEM_WAVEPACKET14 = 13,
    STA_LAZ_ITEM_BYTE14 = 14,
} sta_laz_item_type;

enum {
    STA_LAZ_COMPRESSOR_POINTWISE = 1,         /* one stream, no chunks, no table */
    STA_LAZ_COMPRESSOR_POINTWISE_CHUNKED = 2, /* point10 family */
    STA_LAZ_COMPRESSOR_LAYERED_CHUNKED = 3,   /* point14 family */
    STA_LAZ_MAX_ITEMS = 8,                    /* more items than any point format has */
    STA_LAZ_BATCH_RECORDS = 1024,             /* raw records decoded per step */
};

typedef struct sta_laz_item {
    uint16_t type;    /* sta_laz_item_type */
    uint16_t size;    /* bytes of the record it fills */
    uint16_t version; /* compressor version of the item */
} sta_laz_item;

/* The LASzip VLR ("laszip encoded"/22204). */
typedef struct sta_laz_vlr {
    uint16_t compressor;
    uint16_t coder;
    uint8_t version_major;
    uint8_t version_minor;
    uint16_t version_revision;
    uint32_t options;
    uint32_t chunk_size; /* points per chunk, 0xffffffff = variable */
    uint16_t item_count;
    sta_laz_item items[STA_LAZ_MAX_ITEMS];
} sta_laz_vlr;

/* Name of an item type for messages ("POINT10", "RGB12", ...). */
const char *sta_laz_item_name(uint16_t type);

/* Parses the VLR payload and checks that its items describe `point_format` records of
 * `record_length` bytes and that we decode them (STA_ERR_UNSUPPORTED names the item
 * and version otherwise; STA_ERR_FORMAT for a malformed VLR). */
sta_status sta_laz_parse_vlr(const char *path, const uint8_t *payload, uint64_t length,
                             int point_format, size_t record_length, sta_laz_vlr *out_vlr,
                             sta_error *err);

/* ---- point10 family (formats 0-5: POINT10, GPSTIME11, RGB12, WAVEPACKET13, BYTE) ---- */

typedef struct sta_laz_p10 sta_laz_p10;

/* Item decoders for `vlr`'s items (checked by sta_laz_parse_vlr), version 2 ones here and
 * version 1 ones through sta_laz_v1_item, in record order; NULL on no memory. */
sta_laz_p10 *sta_laz_p10_create(const sta_laz_vlr *vlr);
void sta_laz_p10_destroy(sta_laz_p10 *state);
/* Starts a chunk whose first record (raw) is `first`; resets every model. */
void sta_laz_p10_begin(sta_laz_p10 *state, const uint8_t *first);
/* Decodes the next record of the chunk into `record`. False when out of memory. */
bool sta_laz_p10_decode(sta_laz_p10 *state, sta_laz_dec *dec, uint8_t *record);

/* ---- point10 family, version 1 items (laz_point10_v1.c; LASzip 1.x files) ---- */

/* One version 1 item: POINT10, GPSTIME11, RGB12, WAVEPACKET13 (the only version the
 * wave packet item has, so it also serves files of version 2 items) or BYTE. */
typedef struct sta_laz_v1_item sta_laz_v1_item;

/* Decoder for `item` (a point10 family type); NULL when out of memory. */
sta_laz_v1_item *sta_laz_v1_item_create(const sta_laz_item *item);
void sta_laz_v1_item_destroy(sta_laz_v1_item *item);
/* Starts a chunk: `first` is this item's bytes of the chunk's raw first record. */
void sta_laz_v1_item_begin(sta_laz_v1_item *item, const uint8_t *first);
/* Decodes this item's bytes of the next record into `out`. False when out of memory. */
bool sta_laz_v1_item_decode(sta_laz_v1_item *item, sta_laz_dec *dec, uint8_t *out);

/* ---- point14 family (formats 6-10, layered, versions 3 and 4) ---- */

typedef struct sta_laz_p14 sta_laz_p14;

sta_laz_p14 *sta_laz_p14_create(const sta_laz_vlr *vlr);
void sta_laz_p14_destroy(sta_laz_p14 *state);
/* Starts a layered chunk: `first` is the raw first record, `p` the bytes after it
 * (point count, layer sizes, layers) up to `end`. Sets *out_count to the chunk's
 * point count as stored and *out_end to the end of the chunk's layers. False when the
 * layer sizes run past `end` (damaged chunk). */
bool sta_laz_p14_begin(sta_laz_p14 *state, const uint8_t *first, const uint8_t *p,
                       const uint8_t *end, uint32_t *out_count, const uint8_t **out_end);
/* Decodes the next record. False when a layer overran its bytes or out of memory. */
bool sta_laz_p14_decode(sta_laz_p14 *state, uint8_t *record);

/* ---- the decoder object ---- */

typedef struct sta_laz sta_laz;

/* Opens the point data of a LAZ file: `data`/`size` is the whole file (borrowed),
 * `point_data` its offset_to_point_data, `vlr` the parsed LASzip VLR. Reads the chunk
 * table; when it is missing or damaged, decodes sequentially (warning). */
sta_status sta_laz_open(const char *path, const uint8_t *data, size_t size, uint64_t point_data,
                        const sta_laz_vlr *vlr, uint64_t point_count, size_t record_length,
                        sta_laz **out_laz, sta_error *err);
void sta_laz_close(sta_laz *laz);
/* Decodes the next `count` raw records into `out` (count * record_length bytes).
 * STA_ERR_FORMAT names the file, the chunk and the point when the data is damaged. */
sta_status sta_laz_decode(sta_laz *laz, uint8_t *out, size_t count, sta_error *err);
/* Positions at point `index` (< point count): decodes from its chunk's start. */
sta_status sta_laz_seek(sta_laz *laz, uint64_t index, sta_error *err);
/* Whether the chunk table was used (false: sequential fallback). */
bool sta_laz_has_chunk_table(const sta_laz *laz);

#endif
