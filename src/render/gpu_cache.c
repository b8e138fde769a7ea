/* SPDX-License-Identifier: MIT
 * GPU node arena. */
#include "render/gpu_cache.h"

#include <string.h>

#include "core/alloc.h"
#include "stream/gpu_points.h"
#include "stream/gpu_splats.h"

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

void sta_gpu_cache_enable_splats(sta_gpu_cache *cache)
{
    cache->has_splats = true;
}

void sta_gpu_cache_release(sta_gpu_cache *cache)
{
    if (cache->buffer) {
        glDeleteBuffers(1, &cache->buffer);
    }
    if (cache->splat_buffer) {
        glDeleteBuffers(1, &cache->splat_buffer);
    }
    sta_free(cache->entries);
    memset(cache, 0, sizeof(*cache));
}

static void evict(sta_gpu_cache *cache, uint32_t node)
{
    sta_gpu_cache_entry *e = &cache->entries[node];
    if (e->is_resident) {
        cache->live -= e->count;
    }
    memset(e, 0, sizeof(*e));
}

// Packs the live nodes into a new arena with room for `extra` more points.
static sta_status repack(sta_gpu_cache *cache, uint32_t extra, sta_error *err)
{
    uint64_t need = cache->live + extra;
    uint64_t capacity = need + need / 2;
    if (capacity < STA_GPU_CACHE_MIN_POINTS) {
        capacity = STA_GPU_CACHE_MIN_POINTS;
    }
    if (capacity > UINT32_MAX) {
        capacity = UINT32_MAX;
    }
    if (need > capacity) {
        return sta_fail(err, STA_ERR_NOMEM, "GPU arena: %llu points exceed 2^32",
                        (unsigned long long)need);
    }
    GLuint buffer = 0, splats = 0;
    glCreateBuffers(1, &buffer);
    glNamedBufferStorage(buffer, (GLsizeiptr)(capacity * STA_GPU_POINT_SIZE), NULL,
                         GL_DYNAMIC_STORAGE_BIT);
    if (cache->has_splats) {
        glCreateBuffers(1, &splats);
        glNamedBufferStorage(splats, (GLsizeiptr)(capacity * STA_GPU_SPLAT_SIZE), NULL,
                             GL_DYNAMIC_STORAGE_BIT);
    }
    uint32_t end = 0;
    for (uint32_t i = 0; i < cache->node_count; i++) {
        sta_gpu_cache_entry *e = &cache->entries[i];
        if (!e->is_resident) {
            continue;
        }
        if (e->count > 0) {
            glCopyNamedBufferSubData(cache->buffer, buffer,
                                     (GLintptr)((uint64_t)e->offset * STA_GPU_POINT_SIZE),
                                     (GLintptr)((uint64_t)end * STA_GPU_POINT_SIZE),
                                     (GLsizeiptr)((uint64_t)e->count * STA_GPU_POINT_SIZE));
            if (splats) {
                glCopyNamedBufferSubData(cache->splat_buffer, splats,
                                         (GLintptr)((uint64_t)e->offset * STA_GPU_SPLAT_SIZE),
                                         (GLintptr)((uint64_t)end * STA_GPU_SPLAT_SIZE),
                                         (GLsizeiptr)((uint64_t)e->count * STA_GPU_SPLAT_SIZE));
            }
        }
        e->offset = end;
        end += e->count;
    }
    if (cache->buffer) {
        glDeleteBuffers(1, &cache->buffer);
        cache->compactions++;
    }
    if (cache->splat_buffer) {
        glDeleteBuffers(1, &cache->splat_buffer);
    }
    cache->buffer = buffer;
    cache->splat_buffer = splats;
    cache->generation++;
    cache->capacity = (uint32_t)capacity;
    cache->end = end;
    return STA_OK;
}

sta_status sta_gpu_cache_apply(sta_gpu_cache *cache, const sta_stream_frame *frame, sta_error *err)
{
    for (size_t i = 0; i < frame->evict_count; i++) {
        evict(cache, frame->evict[i]);
    }
    for (size_t i = 0; i < frame->upload_count; i++) {
        const sta_stream_upload *u = &frame->upload[i];
        evict(cache, u->node);
        if (!cache->buffer || (uint64_t)cache->end + u->count > cache->capacity) {
            sta_status status = repack(cache, u->count, err);
            if (status != STA_OK) {
                return status;
            }
        }
        sta_gpu_cache_entry *e = &cache->entries[u->node];
        e->offset = cache->end;
        e->count = u->count;
        e->is_resident = true; // an empty node is resident too, and drawn as such
        if (u->count > 0) {
            glNamedBufferSubData(cache->buffer,
                                 (GLintptr)((uint64_t)e->offset * STA_GPU_POINT_SIZE),
                                 (GLsizeiptr)((uint64_t)u->count * STA_GPU_POINT_SIZE), u->gpu);
            if (cache->has_splats) { // the section after the node's points
                glNamedBufferSubData(cache->splat_buffer,
                                     (GLintptr)((uint64_t)e->offset * STA_GPU_SPLAT_SIZE),
                                     (GLsizeiptr)((uint64_t)u->count * STA_GPU_SPLAT_SIZE),
                                     u->gpu + (size_t)u->count * STA_GPU_POINT_SIZE);
            }
        }
        cache->end += u->count;
        cache->live += u->count;
    }
    return STA_OK;
}
