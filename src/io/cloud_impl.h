/* SPDX-License-Identifier: MIT
 * Internal: the table each format reader fills so sta_cloud_* can dispatch to it.
 */
#ifndef STA_IO_CLOUD_IMPL_H
#define STA_IO_CLOUD_IMPL_H

#include "core/file_map.h"
#include "io/cloud.h"

typedef struct sta_cloud_ops {
    sta_status (*read)(void *impl, sta_point_batch *batch, sta_error *err);
    /* Optional: as read, setting only X, Y and Z (NULL: read is used). */
    sta_status (*read_positions)(void *impl, sta_point_batch *batch, sta_error *err);
    sta_status (*seek)(void *impl, uint64_t index, sta_error *err);
    const sta_cloud_info *(*info)(const void *impl);
    void (*close)(void *impl); /* frees impl; does not close the map */
} sta_cloud_ops;

/* Each format's opener: parses `map` (borrowed; it outlives the reader) and returns
 * its implementation object and ops. */
typedef sta_status (*sta_cloud_open_fn)(const sta_file_map *map, const sta_read_options *options,
                                        void **out_impl, const sta_cloud_ops **out_ops,
                                        sta_error *err);

#endif
