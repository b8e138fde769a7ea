/* SPDX-License-Identifier: MIT
 * Phase 1 of the conversion: open every input, check it, and decide the output's
 * integer grid and attribute layout.
 */
#ifndef STA_PREPROCESS_INPUTS_H
#define STA_PREPROCESS_INPUTS_H

#include <stdbool.h>
#include <stdint.h>

#include "io/cloud.h"
#include "mirror/mirror_set.h"
#include "output_grid.h"
#include "record.h"

typedef struct sta_input_set {
    sta_cloud_reader **readers; /* one per input, open */
    const char *const *paths;   /* borrowed from the caller, one per input */
    bool salvage;               /* inputs were opened with salvage_truncated */
    size_t count;
    uint64_t point_count;               /* sum over inputs */
    sta_grid grid;                      /* the output grid */
    bool is_regridded;                  /* some input's grid differs from the output grid */
    sta_regrid *regrids;                /* one per input when is_regridded, else NULL */
    uint32_t attributes;                /* union of the inputs' attributes */
    size_t extra_size;                  /* extra bytes kept per point (0 unless all agree) */
    const sta_cloud_info *extra_source; /* input whose extra dims describe them */
    sta_record_layout layout;           /* packed record for the temporary files */
    const sta_mirror_set *mirrors;      /* classify ghosts into sta_point.mirror, or NULL */
    int64_t header_min[3];              /* declared bounds on the output grid (a guess only) */
    int64_t header_max[3];
} sta_input_set;

/* Opens and validates every path. `keep_extra` keeps extra bytes when every input
 * has the same extra-bytes layout (else a warning drops them). */
sta_status sta_inputs_open(const char *const *paths, size_t count, bool salvage, bool keep_extra,
                           sta_input_set *out_set, sta_error *err);

/* Closes every reader and frees the set; a zeroed set is a no-op. */
void sta_inputs_close(sta_input_set *set);

/* Moves a point of input `input` from its grid to the output grid (exact when the
 * grids agree). Returns false when the result does not fit int32 (an error). */
bool sta_inputs_to_output(const sta_input_set *set, size_t input, sta_point *point);

#endif
