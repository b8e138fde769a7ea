/* SPDX-License-Identifier: MIT
 * Reading .strata files: map, validate, decode node payloads.
 *
 * Design: open does every check that needs no payload; the reader is then read-only
 * and shared by threads. Decoding buffers live in per-thread sta_strata_decoder
 * objects and only grow. Nothing mapped is ever cast to a struct.
 */
#include "format/strata_reader.h"

#include <inttypes.h>
#include <string.h>

#include <zstd.h>

#include "core/alloc.h"
#include "core/file_map.h"
#include "format/strata_internal.h"

#define DEFAULT_MAX_NODE_RAW_BYTES ((uint64_t)4 << 30)

struct sta_strata_reader {
    sta_file_map map;                   // the file's bytes
    sta_strata_info info;               // parsed header; layout.extra_dims = dims
    sta_strata_extra_dim *dims;         // owned
    sta_strata_node *nodes;             // owned, info.node_count entries
    sta_strata_las_source las_source;   // valid when has_las_source
    sta_strata_las_record *las_records; // owned; data points into the map
    bool has_las_source;                // the file has a LAS source block (1.2)
    bool ignore_checksums;              // open option
    uint64_t max_node_raw_bytes;        // open option, resolved
};

struct sta_strata_decoder {
    ZSTD_DCtx *dctx;          // owned by the decoder's thread
    uint8_t *raw;             // decompressed payload
    size_t raw_capacity;      // bytes
    uint8_t *shuffled;        // zstd output of a shuffled payload, before unshuffling
    size_t shuffled_capacity; // bytes
    sta_point *points;        // decoded points
    size_t point_capacity;    // elements
    uint8_t *extra;           // decoded extra bytes
    size_t extra_capacity;    // bytes
};

// The LAS source block (1.2): inside the payload area, checksummed, well formed.
static sta_status open_las_source(sta_strata_reader *r, sta_error *err)
{
    const sta_strata_info *info = &r->info;
    const char *name = r->map.path;
    if (info->source_offset == 0) {
        return STA_OK;
    }
    if (info->source_offset < info->data_offset || info->source_offset > info->table_offset ||
        info->source_size > info->table_offset - info->source_offset) {
        return sta_fail(err, STA_ERR_FORMAT,
                        "%s: LAS source block at %" PRIu64 " (%" PRIu64
                        " bytes) is outside the payload area %" PRIu64 "..%" PRIu64,
                        name, info->source_offset, info->source_size, info->data_offset,
                        info->table_offset);
    }
    const uint8_t *block = r->map.data + info->source_offset;
    uint64_t sum = sta_strata_checksum(block, (size_t)info->source_size);
    if (!r->ignore_checksums && sum != info->source_checksum) {
        return sta_fail(err, STA_ERR_FORMAT,
                        "%s: LAS source checksum 0x%016" PRIx64 " does not match 0x%016" PRIx64
                        " (corrupted file)",
                        name, sum, info->source_checksum);
    }
    sta_status s = sta_strata_las_source_parse(block, info->source_size, name, &r->las_source,
                                               &r->las_records, err);
    r->has_las_source = s == STA_OK;
    return s;
}

static sta_status open_map(sta_strata_reader *r, const sta_strata_open_options *options,
                           sta_error *err)
{
    const char *name = r->map.path;
    const uint8_t *data = r->map.data;
    size_t size = r->map.size;
    if (options) {
        r->ignore_checksums = options->ignore_checksums;
        r->max_node_raw_bytes = options->max_node_raw_bytes;
    }
    if (r->max_node_raw_bytes == 0) {
        r->max_node_raw_bytes = DEFAULT_MAX_NODE_RAW_BYTES;
    }
    if (size == 0) {
        return sta_fail(err, STA_ERR_FORMAT, "%s: file is empty (truncated)", name);
    }
    sta_status s =
        sta_strata_header_parse(data, size, name, r->ignore_checksums, &r->info, &r->dims, err);
    if (s != STA_OK) {
        return s;
    }
    const sta_strata_info *info = &r->info;
    const uint8_t *table = data + info->table_offset;
    size_t table_size = (size_t)info->node_count * info->node_entry_size;
    uint64_t sum = sta_strata_checksum(table, table_size);
    if (!r->ignore_checksums && sum != info->table_checksum) {
        return sta_fail(err, STA_ERR_FORMAT,
                        "%s: node table checksum 0x%016" PRIx64 " does not match 0x%016" PRIx64
                        " (corrupted file)",
                        name, sum, info->table_checksum);
    }
    r->nodes = sta_alloc_array(info->node_count, sizeof(*r->nodes));
    if (!r->nodes) {
        return sta_fail(err, STA_ERR_NOMEM, "%s: out of memory for %" PRIu32 " nodes", name,
                        info->node_count);
    }
    for (uint32_t i = 0; i < info->node_count; i++) {
        sta_strata_node_load(table + (size_t)i * info->node_entry_size, &r->nodes[i]);
    }
    s = sta_strata_table_check(info, r->nodes, name, err);
    return s == STA_OK ? open_las_source(r, err) : s;
}

// Takes ownership of *map (also on failure).
static sta_status open_common(sta_file_map *map, const sta_strata_open_options *options,
                              sta_strata_reader **out_reader, sta_error *err)
{
    sta_strata_reader *r = sta_calloc(1, sizeof(*r));
    if (!r) {
        sta_status s = sta_fail(err, STA_ERR_NOMEM, "%s: out of memory", map->path);
        sta_file_map_close(map);
        return s;
    }
    r->map = *map;
    sta_status s = open_map(r, options, err);
    if (s != STA_OK) {
        sta_strata_close(r);
        return s;
    }
    r->info.path = r->map.path;
    *out_reader = r;
    return STA_OK;
}

sta_status sta_strata_open(const char *path, const sta_strata_open_options *options,
                           sta_strata_reader **out_reader, sta_error *err)
{
    *out_reader = NULL;
    sta_file_map map;
    sta_status s = sta_file_map_open(path, &map, err);
    if (s != STA_OK) {
        return s;
    }
    return open_common(&map, options, out_reader, err);
}

sta_status sta_strata_open_memory(const uint8_t *data, size_t size, const char *name,
                                  const sta_strata_open_options *options,
                                  sta_strata_reader **out_reader, sta_error *err)
{
    *out_reader = NULL;
    sta_file_map map;
    sta_status s = sta_file_map_wrap(data, size, name, &map, err);
    if (s != STA_OK) {
        return s;
    }
    return open_common(&map, options, out_reader, err);
}

void sta_strata_close(sta_strata_reader *reader)
{
    if (!reader) {
        return;
    }
    sta_free(reader->nodes);
    sta_free(reader->dims);
    sta_free(reader->las_records);
    sta_file_map_close(&reader->map);
    sta_free(reader);
}

const sta_strata_info *sta_strata_reader_info(const sta_strata_reader *reader)
{
    return &reader->info;
}

const sta_strata_las_source *sta_strata_reader_las_source(const sta_strata_reader *reader)
{
    return reader->has_las_source ? &reader->las_source : NULL;
}

const sta_strata_node *sta_strata_reader_node(const sta_strata_reader *reader, uint32_t index)
{
    return index < reader->info.node_count ? &reader->nodes[index] : NULL;
}

const uint8_t *sta_strata_reader_data(const sta_strata_reader *reader, size_t *out_size)
{
    *out_size = reader->map.size;
    return reader->map.data;
}

sta_status sta_strata_decoder_create(sta_strata_decoder **out_decoder, sta_error *err)
{
    *out_decoder = NULL;
    sta_strata_decoder *d = sta_calloc(1, sizeof(*d));
    if (!d) {
        return sta_fail(err, STA_ERR_NOMEM, "strata decoder: out of memory");
    }
    d->dctx = ZSTD_createDCtx();
    if (!d->dctx) {
        sta_free(d);
        return sta_fail(err, STA_ERR_NOMEM, "strata decoder: out of memory for zstd");
    }
    *out_decoder = d;
    return STA_OK;
}

void sta_strata_decoder_destroy(sta_strata_decoder *decoder)
{
    if (!decoder) {
        return;
    }
    ZSTD_freeDCtx(decoder->dctx);
    sta_free(decoder->raw);
    sta_free(decoder->shuffled);
    sta_free(decoder->points);
    sta_free(decoder->extra);
    sta_free(decoder);
}

// Grows a buffer of `count` elements of `size` bytes (contents not kept).
static bool reserve(void **buf, size_t *capacity, size_t count, size_t size)
{
    if (count <= *capacity) {
        return true;
    }
    void *grown = sta_alloc_array(count, size);
    if (!grown) {
        return false;
    }
    sta_free(*buf);
    *buf = grown;
    *capacity = count;
    return true;
}

sta_status sta_strata_load_node(const sta_strata_reader *r, uint32_t index, sta_strata_decoder *d,
                                const uint8_t **out_raw, sta_error *err)
{
    static const uint8_t empty[1] = { 0 };
    *out_raw = empty;
    const char *name = r->map.path;
    if (index >= r->info.node_count) {
        return sta_fail(err, STA_ERR_ARG, "%s: node %" PRIu32 " does not exist (%" PRIu32 " nodes)",
                        name, index, r->info.node_count);
    }
    const sta_strata_node *n = &r->nodes[index];
    const sta_strata_payload *p = &n->payload;
    char label[96];
    sta_strata_node_label(label, sizeof(label), index, n->key);
    if (p->raw_size > r->max_node_raw_bytes || p->raw_size > SIZE_MAX) {
        return sta_fail(err, STA_ERR_UNSUPPORTED,
                        "%s: %s: payload of %" PRIu64
                        " bytes exceeds the decoder limit of %" PRIu64,
                        name, label, p->raw_size, r->max_node_raw_bytes);
    }
    // The table check put [offset, offset + stored_size) inside the file.
    const uint8_t *stored = p->stored_size ? r->map.data + p->offset : empty;
    size_t stored_size = (size_t)p->stored_size;
    uint64_t sum = sta_strata_checksum(stored, stored_size);
    if (!r->ignore_checksums && sum != p->checksum) {
        return sta_fail(err, STA_ERR_FORMAT,
                        "%s: %s: payload checksum 0x%016" PRIx64 " does not match 0x%016" PRIx64
                        " (corrupted file)",
                        name, label, sum, p->checksum);
    }
    if (p->compression == STA_STRATA_COMPRESSION_NONE) {
        *out_raw = stored;
        return STA_OK;
    }
    size_t raw_size = (size_t)p->raw_size;
    unsigned long long content = ZSTD_getFrameContentSize(stored, stored_size);
    if (content != p->raw_size) {
        return sta_fail(err, STA_ERR_FORMAT,
                        "%s: %s: zstd frame does not declare the table's raw size %" PRIu64
                        " (corrupted file)",
                        name, label, p->raw_size);
    }
    if (!reserve((void **)&d->raw, &d->raw_capacity, raw_size, 1)) {
        return sta_fail(err, STA_ERR_NOMEM, "%s: %s: out of memory for %zu bytes", name, label,
                        raw_size);
    }
    bool shuffled = p->compression == STA_STRATA_COMPRESSION_ZSTD_SHUFFLE;
    if (shuffled && !reserve((void **)&d->shuffled, &d->shuffled_capacity, raw_size, 1)) {
        return sta_fail(err, STA_ERR_NOMEM, "%s: %s: out of memory for %zu bytes", name, label,
                        raw_size);
    }
    uint8_t *target = shuffled ? d->shuffled : d->raw;
    size_t got = ZSTD_decompressDCtx(d->dctx, target, raw_size, stored, stored_size);
    if (ZSTD_isError(got) || got != raw_size) {
        return sta_fail(
            err, STA_ERR_FORMAT,
            "%s: %s: zstd payload does not decompress to %zu bytes: %s (corrupted file)", name,
            label, raw_size, ZSTD_isError(got) ? ZSTD_getErrorName(got) : "wrong size");
    }
    if (shuffled) {
        sta_strata_unshuffle(&r->info.layout, (size_t)n->point_count, d->shuffled, d->raw);
    }
    *out_raw = d->raw;
    return STA_OK;
}

sta_status sta_strata_decode_node(const sta_strata_reader *r, uint32_t index, sta_strata_decoder *d,
                                  sta_strata_points *out, sta_error *err)
{
    memset(out, 0, sizeof(*out));
    const uint8_t *raw;
    sta_status s = sta_strata_load_node(r, index, d, &raw, err);
    if (s != STA_OK) {
        return s;
    }
    const sta_strata_node *n = &r->nodes[index];
    const sta_strata_layout *layout = &r->info.layout;
    size_t count = (size_t)n->point_count; // raw_size = count * record_size fits size_t
    char label[96];
    sta_strata_node_label(label, sizeof(label), index, n->key);
    if (!reserve((void **)&d->points, &d->point_capacity, count, sizeof(sta_point)) ||
        !reserve((void **)&d->extra, &d->extra_capacity, count * layout->extra_size, 1)) {
        return sta_fail(err, STA_ERR_NOMEM, "%s: %s: out of memory for %zu points", r->map.path,
                        label, count);
    }
    int64_t corner[3], size[3];
    sta_strata_node_grid_bounds(&r->info.geometry, n->key, corner, size);
    s = sta_strata_decode_points(layout, raw, count, corner, d->points, d->extra, err);
    if (s != STA_OK) {
        sta_error_prefix(err, "%s: %s", r->map.path, label);
        return s;
    }
    out->points = d->points;
    out->extra = layout->extra_size ? d->extra : NULL;
    out->count = count;
    out->extra_size = layout->extra_size;
    return STA_OK;
}
