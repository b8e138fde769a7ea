/* SPDX-License-Identifier: MIT
 * LAS public header block: parsing and the checks of each field against the file
 * and against the others.
 *
 * Decisions:
 * - LAS 1.4: the 64-bit point count is the count. A non-zero legacy count that
 *   disagrees with it is reported with a warning, not an error (the 64-bit field is
 *   authoritative in 1.4, and the count is checked against the file size anyway).
 * - Point formats newer than the version (4/5 before 1.3, 6-10 before 1.4) are read
 *   with a warning: the record layout depends on the format alone.
 * - The header bounds are reported, never trusted (real files get them wrong).
 */
#include <math.h>
#include <string.h>

#include "core/bytes.h"
#include "core/log.h"
#include "io/las_internal.h"

// Byte offsets of the public header block fields (LAS 1.4 R15, table 3).
enum {
    AT_FILE_SOURCE_ID = 4,
    AT_GLOBAL_ENCODING = 6,
    AT_VERSION_MAJOR = 24,
    AT_VERSION_MINOR = 25,
    AT_SYSTEM_IDENTIFIER = 26,
    AT_GENERATING_SOFTWARE = 58,
    AT_CREATION_DAY = 90,
    AT_CREATION_YEAR = 92,
    AT_HEADER_SIZE = 94,
    AT_OFFSET_TO_POINT_DATA = 96,
    AT_NUMBER_OF_VLRS = 100,
    AT_POINT_FORMAT = 104,
    AT_RECORD_LENGTH = 105,
    AT_LEGACY_POINT_COUNT = 107,
    AT_LEGACY_BY_RETURN = 111,
    AT_SCALE = 131,
    AT_OFFSET = 155,
    AT_MAX_X = 179, // then min x, max y, min y, max z, min z
    AT_WAVEFORM_START = 227,
    AT_FIRST_EVLR = 235,
    AT_NUMBER_OF_EVLRS = 243,
    AT_POINT_COUNT = 247,
    AT_BY_RETURN = 255,
};

static const char axis_names[3] = { 'x', 'y', 'z' };

void sta_las_copy_text(char *out, const uint8_t *field, size_t size)
{
    size_t length = 0;
    while (length < size && field[length] != 0) {
        length++;
    }
    // Some writers pad with spaces instead of NULs (vegetation_1_3.las: "RS Survey   ...").
    while (length > 0 && field[length - 1] == ' ') {
        length--;
    }
    memcpy(out, field, length);
    out[length] = '\0';
}

const char *sta_las_printable(char *out, const char *text)
{
    // Text fields come from the file: a byte that is not printable ASCII (control
    // characters, invalid UTF-8) is shown as \xNN so it never reaches a terminal raw.
    static const char hex[] = "0123456789abcdef";
    size_t n = 0;
    for (size_t i = 0; text[i] != '\0' && n + 5 <= STA_LAS_PRINTABLE_SIZE; i++) {
        unsigned char c = (unsigned char)text[i];
        if (c >= 0x20 && c < 0x7f && c != '\\') {
            out[n++] = (char)c;
        } else {
            out[n++] = '\\';
            out[n++] = 'x';
            out[n++] = hex[c >> 4];
            out[n++] = hex[c & 15];
        }
    }
    out[n] = '\0';
    return out;
}

static unsigned minimum_header_size(int version_minor)
{
    if (version_minor >= 4) {
        return STA_LAS_HEADER_SIZE_14;
    }
    if (version_minor == 3) {
        return STA_LAS_HEADER_SIZE_13;
    }
    return STA_LAS_HEADER_SIZE_10;
}

// Version, header size and point format: what decides how the rest is read.
static sta_status check_layout(sta_las_reader *reader, sta_las_header *header, sta_error *err)
{
    const sta_file_map *map = reader->map;
    const uint8_t *d = map->data;
    sta_cloud_info *info = &reader->info;

    info->version_major = d[AT_VERSION_MAJOR];
    info->version_minor = d[AT_VERSION_MINOR];
    if (info->version_major != 1 || info->version_minor > 4) {
        return sta_fail(err, STA_ERR_UNSUPPORTED,
                        "%s: LAS version %d.%d is not supported (versions 1.0 to 1.4 are)",
                        map->path, info->version_major, info->version_minor);
    }
    info->header_size = sta_load_u16le(d + AT_HEADER_SIZE);
    unsigned minimum = minimum_header_size(info->version_minor);
    if (info->header_size < minimum) {
        return sta_fail(err, STA_ERR_FORMAT,
                        "%s: header_size %u is smaller than the %u bytes of a LAS 1.%d header",
                        map->path, info->header_size, minimum, info->version_minor);
    }
    if (info->header_size > map->size) {
        return sta_fail(err, STA_ERR_FORMAT,
                        "%s: header_size %u is larger than the file (%zu bytes)", map->path,
                        info->header_size, map->size);
    }

    header->point_format_byte = d[AT_POINT_FORMAT];
    // LAZ hook: a compression bit marks LASzip point data (decoded by laz_*.c).
    header->is_compressed = (header->point_format_byte & 0xc0) != 0;
    info->point_format = header->point_format_byte & 0x3f;
    if (info->point_format > STA_LAS_MAX_POINT_FORMAT) {
        return sta_fail(err, STA_ERR_FORMAT,
                        "%s: point data format %d is unknown (LAS 1.4 defines 0 to 10)", map->path,
                        info->point_format);
    }
    info->record_length = sta_load_u16le(d + AT_RECORD_LENGTH);
    unsigned format_size = sta_las_format_record_size(info->point_format);
    if (info->record_length < format_size) {
        return sta_fail(err, STA_ERR_FORMAT,
                        "%s: point data record length %u is too short for point format %d "
                        "(%u bytes)",
                        map->path, info->record_length, info->point_format, format_size);
    }
    if (info->point_format >= 6 && info->version_minor < 4) {
        sta_log_warn("%s: point format %d needs LAS 1.4 but the file says 1.%d; reading it "
                     "anyway",
                     map->path, info->point_format, info->version_minor);
    } else if (info->point_format >= 4 && info->point_format <= 5 && info->version_minor < 3) {
        sta_log_warn("%s: point format %d needs LAS 1.3 or later but the file says 1.%d; "
                     "reading it anyway",
                     map->path, info->point_format, info->version_minor);
    }
    return STA_OK;
}

static sta_status check_grid(sta_las_reader *reader, sta_error *err)
{
    const sta_file_map *map = reader->map;
    sta_grid *grid = &reader->info.grid;
    for (int axis = 0; axis < 3; axis++) {
        grid->scale[axis] = sta_load_f64le(map->data + AT_SCALE + 8 * axis);
        grid->offset[axis] = sta_load_f64le(map->data + AT_OFFSET + 8 * axis);
        // The negated test also catches NaN.
        if (!(grid->scale[axis] > 0.0) || !isfinite(grid->scale[axis])) {
            return sta_fail(err, STA_ERR_FORMAT,
                            "%s: %c scale factor %g is not a positive finite number", map->path,
                            axis_names[axis], grid->scale[axis]);
        }
        if (!isfinite(grid->offset[axis])) {
            return sta_fail(err, STA_ERR_FORMAT, "%s: %c offset %g is not finite", map->path,
                            axis_names[axis], grid->offset[axis]);
        }
    }
    return STA_OK;
}

// Point counts: legacy fields always, 64-bit fields from LAS 1.4 on.
static void read_counts(sta_las_reader *reader)
{
    const sta_file_map *map = reader->map;
    const uint8_t *d = map->data;
    sta_cloud_info *info = &reader->info;

    info->legacy_point_count = sta_load_u32le(d + AT_LEGACY_POINT_COUNT);
    if (info->version_minor < 4) {
        info->header_point_count = info->legacy_point_count;
        for (int i = 0; i < 5; i++) {
            info->points_by_return[i] = sta_load_u32le(d + AT_LEGACY_BY_RETURN + 4 * i);
        }
        return;
    }
    info->header_point_count = sta_load_u64le(d + AT_POINT_COUNT);
    for (int i = 0; i < 15; i++) {
        info->points_by_return[i] = sta_load_u64le(d + AT_BY_RETURN + 8 * i);
    }
    if (info->legacy_point_count != 0 && info->legacy_point_count != info->header_point_count) {
        sta_log_warn("%s: legacy point count %u disagrees with the 64-bit point count %llu; "
                     "using the 64-bit count",
                     map->path, info->legacy_point_count,
                     (unsigned long long)info->header_point_count);
    }
}

sta_status sta_las_parse_header(sta_las_reader *reader, sta_las_header *out_header, sta_error *err)
{
    const sta_file_map *map = reader->map;
    const uint8_t *d = map->data;
    sta_cloud_info *info = &reader->info;
    memset(out_header, 0, sizeof(*out_header));

    if (map->size < STA_LAS_HEADER_SIZE_10) {
        return sta_fail(err, STA_ERR_FORMAT,
                        "%s: file has %zu bytes, fewer than the %d of a LAS header", map->path,
                        map->size, STA_LAS_HEADER_SIZE_10);
    }
    if (memcmp(d, "LASF", 4) != 0) {
        return sta_fail(err, STA_ERR_FORMAT, "%s: no \"LASF\" file signature", map->path);
    }
    sta_status status = check_layout(reader, out_header, err);
    if (status != STA_OK) {
        return status;
    }
    status = check_grid(reader, err);
    if (status != STA_OK) {
        return status;
    }

    info->offset_to_point_data = sta_load_u32le(d + AT_OFFSET_TO_POINT_DATA);
    if (info->offset_to_point_data < info->header_size) {
        return sta_fail(err, STA_ERR_FORMAT,
                        "%s: offset_to_point_data %u lies inside the %u-byte header", map->path,
                        info->offset_to_point_data, info->header_size);
    }
    if (info->offset_to_point_data > map->size) {
        return sta_fail(err, STA_ERR_FORMAT,
                        "%s: offset_to_point_data %u is past the end of the file (%zu bytes)",
                        map->path, info->offset_to_point_data, map->size);
    }
    out_header->number_of_vlrs = sta_load_u32le(d + AT_NUMBER_OF_VLRS);

    if (info->version_minor >= 1) {
        info->file_source_id = sta_load_u16le(d + AT_FILE_SOURCE_ID);
    }
    if (info->version_minor >= 2) {
        info->global_encoding = sta_load_u16le(d + AT_GLOBAL_ENCODING);
    }
    info->has_internal_waveform = (info->global_encoding & 2u) != 0;
    sta_las_copy_text(info->system_identifier, d + AT_SYSTEM_IDENTIFIER, 32);
    sta_las_copy_text(info->generating_software, d + AT_GENERATING_SOFTWARE, 32);
    info->creation_day = sta_load_u16le(d + AT_CREATION_DAY);
    info->creation_year = sta_load_u16le(d + AT_CREATION_YEAR);
    for (int axis = 0; axis < 3; axis++) {
        info->header_max[axis] = sta_load_f64le(d + AT_MAX_X + 16 * axis);
        info->header_min[axis] = sta_load_f64le(d + AT_MAX_X + 16 * axis + 8);
    }
    if (info->version_minor >= 3) {
        out_header->start_of_waveform_data = sta_load_u64le(d + AT_WAVEFORM_START);
        info->waveform_data_start = out_header->start_of_waveform_data;
    }
    if (info->version_minor >= 4) {
        out_header->start_of_first_evlr = sta_load_u64le(d + AT_FIRST_EVLR);
        out_header->number_of_evlrs = sta_load_u32le(d + AT_NUMBER_OF_EVLRS);
    }
    read_counts(reader);

    info->attributes = sta_las_format_attributes(info->point_format);
    int format = info->point_format;
    info->has_waveform_packets = format == 4 || format == 5 || format == 9 || format == 10;
    return STA_OK;
}
