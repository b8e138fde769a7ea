/* SPDX-License-Identifier: MIT
 * LAZ point14 family (layered, version 3): not decoded yet.
 */
#include "io/laz_internal.h"

sta_laz_p14 *sta_laz_p14_create(const sta_laz_vlr *vlr)
{
    (void)vlr;
    return NULL;
}

void sta_laz_p14_destroy(sta_laz_p14 *state)
{
    (void)state;
}

bool sta_laz_p14_begin(sta_laz_p14 *state, const uint8_t *first, const uint8_t *p,
                       const uint8_t *end, uint32_t *out_count, const uint8_t **out_end)
{
    (void)state;
    (void)first;
    (void)p;
    (void)end;
    *out_count = 0;
    *out_end = NULL;
    return false;
}

bool sta_laz_p14_decode(sta_laz_p14 *state, uint8_t *record)
{
    (void)state;
    (void)record;
    return false;
}
