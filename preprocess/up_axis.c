/* SPDX-License-Identifier: MIT
 * The up axis of the converter's inputs: from the source format, checked against the
 * bounds for PLY models. */
#include "up_axis.h"

#include <math.h>
#include <stdio.h>

#include "format/strata.h"

int sta_inputs_up_axis(const sta_input_set *set, char *why, size_t why_size)
{
    char scratch[8];
    if (!why) {
        why = scratch;
        why_size = sizeof(scratch);
    }
    double lo[3] = { INFINITY, INFINITY, INFINITY }, hi[3] = { -INFINITY, -INFINITY, -INFINITY };
    for (size_t i = 0; i < set->count; i++) {
        const sta_cloud_info *info = sta_cloud_reader_info(set->readers[i]);
        if (info->kind != STA_CLOUD_PLY) {
            snprintf(why, why_size, "%s is LAS: +Z up", info->path);
            return STA_STRATA_UP_Z;
        }
        for (int a = 0; a < 3; a++) {
            lo[a] = fmin(lo[a], info->header_min[a]);
            hi[a] = fmax(hi[a], info->header_max[a]);
        }
    }
    if (set->count == 0) {
        snprintf(why, why_size, "no inputs: +Z up");
        return STA_STRATA_UP_Z;
    }
    double ex = hi[0] - lo[0], ey = hi[1] - lo[1], ez = hi[2] - lo[2];
    double horizontal = fmax(ex, ey);
    if (ez >= horizontal) {
        snprintf(why, why_size, "PLY model, z its largest extent (%.3g x %.3g x %.3g): +Z up", ex,
                 ey, ez);
        return STA_STRATA_UP_Z;
    }
    if (ez < STA_UP_AXIS_FLAT_RATIO * horizontal) {
        snprintf(why, why_size, "PLY data flat in z (%.3g x %.3g x %.3g, map-like): +Z up", ex, ey,
                 ez);
        return STA_STRATA_UP_Z;
    }
    snprintf(why, why_size, "PLY model (%.3g x %.3g x %.3g): +Y up, the PLY models' convention", ex,
             ey, ez);
    return STA_STRATA_UP_Y;
}
