/* SPDX-License-Identifier: MIT
 * Test encoder: the LASzip VLR, chunking, the chunk table and whole LAZ files made
 * from LAS files (see lazenc.h). Layout as LASzip writes it: at the start of the
 * point data an int64 with the chunk table's offset (not for compressor 1), the
 * chunks, then the table: u32 version 0, u32 chunk count and an arithmetic-coded
 * list of (point count when chunks are variable, byte size) per chunk, each
 * predicted from the previous chunk's.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/bytes.h"
#include "lazenc.h"

bool lazenc_make_vlr(int point_format, size_t record_length, const lazenc_options *options,
                     sta_laz_vlr *vlr)
{
    static const size_t base_size[11] = { 20, 28, 26, 34, 57, 63, 30, 36, 38, 59, 67 };
    if (point_format < 0 || point_format > 10 || record_length < base_size[point_format]) {
        return false;
    }
    *vlr = (sta_laz_vlr){ .compressor = options->compressor,
                          .version_major = 2,
                          .version_minor = options->version >= 3 ? 4 : 2,
                          .chunk_size = options->chunk_size };
    bool layered = point_format >= 6;
    if (layered != (options->compressor == STA_LAZ_COMPRESSOR_LAYERED_CHUNKED)) {
        return false;
    }
    uint16_t v = options->version;
    size_t n = 0;
#define ITEM(t, s, ver) (vlr->items[n++] = (sta_laz_item){ (t), (s), (ver) })
    if (!layered) {
        ITEM(STA_LAZ_ITEM_POINT10, 20, v);
        if (point_format == 1 || point_format >= 3) {
            ITEM(STA_LAZ_ITEM_GPSTIME11, 8, v);
        }
        if (point_format == 2 || point_format == 3 || point_format == 5) {
            ITEM(STA_LAZ_ITEM_RGB12, 6, v);
        }
        if (point_format >= 4) { // LASzip has wave packets only as version 1
            ITEM(STA_LAZ_ITEM_WAVEPACKET13, 29, 1);
        }
        if (record_length > base_size[point_format]) {
            ITEM(STA_LAZ_ITEM_BYTE, (uint16_t)(record_length - base_size[point_format]), v);
        }
    } else {
        ITEM(STA_LAZ_ITEM_POINT14, 30, v);
        if (point_format == 7) {
            ITEM(STA_LAZ_ITEM_RGB14, 6, v);
        } else if (point_format == 8 || point_format == 10) {
            ITEM(STA_LAZ_ITEM_RGBNIR14, 8, v);
        }
        if (point_format >= 9) {
            ITEM(STA_LAZ_ITEM_WAVEPACKET14, 29, v);
        }
        if (record_length > base_size[point_format]) {
            ITEM(STA_LAZ_ITEM_BYTE14, (uint16_t)(record_length - base_size[point_format]), v);
        }
    }
#undef ITEM
    vlr->item_count = (uint16_t)n;
    return true;
}

void lazenc_vlr_payload(const sta_laz_vlr *vlr, lazenc_buf *out)
{
    lazenc_buf_put_u16(out, vlr->compressor);
    lazenc_buf_put_u16(out, vlr->coder);
    uint8_t version[2] = { vlr->version_major, vlr->version_minor };
    lazenc_buf_put(out, version, 2);
    lazenc_buf_put_u16(out, vlr->version_revision);
    lazenc_buf_put_u32(out, vlr->options);
    lazenc_buf_put_u32(out, vlr->chunk_size);
    lazenc_buf_put_u64(out, UINT64_MAX); // number of special EVLRs: none
    lazenc_buf_put_u64(out, UINT64_MAX); // their offset: none
    lazenc_buf_put_u16(out, vlr->item_count);
    for (size_t i = 0; i < vlr->item_count; i++) {
        lazenc_buf_put_u16(out, vlr->items[i].type);
        lazenc_buf_put_u16(out, vlr->items[i].size);
        lazenc_buf_put_u16(out, vlr->items[i].version);
    }
}

// One point10-family chunk: the first record raw, the rest in one stream.
static bool sequential_chunk(const sta_laz_vlr *vlr, const uint8_t *records, size_t count,
                             size_t record_length, lazenc_buf *out)
{
    lazenc_seq_item items[STA_LAZ_MAX_ITEMS];
    size_t offsets[STA_LAZ_MAX_ITEMS];
    size_t at = 0;
    bool ok = true;
    size_t made = 0;
    for (; made < vlr->item_count; made++) {
        const sta_laz_item *item = &vlr->items[made];
        offsets[made] = at;
        at += item->size;
        if (!lazenc_point10_v2_item(item, &items[made]) &&
            !lazenc_point10_v1_item(item, &items[made])) {
            ok = false;
            break;
        }
    }
    if (ok && at == record_length) {
        lazenc_buf_put(out, records, record_length);
        for (size_t i = 0; i < made; i++) {
            items[i].begin(items[i].state, records + offsets[i]);
        }
        lazenc_arith enc;
        lazenc_arith_init(&enc, out);
        for (size_t p = 1; p < count; p++) {
            const uint8_t *record = records + p * record_length;
            for (size_t i = 0; i < made; i++) {
                items[i].encode(items[i].state, &enc, record + offsets[i]);
            }
        }
        lazenc_arith_done(&enc);
    }
    for (size_t i = 0; i < made; i++) {
        items[i].destroy(items[i].state);
    }
    return ok && at == record_length;
}

static bool write_chunk_table(const lazenc_options *o, const uint64_t *points,
                              const uint64_t *sizes, size_t chunks, lazenc_buf *out)
{
    lazenc_buf_put_u32(out, 0);
    lazenc_buf_put_u32(out, (uint32_t)chunks);
    if (chunks == 0) {
        return true;
    }
    sta_laz_ic ic;
    if (!sta_laz_ic_init(&ic, 32, 2)) {
        abort();
    }
    lazenc_arith enc;
    lazenc_arith_init(&enc, out);
    for (size_t i = 0; i < chunks; i++) {
        if (o->chunk_size == UINT32_MAX) {
            lazenc_ic_encode(&ic, &enc, i ? (int32_t)points[i - 1] : 0, (int32_t)points[i], 0);
        }
        lazenc_ic_encode(&ic, &enc, i ? (int32_t)sizes[i - 1] : 0, (int32_t)sizes[i], 1);
    }
    lazenc_arith_done(&enc);
    sta_laz_ic_release(&ic);
    return true;
}

bool lazenc_point_data(const lazenc_options *o, const sta_laz_vlr *vlr, const uint8_t *records,
                       uint64_t count, size_t record_length, uint64_t data_offset, lazenc_buf *out)
{
    bool layered = o->compressor == STA_LAZ_COMPRESSOR_LAYERED_CHUNKED;
    if (o->compressor == STA_LAZ_COMPRESSOR_POINTWISE) {
        return count == 0 || sequential_chunk(vlr, records, count, record_length, out);
    }
    size_t start = out->size;
    lazenc_buf_put_u64(out, 0); // patched below
    size_t max_chunks =
        o->chunk_size == UINT32_MAX
            ? o->chunk_count
            : (size_t)((count + o->chunk_size - 1) / (o->chunk_size ? o->chunk_size : 1));
    uint64_t *points = calloc(max_chunks + 1, sizeof(*points));
    uint64_t *sizes = calloc(max_chunks + 1, sizeof(*sizes));
    if (!points || !sizes || (o->chunk_size == 0)) {
        free(points);
        free(sizes);
        return false;
    }
    size_t chunks = 0;
    uint64_t done = 0;
    bool ok = true;
    while (ok && done < count && chunks < max_chunks) {
        uint64_t n = o->chunk_size == UINT32_MAX ? o->chunk_points[chunks] : o->chunk_size;
        if (n > count - done) {
            n = count - done;
        }
        size_t before = out->size;
        const uint8_t *first = records + done * record_length;
        ok = n > 0 && (layered ? lazenc_point14_chunk(vlr, first, (size_t)n, record_length, out)
                               : sequential_chunk(vlr, first, (size_t)n, record_length, out));
        points[chunks] = n;
        sizes[chunks] = out->size - before;
        chunks++;
        done += n;
    }
    ok = ok && done == count;
    if (ok) {
        uint64_t table_at = o->no_chunk_table ? UINT64_MAX : data_offset + (out->size - start);
        for (int i = 0; i < 8; i++) {
            out->data[start + (size_t)i] = (uint8_t)(table_at >> (8 * i));
        }
        if (!o->no_chunk_table) {
            write_chunk_table(o, points, sizes, chunks, out);
        }
    }
    free(points);
    free(sizes);
    return ok;
}

// ---- whole files ----

enum {
    AT_VERSION_MINOR = 25,
    AT_HEADER_SIZE = 94,
    AT_POINT_DATA = 96,
    AT_VLR_COUNT = 100,
    AT_FORMAT = 104,
    AT_RECORD_LENGTH = 105,
    AT_LEGACY_COUNT = 107,
    AT_WAVEFORM_DATA = 227,
    AT_FIRST_EVLR = 235,
    AT_EVLR_COUNT = 243,
    AT_COUNT_14 = 247,
    VLR_HEADER = 54,
};

static bool refuse(char *why, size_t why_size, const char *what)
{
    snprintf(why, why_size, "%s", what);
    return false;
}

bool lazenc_from_las(const uint8_t *las, size_t las_size, const lazenc_options *options,
                     lazenc_buf *out, char *why, size_t why_size)
{
    if (las_size < 227 || memcmp(las, "LASF", 4) != 0) {
        return refuse(why, why_size, "not a LAS file");
    }
    uint16_t header_size = sta_load_u16le(las + AT_HEADER_SIZE);
    uint32_t point_data = sta_load_u32le(las + AT_POINT_DATA);
    int format = las[AT_FORMAT] & 0x3f;
    size_t record_length = sta_load_u16le(las + AT_RECORD_LENGTH);
    bool v14 = las[AT_VERSION_MINOR] >= 4 && header_size >= 375;
    uint64_t count = sta_load_u32le(las + AT_LEGACY_COUNT);
    uint64_t first_evlr = 0;
    uint32_t evlrs = 0;
    if (v14) {
        count = sta_load_u64le(las + AT_COUNT_14);
        first_evlr = sta_load_u64le(las + AT_FIRST_EVLR);
        evlrs = sta_load_u32le(las + AT_EVLR_COUNT);
    }
    if (header_size > point_data || point_data > las_size || record_length == 0 ||
        count > (las_size - point_data) / record_length) {
        return refuse(why, why_size, "LAS header does not fit the file");
    }
    uint64_t points_end = point_data + count * record_length;
    if (evlrs == 0 || first_evlr < points_end || first_evlr > las_size) {
        first_evlr = las_size; // EVLRs: everything after the records, if declared
        evlrs = 0;
    }
    sta_laz_vlr vlr;
    if (!lazenc_make_vlr(format, record_length, options, &vlr)) {
        return refuse(why, why_size, "no LAZ items for this point format and options");
    }
    lazenc_buf payload = { 0 };
    lazenc_vlr_payload(&vlr, &payload);

    // Header and existing VLRs, the LASzip VLR, then any bytes before the points.
    size_t vlr_end = header_size;
    for (uint32_t i = 0; i < sta_load_u32le(las + AT_VLR_COUNT); i++) {
        if (vlr_end + VLR_HEADER > point_data) {
            return refuse(why, why_size, "VLRs run into the point data");
        }
        vlr_end += VLR_HEADER + sta_load_u16le(las + vlr_end + 20);
    }
    if (vlr_end > point_data) {
        return refuse(why, why_size, "VLRs run into the point data");
    }
    size_t start = out->size;
    lazenc_buf_put(out, las, vlr_end);
    uint8_t vlr_header[VLR_HEADER] = { 0 };
    memcpy(vlr_header + 2, "laszip encoded", 14);
    vlr_header[18] = (uint8_t)(22204 & 0xff);
    vlr_header[19] = (uint8_t)(22204 >> 8);
    vlr_header[20] = (uint8_t)(payload.size & 0xff);
    vlr_header[21] = (uint8_t)(payload.size >> 8);
    memcpy(vlr_header + 22, "by strata tests", 15);
    lazenc_buf_put(out, vlr_header, sizeof(vlr_header));
    lazenc_buf_put(out, payload.data, payload.size);
    lazenc_buf_free(&payload);
    lazenc_buf_put(out, las + vlr_end, point_data - vlr_end);
    uint64_t new_point_data = out->size - start;
    uint8_t *h = out->data + start;
    h[AT_FORMAT] = (uint8_t)(las[AT_FORMAT] | 0x80);
    sta_store_u32le(h + AT_POINT_DATA, (uint32_t)new_point_data);
    sta_store_u32le(h + AT_VLR_COUNT, sta_load_u32le(las + AT_VLR_COUNT) + 1);

    if (!lazenc_point_data(options, &vlr, las + point_data, count, record_length, new_point_data,
                           out)) {
        return refuse(why, why_size, "an item could not be encoded");
    }
    // Whatever followed the records (EVLRs, LAS 1.3 waveform data) follows the chunk
    // table; offsets into it move by the same amount.
    uint64_t tail = v14 && evlrs > 0 ? first_evlr : points_end;
    uint64_t moved_to = out->size - start;
    lazenc_buf_put(out, las + tail, las_size - tail);
    if (v14 && evlrs > 0) {
        sta_store_u64le(out->data + start + AT_FIRST_EVLR, moved_to);
    }
    uint64_t waveform = header_size >= 235 ? sta_load_u64le(las + AT_WAVEFORM_DATA) : 0;
    if (waveform >= tail && waveform < las_size) {
        sta_store_u64le(out->data + start + AT_WAVEFORM_DATA, waveform - tail + moved_to);
    }
    return true;
}
