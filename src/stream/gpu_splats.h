/* SPDX-License-Identifier: MIT
 * The GPU layout of a point's splat attributes (issue 12): 8 bytes per point, kept in
 * a second section after a node's 16-byte points (stream/gpu_points.h) when the scene
 * was converted with `--normals`.
 *
 * bytes 0..3  uint16 u, v: the unit normal, octahedral (x, y of the octahedron map,
 *             each as snorm16: GLSL unpackSnorm2x16 of the first word)
 * bytes 4..5  binary16 radius in metres (GLSL unpackHalf2x16(second word).x); 0 = none
 * bytes 6..7  reserved (0)
 */
#ifndef STA_STREAM_GPU_SPLATS_H
#define STA_STREAM_GPU_SPLATS_H

#include <stddef.h>
#include <stdint.h>

#include "core/octahedral.h" /* sta_octahedral_*, sta_half_* */

enum {
    STA_GPU_SPLAT_SIZE = 8
};

/* Writes one 8-byte record per point into `out` (count * STA_GPU_SPLAT_SIZE bytes). */
void sta_gpu_splats_encode(const float (*normals)[3], const float *radii, size_t count,
                           uint8_t *out);

/* Reads record `i` back (for CPU twins and tests). */
void sta_gpu_splat_decode(const uint8_t *record, float normal[3], float *radius);

#endif
