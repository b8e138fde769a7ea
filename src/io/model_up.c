/* SPDX-License-Identifier: MIT
 * The up axis of a model from its extents. */
#include "io/model_up.h"

#include <math.h>
#include <stdio.h>

bool sta_model_is_y_up(double ex, double ey, double ez, const char *kind, char *why,
                       size_t why_size)
{
    char scratch[8];
    if (!why) {
        why = scratch;
        why_size = sizeof(scratch);
    }
    double horizontal = fmax(ex, ey);
    if (ez >= horizontal) {
        snprintf(why, why_size, "%s model, z its largest extent (%.3g x %.3g x %.3g): +Z up", kind,
                 ex, ey, ez);
        return false;
    }
    if (ez < STA_MODEL_FLAT_RATIO * horizontal) {
        snprintf(why, why_size, "%s data flat in z (%.3g x %.3g x %.3g, map-like): +Z up", kind, ex,
                 ey, ez);
        return false;
    }
    snprintf(why, why_size, "%s model (%.3g x %.3g x %.3g): +Y up, the %s models' convention", kind,
             ex, ey, ez, kind);
    return true;
}
