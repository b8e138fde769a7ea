/* SPDX-License-Identifier: MIT
 * Splat attribute layout: octahedral normals and half-float radii. */
#include "stream/gpu_splats.h"

#include <math.h>
#include <string.h>

#include "core/bytes.h"

void sta_gpu_splats_encode(const float (*normals)[3], const float *radii, size_t count,
                           uint8_t *out)
{
    for (size_t i = 0; i < count; i++) {
        uint8_t *o = out + i * STA_GPU_SPLAT_SIZE;
        uint16_t oct[2];
        sta_octahedral_encode(normals[i], oct);
        sta_store_u16le(o, oct[0]);
        sta_store_u16le(o + 2, oct[1]);
        sta_store_u16le(o + 4, sta_half_from_float(radii[i]));
        sta_store_u16le(o + 6, 0);
    }
}

void sta_gpu_splat_decode(const uint8_t *record, float normal[3], float *radius)
{
    const uint16_t oct[2] = { sta_load_u16le(record), sta_load_u16le(record + 2) };
    sta_octahedral_decode(oct, normal);
    *radius = sta_half_to_float(sta_load_u16le(record + 4));
}
