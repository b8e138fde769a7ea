/* SPDX-License-Identifier: MIT
 * The GPU layout of a resident point: 16 bytes, node-relative quantized position.
 *
 * bytes  0..5   uint16 qx, qy, qz: position relative to the node's corner in steps of
 *               (2^shift grid units); shift = max(0, node edge log2 - 16), so nodes up
 *               to 65536 grid units wide are exact
 * bytes  6..7   uint16 intensity
 * bytes  8..10  uint8 red, green, blue (16-bit colour scaled down by the scene's depth)
 * byte   11     uint8 classification
 * byte   12     uint8 return number, byte 13 number of returns
 * byte   14     uint8 flags: bit 0 STA_GPU_FLAG_MIRROR_GHOST (the viewer hides these
 *               unless asked: docs/MIRRORS.md)
 * byte   15     reserved (0)
 */
#ifndef STA_STREAM_GPU_POINTS_H
#define STA_STREAM_GPU_POINTS_H

#include <stddef.h>
#include <stdint.h>

#include "core/status.h"
#include "format/strata.h"

enum {
    STA_GPU_POINT_SIZE = 16,
    STA_GPU_POINT_FLAGS_BYTE = 14,
    STA_GPU_FLAG_MIRROR_GHOST = 1u << 0, /* a ghost seen through a mirror */
};

/* Per-axis dequantisation of one node: real position relative to the node corner is
 * q * step[axis] metres. */
typedef struct sta_gpu_node_frame {
    int64_t grid_corner[3]; /* corner of the node in grid units */
    double corner[3];       /* real-world corner of the node, metres */
    double step[3];         /* metres per quantisation step */
    int shift[3];           /* grid units per step = 2^shift */
    double spacing;         /* metres between the node's points (sta_strata_node_spacing) */
} sta_gpu_node_frame;

/* The frame of node `key` in a scene. */
void sta_gpu_node_frame_init(sta_gpu_node_frame *frame, const sta_strata_geometry *geometry,
                             sta_strata_key key);

/* Converts decoded points (absolute grid integers) to the GPU layout. `colour_shift`
 * is 8 for 16-bit colour, 0 for 8-bit. `out` holds count * 16 bytes. */
void sta_gpu_points_encode(const sta_gpu_node_frame *frame, const sta_point *points, size_t count,
                           int colour_shift, uint8_t *out);

/* Real-world position of GPU point `gpu` (for CPU references and tests). */
void sta_gpu_point_position(const sta_gpu_node_frame *frame, const uint8_t *gpu, double out[3]);

#endif
