/* SPDX-License-Identifier: MIT
 * Where the loader's nodes come from: a small interface so that the streaming policy
 * can run on a .strata file (stream/strata_source.h) or, in tests, on a fake source.
 *
 * Thread rules: `worker_begin`, `load` and `worker_end` run on loader threads, each
 * worker with its own state; a source must be safe to `load` from several workers at
 * once (the .strata reader is read-only). They never call back into the loader.
 */
#ifndef STA_STREAM_NODE_SOURCE_H
#define STA_STREAM_NODE_SOURCE_H

#include <stddef.h>
#include <stdint.h>

#include "core/status.h"

typedef struct sta_node_source {
    void *context;       /* borrowed; passed to every call */
    uint32_t node_count; /* nodes are 0 .. node_count - 1 */
    int has_splats;      /* loads carry a splat section (see `load`) */
    /* Per-worker state (a decoder, ...): *out_worker may stay NULL. Optional. */
    sta_status (*worker_begin)(void *context, void **out_worker, sta_error *err);
    void (*worker_end)(void *context, void *worker); /* optional */
    /* Decodes node `node` into *out_count points of the GPU layout (stream/gpu_points.h);
     * *out_gpu is allocated with core/alloc.h (sta_free), NULL when the node is empty.
     * When `has_splats` is set, *out_gpu holds count * STA_GPU_POINT_SIZE bytes of points
     * followed by count * STA_GPU_SPLAT_SIZE bytes of splat attributes
     * (stream/gpu_splats.h), point i's at the same index.
     * A node that cannot be shown returns an error naming the file and the node. */
    sta_status (*load)(void *context, void *worker, uint32_t node, uint8_t **out_gpu,
                       size_t *out_count, sta_error *err);
} sta_node_source;

#endif
