/* SPDX-License-Identifier: MIT
 * A CPU-side subsample of the resident points, kept per node, for visibility computed on
 * the CPU (the live Katz mode, visibility/katz_worker.h). The loader's GPU records are
 * freed after upload, so this keeps every k-th record of each upload (k = ceil(points /
 * cap), so that a draw list of `points` points yields about `cap`) and drops a node's
 * records when the node is evicted. No GL; main thread only.
 */
#ifndef STA_STREAM_POINT_SAMPLE_H
#define STA_STREAM_POINT_SAMPLE_H

#include <stddef.h>
#include <stdint.h>

#include "core/status.h"
#include "stream/gpu_points.h"
#include "stream/streamer.h"

/* Default points the live Katz mode hands to the hull per submission. */
#define STA_DEFAULT_KATZ_SAMPLE_POINTS 25000

typedef struct sta_point_sample sta_point_sample;

/* For a scene of `node_count` nodes drawing about `budget_points` per frame; about
 * `cap_points` points per such draw list (both > 0). *out: owned by the caller. */
sta_status sta_point_sample_create(uint32_t node_count, uint64_t cap_points, uint64_t budget_points,
                                   sta_point_sample **out, sta_error *err);

/* NULL is a no-op. */
void sta_point_sample_destroy(sta_point_sample *sample);

/* Carries out a streamer frame: drops the evicted nodes' records, keeps every k-th record
 * of the uploaded ones. Call with every frame of the streamer. STA_ERR_NOMEM leaves the
 * node without records (it is then absent from gathers). */
sta_status sta_point_sample_apply(sta_point_sample *sample, const sta_stream_frame *frame,
                                  sta_error *err);

/* The kept records of `node` (STA_GPU_POINT_SIZE bytes each; owned by the sample, valid
 * until the node is evicted), their count in *out_count; NULL when none. */
const uint8_t *sta_point_sample_records(const sta_point_sample *sample, uint32_t node,
                                        uint32_t *out_count);

/* Kept points of the nodes in `draw`: positions relative to `origin` (metres, float) and
 * tags (node << 32 | record index); when they are more than `capacity`, every step-th of
 * the whole list (evenly thinned, not cut off); returns how many were written. */
size_t sta_point_sample_gather(const sta_point_sample *sample, const sta_gpu_node_frame *frames,
                               const uint32_t *draw, size_t draw_count, const double origin[3],
                               float (*out_points)[3], uint64_t *out_tags, size_t capacity);

/* Every k-th record is kept. */
uint32_t sta_point_sample_stride(const sta_point_sample *sample);

#endif
