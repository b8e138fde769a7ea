/* SPDX-License-Identifier: MIT
 * Where the octree builders hand finished nodes: the writer (or a test).
 */
#ifndef STA_PREPROCESS_NODE_SINK_H
#define STA_PREPROCESS_NODE_SINK_H

#include <stddef.h>
#include <stdint.h>

#include "core/status.h"
#include "octree.h"

/* Node flags. */
enum {
    STA_NODE_UNGRIDDED = 1u << 0, /* a leaf bucket: may hold several points per cell */
};

typedef struct sta_node_sink {
    /* Takes a finished node: `count` packed records (contiguous, borrowed for the call).
     * Called from worker `worker` (0 .. threads-1) or the main thread (worker 0 after
     * the workers stopped). Must be thread-safe across different workers. */
    sta_status (*emit)(void *context, int worker, const sta_node_key *key, const uint8_t *records,
                       size_t count, unsigned flags, sta_error *err);
    void *context;
} sta_node_sink;

#endif
