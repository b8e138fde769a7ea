/* SPDX-License-Identifier: MIT
 * LAS variable length records: the VLRs between the header and the point data, the
 * EVLRs after the points (LAS 1.4; in LAS 1.3 the one waveform data packet record),
 * and the coordinate reference system records among them.
 *
 * Every count and length is checked against the bytes that can hold it before
 * anything is allocated or read: a header claiming a billion VLRs is an error, not a
 * billion allocations.
 */
#include <stdio.h>
#include <string.h>

#include "core/alloc.h"
#include "core/bytes.h"
#include "core/log.h"
#include "io/las_internal.h"

// Offsets inside a VLR / EVLR header (LAS 1.4 R15, tables 15 and 18).
enum {
    AT_USER_ID = 2,
    AT_RECORD_ID = 18,
    AT_LENGTH = 20,
    AT_VLR_DESCRIPTION = 22,
    AT_EVLR_DESCRIPTION = 28,
};

static bool has_user_id(const sta_vlr_info *vlr, const char *user_id, uint16_t record_id)
{
    return vlr->record_id == record_id && strcmp(vlr->user_id, user_id) == 0;
}

// Decodes the record header at byte `pos` (its header bytes lie inside the map).
static void decode_record_header(const sta_file_map *map, uint64_t pos, bool extended,
                                 sta_vlr_info *vlr)
{
    const uint8_t *p = map->data + pos;
    memset(vlr, 0, sizeof(*vlr));
    sta_las_copy_text(vlr->user_id, p + AT_USER_ID, 16);
    vlr->record_id = sta_load_u16le(p + AT_RECORD_ID);
    if (extended) {
        vlr->length = sta_load_u64le(p + AT_LENGTH);
        sta_las_copy_text(vlr->description, p + AT_EVLR_DESCRIPTION, 32);
        vlr->data_offset = pos + STA_LAS_EVLR_HEADER_SIZE;
    } else {
        vlr->length = sta_load_u16le(p + AT_LENGTH);
        sta_las_copy_text(vlr->description, p + AT_VLR_DESCRIPTION, 32);
        vlr->data_offset = pos + STA_LAS_VLR_HEADER_SIZE;
    }
    vlr->is_extended = extended;
}

// Appends the `count` records from `pos` (already checked by a walk) to info.vlrs.
static sta_status append_records(sta_las_reader *reader, uint64_t pos, uint64_t count,
                                 bool extended, sta_error *err)
{
    const sta_file_map *map = reader->map;
    sta_cloud_info *info = &reader->info;
    if (count == 0) {
        return STA_OK;
    }
    // Each record takes at least 54 bytes of the map, so the sum fits size_t.
    sta_vlr_info *grown =
        sta_realloc_array(info->vlrs, info->vlr_count + (size_t)count, sizeof(*info->vlrs));
    if (!grown) {
        return sta_fail(err, STA_ERR_NOMEM, "%s: out of memory for %llu %s", map->path,
                        (unsigned long long)count, extended ? "EVLRs" : "VLRs");
    }
    info->vlrs = grown;
    for (uint64_t i = 0; i < count; i++) {
        sta_vlr_info *vlr = &info->vlrs[info->vlr_count++];
        decode_record_header(map, pos, extended, vlr);
        pos = vlr->data_offset + vlr->length;
    }
    return STA_OK;
}

// A VLR that does not fit before the points: an error, or when salvaging a warning
// that keeps the `whole` records before it.
static sta_status vlr_overshoot(const sta_las_reader *reader, const sta_read_options *options,
                                const char *what, uint64_t whole, sta_error *err)
{
    const sta_file_map *map = reader->map;
    if (options->salvage_truncated) {
        sta_log_warn("%s: %s; salvaging: keeping the %llu whole VLRs before it, points from "
                     "offset_to_point_data",
                     map->path, what, (unsigned long long)whole);
        return STA_OK;
    }
    return sta_fail(err, STA_ERR_FORMAT, "%s: %s", map->path, what);
}

sta_status sta_las_read_vlrs(sta_las_reader *reader, const sta_las_header *header,
                             const sta_read_options *options, sta_error *err)
{
    const sta_file_map *map = reader->map;
    sta_cloud_info *info = &reader->info;
    uint64_t end = info->offset_to_point_data;
    uint64_t room = end - info->header_size; // header_size <= offset_to_point_data
    uint64_t count = header->number_of_vlrs;
    char what[320];

    if (count * STA_LAS_VLR_HEADER_SIZE > room && !options->salvage_truncated) {
        return sta_fail(err, STA_ERR_FORMAT,
                        "%s: number of VLRs %llu cannot be right: their headers alone need %llu "
                        "bytes but only %llu lie between header_size %u and "
                        "offset_to_point_data %u",
                        map->path, (unsigned long long)count,
                        (unsigned long long)(count * STA_LAS_VLR_HEADER_SIZE),
                        (unsigned long long)room, info->header_size, info->offset_to_point_data);
    }
    // Walk first, allocate after: a lying count costs no memory.
    uint64_t pos = info->header_size;
    uint64_t whole = 0;
    for (; whole < count; whole++) {
        if (end - pos < STA_LAS_VLR_HEADER_SIZE) {
            snprintf(what, sizeof(what),
                     "VLR %llu of %llu (number of VLRs) starts at byte %llu and runs past "
                     "offset_to_point_data %u",
                     (unsigned long long)whole, (unsigned long long)count, (unsigned long long)pos,
                     info->offset_to_point_data);
            break;
        }
        sta_vlr_info vlr;
        decode_record_header(map, pos, false, &vlr);
        if (vlr.length > end - vlr.data_offset) {
            char user_id[STA_LAS_PRINTABLE_SIZE];
            snprintf(what, sizeof(what),
                     "VLR %llu (%s/%u) record length after header %llu at byte %llu runs past "
                     "offset_to_point_data %u",
                     (unsigned long long)whole, sta_las_printable(user_id, vlr.user_id),
                     vlr.record_id, (unsigned long long)vlr.length,
                     (unsigned long long)vlr.data_offset, info->offset_to_point_data);
            break;
        }
        // LAZ hook: the LASzip VLR belongs with a compression bit in the format byte.
        if (has_user_id(&vlr, "laszip encoded", 22204) && !header->is_compressed) {
            return sta_fail(err, STA_ERR_UNSUPPORTED,
                            "%s: the file has a \"laszip encoded\"/22204 VLR (LAZ) but point "
                            "data format byte 0x%02x has no compression bit; cannot tell how "
                            "its points are stored",
                            map->path, header->point_format_byte);
        }
        pos = vlr.data_offset + vlr.length;
    }
    if (whole < count) {
        sta_status status = vlr_overshoot(reader, options, what, whole, err);
        if (status != STA_OK) {
            return status;
        }
    }
    return append_records(reader, info->header_size, whole, false, err);
}

// Records past the end: an error, or when salvaging a truncated file a warning.
static sta_status past_end(const sta_las_reader *reader, const sta_read_options *options,
                           const char *what, sta_error *err)
{
    const sta_file_map *map = reader->map;
    if (options->salvage_truncated) {
        sta_log_warn("%s: %s; the file is truncated, ignoring the extended VLRs from there on",
                     map->path, what);
        return STA_OK;
    }
    return sta_fail(err, STA_ERR_FORMAT, "%s: %s", map->path, what);
}

sta_status sta_las_read_evlrs(sta_las_reader *reader, const sta_las_header *header,
                              uint64_t point_data_end, const sta_read_options *options,
                              sta_error *err)
{
    const sta_file_map *map = reader->map;
    sta_cloud_info *info = &reader->info;
    uint64_t start = header->start_of_first_evlr;
    uint64_t count = header->number_of_evlrs;
    const char *start_field = "start_of_first_evlr";
    char what[320];

    if (info->version_minor == 3 && header->start_of_waveform_data != 0) {
        // LAS 1.3 has exactly one extended record: the waveform data packet record. A
        // pointer that cannot hold it (past the end, or inside the points) is only
        // warned about, as in 1.4: the points do not depend on it.
        start = header->start_of_waveform_data;
        count = 1;
        start_field = "start_of_waveform_data";
        if (start < point_data_end || start > map->size ||
            map->size - start < STA_LAS_EVLR_HEADER_SIZE) {
            sta_log_warn("%s: start_of_waveform_data %llu leaves no room for the waveform data "
                         "packet record (point data ends at byte %llu, the file has %zu bytes); "
                         "ignoring it",
                         map->path, (unsigned long long)start, (unsigned long long)point_data_end,
                         map->size);
            return STA_OK;
        }
    }
    if (info->version_minor >= 4 && info->waveform_data_start > map->size) {
        sta_log_warn("%s: start_of_waveform_data %llu is past the end of the file (%zu bytes)",
                     map->path, (unsigned long long)info->waveform_data_start, map->size);
    }
    if (count == 0) {
        return STA_OK;
    }
    if (start < point_data_end) {
        return sta_fail(err, STA_ERR_FORMAT,
                        "%s: %s %llu lies inside the header, VLRs or point data (point count "
                        "%llu x record length %u from offset_to_point_data %u ends at byte "
                        "%llu)",
                        map->path, start_field, (unsigned long long)start,
                        (unsigned long long)info->point_count, info->record_length,
                        info->offset_to_point_data, (unsigned long long)point_data_end);
    }
    if (start > map->size || count > (map->size - start) / STA_LAS_EVLR_HEADER_SIZE) {
        snprintf(what, sizeof(what),
                 "%llu EVLRs (number of EVLRs) from %s %llu need at least %llu bytes, past the "
                 "end of the file (%zu bytes)",
                 (unsigned long long)count, start_field, (unsigned long long)start,
                 (unsigned long long)(count * STA_LAS_EVLR_HEADER_SIZE), map->size);
        return past_end(reader, options, what, err);
    }

    // Walk first: count the whole records, then list them.
    uint64_t pos = start;
    uint64_t whole = 0;
    for (; whole < count; whole++) {
        if (map->size - pos < STA_LAS_EVLR_HEADER_SIZE) {
            snprintf(what, sizeof(what),
                     "EVLR %llu of %llu (number of EVLRs) starts at byte %llu and runs past the "
                     "end of the file (%zu bytes)",
                     (unsigned long long)whole, (unsigned long long)count, (unsigned long long)pos,
                     map->size);
            break;
        }
        sta_vlr_info vlr;
        decode_record_header(map, pos, true, &vlr);
        if (vlr.length > map->size - vlr.data_offset) {
            char user_id[STA_LAS_PRINTABLE_SIZE];
            snprintf(what, sizeof(what),
                     "EVLR %llu (%s/%u) record length after header %llu at byte %llu runs past "
                     "the end of the file (%zu bytes)",
                     (unsigned long long)whole, sta_las_printable(user_id, vlr.user_id),
                     vlr.record_id, (unsigned long long)vlr.length,
                     (unsigned long long)vlr.data_offset, map->size);
            break;
        }
        pos = vlr.data_offset + vlr.length;
    }
    if (whole < count) {
        sta_status status = past_end(reader, options, what, err);
        if (status != STA_OK) {
            return status;
        }
    }
    return append_records(reader, start, whole, true, err);
}

sta_status sta_las_read_crs(sta_las_reader *reader, sta_error *err)
{
    const sta_file_map *map = reader->map;
    sta_cloud_info *info = &reader->info;
    const sta_vlr_info *wkt = NULL;
    for (size_t i = 0; i < info->vlr_count; i++) {
        const sta_vlr_info *vlr = &info->vlrs[i];
        if (has_user_id(vlr, "LASF_Projection", 34735)) {
            info->has_geotiff_crs = true;
        }
        if (!wkt && has_user_id(vlr, "LASF_Projection", 2112)) {
            wkt = vlr;
        }
    }
    if (!wkt) {
        return STA_OK;
    }
    // The payload lies inside the map (checked by the walks), so its length fits size_t.
    const uint8_t *text = map->data + wkt->data_offset;
    size_t length = 0;
    while (length < wkt->length && text[length] != 0) {
        length++;
    }
    reader->wkt = sta_malloc(length + 1);
    if (!reader->wkt) {
        return sta_fail(err, STA_ERR_NOMEM, "%s: out of memory for a %zu-byte WKT", map->path,
                        length);
    }
    memcpy(reader->wkt, text, length);
    reader->wkt[length] = '\0';
    info->crs_wkt = reader->wkt;
    return STA_OK;
}
