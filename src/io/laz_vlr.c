/* SPDX-License-Identifier: MIT
 * The LASzip VLR ("laszip encoded"/22204): compressor, coder, chunk size and the
 * items that make up a compressed record, checked against the point format.
 *
 * Payload layout (little-endian): u16 compressor, u16 coder, u8 version major,
 * u8 version minor, u16 version revision, u32 options, u32 chunk size, i64 number of
 * special EVLRs, i64 offset of special EVLRs, u16 item count, then per item u16 type,
 * u16 size, u16 version (34 + 6 * items bytes).
 *
 * Decisions:
 * - The items must be exactly those of the point format, in record order, with the
 *   extra bytes as one trailing BYTE / BYTE14 item, and their sizes must add up to
 *   the header's record length: a mismatch is STA_ERR_FORMAT, because decoding would
 *   otherwise mix up fields.
 * - Supported: point10 family versions 1 and 2 (POINT10, GPSTIME11, RGB12, BYTE; any
 *   mix, as LASzip reads each item by its own version) and WAVEPACKET13 version 1 with
 *   the pointwise (1) or pointwise-chunked (2) compressor; point14 family versions 3
 *   and 4 (POINT14, RGB14, RGBNIR14, WAVEPACKET14, BYTE14) with the layered
 *   compressor (3). Anything else is STA_ERR_UNSUPPORTED naming the item and its
 *   version.
 */
#include <stdio.h>

#include "core/bytes.h"
#include "io/las.h"
#include "io/laz_internal.h"

enum {
    AT_COMPRESSOR = 0,
    AT_CODER = 2,
    AT_VERSION_MAJOR = 4,
    AT_VERSION_MINOR = 5,
    AT_VERSION_REVISION = 6,
    AT_OPTIONS = 8,
    AT_CHUNK_SIZE = 12,
    AT_ITEM_COUNT = 32,
    AT_ITEMS = 34,
    ITEM_SIZE = 6,
};

const char *sta_laz_item_name(uint16_t type)
{
    static const char *const names[] = {
        "BYTE",    "SHORT",   "INT",       "LONG",         "FLOAT",
        "DOUBLE",  "POINT10", "GPSTIME11", "RGB12",        "WAVEPACKET13",
        "POINT14", "RGB14",   "RGBNIR14",  "WAVEPACKET14", "BYTE14",
    };
    return type < sizeof(names) / sizeof(names[0]) ? names[type] : "unknown";
}

// The items a record of `point_format` with `extra` extra bytes is made of.
static size_t expected_items(int point_format, size_t extra, sta_laz_item *out)
{
    size_t n = 0;
    if (point_format <= 5) {
        out[n++] = (sta_laz_item){ STA_LAZ_ITEM_POINT10, 20, 2 };
        if (point_format == 1 || point_format >= 3) {
            out[n++] = (sta_laz_item){ STA_LAZ_ITEM_GPSTIME11, 8, 2 };
        }
        if (point_format == 2 || point_format == 3 || point_format == 5) {
            out[n++] = (sta_laz_item){ STA_LAZ_ITEM_RGB12, 6, 2 };
        }
        if (point_format == 4 || point_format == 5) {
            out[n++] = (sta_laz_item){ STA_LAZ_ITEM_WAVEPACKET13, 29, 1 };
        }
        if (extra > 0) {
            out[n++] = (sta_laz_item){ STA_LAZ_ITEM_BYTE, (uint16_t)extra, 2 };
        }
    } else {
        out[n++] = (sta_laz_item){ STA_LAZ_ITEM_POINT14, 30, 3 };
        if (point_format == 7) {
            out[n++] = (sta_laz_item){ STA_LAZ_ITEM_RGB14, 6, 3 };
        }
        if (point_format == 8 || point_format == 10) {
            out[n++] = (sta_laz_item){ STA_LAZ_ITEM_RGBNIR14, 8, 3 };
        }
        if (point_format == 9 || point_format == 10) {
            out[n++] = (sta_laz_item){ STA_LAZ_ITEM_WAVEPACKET14, 29, 3 };
        }
        if (extra > 0) {
            out[n++] = (sta_laz_item){ STA_LAZ_ITEM_BYTE14, (uint16_t)extra, 3 };
        }
    }
    return n;
}

static bool is_decoded(const sta_laz_item *item)
{
    switch (item->type) {
    case STA_LAZ_ITEM_POINT10:
    case STA_LAZ_ITEM_GPSTIME11:
    case STA_LAZ_ITEM_RGB12:
    case STA_LAZ_ITEM_BYTE:
        return item->version == 1 || item->version == 2;
    case STA_LAZ_ITEM_WAVEPACKET13: // has only version 1, next to version 1 or 2 items
        return item->version == 1;
    case STA_LAZ_ITEM_POINT14:
    case STA_LAZ_ITEM_RGB14:
    case STA_LAZ_ITEM_RGBNIR14:
    case STA_LAZ_ITEM_WAVEPACKET14:
    case STA_LAZ_ITEM_BYTE14:
        return item->version == 3 || item->version == 4;
    default:
        return false;
    }
}

sta_status sta_laz_parse_vlr(const char *path, const uint8_t *payload, uint64_t length,
                             int point_format, size_t record_length, sta_laz_vlr *out_vlr,
                             sta_error *err)
{
    sta_laz_vlr *vlr = out_vlr;
    *vlr = (sta_laz_vlr){ 0 };
    if (length < AT_ITEMS) {
        return sta_fail(err, STA_ERR_FORMAT,
                        "%s: LASzip VLR is %llu bytes, shorter than its 34-byte fixed part", path,
                        (unsigned long long)length);
    }
    vlr->compressor = sta_load_u16le(payload + AT_COMPRESSOR);
    vlr->coder = sta_load_u16le(payload + AT_CODER);
    vlr->version_major = payload[AT_VERSION_MAJOR];
    vlr->version_minor = payload[AT_VERSION_MINOR];
    vlr->version_revision = sta_load_u16le(payload + AT_VERSION_REVISION);
    vlr->options = sta_load_u32le(payload + AT_OPTIONS);
    vlr->chunk_size = sta_load_u32le(payload + AT_CHUNK_SIZE);
    uint16_t item_count = sta_load_u16le(payload + AT_ITEM_COUNT);
    if ((uint64_t)AT_ITEMS + (uint64_t)item_count * ITEM_SIZE > length) {
        return sta_fail(err, STA_ERR_FORMAT,
                        "%s: LASzip VLR lists %u items (%u bytes) but is %llu bytes long", path,
                        item_count, AT_ITEMS + item_count * ITEM_SIZE, (unsigned long long)length);
    }
    if (vlr->coder != 0) {
        return sta_fail(err, STA_ERR_UNSUPPORTED,
                        "%s: LASzip coder %u is not supported (only 0, arithmetic)", path,
                        vlr->coder);
    }
    if (vlr->compressor < STA_LAZ_COMPRESSOR_POINTWISE ||
        vlr->compressor > STA_LAZ_COMPRESSOR_LAYERED_CHUNKED) {
        return sta_fail(err, STA_ERR_UNSUPPORTED,
                        "%s: LASzip compressor %u is not supported (1 pointwise, 2 chunked, 3 "
                        "layered are)",
                        path, vlr->compressor);
    }
    if (vlr->chunk_size == 0 && vlr->compressor != STA_LAZ_COMPRESSOR_POINTWISE) {
        return sta_fail(err, STA_ERR_FORMAT, "%s: LASzip VLR chunk size is 0", path);
    }
    size_t format_size = sta_las_format_record_size(point_format);
    size_t total = 0;
    for (uint16_t i = 0; i < item_count; i++) {
        total += sta_load_u16le(payload + AT_ITEMS + i * ITEM_SIZE + 2);
    }
    if (total != record_length) {
        return sta_fail(err, STA_ERR_FORMAT,
                        "%s: LASzip items add up to %zu bytes per point, the header's record "
                        "length is %zu",
                        path, total, record_length);
    }
    sta_laz_item expected[STA_LAZ_MAX_ITEMS];
    size_t extra = record_length > format_size ? record_length - format_size : 0;
    size_t expected_count = expected_items(point_format, extra, expected);
    if (item_count != expected_count) {
        return sta_fail(err, STA_ERR_FORMAT,
                        "%s: LASzip VLR lists %u items, point format %d with %zu extra bytes "
                        "needs %zu",
                        path, item_count, point_format, extra, expected_count);
    }
    vlr->item_count = item_count;
    for (uint16_t i = 0; i < item_count; i++) {
        sta_laz_item *item = &vlr->items[i];
        const uint8_t *p = payload + AT_ITEMS + i * ITEM_SIZE;
        item->type = sta_load_u16le(p);
        item->size = sta_load_u16le(p + 2);
        item->version = sta_load_u16le(p + 4);
        if (item->type != expected[i].type || item->size != expected[i].size) {
            return sta_fail(err, STA_ERR_FORMAT,
                            "%s: LASzip item %u is %s (type %u) of %u bytes, point format %d "
                            "needs %s of %u bytes there",
                            path, i, sta_laz_item_name(item->type), item->type, item->size,
                            point_format, sta_laz_item_name(expected[i].type), expected[i].size);
        }
    }
    for (uint16_t i = 0; i < item_count; i++) {
        const sta_laz_item *item = &vlr->items[i];
        if (!is_decoded(item)) {
            return sta_fail(
                err, STA_ERR_UNSUPPORTED,
                "%s: LAZ item %s version %u is not one LASzip writes (decoded: POINT10, "
                "GPSTIME11, RGB12, BYTE version 1 or 2, WAVEPACKET13 version 1; POINT14, "
                "RGB14, RGBNIR14, WAVEPACKET14, BYTE14 version 3 or 4)",
                path, sta_laz_item_name(item->type), item->version);
        }
    }
    bool layered = point_format > 5;
    if (layered != (vlr->compressor == STA_LAZ_COMPRESSOR_LAYERED_CHUNKED)) {
        return sta_fail(err, STA_ERR_FORMAT,
                        "%s: LASzip compressor %u does not fit point format %d (formats 6-10 use "
                        "the layered compressor 3, formats 0-5 compressor 1 or 2)",
                        path, vlr->compressor, point_format);
    }
    return STA_OK;
}
