/* SPDX-License-Identifier: MIT
 * The GPU side of node residency: one buffer per resident node. It holds no policy:
 * the streamer (stream/streamer.h) decides what to evict and upload each frame and
 * this carries it out. GL calls: main thread only.
 */
#ifndef STA_RENDER_GPU_CACHE_H
#define STA_RENDER_GPU_CACHE_H

#include <epoxy/gl.h>
#include <stdint.h>

#include "core/status.h"
#include "stream/streamer.h"

typedef struct sta_gpu_cache_entry {
    GLuint buffer;  /* 0 when not resident */
    uint32_t count; /* points (16 bytes each) */
} sta_gpu_cache_entry;

typedef struct sta_gpu_cache {
    sta_gpu_cache_entry *entries; /* one per node */
    uint32_t node_count;
} sta_gpu_cache;

sta_status sta_gpu_cache_init(sta_gpu_cache *cache, uint32_t node_count, sta_error *err);

/* Frees every buffer (needs the GL context current); a zeroed cache is a no-op. */
void sta_gpu_cache_release(sta_gpu_cache *cache);

/* Frees the frame's evicted nodes, then uploads its finished ones. */
void sta_gpu_cache_apply(sta_gpu_cache *cache, const sta_stream_frame *frame);

#endif
