/* SPDX-License-Identifier: MIT
 * LAZ behind the LAS reader: finds the LASzip VLR, opens the decoder and turns each
 * step of decoded raw records into points with the LAS reader's own per-format
 * decoder (las_points.c), so a .laz file reads exactly like its .las twin.
 *
 * Decisions:
 * - A compressed format byte without a LASzip VLR is STA_ERR_UNSUPPORTED (some other
 *   compressor may have set the bit); unsupported items are named by sta_laz_parse_vlr.
 * - The point count is the header's; damage found while decoding is an error of the
 *   read that meets it, naming the chunk and point (sta_read_options.salvage_truncated
 *   does not apply to compressed data: there is no partial record count to trust).
 * - Memory: one buffer of STA_LAZ_BATCH_RECORDS raw records, reused for every read.
 */
#include <string.h>

#include "core/alloc.h"
#include "io/las_internal.h"
#include "io/laz_internal.h"

sta_status sta_las_open_laz(sta_las_reader *reader, const sta_las_header *header,
                            const sta_read_options *options, sta_error *err)
{
    (void)options;
    const sta_file_map *map = reader->map;
    sta_cloud_info *info = &reader->info;
    const sta_vlr_info *laszip = NULL;
    for (size_t i = 0; i < info->vlr_count; i++) {
        const sta_vlr_info *vlr = &info->vlrs[i];
        if (vlr->record_id == 22204 && strcmp(vlr->user_id, "laszip encoded") == 0) {
            laszip = vlr;
            break;
        }
    }
    if (!laszip) {
        return sta_fail(err, STA_ERR_UNSUPPORTED,
                        "%s: LAZ: point data format byte 0x%02x has a compression bit set but "
                        "the file has no \"laszip encoded\"/22204 VLR describing the compressed "
                        "points",
                        map->path, header->point_format_byte);
    }
    sta_laz_vlr vlr;
    sta_status status =
        sta_laz_parse_vlr(map->path, map->data + laszip->data_offset, laszip->length,
                          info->point_format, info->record_length, &vlr, err);
    if (status != STA_OK) {
        return status;
    }
    info->point_count = info->header_point_count;
    status = sta_laz_open(map->path, map->data, map->size, info->offset_to_point_data, &vlr,
                          info->point_count, info->record_length, &reader->laz, err);
    if (status != STA_OK) {
        return status;
    }
    reader->laz_records = sta_alloc_array(STA_LAZ_BATCH_RECORDS, info->record_length);
    if (!reader->laz_records) {
        return sta_fail(err, STA_ERR_NOMEM, "%s: out of memory for LAZ records", map->path);
    }
    return STA_OK;
}

sta_status sta_las_read_laz(sta_las_reader *reader, sta_point_batch *batch, sta_error *err)
{
    uint64_t left = reader->info.point_count - reader->next_index;
    size_t count = left < batch->capacity ? (size_t)left : batch->capacity;
    batch->first_index = reader->next_index;
    batch->count = 0;
    size_t stride = reader->record_length;
    size_t extra_size = reader->info.extra_size;
    size_t done = 0;
    while (done < count) {
        size_t step = count - done < STA_LAZ_BATCH_RECORDS ? count - done : STA_LAZ_BATCH_RECORDS;
        sta_status status = sta_laz_decode(reader->laz, reader->laz_records, step, err);
        if (status != STA_OK) {
            // Nothing of this batch is delivered; the next read retries from its start.
            reader->next_index = batch->first_index;
            (void)sta_laz_seek(reader->laz, reader->next_index, NULL);
            return status;
        }
        reader->decode(reader->laz_records, stride, batch->points + done, step);
        if (extra_size > 0) {
            const uint8_t *src = reader->laz_records + reader->format_size;
            uint8_t *dst = batch->extra + done * extra_size;
            for (size_t i = 0; i < step; i++) {
                memcpy(dst + i * extra_size, src + i * stride, extra_size);
            }
        }
        done += step;
        reader->next_index += step;
    }
    batch->count = count;
    return STA_OK;
}

void sta_las_close_laz(sta_las_reader *reader)
{
    sta_laz_close(reader->laz);
    sta_free(reader->laz_records);
    reader->laz = NULL;
    reader->laz_records = NULL;
}
