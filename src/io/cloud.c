/* SPDX-License-Identifier: MIT
 * Format detection and dispatch for point file readers. */
#include "io/cloud.h"

#include <string.h>

#include "core/alloc.h"
#include "io/las.h"
#include "io/ply.h"

struct sta_cloud_reader {
    sta_file_map map;         /* owned */
    void *impl;               /* owned by ops->close */
    const sta_cloud_ops *ops; /* static table of the format */
};

static sta_status open_on_map(sta_cloud_reader *reader, const sta_read_options *options,
                              sta_error *err)
{
    static const sta_read_options no_options = { 0 };
    if (!options) {
        options = &no_options;
    }
    const sta_file_map *map = &reader->map;
    if (map->size >= 4 && memcmp(map->data, "LASF", 4) == 0) {
        return sta_las_open_map(map, options, &reader->impl, &reader->ops, err);
    }
    if (map->size >= 4 && memcmp(map->data, "ply", 3) == 0 &&
        (map->data[3] == '\n' || map->data[3] == '\r')) {
        return sta_ply_open_map(map, options, &reader->impl, &reader->ops, err);
    }
    if (map->size == 0) {
        return sta_fail(err, STA_ERR_FORMAT, "%s: file is empty", map->path);
    }
    return sta_fail(err, STA_ERR_UNSUPPORTED,
                    "%s: not a LAS or PLY file (no \"LASF\" or \"ply\" signature)", map->path);
}

static sta_status finish_open(sta_cloud_reader *reader, const sta_read_options *options,
                              sta_cloud_reader **out_reader, sta_error *err)
{
    sta_status status = open_on_map(reader, options, err);
    if (status != STA_OK) {
        sta_file_map_close(&reader->map);
        sta_free(reader);
        return status;
    }
    *out_reader = reader;
    return STA_OK;
}

sta_status sta_cloud_open(const char *path, const sta_read_options *options,
                          sta_cloud_reader **out_reader, sta_error *err)
{
    *out_reader = NULL;
    sta_cloud_reader *reader = sta_calloc(1, sizeof(*reader));
    if (!reader) {
        return sta_fail(err, STA_ERR_NOMEM, "%s: out of memory", path);
    }
    sta_status status = sta_file_map_open(path, &reader->map, err);
    if (status != STA_OK) {
        sta_free(reader);
        return status;
    }
    return finish_open(reader, options, out_reader, err);
}

sta_status sta_cloud_open_memory(const uint8_t *data, size_t size, const char *name,
                                 const sta_read_options *options, sta_cloud_reader **out_reader,
                                 sta_error *err)
{
    *out_reader = NULL;
    sta_cloud_reader *reader = sta_calloc(1, sizeof(*reader));
    if (!reader) {
        return sta_fail(err, STA_ERR_NOMEM, "%s: out of memory", name);
    }
    sta_status status = sta_file_map_wrap(data, size, name, &reader->map, err);
    if (status != STA_OK) {
        sta_free(reader);
        return status;
    }
    return finish_open(reader, options, out_reader, err);
}

const sta_cloud_info *sta_cloud_reader_info(const sta_cloud_reader *reader)
{
    return reader->ops->info(reader->impl);
}

static sta_status check_batch(const sta_cloud_reader *reader, const sta_point_batch *batch,
                              sta_error *err)
{
    const sta_cloud_info *info = sta_cloud_reader_info(reader);
    if (batch->capacity == 0 || batch->extra_size != info->extra_size) {
        return sta_fail(err, STA_ERR_ARG, "%s: batch holds %zu extra bytes per point, file has %zu",
                        info->path, batch->extra_size, info->extra_size);
    }
    return STA_OK;
}

sta_status sta_cloud_read(sta_cloud_reader *reader, sta_point_batch *batch, sta_error *err)
{
    sta_status status = check_batch(reader, batch, err);
    return status == STA_OK ? reader->ops->read(reader->impl, batch, err) : status;
}

sta_status sta_cloud_read_positions(sta_cloud_reader *reader, sta_point_batch *batch,
                                    sta_error *err)
{
    sta_status status = check_batch(reader, batch, err);
    if (status != STA_OK) {
        return status;
    }
    return reader->ops->read_positions ? reader->ops->read_positions(reader->impl, batch, err)
                                       : reader->ops->read(reader->impl, batch, err);
}

sta_status sta_cloud_seek(sta_cloud_reader *reader, uint64_t index, sta_error *err)
{
    const sta_cloud_info *info = sta_cloud_reader_info(reader);
    if (index > info->point_count) {
        return sta_fail(err, STA_ERR_ARG, "%s: seek to point %llu past the %llu points", info->path,
                        (unsigned long long)index, (unsigned long long)info->point_count);
    }
    return reader->ops->seek(reader->impl, index, err);
}

void sta_cloud_close(sta_cloud_reader *reader)
{
    if (!reader) {
        return;
    }
    reader->ops->close(reader->impl);
    sta_file_map_close(&reader->map);
    sta_free(reader);
}
