/* SPDX-License-Identifier: MIT
 * Internal: the "mirror" scene, a closed room scanned by a terrestrial scanner from a
 * few stations, with planar mirrors of polygonal outline on (and leaning against)
 * its walls. A pulse that meets a mirror's front is reflected (up to
 * ROOM_MAX_BOUNCES times) and its return is recorded where the scanner believes it
 * is: along the first direction at the whole path length, i.e. behind the mirror.
 * That point is a ghost, labelled with the first mirror it went through.
 *
 * Scene-local metres: the room is [0, 12] x [0, 8] x [0, 3] (docs/SYNTH.md).
 */
#ifndef STA_SYNTH_MIRROR_ROOM_H
#define STA_SYNTH_MIRROR_ROOM_H

#include <stdbool.h>
#include <stdint.h>

#include "core/point.h"
#include "core/status.h"
#include "mirror/mirror_set.h"

#define ROOM_STATIONS        3    /* scanner set-ups */
#define ROOM_MAX_BOUNCES     4    /* mirror reflections one pulse may take */
#define ROOM_RAY_PERIOD_S    1e-5 /* GPS time between two pulses */
#define ROOM_GPS_START       1000.0
#define ROOM_DEFAULT_NOISE_M 0.003 /* range noise of a terrestrial scanner */

typedef struct synth_room {
    sta_mirror_set mirrors; /* scene-local coordinates */
    double stations[ROOM_STATIONS][3];
    uint64_t rays_per_station;                       /* ceil(point_count / ROOM_STATIONS) */
    uint64_t ghost_counts[STA_MIRROR_MAX_COUNT + 1]; /* points per label, while generating */
} synth_room;

/* Builds the room for `point_count` points. */
sta_status sta_room_init(synth_room *room, uint64_t point_count, sta_error *err);

void sta_room_release(synth_room *room);

/* Nearest surface (mirrors are opaque from behind, and reflect from the front only
 * through sta_room_pulse). */
bool sta_room_raycast(const synth_room *room, const double origin[3], const double dir[3],
                      double min_t, double max_t, double *out_t, double out_normal[3],
                      int *out_surface);

/* Station of pulse number `ray`. */
int sta_room_station_of(const synth_room *room, uint64_t ray);

#endif
