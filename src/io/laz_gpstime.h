/* SPDX-License-Identifier: MIT
 * The LAZ GPS time predictor, shared by GPSTIME11 version 2 (point10 family,
 * laz_point10.c) and the GPS time layer of POINT14 versions 3 and 4 (laz_point14.c):
 * up to four interleaved time sequences, each predicted as a multiple of its last
 * difference.
 *
 * Design: times are the raw 64-bit patterns of the doubles. A sequence without a
 * difference yet codes its first difference, a time in full (upper half predicted
 * from the current sequence's, lower half raw, into the next of the four slots) or a
 * switch to another sequence. Otherwise a multiplier symbol picks the prediction
 * (multiples 0..500 and -1..-10 of the last difference, each range with its own
 * corrector context), a time in full or a switch. An extreme multiple (0, 500, -10)
 * repeated more than three times in a row becomes the sequence's new difference.
 * The two items code the same choices with the same models and contexts; GPSTIME11
 * alone has an "unchanged" symbol (POINT14 says so in its change mask), first in the
 * zero-difference model and after the multiples in the multiplier model, which moves
 * the codes after it up by one.
 *
 * Based on: M. Isenburg, "LASzip: lossless compression of LiDAR data", PE&RS 79(2),
 * 2013, section on the GPS time predictor; the LAZ specification's description of
 * the GPSTIME11 version 2 item and the POINT14 GPS time layer.
 */
#ifndef STA_IO_LAZ_GPSTIME_H
#define STA_IO_LAZ_GPSTIME_H

#include <stdbool.h>
#include <stdint.h>

#include "io/laz_arith.h"

/* The predictor's state and models (caller-owned; _init, _begin per chunk, _release). */
typedef struct sta_laz_gpstime {
    uint64_t time[4];           /* last time of each sequence (bits of the double) */
    int32_t diff[4];            /* last difference of each sequence; 0: none yet */
    int32_t extreme[4];         /* extreme multiples in a row, per sequence */
    uint32_t last;              /* sequence of the last decoded time (0..3) */
    uint32_t next;              /* slot the last full time went to (0..3) */
    bool has_unchanged;         /* GPSTIME11: the codes include "unchanged" */
    sta_laz_model *m_multi;     /* multiplier, when the sequence has a difference */
    sta_laz_model *m_zero_diff; /* choice when it has none */
    sta_laz_ic ic;              /* 32 bits, 9 contexts */
} sta_laz_gpstime;

/* Allocates the models: with `has_unchanged` those of GPSTIME11 version 2, else those
 * of POINT14. False when out of memory (then release it). */
bool sta_laz_gpstime_init(sta_laz_gpstime *g, bool has_unchanged);
/* Frees the models; a zeroed struct is a no-op. */
void sta_laz_gpstime_release(sta_laz_gpstime *g);
/* Starts over from time `first` (bits of the double) in sequence 0: chunk start
 * (POINT14: first use of a context in a chunk); resets every model. */
void sta_laz_gpstime_begin(sta_laz_gpstime *g, uint64_t first);
/* Decodes the next time into time[last] (read it with sta_laz_gpstime_last). False
 * when the stream switched sequence `max_switches` times in a row without a time
 * (corrupt: a valid stream switches at most once per point); time[last] is then the
 * unchanged time of the sequence switched to. */
bool sta_laz_gpstime_decode(sta_laz_gpstime *g, sta_laz_dec *dec, uint32_t max_switches);

/* The last decoded time (bits of the double). */
static inline uint64_t sta_laz_gpstime_last(const sta_laz_gpstime *g)
{
    return g->time[g->last];
}

#endif
