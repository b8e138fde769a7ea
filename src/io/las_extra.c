/* SPDX-License-Identifier: MIT
 * The Extra Bytes VLR (LASF_Spec/4): 192-byte descriptors of the fields that follow
 * the point format's own fields in each record (LAS 1.4 R15, table 24).
 *
 * Decisions:
 * - The first Extra Bytes record in file order (VLRs, then EVLRs) is used.
 * - Descriptors are laid out one after the other from the first extra byte. A
 *   descriptor that does not fit the record's extra bytes (las/malformed_extrabytes.las
 *   describes a uint16 in records that have no extra bytes), or has a reserved data
 *   type, is dropped with a warning together with all after it: the file stays
 *   readable and the bytes stay available, raw, in the batch's extra array.
 * - Extra bytes not covered by any descriptor become one opaque dimension named
 *   "undeclared" (data_type 0, options 0).
 * - For data type 0 (undocumented bytes) the options byte is the field's size, as the
 *   specification says; it is kept as stored.
 *
 * Also here: the names of the data type codes (sta_extra_type_name, declared in
 * cloud.h for every reader's callers).
 */
#include <string.h>

#include "core/alloc.h"
#include "core/bytes.h"
#include "core/log.h"
#include "io/las_internal.h"

// Offsets inside one descriptor.
enum {
    AT_DATA_TYPE = 2,
    AT_OPTIONS = 3,
    AT_NAME = 4,
    AT_NO_DATA = 40,
    AT_SCALE = 112,
    AT_OFFSET = 136,
    AT_DESCRIPTION = 160,
};

enum {
    OPTION_NO_DATA = 1u << 0,
    OPTION_SCALE = 1u << 3,
    OPTION_OFFSET = 1u << 4,
};

// Bytes of the scalar types 1..10 (index 0 unused).
static const uint8_t scalar_sizes[11] = { 0, 1, 1, 2, 2, 4, 4, 8, 8, 4, 8 };

const char *sta_extra_type_name(uint8_t data_type)
{
    static const char *const scalar_names[] = { "opaque", "uint8",  "int8",  "uint16",
                                                "int16",  "uint32", "int32", "uint64",
                                                "int64",  "float",  "double" };
    if (data_type <= 10) {
        return scalar_names[data_type];
    }
    if (data_type <= 30) {
        return "deprecated tuple";
    }
    return "reserved";
}

// A no_data / min / max slot ("anytype": 8 bytes, integer or double by base type).
static double load_anytype(const uint8_t *p, int base_type)
{
    switch (base_type) {
    case 1:
    case 3:
    case 5:
    case 7:
        return (double)sta_load_u64le(p);
    case 2:
    case 4:
    case 6:
    case 8:
        return (double)sta_load_i64le(p);
    default:
        return sta_load_f64le(p);
    }
}

static const sta_vlr_info *find_extra_bytes_record(const sta_cloud_info *info)
{
    const sta_vlr_info *found = NULL;
    for (size_t i = 0; i < info->vlr_count; i++) {
        const sta_vlr_info *vlr = &info->vlrs[i];
        if (vlr->record_id == 4 && strcmp(vlr->user_id, "LASF_Spec") == 0) {
            if (found) {
                sta_log_warn("%s: more than one Extra Bytes record; using the first", info->path);
                break;
            }
            found = vlr;
        }
    }
    return found;
}

// Decodes descriptor `p` into `dim`; false (with a warning) when its type is reserved.
static bool decode_descriptor(const sta_cloud_info *info, const uint8_t *p, size_t index,
                              sta_extra_dim *dim)
{
    memset(dim, 0, sizeof(*dim));
    dim->data_type = p[AT_DATA_TYPE];
    dim->options = p[AT_OPTIONS];
    sta_las_copy_text(dim->name, p + AT_NAME, 32);
    sta_las_copy_text(dim->description, p + AT_DESCRIPTION, 32);
    for (int k = 0; k < 3; k++) {
        dim->scale[k] = 1.0;
    }

    int base_type = dim->data_type;
    dim->component_count = 1;
    if (dim->data_type == 0) {
        dim->size_bytes = dim->options;
        return true;
    }
    if (dim->data_type > 30) {
        char name[STA_LAS_PRINTABLE_SIZE];
        sta_log_warn("%s: Extra Bytes field %zu ('%s') has reserved data type %u", info->path,
                     index, sta_las_printable(name, dim->name), dim->data_type);
        return false;
    }
    if (dim->data_type > 20) {
        dim->component_count = 3;
        base_type -= 20;
    } else if (dim->data_type > 10) {
        dim->component_count = 2;
        base_type -= 10;
    }
    dim->size_bytes = (size_t)scalar_sizes[base_type] * (size_t)dim->component_count;
    for (int k = 0; k < dim->component_count; k++) {
        if (dim->options & OPTION_NO_DATA) {
            dim->no_data[k] = load_anytype(p + AT_NO_DATA + 8 * k, base_type);
        }
        if (dim->options & OPTION_SCALE) {
            dim->scale[k] = sta_load_f64le(p + AT_SCALE + 8 * k);
        }
        if (dim->options & OPTION_OFFSET) {
            dim->offset[k] = sta_load_f64le(p + AT_OFFSET + 8 * k);
        }
    }
    return true;
}

sta_status sta_las_read_extra_bytes(sta_las_reader *reader, sta_error *err)
{
    const sta_file_map *map = reader->map;
    sta_cloud_info *info = &reader->info;
    size_t extra_size = info->extra_size;
    const sta_vlr_info *vlr = find_extra_bytes_record(info);
    size_t descriptor_count = 0;
    if (vlr) {
        descriptor_count = (size_t)(vlr->length / STA_LAS_EXTRA_BYTES_DESCRIPTOR_SIZE);
        if (vlr->length % STA_LAS_EXTRA_BYTES_DESCRIPTOR_SIZE != 0) {
            sta_log_warn("%s: Extra Bytes record length %llu is not a multiple of %d; ignoring "
                         "the last %llu bytes",
                         map->path, (unsigned long long)vlr->length,
                         STA_LAS_EXTRA_BYTES_DESCRIPTOR_SIZE,
                         (unsigned long long)(vlr->length % STA_LAS_EXTRA_BYTES_DESCRIPTOR_SIZE));
        }
    }
    if (descriptor_count == 0 && extra_size == 0) {
        return STA_OK;
    }
    // The descriptors lie inside the map, so descriptor_count + 1 cannot overflow.
    info->extra_dims = sta_calloc(descriptor_count + 1, sizeof(*info->extra_dims));
    if (!info->extra_dims) {
        return sta_fail(err, STA_ERR_NOMEM, "%s: out of memory for %zu extra dimensions", map->path,
                        descriptor_count + 1);
    }

    size_t used = 0;
    for (size_t i = 0; i < descriptor_count; i++) {
        const uint8_t *p =
            map->data + vlr->data_offset + i * (size_t)STA_LAS_EXTRA_BYTES_DESCRIPTOR_SIZE;
        sta_extra_dim *dim = &info->extra_dims[info->extra_dim_count];
        if (!decode_descriptor(info, p, i, dim)) {
            sta_log_warn("%s: ignoring Extra Bytes fields from %zu on", map->path, i);
            break;
        }
        char name[STA_LAS_PRINTABLE_SIZE];
        sta_las_printable(name, dim->name);
        if (dim->size_bytes == 0) {
            sta_log_warn("%s: Extra Bytes field %zu ('%s') has size 0; ignoring it", map->path, i,
                         name);
            continue;
        }
        if (dim->size_bytes > extra_size - used) {
            sta_log_warn("%s: Extra Bytes field %zu ('%s', %s, %zu bytes at extra byte %zu) does "
                         "not fit the %zu extra bytes of each record (record length %u, point "
                         "format %d uses %u); ignoring it and the fields after it",
                         map->path, i, name, sta_extra_type_name(dim->data_type), dim->size_bytes,
                         used, extra_size, info->record_length, info->point_format,
                         sta_las_format_record_size(info->point_format));
            break;
        }
        dim->offset_bytes = used;
        used += dim->size_bytes;
        info->extra_dim_count++;
    }
    if (used < extra_size) {
        sta_extra_dim *dim = &info->extra_dims[info->extra_dim_count++];
        memset(dim, 0, sizeof(*dim));
        strcpy(dim->name, "undeclared");
        dim->component_count = 1;
        dim->offset_bytes = used;
        dim->size_bytes = extra_size - used;
        for (int k = 0; k < 3; k++) {
            dim->scale[k] = 1.0;
        }
    }
    if (info->extra_dim_count == 0) {
        sta_free(info->extra_dims);
        info->extra_dims = NULL;
    }
    return STA_OK;
}
