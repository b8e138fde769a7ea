/* SPDX-License-Identifier: MIT
 * The scanner's path as far as the points tell it (strata-convert --normals): the
 * centroid of the points measured in each short GPS-time bin. A mobile or airborne
 * scanner sweeps profiles around itself, so the centroid of one bin lies on the side
 * of a wall the scanner saw it from; vertical surfaces are oriented towards it.
 *
 * Usable only when bins are compact (a scan pattern): the median bin extent is below a
 * fraction of the scene's extent. Points sampled in no scan order (strata-synth's
 * analytic scenes number their points in random places) fail that test. Sums are
 * integers and extents min/max, so the result does not depend on the order points are
 * added in (deterministic output with any number of threads).
 */
#ifndef STA_PREPROCESS_TRAJECTORY_H
#define STA_PREPROCESS_TRAJECTORY_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include "core/status.h"

#define STA_TRAJECTORY_BIN_S          0.05 /* 10 profiles of a 200 Hz scanner */
#define STA_TRAJECTORY_COMPACT_FACTOR 0.25 /* median bin extent / scene extent below */

typedef struct sta_trajectory_bin {
    int64_t key;    /* floor(gps_time / bin); INT64_MIN: empty slot */
    int64_t sum[3]; /* grid integers */
    uint64_t count;
    int32_t min[3], max[3];
} sta_trajectory_bin;

typedef struct sta_trajectory {
    sta_trajectory_bin *bins; /* open addressing, power-of-two capacity */
    size_t capacity, count;
    bool usable; /* set by sta_trajectory_finish */
    size_t last; /* the slot sta_trajectory_add filled last, + 1 (0: none; growing forgets) */
    double last_from, last_to; /* the times of that slot's bin: [from, to) exactly */
} sta_trajectory;

/* Adds a point to bin b (sta_trajectory_add's last step). */
static inline void sta_trajectory_bin_add(sta_trajectory_bin *b, const int32_t xyz[3])
{
    for (int a = 0; a < 3; a++) {
        b->sum[a] += xyz[a];
        b->min[a] = xyz[a] < b->min[a] ? xyz[a] : b->min[a];
        b->max[a] = xyz[a] > b->max[a] ? xyz[a] : b->max[a];
    }
    b->count++;
}

/* sta_trajectory_add where `gps_time` is not in the bin filled last: finds (or makes) its
 * bin and adds the point there. */
sta_status sta_trajectory_add_elsewhere(sta_trajectory *t, double gps_time, const int32_t xyz[3],
                                        sta_error *err);

/* Adds a point measured at `gps_time` (non-finite times are ignored). Inline: points come
 * in runs of one bin (scan order), and a time in the last bin costs two comparisons. */
static inline sta_status sta_trajectory_add(sta_trajectory *t, double gps_time,
                                            const int32_t xyz[3], sta_error *err)
{
    if (t->last > 0 && gps_time >= t->last_from && gps_time < t->last_to) {
        sta_trajectory_bin_add(&t->bins[t->last - 1], xyz);
        return STA_OK;
    }
    return sta_trajectory_add_elsewhere(t, gps_time, xyz, err);
}

/* Adds all of `from`'s bins to `into`. */
sta_status sta_trajectory_merge(sta_trajectory *into, const sta_trajectory *from, sta_error *err);

/* Decides `usable` from the bins' extents against the scene's (grid units per axis). */
void sta_trajectory_finish(sta_trajectory *t, const int64_t scene_min[3],
                           const int64_t scene_max[3]);

/* The centroid (grid units) of the bin of `gps_time`; false when none. */
bool sta_trajectory_at(const sta_trajectory *t, double gps_time, double out[3]);

/* The last bin sta_trajectory_at_memo found or missed (zero-initialised: none). */
typedef struct sta_trajectory_memo {
    bool valid, seen;
    int64_t key;
    double from, to; /* the times of bin `key`: [from, to) exactly */
    double at[3];
} sta_trajectory_memo;

/* Moves `memo` to the bin of `gps_time` (looked up when it is not the memo's key already);
 * false, the memo unchanged, when the time has no bin (not finite, out of range). */
bool sta_trajectory_memo_move(const sta_trajectory *t, sta_trajectory_memo *memo, double gps_time);

/* sta_trajectory_at, remembering the last bin in `memo` (the same answer: points taken in
 * space order come in runs of one bin, one look-up a run; inline, so that a time inside
 * the memo's bin costs a comparison, not a call). */
static inline bool sta_trajectory_at_memo(const sta_trajectory *t, sta_trajectory_memo *memo,
                                          double gps_time, double out[3])
{
    if ((!memo->valid || !(gps_time >= memo->from && gps_time < memo->to)) &&
        !sta_trajectory_memo_move(t, memo, gps_time)) {
        return false;
    }
    if (memo->seen) {
        memcpy(out, memo->at, sizeof(memo->at));
    }
    return memo->seen;
}

void sta_trajectory_release(sta_trajectory *t);

#endif
