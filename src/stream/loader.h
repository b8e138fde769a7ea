/* SPDX-License-Identifier: MIT
 * The loader: worker threads that load wanted nodes from a node source (the mapped
 * .strata file: check, decompress, convert to the GPU layout; or a test's fake).
 *
 * Design: the main thread hands over the wanted nodes in priority order each frame
 * (sta_loader_request, replacing the previous list, so nodes no longer wanted are
 * dropped before they are read). Workers take the first wanted node that is not
 * already loading or loaded, decode it with their own decoder, and post the result
 * to a queue bounded in bytes (they wait when it is full). The main thread takes
 * results (sta_loader_take) and uploads them. A node that fails its checksum or
 * decoding comes back with an error once and is never loaded again.
 *
 * Lock order: only `lock`. No decoding or allocation happens under it.
 */
#ifndef STA_STREAM_LOADER_H
#define STA_STREAM_LOADER_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "core/status.h"
#include "stream/node_source.h"

typedef struct sta_loader sta_loader;

typedef struct sta_loader_options {
    int threads;            /* 0: 1 */
    size_t ready_bytes_cap; /* 0: 256 MiB of finished nodes waiting for upload */
    size_t point_bytes;     /* bytes per finished point; 0: STA_GPU_POINT_SIZE (the
                               source's splat section adds STA_GPU_SPLAT_SIZE) */
} sta_loader_options;

/* Fills the zero fields of `options` with their defaults. */
void sta_loader_options_defaults(sta_loader_options *options);

/* A finished node. `gpu` (count * point_bytes: the points, then a splat section when
 * the source has one) is owned by the taker
 * and freed with sta_loaded_node_release. */
typedef struct sta_loaded_node {
    uint32_t node;
    uint8_t *gpu;
    size_t count;
    sta_status status; /* STA_OK, or why the node cannot be shown */
    char message[STA_ERROR_MESSAGE_SIZE];
} sta_loaded_node;

/* Starts the workers over `source` (borrowed: it must outlive the loader). */
sta_status sta_loader_create(const sta_node_source *source, const sta_loader_options *options,
                             sta_loader **out_loader, sta_error *err);

/* Replaces the wanted list (highest priority first). Main thread. */
sta_status sta_loader_request(sta_loader *loader, const uint32_t *nodes, size_t count,
                              sta_error *err);

/* Takes one finished node if any; returns false when none is ready. Main thread. */
bool sta_loader_take(sta_loader *loader, sta_loaded_node *out_node);

void sta_loaded_node_release(sta_loaded_node *node);

/* Nodes wanted but not finished yet (loading or waiting). */
size_t sta_loader_backlog(sta_loader *loader);

/* Totals since creation: points decoded and converted, and worker seconds spent. */
void sta_loader_stats(sta_loader *loader, uint64_t *out_points, double *out_busy_s);

/* Stops the workers and frees everything not taken; NULL is a no-op. */
void sta_loader_destroy(sta_loader *loader);

#endif
