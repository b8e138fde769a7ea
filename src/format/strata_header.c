/* SPDX-License-Identifier: MIT
 * The .strata header and extra-dimension descriptors: serialising, parsing and
 * validating them against the file (docs/FORMAT.md §3, §4).
 */
#include <inttypes.h>
#include <math.h>
#include <string.h>

#define XXH_STATIC_LINKING_ONLY // XXH3_state_t on the stack
#include <xxhash.h>

#include "core/alloc.h"
#include "core/bytes.h"
#include "format/strata_internal.h"

uint64_t sta_strata_checksum(const void *data, size_t size)
{
    return XXH3_64bits(data, size);
}

uint64_t sta_strata_header_checksum(const uint8_t *header, size_t size)
{
    static const uint8_t zeros[8] = { 0 };
    XXH3_state_t state;
    XXH3_64bits_reset(&state);
    XXH3_64bits_update(&state, header, STA_STRATA_H_HEADER_CHECKSUM_OFF);
    XXH3_64bits_update(&state, zeros, sizeof(zeros));
    XXH3_64bits_update(&state, header + STA_STRATA_H_HEADER_CHECKSUM_OFF + 8,
                       size - STA_STRATA_H_HEADER_CHECKSUM_OFF - 8);
    return XXH3_64bits_digest(&state);
}

void sta_strata_header_store(const sta_strata_info *info, uint8_t *out)
{
    const sta_strata_geometry *g = &info->geometry;
    memset(out, 0, info->header_size);
    memcpy(out + STA_STRATA_H_MAGIC_OFF, STA_STRATA_MAGIC, STA_STRATA_MAGIC_SIZE);
    sta_store_u16le(out + STA_STRATA_H_VERSION_MAJOR_OFF, info->version_major);
    sta_store_u16le(out + STA_STRATA_H_VERSION_MINOR_OFF, info->version_minor);
    sta_store_u32le(out + STA_STRATA_H_HEADER_SIZE_OFF, info->header_size);
    sta_store_u64le(out + STA_STRATA_H_FILE_SIZE_OFF, info->file_size);
    sta_store_u32le(out + STA_STRATA_H_FLAGS_OFF, info->flags);
    sta_store_u32le(out + STA_STRATA_H_CHECKSUM_ALGO_OFF, STA_STRATA_CHECKSUM_XXH3);
    sta_store_u32le(out + STA_STRATA_H_GRID_CELLS_OFF, g->grid_cells);
    sta_store_u32le(out + STA_STRATA_H_ALIGNMENT_OFF, info->payload_alignment);
    for (int a = 0; a < 3; a++) {
        sta_store_f64le(out + STA_STRATA_H_SCALE_OFF + 8 * a, g->grid.scale[a]);
        sta_store_f64le(out + STA_STRATA_H_OFFSET_OFF + 8 * a, g->grid.offset[a]);
        sta_store_u64le(out + STA_STRATA_H_ROOT_CORNER_OFF + 8 * a, (uint64_t)g->root_corner[a]);
        out[STA_STRATA_H_ROOT_LOG2_OFF + a] = g->root_size_log2[a];
        sta_store_i32le(out + STA_STRATA_H_GRID_MIN_OFF + 4 * a, info->grid_min[a]);
        sta_store_i32le(out + STA_STRATA_H_GRID_MAX_OFF + 4 * a, info->grid_max[a]);
        sta_store_f64le(out + STA_STRATA_H_BOUNDS_MIN_OFF + 8 * a, info->bounds_min[a]);
        sta_store_f64le(out + STA_STRATA_H_BOUNDS_MAX_OFF + 8 * a, info->bounds_max[a]);
    }
    out[STA_STRATA_H_MAX_LEVEL_OFF] = info->max_level;
    sta_store_u32le(out + STA_STRATA_H_ATTRIBUTES_OFF, info->layout.attributes);
    for (int b = 0; b < STA_STRATA_ATTR_BITS; b++) {
        sta_store_u16le(out + STA_STRATA_H_ATTR_SIZES_OFF + 2 * b, info->layout.attr_size[b]);
    }
    sta_store_u32le(out + STA_STRATA_H_RECORD_SIZE_OFF, info->layout.record_size);
    sta_store_u32le(out + STA_STRATA_H_EXTRA_COUNT_OFF, info->layout.extra_dim_count);
    sta_store_u64le(out + STA_STRATA_H_POINT_COUNT_OFF, info->point_count);
    sta_store_u32le(out + STA_STRATA_H_NODE_COUNT_OFF, info->node_count);
    sta_store_u32le(out + STA_STRATA_H_ENTRY_SIZE_OFF, info->node_entry_size);
    sta_store_u64le(out + STA_STRATA_H_TABLE_OFFSET_OFF, info->table_offset);
    sta_store_u64le(out + STA_STRATA_H_TABLE_CHECKSUM_OFF, info->table_checksum);
    sta_store_u64le(out + STA_STRATA_H_EXTRA_CHECKSUM_OFF, info->extra_dims_checksum);
    size_t n = strnlen(info->generator, 32);
    memcpy(out + STA_STRATA_H_GENERATOR_OFF, info->generator, n);
    out[STA_STRATA_H_UP_AXIS_OFF] = info->up_axis;
    sta_store_u64le(out + STA_STRATA_H_SOURCE_OFFSET_OFF, info->source_offset);
    sta_store_u64le(out + STA_STRATA_H_SOURCE_SIZE_OFF, info->source_size);
    sta_store_u64le(out + STA_STRATA_H_SOURCE_CHECKSUM_OFF, info->source_checksum);
    sta_store_u64le(out + STA_STRATA_H_HEADER_CHECKSUM_OFF,
                    sta_strata_header_checksum(out, info->header_size));
}

void sta_strata_extra_dims_store(const sta_strata_extra_dim *dims, uint32_t count, uint8_t *out)
{
    memset(out, 0, (size_t)count * STA_STRATA_EXTRA_DIM_SIZE);
    for (uint32_t i = 0; i < count; i++) {
        uint8_t *d = out + (size_t)i * STA_STRATA_EXTRA_DIM_SIZE;
        memcpy(d + STA_STRATA_D_NAME_OFF, dims[i].name, strnlen(dims[i].name, 32));
        memcpy(d + STA_STRATA_D_DESCRIPTION_OFF, dims[i].description,
               strnlen(dims[i].description, 32));
        d[STA_STRATA_D_DATA_TYPE_OFF] = dims[i].data_type;
        sta_store_u16le(d + STA_STRATA_D_SIZE_OFF, dims[i].size_bytes);
        for (int c = 0; c < 3; c++) {
            sta_store_f64le(d + STA_STRATA_D_SCALE_OFF + 8 * c, dims[i].scale[c]);
            sta_store_f64le(d + STA_STRATA_D_OFFSET_OFF + 8 * c, dims[i].offset[c]);
        }
    }
}

// Copies a NUL-padded field of `size` bytes into a NUL-terminated string.
static void copy_text(char *dst, const uint8_t *src, size_t size)
{
    size_t n = strnlen((const char *)src, size);
    memcpy(dst, src, n);
    dst[n] = '\0';
}

static sta_status parse_extra_dims(const uint8_t *data, const char *name, sta_strata_info *info,
                                   bool ignore_checksums, sta_strata_extra_dim **out_dims,
                                   sta_error *err)
{
    uint32_t count = info->layout.extra_dim_count;
    const uint8_t *table = data + info->header_size;
    size_t table_size = (size_t)count * STA_STRATA_EXTRA_DIM_SIZE;
    uint64_t sum = sta_strata_checksum(table, table_size);
    if (!ignore_checksums && sum != info->extra_dims_checksum) {
        return sta_fail(err, STA_ERR_FORMAT,
                        "%s: extra-dimension descriptors checksum 0x%016" PRIx64
                        " does not match 0x%016" PRIx64 " (corrupted file)",
                        name, sum, info->extra_dims_checksum);
    }
    if (count == 0) {
        return STA_OK;
    }
    sta_strata_extra_dim *dims = sta_calloc(count, sizeof(*dims));
    if (!dims) {
        return sta_fail(err, STA_ERR_NOMEM, "%s: out of memory for %" PRIu32 " extra dimensions",
                        name, count);
    }
    uint64_t total = 0;
    for (uint32_t i = 0; i < count; i++) {
        const uint8_t *d = table + (size_t)i * STA_STRATA_EXTRA_DIM_SIZE;
        sta_strata_extra_dim *x = &dims[i];
        copy_text(x->name, d + STA_STRATA_D_NAME_OFF, 32);
        copy_text(x->description, d + STA_STRATA_D_DESCRIPTION_OFF, 32);
        x->data_type = d[STA_STRATA_D_DATA_TYPE_OFF];
        x->size_bytes = sta_load_u16le(d + STA_STRATA_D_SIZE_OFF);
        for (int c = 0; c < 3; c++) {
            x->scale[c] = sta_load_f64le(d + STA_STRATA_D_SCALE_OFF + 8 * c);
            x->offset[c] = sta_load_f64le(d + STA_STRATA_D_OFFSET_OFF + 8 * c);
        }
        uint16_t type_size = sta_strata_extra_type_size(x->data_type);
        if (x->data_type > 30 || x->size_bytes == 0 ||
            (type_size != 0 && type_size != x->size_bytes)) {
            sta_status s = sta_fail(err, STA_ERR_FORMAT,
                                    "%s: extra dimension %" PRIu32 " '%s': data type %u with %u "
                                    "bytes per point is not valid",
                                    name, i, x->name, x->data_type, x->size_bytes);
            sta_free(dims);
            return s;
        }
        total += x->size_bytes;
    }
    if (total != info->layout.attr_size[13]) {
        sta_free(dims);
        return sta_fail(err, STA_ERR_FORMAT,
                        "%s: extra dimensions take %" PRIu64
                        " bytes per point but the attribute sizes say %u",
                        name, total, info->layout.attr_size[13]);
    }
    info->layout.extra_dims = dims;
    info->layout.extra_size = (uint32_t)total;
    *out_dims = dims;
    return STA_OK;
}

// The geometry and bounds fields: grid, root box, grid cells, tight bounds.
static sta_status check_geometry(const sta_strata_info *info, const char *name, sta_error *err)
{
    const sta_strata_geometry *g = &info->geometry;
    if (g->grid_cells < 1 || g->grid_cells > STA_STRATA_MAX_CELLS) {
        return sta_fail(err, STA_ERR_FORMAT, "%s: grid_cells %" PRIu32 " is not in 1..%u", name,
                        g->grid_cells, STA_STRATA_MAX_CELLS);
    }
    for (int a = 0; a < 3; a++) {
        if (!isfinite(g->grid.scale[a]) || !(g->grid.scale[a] > 0.0) ||
            !isfinite(g->grid.offset[a])) {
            return sta_fail(err, STA_ERR_FORMAT, "%s: axis %d has scale %g and offset %g", name, a,
                            g->grid.scale[a], g->grid.offset[a]);
        }
        if (g->root_size_log2[a] > STA_STRATA_MAX_ROOT_LOG2) {
            return sta_fail(err, STA_ERR_FORMAT, "%s: root_size_log2[%d] %u exceeds %u", name, a,
                            g->root_size_log2[a], STA_STRATA_MAX_ROOT_LOG2);
        }
        int64_t corner = g->root_corner[a];
        int64_t size = (int64_t)1 << g->root_size_log2[a];
        if (corner < INT32_MIN || corner > (int64_t)INT32_MAX + 1 - size) {
            return sta_fail(err, STA_ERR_FORMAT,
                            "%s: root box axis %d [%" PRId64 ", %" PRId64 " + 2^%u) leaves the "
                            "int32 grid",
                            name, a, corner, corner, g->root_size_log2[a]);
        }
    }
    if (info->max_level > sta_strata_level_cap(g)) {
        return sta_fail(err, STA_ERR_FORMAT, "%s: max_level %u exceeds the root's depth limit %u",
                        name, info->max_level, sta_strata_level_cap(g));
    }
    for (int a = 0; a < 3; a++) {
        int64_t lo = g->root_corner[a], hi = lo + ((int64_t)1 << g->root_size_log2[a]);
        bool empty = info->point_count == 0;
        if (empty ? (info->grid_min[a] != 0 || info->grid_max[a] != 0)
                  : (info->grid_min[a] > info->grid_max[a] || info->grid_min[a] < lo ||
                     info->grid_max[a] >= hi)) {
            return sta_fail(err, STA_ERR_FORMAT,
                            "%s: grid bounds axis %d [%" PRId32 ", %" PRId32
                            "] do not fit the root box [%" PRId64 ", %" PRId64 ")",
                            name, a, info->grid_min[a], info->grid_max[a], lo, hi);
        }
        if (!isfinite(info->bounds_min[a]) || !isfinite(info->bounds_max[a]) ||
            info->bounds_min[a] > info->bounds_max[a]) {
            return sta_fail(err, STA_ERR_FORMAT, "%s: bounds axis %d [%g, %g] are not valid", name,
                            a, info->bounds_min[a], info->bounds_max[a]);
        }
    }
    return STA_OK;
}

// Attribute mask against the per-bit sizes and the record size.
static sta_status check_attributes(sta_strata_info *info, const char *name, sta_error *err)
{
    sta_strata_layout *l = &info->layout;
    uint64_t record = STA_STRATA_POSITION_SIZE;
    for (int b = 0; b < STA_STRATA_ATTR_BITS; b++) {
        uint32_t bit = 1u << b;
        uint16_t size = l->attr_size[b];
        bool present = (l->attributes & bit) != 0;
        bool known = (bit & STA_STRATA_ATTR_KNOWN) && bit != STA_STRATA_ATTR_EXTRA;
        if (present ? (size == 0 || (known && size != sta_strata_attr_size(bit))) : size != 0) {
            return sta_fail(err, STA_ERR_FORMAT,
                            "%s: attribute bit %d is %s with %u bytes per point", name, b,
                            present ? "present" : "absent", size);
        }
        record += size;
    }
    if (record != l->record_size) {
        return sta_fail(err, STA_ERR_FORMAT,
                        "%s: record_size %" PRIu32 " does not match the attributes (%" PRIu64 ")",
                        name, l->record_size, record);
    }
    bool has_extra = (l->attributes & STA_STRATA_ATTR_EXTRA) != 0;
    if (has_extra != (l->extra_dim_count > 0) || l->extra_dim_count > STA_STRATA_MAX_EXTRA_DIMS) {
        return sta_fail(err, STA_ERR_FORMAT,
                        "%s: %" PRIu32 " extra dimensions with the extra attribute bit %s", name,
                        l->extra_dim_count, has_extra ? "set" : "clear");
    }
    return STA_OK;
}

// Offsets of descriptors, payload area and table against each other and the file.
static sta_status check_offsets(sta_strata_info *info, const char *name, sta_error *err)
{
    uint32_t align = info->payload_alignment;
    if (align == 0 || (align & (align - 1)) != 0 || align > 65536) {
        return sta_fail(err, STA_ERR_FORMAT,
                        "%s: payload_alignment %" PRIu32 " is not a power of two up to 65536", name,
                        align);
    }
    uint64_t dims_end = (uint64_t)info->header_size +
                        (uint64_t)info->layout.extra_dim_count * STA_STRATA_EXTRA_DIM_SIZE;
    if (dims_end > info->file_size) {
        return sta_fail(err, STA_ERR_FORMAT,
                        "%s: %" PRIu32 " extra-dimension descriptors end at %" PRIu64
                        ", past the end of the file (%" PRIu64 " bytes)",
                        name, info->layout.extra_dim_count, dims_end, info->file_size);
    }
    info->data_offset = sta_strata_align(dims_end, align);
    if (info->node_count == 0) {
        return sta_fail(err, STA_ERR_FORMAT, "%s: node_count is 0 (the root is missing)", name);
    }
    if (info->node_entry_size < STA_STRATA_NODE_ENTRY_SIZE ||
        info->node_entry_size > STA_STRATA_NODE_ENTRY_MAX) {
        return sta_fail(err, STA_ERR_FORMAT, "%s: node_entry_size %" PRIu32 " is not in %u..%u",
                        name, info->node_entry_size, STA_STRATA_NODE_ENTRY_SIZE,
                        STA_STRATA_NODE_ENTRY_MAX);
    }
    uint64_t table_size = (uint64_t)info->node_count * info->node_entry_size;
    if (info->table_offset % align != 0 || info->table_offset < info->data_offset ||
        info->table_offset > info->file_size ||
        table_size != info->file_size - info->table_offset) {
        return sta_fail(err, STA_ERR_FORMAT,
                        "%s: node table of %" PRIu32 " entries at offset %" PRIu64
                        " does not end the file (%" PRIu64 " bytes, payloads from %" PRIu64 ")",
                        name, info->node_count, info->table_offset, info->file_size,
                        info->data_offset);
    }
    return STA_OK;
}

static void load_fields(const uint8_t *h, sta_strata_info *info)
{
    sta_strata_geometry *g = &info->geometry;
    info->version_minor = sta_load_u16le(h + STA_STRATA_H_VERSION_MINOR_OFF);
    info->header_checksum = sta_load_u64le(h + STA_STRATA_H_HEADER_CHECKSUM_OFF);
    info->file_size = sta_load_u64le(h + STA_STRATA_H_FILE_SIZE_OFF);
    info->flags = sta_load_u32le(h + STA_STRATA_H_FLAGS_OFF);
    g->grid_cells = sta_load_u32le(h + STA_STRATA_H_GRID_CELLS_OFF);
    info->payload_alignment = sta_load_u32le(h + STA_STRATA_H_ALIGNMENT_OFF);
    for (int a = 0; a < 3; a++) {
        g->grid.scale[a] = sta_load_f64le(h + STA_STRATA_H_SCALE_OFF + 8 * a);
        g->grid.offset[a] = sta_load_f64le(h + STA_STRATA_H_OFFSET_OFF + 8 * a);
        g->root_corner[a] = sta_load_i64le(h + STA_STRATA_H_ROOT_CORNER_OFF + 8 * a);
        g->root_size_log2[a] = h[STA_STRATA_H_ROOT_LOG2_OFF + a];
        info->grid_min[a] = sta_load_i32le(h + STA_STRATA_H_GRID_MIN_OFF + 4 * a);
        info->grid_max[a] = sta_load_i32le(h + STA_STRATA_H_GRID_MAX_OFF + 4 * a);
        info->bounds_min[a] = sta_load_f64le(h + STA_STRATA_H_BOUNDS_MIN_OFF + 8 * a);
        info->bounds_max[a] = sta_load_f64le(h + STA_STRATA_H_BOUNDS_MAX_OFF + 8 * a);
    }
    info->max_level = h[STA_STRATA_H_MAX_LEVEL_OFF];
    info->layout.attributes = sta_load_u32le(h + STA_STRATA_H_ATTRIBUTES_OFF);
    for (int b = 0; b < STA_STRATA_ATTR_BITS; b++) {
        info->layout.attr_size[b] = sta_load_u16le(h + STA_STRATA_H_ATTR_SIZES_OFF + 2 * b);
    }
    info->layout.record_size = sta_load_u32le(h + STA_STRATA_H_RECORD_SIZE_OFF);
    info->layout.extra_dim_count = sta_load_u32le(h + STA_STRATA_H_EXTRA_COUNT_OFF);
    info->point_count = sta_load_u64le(h + STA_STRATA_H_POINT_COUNT_OFF);
    info->node_count = sta_load_u32le(h + STA_STRATA_H_NODE_COUNT_OFF);
    info->node_entry_size = sta_load_u32le(h + STA_STRATA_H_ENTRY_SIZE_OFF);
    info->table_offset = sta_load_u64le(h + STA_STRATA_H_TABLE_OFFSET_OFF);
    info->table_checksum = sta_load_u64le(h + STA_STRATA_H_TABLE_CHECKSUM_OFF);
    info->extra_dims_checksum = sta_load_u64le(h + STA_STRATA_H_EXTRA_CHECKSUM_OFF);
    copy_text(info->generator, h + STA_STRATA_H_GENERATOR_OFF, 32);
    // Unknown values (a later minor) and files before 1.2 (zero) read as +Z.
    info->up_axis =
        h[STA_STRATA_H_UP_AXIS_OFF] == STA_STRATA_UP_Y ? STA_STRATA_UP_Y : STA_STRATA_UP_Z;
    if (info->version_minor >= 2) { // reserved (ignored) before 1.2
        info->source_offset = sta_load_u64le(h + STA_STRATA_H_SOURCE_OFFSET_OFF);
        info->source_size = sta_load_u64le(h + STA_STRATA_H_SOURCE_SIZE_OFF);
        info->source_checksum = sta_load_u64le(h + STA_STRATA_H_SOURCE_CHECKSUM_OFF);
    }
}

sta_status sta_strata_header_parse(const uint8_t *data, size_t size, const char *name,
                                   bool ignore_checksums, sta_strata_info *out,
                                   sta_strata_extra_dim **out_dims, sta_error *err)
{
    memset(out, 0, sizeof(*out));
    *out_dims = NULL;
    out->path = name;
    size_t magic_bytes = size < STA_STRATA_MAGIC_SIZE ? size : STA_STRATA_MAGIC_SIZE;
    if (magic_bytes == 0 || memcmp(data, STA_STRATA_MAGIC, magic_bytes) != 0) {
        return sta_fail(err, STA_ERR_FORMAT, "%s: not a .strata file (wrong magic bytes)", name);
    }
    if (size < STA_STRATA_HEADER_SIZE) {
        return sta_fail(err, STA_ERR_FORMAT,
                        "%s: file is %zu bytes, shorter than the %u-byte header (truncated)", name,
                        size, STA_STRATA_HEADER_SIZE);
    }
    out->version_major = sta_load_u16le(data + STA_STRATA_H_VERSION_MAJOR_OFF);
    if (out->version_major != STA_STRATA_VERSION_MAJOR) {
        return sta_fail(err, STA_ERR_UNSUPPORTED,
                        "%s: format version %u.%u is not supported (this reader reads %u.x)", name,
                        out->version_major, sta_load_u16le(data + STA_STRATA_H_VERSION_MINOR_OFF),
                        STA_STRATA_VERSION_MAJOR);
    }
    out->header_size = sta_load_u32le(data + STA_STRATA_H_HEADER_SIZE_OFF);
    if (out->header_size < STA_STRATA_HEADER_SIZE ||
        out->header_size > STA_STRATA_HEADER_SIZE_MAX || out->header_size % 8 != 0) {
        return sta_fail(err, STA_ERR_FORMAT,
                        "%s: header_size %" PRIu32 " is not a multiple of 8 in %u..%u", name,
                        out->header_size, STA_STRATA_HEADER_SIZE, STA_STRATA_HEADER_SIZE_MAX);
    }
    if (out->header_size > size) {
        return sta_fail(err, STA_ERR_FORMAT,
                        "%s: file is %zu bytes, shorter than its %" PRIu32
                        "-byte header (truncated)",
                        name, size, out->header_size);
    }
    load_fields(data, out);
    uint64_t sum = sta_strata_header_checksum(data, out->header_size);
    if (!ignore_checksums && sum != out->header_checksum) {
        return sta_fail(err, STA_ERR_FORMAT,
                        "%s: header checksum 0x%016" PRIx64 " does not match 0x%016" PRIx64
                        " (corrupted header)",
                        name, sum, out->header_checksum);
    }
    if (out->file_size != size) {
        return sta_fail(err, STA_ERR_FORMAT,
                        "%s: header says the file has %" PRIu64 " bytes but it has %zu (%s)", name,
                        out->file_size, size, size < out->file_size ? "truncated" : "appended to");
    }
    if (out->flags != 0) {
        return sta_fail(err, STA_ERR_UNSUPPORTED,
                        "%s: file uses features 0x%08" PRIx32 " this reader does not know", name,
                        out->flags);
    }
    uint32_t algorithm = sta_load_u32le(data + STA_STRATA_H_CHECKSUM_ALGO_OFF);
    if (algorithm != STA_STRATA_CHECKSUM_XXH3) {
        return sta_fail(err, STA_ERR_UNSUPPORTED, "%s: checksum algorithm %" PRIu32 " is unknown",
                        name, algorithm);
    }
    sta_status s = check_geometry(out, name, err);
    if (s == STA_OK) {
        s = check_attributes(out, name, err);
    }
    if (s == STA_OK) {
        s = check_offsets(out, name, err);
    }
    if (s == STA_OK) {
        s = parse_extra_dims(data, name, out, ignore_checksums, out_dims, err);
    }
    return s;
}
