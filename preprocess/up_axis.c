/* SPDX-License-Identifier: MIT
 * The up axis of the converter's inputs: from the source format, checked against the
 * bounds for PLY models. */
#include "up_axis.h"

#include <math.h>
#include <stdio.h>

#include "format/strata.h"
#include "io/model_up.h"

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
    bool y_up =
        sta_model_is_y_up(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2], "PLY", why, why_size);
    return y_up ? STA_STRATA_UP_Y : STA_STRATA_UP_Z;
}
