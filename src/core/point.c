/* SPDX-License-Identifier: MIT
 * Point batches. */
#include "core/point.h"

#include <string.h>

#include "core/alloc.h"

sta_status sta_point_batch_init(sta_point_batch *batch, size_t capacity, size_t extra_size,
                                sta_error *err)
{
    memset(batch, 0, sizeof(*batch));
    if (capacity == 0) {
        return sta_fail(err, STA_ERR_ARG, "point batch capacity must be positive");
    }
    batch->points = sta_calloc(capacity, sizeof(*batch->points));
    if (!batch->points) {
        return sta_fail(err, STA_ERR_NOMEM, "out of memory for a batch of %zu points", capacity);
    }
    if (extra_size > 0) {
        batch->extra = sta_calloc(capacity, extra_size);
        if (!batch->extra) {
            sta_free(batch->points);
            batch->points = NULL;
            return sta_fail(err, STA_ERR_NOMEM, "out of memory for %zu x %zu extra bytes", capacity,
                            extra_size);
        }
    }
    batch->capacity = capacity;
    batch->extra_size = extra_size;
    return STA_OK;
}

void sta_point_batch_release(sta_point_batch *batch)
{
    sta_free(batch->points);
    sta_free(batch->extra);
    memset(batch, 0, sizeof(*batch));
}

const char *sta_attr_name(uint32_t bit)
{
    switch (bit) {
    case STA_ATTR_INTENSITY:
        return "intensity";
    case STA_ATTR_RETURNS:
        return "returns";
    case STA_ATTR_CLASSIFICATION:
        return "classification";
    case STA_ATTR_SCAN_ANGLE:
        return "scan_angle";
    case STA_ATTR_USER_DATA:
        return "user_data";
    case STA_ATTR_POINT_SOURCE_ID:
        return "point_source_id";
    case STA_ATTR_SCAN_FLAGS:
        return "scan_flags";
    case STA_ATTR_GPS_TIME:
        return "gps_time";
    case STA_ATTR_RGB:
        return "rgb";
    case STA_ATTR_NIR:
        return "nir";
    case STA_ATTR_WAVE_PACKET:
        return "wave_packet";
    case STA_ATTR_SPLAT:
        return "splat";
    case STA_ATTR_NORMAL:
        return "normal";
    case STA_ATTR_SCANNER_CHANNEL:
        return "scanner_channel";
    case STA_ATTR_MIRROR:
        return "mirror";
    }
    return NULL;
}
