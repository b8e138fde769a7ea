/* SPDX-License-Identifier: MIT
 * Test encoder: point10 family items, version 1. Placeholder until the version 1
 * encoders land (this branch): no item is encodable yet. */
#include "lazenc.h"

bool lazenc_point10_v1_item(const sta_laz_item *item, lazenc_seq_item *out)
{
    (void)item;
    (void)out;
    return false;
}
