/* SPDX-License-Identifier: MIT
 * GPU node buffers. */
#include "render/gpu_cache.h"

#include <string.h>

#include "core/alloc.h"
#include "stream/gpu_points.h"

sta_status sta_gpu_cache_init(sta_gpu_cache *cache, uint32_t node_count, sta_error *err)
{
    memset(cache, 0, sizeof(*cache));
    cache->entries = sta_calloc(node_count ? node_count : 1, sizeof(*cache->entries));
    if (!cache->entries) {
        return sta_fail(err, STA_ERR_NOMEM, "out of memory for the node cache");
    }
    cache->node_count = node_count;
    return STA_OK;
}

static void free_buffer(sta_gpu_cache_entry *e)
{
    if (e->buffer) {
        glDeleteBuffers(1, &e->buffer);
    }
    e->buffer = 0;
    e->count = 0;
}

void sta_gpu_cache_release(sta_gpu_cache *cache)
{
    for (uint32_t i = 0; cache->entries && i < cache->node_count; i++) {
        free_buffer(&cache->entries[i]);
    }
    sta_free(cache->entries);
    memset(cache, 0, sizeof(*cache));
}

void sta_gpu_cache_apply(sta_gpu_cache *cache, const sta_stream_frame *frame)
{
    for (size_t i = 0; i < frame->evict_count; i++) {
        free_buffer(&cache->entries[frame->evict[i]]);
    }
    for (size_t i = 0; i < frame->upload_count; i++) {
        const sta_stream_upload *u = &frame->upload[i];
        sta_gpu_cache_entry *e = &cache->entries[u->node];
        free_buffer(e);
        uint64_t bytes = (uint64_t)u->count * STA_GPU_POINT_SIZE;
        glCreateBuffers(1, &e->buffer);
        // An empty node still gets a (tiny) buffer so it is drawn as resident.
        glNamedBufferStorage(e->buffer, bytes ? (GLsizeiptr)bytes : 16, bytes ? u->gpu : NULL, 0);
        e->count = u->count;
    }
}
