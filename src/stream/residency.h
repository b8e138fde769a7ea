/* SPDX-License-Identifier: MIT
 * Which nodes the GPU holds, as the streaming policy sees it (no GL): a byte cap and
 * least-recently-used eviction, where nodes used in the current frame are never evicted.
 * render/gpu_cache.c carries out what this decides.
 *
 * Design: one entry per node (last frame used, points); the resident nodes are also kept
 * in an unordered list. To admit a node past the cap, the least recently used resident
 * node not used in this frame is evicted (the first such in the list on ties), repeatedly.
 * Main thread only.
 */
#ifndef STA_STREAM_RESIDENCY_H
#define STA_STREAM_RESIDENCY_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "core/status.h"

typedef struct sta_residency_entry {
    uint64_t last_frame; /* frame in which it was last used */
    uint32_t count;      /* points, when resident */
    bool is_resident;
} sta_residency_entry;

typedef struct sta_residency {
    sta_residency_entry *entries; /* one per node */
    uint32_t node_count;
    uint32_t *resident; /* resident node indices (unordered) */
    uint32_t resident_count;
    uint64_t bytes_used; /* <= bytes_cap */
    uint64_t bytes_cap;
    uint32_t point_bytes; /* GPU bytes per point: STA_GPU_POINT_SIZE, plus
                             STA_GPU_SPLAT_SIZE when the scene has splats (set after init) */
    uint64_t frame;       /* current frame number, from 1 */
    uint64_t evictions;   /* total so far */
} sta_residency;

sta_status sta_residency_init(sta_residency *residency, uint32_t node_count, uint64_t bytes_cap,
                              sta_error *err);

void sta_residency_release(sta_residency *residency);

/* Evicts every resident node, appending them to `evicted` (room for node_count). */
void sta_residency_evict_all(sta_residency *residency, uint32_t *evicted, size_t *evicted_count);

/* Starts a new frame: nodes used before it become evictable. */
void sta_residency_begin_frame(sta_residency *residency);

static inline bool sta_residency_is_resident(const sta_residency *residency, uint32_t node)
{
    return residency->entries[node].is_resident;
}

/* Marks a node used in this frame. */
static inline void sta_residency_touch(sta_residency *residency, uint32_t node)
{
    residency->entries[node].last_frame = residency->frame;
}

/* Admits a node of `count` points (16 bytes each), used in this frame, evicting least
 * recently used nodes not used in this frame to stay under the cap; each evicted node is
 * appended to `evicted` (room for node_count entries) and counted in *evicted_count.
 * Returns false (and admits nothing) when the node is resident already or cannot fit
 * without evicting nodes of this frame; nodes evicted on the way stay evicted. */
bool sta_residency_admit(sta_residency *residency, uint32_t node, uint32_t count, uint32_t *evicted,
                         size_t *evicted_count);

#endif
