/* SPDX-License-Identifier: MIT
 * Node source over a .strata reader. */
#include "stream/strata_source.h"

#include <string.h>

#include "core/alloc.h"
#include "stream/gpu_points.h"
#include "stream/gpu_splats.h"

static sta_status worker_begin(void *context, void **out_worker, sta_error *err)
{
    (void)context;
    sta_strata_decoder *decoder = NULL;
    sta_status status = sta_strata_decoder_create(&decoder, err);
    *out_worker = decoder;
    return status;
}

static void worker_end(void *context, void *worker)
{
    (void)context;
    sta_strata_decoder_destroy(worker);
}

/* The viewer's mirror file, for files converted without --mirrors: flags the ghosts
 * of `count` points encoded at `gpu` (the stored attribute wins when present). */
static void flag_ghosts(const sta_strata_source *s, const sta_strata_info *info,
                        const sta_point *points, size_t count, uint8_t *gpu)
{
    if (!s->mirrors || (info->layout.attributes & STA_STRATA_ATTR_MIRROR)) {
        return;
    }
    const sta_grid *grid = &info->geometry.grid;
    for (size_t i = 0; i < count; i++) {
        const double world[3] = { sta_grid_apply(grid, 0, points[i].X),
                                  sta_grid_apply(grid, 1, points[i].Y),
                                  sta_grid_apply(grid, 2, points[i].Z) };
        if (sta_mirror_ghost_of(s->mirrors, points[i].point_source_id, world)) {
            gpu[i * STA_GPU_POINT_SIZE + STA_GPU_POINT_FLAGS_BYTE] |= STA_GPU_FLAG_MIRROR_GHOST;
        }
    }
}

// The splat records of `count` decoded points (normal and radius from the SPLAT columns).
static void encode_splats(const sta_point *points, size_t count, uint8_t *out)
{
    for (size_t i = 0; i < count; i++) {
        sta_gpu_splats_encode(&points[i].normal, &points[i].radius, 1,
                              out + i * STA_GPU_SPLAT_SIZE);
    }
}

static sta_status load(void *context, void *worker, uint32_t node, uint8_t **out_gpu,
                       size_t *out_count, sta_error *err)
{
    const sta_strata_source *s = context;
    *out_gpu = NULL;
    *out_count = 0;
    sta_strata_points points;
    sta_status status = sta_strata_decode_node(s->reader, node, worker, &points, err);
    if (status != STA_OK || points.count == 0) {
        return status;
    }
    const size_t stride = STA_GPU_POINT_SIZE + (s->source.has_splats ? STA_GPU_SPLAT_SIZE : 0);
    uint8_t *gpu = sta_alloc_array(points.count, stride);
    if (!gpu) {
        return sta_fail(err, STA_ERR_NOMEM, "out of memory loading node %u", node);
    }
    const sta_strata_info *info = sta_strata_reader_info(s->reader);
    sta_gpu_node_frame frame;
    sta_gpu_node_frame_init(&frame, &info->geometry, sta_strata_reader_node(s->reader, node)->key);
    // With splats, the section after the points (node_source.h); written at `count`
    // points' offset and moved down when the clip keeps fewer.
    uint8_t *splats = gpu + points.count * STA_GPU_POINT_SIZE;
    if (!s->clip) {
        sta_gpu_points_encode(&frame, points.points, points.count, s->colour_shift, gpu);
        flag_ghosts(s, info, points.points, points.count, gpu);
        if (s->source.has_splats) {
            encode_splats(points.points, points.count, splats);
        }
        *out_gpu = gpu;
        *out_count = points.count;
        return STA_OK;
    }
    // Only the points the clip keeps, in their order, in runs.
    const uint32_t attributes = sta_strata_attributes_to_sta_attr(info->layout.attributes);
    size_t kept = 0;
    for (size_t i = 0; i < points.count;) {
        size_t end = i;
        while (end < points.count && sta_clip_keeps_point(s->clip, &info->geometry.grid, attributes,
                                                          &points.points[end])) {
            end++;
        }
        if (end > i) {
            sta_gpu_points_encode(&frame, points.points + i, end - i, s->colour_shift,
                                  gpu + kept * STA_GPU_POINT_SIZE);
            flag_ghosts(s, info, points.points + i, end - i, gpu + kept * STA_GPU_POINT_SIZE);
            if (s->source.has_splats) {
                encode_splats(points.points + i, end - i, splats + kept * STA_GPU_SPLAT_SIZE);
            }
            kept += end - i;
        }
        i = end + 1; // points[end] was refused (or end is the count)
    }
    if (kept == 0) {
        sta_free(gpu);
        gpu = NULL;
    } else if (s->source.has_splats && kept < points.count) {
        memmove(gpu + kept * STA_GPU_POINT_SIZE, splats, kept * STA_GPU_SPLAT_SIZE);
    }
    *out_gpu = gpu;
    *out_count = kept;
    return STA_OK;
}

void sta_strata_source_init(sta_strata_source *source, const sta_strata_reader *reader,
                            int colour_shift)
{
    source->reader = reader;
    source->colour_shift = colour_shift;
    source->clip = NULL;
    source->mirrors = NULL;
    source->source = (sta_node_source){ .context = source,
                                        .node_count = sta_strata_reader_info(reader)->node_count,
                                        .worker_begin = worker_begin,
                                        .worker_end = worker_end,
                                        .load = load };
    const sta_strata_info *info = sta_strata_reader_info(reader);
    source->source.has_splats = (info->layout.attributes & STA_STRATA_ATTR_SPLAT) != 0;
}
