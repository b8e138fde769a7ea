/* SPDX-License-Identifier: MIT
 * The LAZ GPS time predictor of GPSTIME11 version 2 and POINT14 (see laz_gpstime.h).
 */
#include "io/laz_gpstime.h"

#include <string.h>

enum {
    GPS_MULTI = 500,                                   // largest positive multiple
    GPS_MULTI_MINUS = -10,                             // most negative multiple
    GPS_CODE_FULL = GPS_MULTI - GPS_MULTI_MINUS + 1,   // 511 (GPSTIME11: 512)
    GPS_MULTI_TOTAL = GPS_MULTI - GPS_MULTI_MINUS + 5, // 515 symbols (GPSTIME11: 516)
    GPS_ZERO_DIFF_TOTAL = 5,                           // symbols (GPSTIME11: 6)
};

bool sta_laz_gpstime_init(sta_laz_gpstime *g, bool has_unchanged)
{
    uint32_t unchanged = has_unchanged ? 1u : 0u;
    g->has_unchanged = has_unchanged;
    g->m_multi = sta_laz_model_create(GPS_MULTI_TOTAL + unchanged);
    g->m_zero_diff = sta_laz_model_create(GPS_ZERO_DIFF_TOTAL + unchanged);
    return g->m_multi && g->m_zero_diff && sta_laz_ic_init(&g->ic, 32, 9);
}

void sta_laz_gpstime_release(sta_laz_gpstime *g)
{
    sta_laz_model_destroy(g->m_multi);
    sta_laz_model_destroy(g->m_zero_diff);
    sta_laz_ic_release(&g->ic);
    g->m_multi = NULL;
    g->m_zero_diff = NULL;
}

void sta_laz_gpstime_begin(sta_laz_gpstime *g, uint64_t first)
{
    g->last = 0;
    g->next = 0;
    memset(g->diff, 0, sizeof(g->diff));
    memset(g->extreme, 0, sizeof(g->extreme));
    sta_laz_model_reset(g->m_multi);
    sta_laz_model_reset(g->m_zero_diff);
    sta_laz_ic_reset(&g->ic);
    g->time[0] = first;
    g->time[1] = g->time[2] = g->time[3] = 0;
}

// A new sequence whose time is sent in full: the upper half predicted from the current
// sequence's time (a "huge" jump), the lower half raw.
static void decode_full(sta_laz_gpstime *g, sta_laz_dec *dec)
{
    g->next = (g->next + 1) & 3;
    uint32_t high =
        (uint32_t)sta_laz_ic_decode(&g->ic, dec, (int32_t)(uint32_t)(g->time[g->last] >> 32), 8);
    uint32_t low = sta_laz_read_u32(dec);
    g->time[g->next] = ((uint64_t)high << 32) | low;
    g->last = g->next;
    g->diff[g->last] = 0;
    g->extreme[g->last] = 0;
}

// The difference predicted as `multi` times the sequence's last difference (corrector
// context `context`); after more than three extreme multiples in a row the new
// difference becomes the base.
static int32_t decode_multiple(sta_laz_gpstime *g, sta_laz_dec *dec, int32_t multi,
                               uint32_t context, bool extreme)
{
    // Multiples wrap in 32 bits, as the writer computed them.
    uint32_t pred = (uint32_t)multi * (uint32_t)g->diff[g->last];
    int32_t diff = sta_laz_ic_decode(&g->ic, dec, (int32_t)pred, context);
    if (extreme) {
        g->extreme[g->last]++;
        if (g->extreme[g->last] > 3) {
            g->diff[g->last] = diff;
            g->extreme[g->last] = 0;
        }
    }
    return diff;
}

bool sta_laz_gpstime_decode(sta_laz_gpstime *g, sta_laz_dec *dec, uint32_t max_switches)
{
    // A sequence switch is followed by the time in the new sequence.
    for (uint32_t round = 0; round < max_switches; round++) {
        uint32_t last = g->last;
        if (g->diff[last] == 0) {
            uint32_t code = sta_laz_decode_symbol(dec, g->m_zero_diff);
            if (g->has_unchanged) {
                if (code == 0) {
                    return true; // unchanged
                }
                code--;
            }
            if (code == 0) {
                g->diff[last] = sta_laz_ic_decode(&g->ic, dec, 0, 0);
                g->time[last] += (uint64_t)(int64_t)g->diff[last];
                g->extreme[last] = 0;
                return true;
            }
            if (code == 1) {
                decode_full(g, dec);
                return true;
            }
            g->last = (last + code - 1) & 3;
            continue;
        }
        uint32_t multi = sta_laz_decode_symbol(dec, g->m_multi);
        if (multi == 1) {
            g->time[last] += (uint64_t)(int64_t)sta_laz_ic_decode(&g->ic, dec, g->diff[last], 1);
            g->extreme[last] = 0;
            return true;
        }
        if (multi < GPS_CODE_FULL) {
            int32_t diff;
            if (multi == 0) {
                diff = decode_multiple(g, dec, 0, 7, true);
            } else if (multi < GPS_MULTI) {
                diff = decode_multiple(g, dec, (int32_t)multi, multi < 10 ? 2 : 3, false);
            } else if (multi == GPS_MULTI) {
                diff = decode_multiple(g, dec, GPS_MULTI, 4, true);
            } else {
                int32_t minus = GPS_MULTI - (int32_t)multi;
                if (minus > GPS_MULTI_MINUS) {
                    diff = decode_multiple(g, dec, minus, 5, false);
                } else {
                    diff = decode_multiple(g, dec, GPS_MULTI_MINUS, 6, true);
                }
            }
            g->time[last] += (uint64_t)(int64_t)diff;
            return true;
        }
        if (g->has_unchanged) {
            if (multi == GPS_CODE_FULL) {
                return true; // unchanged
            }
            multi--;
        }
        if (multi == GPS_CODE_FULL) {
            decode_full(g, dec);
            return true;
        }
        g->last = (last + multi - GPS_CODE_FULL) & 3;
    }
    return false;
}
