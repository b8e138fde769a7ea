/* SPDX-License-Identifier: MIT
 * GPU node cache. */
#include "render/gpu_cache.h"

#include <string.h>

#include "core/alloc.h"
#include "stream/gpu_points.h"

sta_status sta_gpu_cache_init(sta_gpu_cache *cache, uint32_t node_count, uint64_t bytes_cap,
                              sta_error *err)
{
    memset(cache, 0, sizeof(*cache));
    cache->entries = sta_calloc(node_count, sizeof(*cache->entries));
    cache->resident = sta_calloc(node_count, sizeof(*cache->resident));
    if (!cache->entries || !cache->resident) {
        sta_free(cache->entries);
        sta_free(cache->resident);
        memset(cache, 0, sizeof(*cache));
        return sta_fail(err, STA_ERR_NOMEM, "out of memory for the node cache");
    }
    cache->node_count = node_count;
    cache->bytes_cap = bytes_cap;
    cache->frame = 1;
    return STA_OK;
}

void sta_gpu_cache_release(sta_gpu_cache *cache)
{
    for (uint32_t i = 0; i < cache->resident_count; i++) {
        glDeleteBuffers(1, &cache->entries[cache->resident[i]].buffer);
    }
    sta_free(cache->entries);
    sta_free(cache->resident);
    memset(cache, 0, sizeof(*cache));
}

void sta_gpu_cache_begin_frame(sta_gpu_cache *cache)
{
    cache->frame++;
}

static void evict_at(sta_gpu_cache *cache, uint32_t slot)
{
    uint32_t node = cache->resident[slot];
    sta_cache_entry *e = &cache->entries[node];
    glDeleteBuffers(1, &e->buffer);
    cache->bytes_used -= (uint64_t)e->count * STA_GPU_POINT_SIZE;
    e->buffer = 0;
    e->count = 0;
    cache->resident[slot] = cache->resident[--cache->resident_count];
    cache->evictions++;
}

bool sta_gpu_cache_upload(sta_gpu_cache *cache, uint32_t node, const uint8_t *gpu, uint32_t count)
{
    uint64_t bytes = (uint64_t)count * STA_GPU_POINT_SIZE;
    if (bytes > cache->bytes_cap || sta_gpu_cache_is_resident(cache, node)) {
        return false;
    }
    while (cache->bytes_used + bytes > cache->bytes_cap) {
        // Least recently used among those not touched this frame.
        uint32_t victim = UINT32_MAX;
        uint64_t oldest = cache->frame;
        for (uint32_t i = 0; i < cache->resident_count; i++) {
            uint64_t f = cache->entries[cache->resident[i]].last_frame;
            if (f < oldest) {
                oldest = f;
                victim = i;
            }
        }
        if (victim == UINT32_MAX) {
            return false;
        }
        evict_at(cache, victim);
    }
    sta_cache_entry *e = &cache->entries[node];
    glCreateBuffers(1, &e->buffer);
    // An empty node still gets a (tiny) buffer so it counts as resident.
    glNamedBufferStorage(e->buffer, bytes ? (GLsizeiptr)bytes : 16, bytes ? gpu : NULL, 0);
    e->count = count;
    e->last_frame = cache->frame;
    cache->bytes_used += bytes;
    cache->resident[cache->resident_count++] = node;
    return true;
}
