/* SPDX-License-Identifier: MIT
 * The two ghost models of docs/MIRRORS.md: from the scanner's position, and the
 * outline extruded along every view ray up to the largest incidence. */
#include <math.h>

#include "mirror/mirror_set.h"

#define PI 3.14159265358979323846

uint8_t sta_mirror_ghost_from_scanner(const sta_mirror_set *set, const double scanner[3],
                                      const double p[3])
{
    for (size_t k = 0; k < set->count; k++) {
        if (sta_mirror_segment_crosses(&set->mirrors[k], scanner, p, set->behind_m)) {
            return (uint8_t)(k + 1);
        }
    }
    return 0;
}

uint8_t sta_mirror_ghost_of(const sta_mirror_set *set, uint16_t point_source_id, const double p[3])
{
    // A linear search: a scan has a handful of stations (at most STA_MIRROR_MAX_STATIONS).
    for (size_t i = 0; i < set->station_count; i++) {
        if (set->stations[i].point_source_id == point_source_id) {
            return sta_mirror_ghost_from_scanner(set, set->stations[i].position, p);
        }
    }
    return sta_mirror_ghost_in_volume(set, p);
}

uint8_t sta_mirror_ghost_in_volume(const sta_mirror_set *set, const double p[3])
{
    double spread = tan(set->max_incidence_deg * PI / 180.0);
    for (size_t k = 0; k < set->count; k++) {
        const sta_mirror *m = &set->mirrors[k];
        double depth = -sta_mirror_signed_distance(m, p);
        if (!(depth > set->behind_m)) {
            continue;
        }
        double uv[2];
        sta_mirror_project(m, p, uv);
        if (sta_mirror_distance_uv(m, uv) <= depth * spread) {
            return (uint8_t)(k + 1);
        }
    }
    return 0;
}
