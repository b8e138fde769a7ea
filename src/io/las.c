/* SPDX-License-Identifier: MIT
 * LAS 1.0-1.4 reader: opening (the order of the checks) and streaming the points.
 *
 * Design: the file is a borrowed read-only map. Opening validates the header, the
 * VLRs, the extent of the point data and the EVLRs against the map's size, so that
 * reading is a bounds-free decode of the next records and seeking sets an index.
 * Nothing is buffered beyond the map; the only allocations are the VLR list, the
 * extra dimensions and the WKT copy, all made at open.
 *
 * Decisions:
 * - A file whose point data is shorter than the point count says is an error, naming
 *   the count, the bytes needed and the complete records present. With
 *   sta_read_options.salvage_truncated the complete records are read, point_count is
 *   their number and skipped_point_count the missing ones (a warning is printed).
 * - Point data running into the EVLRs is an error. A LAS 1.3 waveform record that
 *   cannot be where start_of_waveform_data says only warns (as in 1.4).
 * - A VLR count that overshoots the VLR area is an error; salvaging keeps the whole
 *   VLRs and reads the points (they start at offset_to_point_data regardless).
 * - The LAS 1.0 start signature (0xDDCC) before the points is skipped with any other
 *   bytes between the VLRs and offset_to_point_data.
 * See las_header.c, las_vlr.c and las_extra.c for their own decisions.
 */
#include "io/las.h"

#include <stdio.h>
#include <string.h>

#include "core/alloc.h"
#include "core/bytes.h"
#include "core/log.h"
#include "io/las_internal.h"
#include "io/laz_internal.h"

static sta_status las_read(void *impl, sta_point_batch *batch, sta_error *err)
{
    (void)err;
    sta_las_reader *reader = impl;
    if (reader->laz) { // LAZ hook
        return sta_las_read_laz(reader, batch, err);
    }
    uint64_t left = reader->info.point_count - reader->next_index;
    size_t count = left < batch->capacity ? (size_t)left : batch->capacity;
    batch->first_index = reader->next_index;
    batch->count = count;
    if (count == 0) {
        return STA_OK;
    }
    // Every record up to point_count lies inside the map (checked at open).
    size_t stride = reader->record_length;
    const uint8_t *src = reader->point_data + (size_t)reader->next_index * stride;
    reader->decode(src, stride, batch->points, count);
    size_t extra_size = reader->info.extra_size;
    if (extra_size > 0) {
        const uint8_t *extra_src = src + reader->format_size;
        uint8_t *extra_dst = batch->extra;
        for (size_t i = 0; i < count; i++) {
            memcpy(extra_dst + i * extra_size, extra_src + i * stride, extra_size);
        }
    }
    reader->next_index += count;
    // Streaming: the decoded records leave the resident set, so reading a file larger
    // than memory keeps RSS at one batch.
    sta_file_map_drop(reader->map, (size_t)(src - reader->map->data), count * stride);
    return STA_OK;
}

// las_read for X, Y and Z only (LAZ decodes whole records anyway).
static sta_status las_read_positions(void *impl, sta_point_batch *batch, sta_error *err)
{
    sta_las_reader *reader = impl;
    if (reader->laz) {
        return sta_las_read_laz(reader, batch, err);
    }
    uint64_t left = reader->info.point_count - reader->next_index;
    size_t count = left < batch->capacity ? (size_t)left : batch->capacity;
    batch->first_index = reader->next_index;
    batch->count = count;
    size_t stride = reader->record_length;
    const uint8_t *src = reader->point_data + (size_t)reader->next_index * stride;
    for (size_t i = 0; i < count; i++) {
        const uint8_t *p = src + i * stride; // X, Y, Z lead every point format
        batch->points[i].X = sta_load_i32le(p);
        batch->points[i].Y = sta_load_i32le(p + 4);
        batch->points[i].Z = sta_load_i32le(p + 8);
    }
    reader->next_index += count;
    if (count > 0) {
        sta_file_map_drop(reader->map, (size_t)(src - reader->map->data), count * stride);
    }
    return STA_OK;
}

static sta_status las_seek(void *impl, uint64_t index, sta_error *err)
{
    sta_las_reader *reader = impl;
    if (index > reader->info.point_count) {
        return sta_fail(err, STA_ERR_ARG, "%s: seek to point %llu past the %llu points",
                        reader->info.path, (unsigned long long)index,
                        (unsigned long long)reader->info.point_count);
    }
    if (reader->laz) { // LAZ hook
        sta_status status = sta_laz_seek(reader->laz, index, err);
        if (status != STA_OK) {
            return status;
        }
    }
    reader->next_index = index;
    return STA_OK;
}

static const sta_cloud_info *las_info(const void *impl)
{
    const sta_las_reader *reader = impl;
    return &reader->info;
}

static void las_close(void *impl)
{
    sta_las_reader *reader = impl;
    if (!reader) {
        return;
    }
    sta_free(reader->info.vlrs);
    sta_free(reader->info.extra_dims);
    sta_free(reader->wkt);
    sta_las_close_laz(reader); // LAZ hook
    sta_free(reader);
}

static const sta_cloud_ops las_ops = {
    .read = las_read,
    .read_positions = las_read_positions,
    .seek = las_seek,
    .info = las_info,
    .close = las_close,
};

// How many records the point data holds; sets point_count and skipped_point_count.
static sta_status check_point_data(sta_las_reader *reader, const sta_read_options *options,
                                   sta_error *err)
{
    const sta_file_map *map = reader->map;
    sta_cloud_info *info = &reader->info;
    uint64_t available = map->size - info->offset_to_point_data; // offset <= size
    uint64_t length = info->record_length;                       // >= 20
    uint64_t complete = available / length;
    uint64_t declared = info->header_point_count;
    if (declared <= complete) {
        info->point_count = declared;
        return STA_OK;
    }
    char needed[64];
    if (declared <= UINT64_MAX / length) {
        snprintf(needed, sizeof(needed), "%llu bytes", (unsigned long long)(declared * length));
    } else {
        snprintf(needed, sizeof(needed), "more than 2^64 bytes");
    }
    if (!options->salvage_truncated) {
        return sta_fail(err, STA_ERR_FORMAT,
                        "%s: point count %llu needs %s of point data (record length %llu) from "
                        "offset_to_point_data %u, file has %llu bytes there (%llu complete "
                        "records); the file is truncated or its header lies",
                        map->path, (unsigned long long)declared, needed, (unsigned long long)length,
                        info->offset_to_point_data, (unsigned long long)available,
                        (unsigned long long)complete);
    }
    sta_log_warn("%s: point count %llu needs %s of point data, file has %llu bytes there; "
                 "salvaging the %llu complete records",
                 map->path, (unsigned long long)declared, needed, (unsigned long long)available,
                 (unsigned long long)complete);
    info->point_count = complete;
    info->skipped_point_count = declared - complete;
    return STA_OK;
}

sta_status sta_las_open_map(const sta_file_map *map, const sta_read_options *options,
                            void **out_impl, const sta_cloud_ops **out_ops, sta_error *err)
{
    static const sta_read_options no_options = { 0 };
    *out_impl = NULL;
    *out_ops = NULL;
    if (!options) {
        options = &no_options;
    }
    sta_las_reader *reader = sta_calloc(1, sizeof(*reader));
    if (!reader) {
        return sta_fail(err, STA_ERR_NOMEM, "%s: out of memory", map->path);
    }
    reader->map = map;
    reader->info.kind = STA_CLOUD_LAS;
    reader->info.path = map->path;

    sta_las_header header;
    sta_status status = sta_las_parse_header(reader, &header, err);
    if (status != STA_OK) {
        goto out_close;
    }
    status = sta_las_read_vlrs(reader, &header, options, err);
    if (status != STA_OK) {
        goto out_close;
    }
    if (header.is_compressed) { // LAZ hook: the decoder checks the compressed data
        status = sta_las_open_laz(reader, &header, options, err);
    } else {
        status = check_point_data(reader, options, err);
    }
    if (status != STA_OK) {
        goto out_close;
    }
    reader->record_length = reader->info.record_length;
    reader->format_size = sta_las_format_record_size(reader->info.point_format);
    reader->info.extra_size = reader->record_length - reader->format_size;
    // point_count records fit the map, so this end fits size_t.
    uint64_t point_data_end = reader->info.offset_to_point_data +
                              reader->info.point_count * (uint64_t)reader->record_length;
    if (reader->laz) { // LAZ hook: compressed points end before the EVLRs, size unknown
        point_data_end = reader->info.offset_to_point_data;
    }
    status = sta_las_read_evlrs(reader, &header, point_data_end, options, err);
    if (status != STA_OK) {
        goto out_close;
    }
    status = sta_las_read_crs(reader, err);
    if (status != STA_OK) {
        goto out_close;
    }
    status = sta_las_read_extra_bytes(reader, err);
    if (status != STA_OK) {
        goto out_close;
    }
    reader->point_data = map->data + reader->info.offset_to_point_data;
    reader->decode = sta_las_decoder(reader->info.point_format);
    *out_impl = reader;
    *out_ops = &las_ops;
    return STA_OK;

out_close:
    las_close(reader);
    return status;
}
