/* SPDX-License-Identifier: MIT
 * Choosing a common integer grid for inputs on different grids (see output_grid.h).
 *
 * Scales such as 0.01 are not exact in binary, so "a whole number of steps" is
 * tested with a relative tolerance far below any real survey's precision
 * (STEP_TOLERANCE); the mapping itself is then done in integers, exactly.
 */
#include "output_grid.h"

#include <math.h>
#include <string.h>

#include "core/log.h"

enum {
    MAX_RATIO = 1 << 20, /* an input step of more than 2^20 output steps is not "exact" */
};
static const double STEP_TOLERANCE = 1e-6; /* in output steps */
static const char axis_names[3] = { 'x', 'y', 'z' };

// `value` as a whole number of steps, or false.
static bool whole_steps(double value, int64_t *out)
{
    double r = nearbyint(value);
    if (!(fabs(value - r) <= STEP_TOLERANCE) || fabs(r) > 9e15) {
        return false;
    }
    *out = (int64_t)r;
    return true;
}

static bool map_axis(const sta_grid *in, double scale, double offset, int a, sta_regrid *map)
{
    int64_t ratio = 0, delta = 0;
    bool exact = whole_steps(in->scale[a] / scale, &ratio) && ratio >= 1 && ratio <= MAX_RATIO &&
                 whole_steps((in->offset[a] - offset) / scale, &delta);
    map->is_exact[a] = exact;
    map->ratio[a] = exact ? ratio : 0;
    map->delta[a] = exact ? delta : 0;
    return exact;
}

// Declared extent of all inputs on axis `a` (real units); false when none is usable.
static bool declared_extent(const sta_cloud_info *const *infos, size_t count, int a, double *lo,
                            double *hi)
{
    *lo = HUGE_VAL;
    *hi = -HUGE_VAL;
    for (size_t i = 0; i < count; i++) {
        double l = infos[i]->header_min[a], h = infos[i]->header_max[a];
        if (infos[i]->point_count == 0 || !isfinite(l) || !isfinite(h) || l > h) {
            continue; // nonsense bounds: the counting pass finds real ones
        }
        *lo = fmin(*lo, l);
        *hi = fmax(*hi, h);
    }
    return *lo <= *hi;
}

void sta_output_grid_choose(const sta_cloud_info *const *infos, size_t count, sta_grid *out_grid,
                            sta_regrid *out_maps)
{
    const sta_grid *first = &infos[0]->grid;
    for (int a = 0; a < 3; a++) {
        double finest = first->scale[a];
        for (size_t i = 1; i < count; i++) {
            finest = fmin(finest, infos[i]->grid.scale[a]);
        }
        // The largest common step on which every input is exact, else the finest scale.
        double scale = finest;
        for (int k = 1; k <= STA_OUTPUT_GRID_MAX_DIVISOR; k++) {
            bool all = true;
            for (size_t i = 0; i < count && all; i++) {
                all = map_axis(&infos[i]->grid, finest / k, first->offset[a], a, &out_maps[i]);
            }
            if (all) {
                scale = finest / k;
                break;
            }
        }
        double offset = first->offset[a];
        double lo, hi;
        if (declared_extent(infos, count, a, &lo, &hi)) {
            // Coarser only when the extent cannot fit 2^32 steps at all (lossy).
            while ((hi - lo) / scale > 4.0e9) {
                scale *= 2.0;
            }
            // Whole steps from the first offset keep the exact mappings exact.
            if ((lo - offset) / scale < -2.0e9 || (hi - offset) / scale > 2.0e9) {
                offset += nearbyint(((lo + hi) / 2 - offset) / scale) * scale;
            }
        }
        out_grid->scale[a] = scale;
        out_grid->offset[a] = offset;
        for (size_t i = 0; i < count; i++) {
            if (!map_axis(&infos[i]->grid, scale, offset, a, &out_maps[i])) {
                sta_log_warn("%s: %c scale %g / offset %.9g is not a whole number of output "
                             "steps (scale %g, offset %.9g): its %c coordinates are rounded, by "
                             "at most %g",
                             infos[i]->path, axis_names[a], infos[i]->grid.scale[a],
                             infos[i]->grid.offset[a], scale, offset, axis_names[a], scale / 2);
            }
        }
    }
}

bool sta_output_grid_apply(const sta_regrid *map, const sta_grid *in, const sta_grid *out,
                           sta_point *point)
{
    int32_t *xyz[3] = { &point->X, &point->Y, &point->Z };
    for (int a = 0; a < 3; a++) {
        int64_t v;
        if (map->is_exact[a]) {
            v = (int64_t)*xyz[a] * map->ratio[a] + map->delta[a];
        } else {
            // The offsets' difference first: it is where precision would be lost.
            double real = (in->offset[a] - out->offset[a]) + (double)*xyz[a] * in->scale[a];
            double steps = nearbyint(real / out->scale[a]);
            if (!(fabs(steps) < 4e9)) {
                return false;
            }
            v = (int64_t)steps;
        }
        if (v < INT32_MIN || v > INT32_MAX) {
            return false;
        }
        *xyz[a] = (int32_t)v;
    }
    return true;
}
