/* SPDX-License-Identifier: MIT
 * Test encoder: point14 family (layered). Placeholder until the layered encoder
 * lands (this branch): no chunk is encodable yet. */
#include "lazenc.h"

bool lazenc_point14_chunk(const sta_laz_vlr *vlr, const uint8_t *records, size_t count,
                          size_t record_length, lazenc_buf *out)
{
    (void)vlr;
    (void)records;
    (void)count;
    (void)record_length;
    (void)out;
    return false;
}
