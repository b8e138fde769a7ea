/* SPDX-License-Identifier: MIT
 * The output's integer grid when inputs use different scales or offsets, and the
 * mapping of each input's integers onto it.
 */
#ifndef STA_PREPROCESS_OUTPUT_GRID_H
#define STA_PREPROCESS_OUTPUT_GRID_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "core/point.h"
#include "core/status.h"
#include "io/cloud.h"

/* Largest k tried when looking for an output step s_min / k on which every input
 * lies exactly (scales 0.01 and 0.025 meet on 0.005 = 0.01 / 2). */
#define STA_OUTPUT_GRID_MAX_DIVISOR 16

/* How one input's integers reach the output grid, per axis: exactly as
 * out = in * ratio + delta, or (not exact) by rounding the real coordinate. */
typedef struct sta_regrid {
    bool is_exact[3];
    int64_t ratio[3]; /* input scale / output scale (exact axes) */
    int64_t delta[3]; /* (input offset - output offset) / output scale (exact axes) */
} sta_regrid;

/* Chooses the output grid for inputs with different grids (`infos`, `count` >= 1)
 * and fills `out_maps` (one per input). Per axis: the largest step s_min / k
 * (k <= STA_OUTPUT_GRID_MAX_DIVISOR, s_min the finest input scale) on which every
 * input's scale and offset fall on whole steps (lossless); the first input's offset,
 * moved by whole steps to the middle of the declared bounds when they would not fit
 * int32 from there; a coarser step (doubled) only when the declared extent does not
 * fit 2^32 steps. Warns, naming the input and axis, for each input that cannot be
 * kept exactly. */
void sta_output_grid_choose(const sta_cloud_info *const *infos, size_t count, sta_grid *out_grid,
                            sta_regrid *out_maps);

/* Moves `point` from input grid `in` to `out` with `map`. Returns false when a
 * coordinate does not fit int32. */
bool sta_output_grid_apply(const sta_regrid *map, const sta_grid *in, const sta_grid *out,
                           sta_point *point);

#endif
