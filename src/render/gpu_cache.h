/* SPDX-License-Identifier: MIT
 * The GPU side of node residency: every resident node's points (16 bytes each,
 * stream/gpu_points.h) in one arena buffer, so that a compute shader reaches all of
 * them in one dispatch. It holds no policy: the streamer (stream/streamer.h) decides
 * what to evict and upload each frame and this carries it out.
 *
 * Design: uploads go to the end of the arena; evictions leave holes. When the end is
 * reached the live nodes are copied, packed, into a new buffer (GPU to GPU) of 1.5x
 * what they need with the new node, so the arena briefly holds two copies. Node
 * offsets change then; readers take them from the entries every frame.
 * Splats (issue 12): a scene whose nodes carry splat records (stream/gpu_splats.h) gets
 * a second arena, `splat_buffer`, parallel to the first (8 bytes per point, same slots),
 * packed and grown with it; scenes without splats never allocate it.
 * GL calls: main thread only.
 */
#ifndef STA_RENDER_GPU_CACHE_H
#define STA_RENDER_GPU_CACHE_H

#include <epoxy/gl.h>
#include <stdbool.h>
#include <stdint.h>

#include "core/status.h"
#include "stream/streamer.h"

/* Smallest arena, points. */
#define STA_GPU_CACHE_MIN_POINTS (UINT32_C(1) << 16)

typedef struct sta_gpu_cache_entry {
    uint32_t offset; /* first point in the arena (valid while resident) */
    uint32_t count;  /* points (16 bytes each) */
    bool is_resident;
} sta_gpu_cache_entry;

typedef struct sta_gpu_cache {
    sta_gpu_cache_entry *entries; /* one per node */
    uint32_t node_count;
    GLuint buffer;        /* the arena; 0 until the first upload */
    uint32_t capacity;    /* points the arena holds */
    uint32_t end;         /* first free point after the last upload */
    uint64_t live;        /* points of resident nodes */
    uint32_t compactions; /* times the arena was repacked (for tests and stats) */
    bool has_splats;      /* uploads carry a splat section (sta_gpu_cache_enable_splats) */
    GLuint splat_buffer;  /* the splat arena, point i's record at i * 8; 0 without splats */
    /* Bumped whenever the arenas are replaced. Texture-buffer views compare it, not the
     * buffer names: a deleted buffer's name comes back for a later one (NVIDIA's driver
     * hands out the lowest free name), and a view still holds the deleted buffer. */
    uint32_t generation;
} sta_gpu_cache;

sta_status sta_gpu_cache_init(sta_gpu_cache *cache, uint32_t node_count, sta_error *err);

/* Uploads from now on carry a splat section after their points (sta_stream_upload);
 * call before the first apply. */
void sta_gpu_cache_enable_splats(sta_gpu_cache *cache);

/* Frees the arena (needs the GL context current); a zeroed cache is a no-op. */
void sta_gpu_cache_release(sta_gpu_cache *cache);

/* Frees the frame's evicted nodes, then uploads its finished ones. Errors: STA_ERR_NOMEM
 * when the arena would pass 2^32 points. */
sta_status sta_gpu_cache_apply(sta_gpu_cache *cache, const sta_stream_frame *frame, sta_error *err);

#endif
