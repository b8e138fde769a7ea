/* SPDX-License-Identifier: MIT
 * The compact unit normal and radius shared by the .strata SPLAT attribute and the GPU
 * splat record (stream/gpu_splats.h): a unit vector as its octahedral map, two snorm16
 * values (about 0.003 degrees), and a non-negative length as IEEE binary16.
 */
#ifndef STA_CORE_OCTAHEDRAL_H
#define STA_CORE_OCTAHEDRAL_H

#include <stdint.h>

/* Octahedral map of a unit vector to two snorm16 values; a zero or non-finite normal
 * encodes as +Z. Decoding gives a unit vector within about 0.003 degrees. */
void sta_octahedral_encode(const float normal[3], uint16_t out[2]);
void sta_octahedral_decode(const uint16_t in[2], float normal[3]);

/* IEEE binary16 of a non-negative radius (round to nearest; NaN and negative -> 0,
 * above the largest finite half -> the largest finite half) and back. */
uint16_t sta_half_from_float(float value);
float sta_half_to_float(uint16_t half);

/* A normal and radius as the three u16 of the SPLAT attribute (u, v, half radius). */
void sta_splat_pack(const float normal[3], float radius, uint16_t out[3]);
void sta_splat_unpack(const uint16_t in[3], float normal[3], float *radius);

#endif
