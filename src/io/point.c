/* SPDX-License-Identifier: MIT
 * Point batches. */
#include "io/point.h"

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
            return sta_fail(err, STA_ERR_NOMEM, "out of memory for %zu x %zu extra bytes",
                            capacity, extra_size);
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
