/* SPDX-License-Identifier: MIT
 * The drawn points of a view from the id target (see drawn_points.h). */
#include "bench/drawn_points.h"

#include <math.h>
#include <string.h>

#include "core/alloc.h"
#include "stream/gpu_points.h"

// A drawn point may project this far outside its pixel: the GPU projects the float
// position relative to the eye, the CPU the double one.
#define PIXEL_SLACK_PX 0.05

// The id target's pair of the point in row-first pixel `pixel` (GL order, bottom row 0).
static void pixel_id(const sta_camera *camera, const uint32_t *ids, uint32_t pixel,
                     uint32_t *out_node, uint32_t *out_index)
{
    const uint32_t w = (uint32_t)camera->width_px, h = (uint32_t)camera->height_px;
    const size_t top_first = (size_t)(h - 1 - pixel / w) * w + pixel % w;
    *out_node = ids[2 * top_first];
    *out_index = ids[2 * top_first + 1];
}

// Moves the points of `node` (the `count` entries of `order`) to their drawn positions.
static sta_status apply_node(const sta_strata_reader *reader, const char *path,
                             sta_strata_decoder *decoder, const sta_camera *camera,
                             const uint32_t *ids, uint32_t node, const size_t *order, size_t count,
                             sta_view_points *points, sta_error *err)
{
    const sta_strata_info *info = sta_strata_reader_info(reader);
    sta_strata_points decoded;
    sta_status s = sta_strata_decode_node(reader, node, decoder, &decoded, err);
    if (s != STA_OK) {
        return s;
    }
    sta_gpu_node_frame frame;
    sta_gpu_node_frame_init(&frame, &info->geometry, sta_strata_reader_node(reader, node)->key);
    const int w = camera->width_px, h = camera->height_px;
    for (size_t k = 0; k < count; k++) {
        const size_t i = order[k];
        const int x = (int)(points->pixel[i] % (uint32_t)w);
        const int y = (int)(points->pixel[i] / (uint32_t)w);
        uint32_t id_node, index;
        pixel_id(camera, ids, points->pixel[i], &id_node, &index);
        if (index >= decoded.count) {
            return sta_fail(err, STA_ERR_FORMAT,
                            "%s: pixel (%d, %d) drew point %u of node %u, which has %zu points",
                            path, x, y, index, node, decoded.count);
        }
        uint8_t gpu[STA_GPU_POINT_SIZE];
        sta_gpu_points_encode(&frame, &decoded.points[index], 1, 0, gpu);
        double world[3], px, py, depth;
        sta_gpu_point_position(&frame, gpu, world);
        // sta_camera_project counts rows from the top, the points from the bottom.
        if (!sta_camera_project(camera, world, &px, &py, &depth) ||
            fabs(px - ((double)x + 0.5)) > 0.5 + PIXEL_SLACK_PX ||
            fabs((double)h - py - ((double)y + 0.5)) > 0.5 + PIXEL_SLACK_PX) {
            return sta_fail(err, STA_ERR_FORMAT,
                            "%s: point %u of node %u, drawn in pixel (%d, %d), projects to "
                            "(%.2f, %.2f): the ids are not of this view",
                            path, index, node, x, y, px, (double)h - py);
        }
        memcpy(points->world[i], world, sizeof(world));
    }
    return STA_OK;
}

sta_status sta_drawn_points_apply(const sta_strata_reader *reader, const char *path,
                                  const sta_camera *camera, const uint32_t *ids,
                                  sta_view_points *points, sta_error *err)
{
    const uint32_t node_count = sta_strata_reader_info(reader)->node_count;
    // Grouped by node (counting sort) so that each node is decoded once.
    size_t *first = sta_calloc((size_t)node_count + 1, sizeof(size_t));
    size_t *order = sta_alloc_array(points->count ? points->count : 1, sizeof(size_t));
    sta_strata_decoder *decoder = NULL;
    sta_status s = STA_OK;
    if (!first || !order) {
        s = sta_fail(err, STA_ERR_NOMEM, "out of memory for the ids of %zu points", points->count);
        goto out;
    }
    for (size_t i = 0; i < points->count; i++) {
        uint32_t node, index;
        pixel_id(camera, ids, points->pixel[i], &node, &index);
        if (node >= node_count) {
            s = sta_fail(err, STA_ERR_FORMAT,
                         "%s: pixel (%u, %u) drew point %u of node %u; the file has %u nodes", path,
                         points->pixel[i] % (uint32_t)camera->width_px,
                         points->pixel[i] / (uint32_t)camera->width_px, index, node, node_count);
            goto out;
        }
        first[node + 1]++;
    }
    for (uint32_t n = 0; n < node_count; n++) {
        first[n + 1] += first[n];
    }
    for (size_t i = 0; i < points->count; i++) {
        uint32_t node, index;
        pixel_id(camera, ids, points->pixel[i], &node, &index);
        order[first[node]++] = i;
    }
    // first[n] is now the end of node n's run, first[n - 1] (or 0) its start.
    s = sta_strata_decoder_create(&decoder, err);
    for (uint32_t n = 0; n < node_count && s == STA_OK; n++) {
        const size_t start = n ? first[n - 1] : 0;
        if (first[n] > start) {
            s = apply_node(reader, path, decoder, camera, ids, n, order + start, first[n] - start,
                           points, err);
        }
    }
out:
    sta_strata_decoder_destroy(decoder);
    sta_free(first);
    sta_free(order);
    return s;
}
