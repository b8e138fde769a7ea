/* SPDX-License-Identifier: MIT
 * Per-node CPU subsample of the resident points (see point_sample.h). */
#include "stream/point_sample.h"

#include <string.h>

#include "core/alloc.h"

typedef struct node_records {
    uint8_t *gpu; // count records, or NULL
    uint32_t count;
} node_records;

struct sta_point_sample {
    node_records *nodes; // one per node
    uint32_t node_count;
    uint32_t stride; // every stride-th record is kept
};

sta_status sta_point_sample_create(uint32_t node_count, uint64_t cap_points, uint64_t budget_points,
                                   sta_point_sample **out, sta_error *err)
{
    *out = NULL;
    if (cap_points == 0 || budget_points == 0) {
        return sta_fail(err, STA_ERR_ARG, "point sample: cap %llu and budget %llu must be above 0",
                        (unsigned long long)cap_points, (unsigned long long)budget_points);
    }
    sta_point_sample *s = sta_calloc(1, sizeof(*s));
    node_records *nodes = sta_calloc(node_count ? node_count : 1, sizeof(*nodes));
    if (!s || !nodes) {
        sta_free(s);
        sta_free(nodes);
        return sta_fail(err, STA_ERR_NOMEM, "point sample: out of memory for %u nodes", node_count);
    }
    uint64_t stride = (budget_points + cap_points - 1) / cap_points;
    s->stride = stride > UINT32_MAX ? UINT32_MAX : (uint32_t)(stride ? stride : 1);
    s->nodes = nodes;
    s->node_count = node_count;
    *out = s;
    return STA_OK;
}

void sta_point_sample_destroy(sta_point_sample *s)
{
    if (!s) {
        return;
    }
    for (uint32_t i = 0; i < s->node_count; i++) {
        sta_free(s->nodes[i].gpu);
    }
    sta_free(s->nodes);
    sta_free(s);
}

static void drop(sta_point_sample *s, uint32_t node)
{
    if (node < s->node_count) {
        sta_free(s->nodes[node].gpu);
        s->nodes[node] = (node_records){ 0 };
    }
}

sta_status sta_point_sample_apply(sta_point_sample *s, const sta_stream_frame *frame,
                                  sta_error *err)
{
    for (size_t i = 0; i < frame->evict_count; i++) {
        drop(s, frame->evict[i]);
    }
    sta_status status = STA_OK;
    for (size_t i = 0; i < frame->upload_count; i++) {
        const sta_stream_upload *u = &frame->upload[i];
        if (u->node >= s->node_count) {
            continue;
        }
        drop(s, u->node);
        uint32_t kept = u->count / s->stride + (u->count % s->stride != 0);
        if (kept == 0) {
            continue;
        }
        uint8_t *gpu = sta_alloc_array(kept, STA_GPU_POINT_SIZE);
        if (!gpu) {
            status =
                sta_fail(err, STA_ERR_NOMEM, "point sample: out of memory for %u points", kept);
            continue;
        }
        for (uint32_t k = 0; k < kept; k++) {
            memcpy(gpu + (size_t)k * STA_GPU_POINT_SIZE,
                   u->gpu + (size_t)k * s->stride * STA_GPU_POINT_SIZE, STA_GPU_POINT_SIZE);
        }
        s->nodes[u->node] = (node_records){ gpu, kept };
    }
    return status;
}

const uint8_t *sta_point_sample_records(const sta_point_sample *s, uint32_t node,
                                        uint32_t *out_count)
{
    if (node >= s->node_count || !s->nodes[node].gpu) {
        *out_count = 0;
        return NULL;
    }
    *out_count = s->nodes[node].count;
    return s->nodes[node].gpu;
}

size_t sta_point_sample_gather(const sta_point_sample *s, const sta_gpu_node_frame *frames,
                               const uint32_t *draw, size_t draw_count, const double origin[3],
                               float (*out_points)[3], uint64_t *out_tags, size_t capacity)
{
    if (capacity == 0) {
        return 0;
    }
    uint64_t total = 0;
    for (size_t d = 0; d < draw_count; d++) {
        uint32_t count = 0;
        sta_point_sample_records(s, draw[d], &count);
        total += count;
    }
    // Over capacity: every step-th kept point of the whole list, so that no node is left
    // out for coming late in the list.
    uint64_t step = total > capacity ? (total + capacity - 1) / capacity : 1;
    size_t n = 0;
    uint64_t seen = 0;
    for (size_t d = 0; d < draw_count && n < capacity; d++) {
        uint32_t count = 0;
        const uint8_t *gpu = sta_point_sample_records(s, draw[d], &count);
        for (uint32_t k = 0; k < count && n < capacity; k++, seen++) {
            if (seen % step != 0) {
                continue;
            }
            double p[3];
            sta_gpu_point_position(&frames[draw[d]], gpu + (size_t)k * STA_GPU_POINT_SIZE, p);
            for (int a = 0; a < 3; a++) {
                out_points[n][a] = (float)(p[a] - origin[a]);
            }
            out_tags[n] = (uint64_t)draw[d] << 32 | k;
            n++;
        }
    }
    return n;
}

uint32_t sta_point_sample_stride(const sta_point_sample *s)
{
    return s->stride;
}
