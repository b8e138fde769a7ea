/* SPDX-License-Identifier: MIT
 * The GPU node cache: one buffer per resident node, a memory cap, LRU eviction.
 * GL calls: main thread only.
 *
 * Entries are addressed by node index (the handle); a node is either resident (its
 * buffer holds count points in the GPU layout) or not. Nodes touched in the current
 * frame are never evicted, so what a frame draws stays valid while it draws.
 */
#ifndef STA_RENDER_GPU_CACHE_H
#define STA_RENDER_GPU_CACHE_H

#include <epoxy/gl.h>
#include <stdbool.h>
#include <stdint.h>

#include "core/status.h"

typedef struct sta_cache_entry {
    GLuint buffer;       /* 0 when not resident */
    uint32_t count;      /* points */
    uint64_t last_frame; /* frame in which it was last touched */
} sta_cache_entry;

typedef struct sta_gpu_cache {
    sta_cache_entry *entries; /* one per node */
    uint32_t node_count;
    uint32_t *resident; /* resident node indices (unordered) */
    uint32_t resident_count;
    uint64_t bytes_used;
    uint64_t bytes_cap;
    uint64_t frame;     /* current frame number */
    uint64_t evictions; /* total so far */
} sta_gpu_cache;

sta_status sta_gpu_cache_init(sta_gpu_cache *cache, uint32_t node_count, uint64_t bytes_cap,
                              sta_error *err);

/* Frees every buffer (needs the GL context current). */
void sta_gpu_cache_release(sta_gpu_cache *cache);

/* Starts a new frame: nodes touched before it become evictable. */
void sta_gpu_cache_begin_frame(sta_gpu_cache *cache);

static inline bool sta_gpu_cache_is_resident(const sta_gpu_cache *cache, uint32_t node)
{
    return cache->entries[node].buffer != 0;
}

/* Marks a node used in this frame. */
static inline void sta_gpu_cache_touch(sta_gpu_cache *cache, uint32_t node)
{
    cache->entries[node].last_frame = cache->frame;
}

/* Uploads a node (count points, 16 bytes each), evicting the least recently used
 * nodes not touched this frame to stay under the cap. Returns false (and uploads
 * nothing) when it cannot fit without evicting nodes of this frame. */
bool sta_gpu_cache_upload(sta_gpu_cache *cache, uint32_t node, const uint8_t *gpu, uint32_t count);

#endif
