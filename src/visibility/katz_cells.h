/* SPDX-License-Identifier: MIT
 * The live Katz mode's input: of a subsample of the drawn points, the nearest to the
 * camera in each cell of a square screen grid, so that the hull gets what the offline
 * reference gets (one point per pixel of a depth buffer), at a coarser pitch: an even
 * angular spacing, the one Katz's radius rule (sta_katz_view_radius) is made for. The
 * cell size is chosen so that about `cap` cells hold a point. No GL; one thread.
 * docs/KATZ.md, "Live mode".
 */
#ifndef STA_VISIBILITY_KATZ_CELLS_H
#define STA_VISIBILITY_KATZ_CELLS_H

#include <stddef.h>
#include <stdint.h>

#include "core/camera.h"
#include "core/status.h"

/* Scratch kept between calls, and what the last call chose. Zero-initialise. */
typedef struct sta_katz_cells {
    float *screen; /* 3 per candidate: x, y pixels and depth */
    int32_t *best; /* per cell: the nearest candidate, -1 none */
    size_t screen_capacity, cell_capacity;
    double cell_px; /* the last call's cell side, pixels (>= 1) */
    size_t in_view; /* the last call's candidates inside the view */
} sta_katz_cells;

/* Keeps in `points` / `tags` (count entries, positions relative to `origin`, metres) the
 * nearest point of each occupied cell, at most `cap` (> 0), and returns how many; points
 * behind the near plane or outside the view are dropped. STA_ERR_NOMEM: nothing kept. */
sta_status sta_katz_cells_select(sta_katz_cells *cells, const sta_camera *camera,
                                 const double origin[3], size_t cap, float (*points)[3],
                                 uint64_t *tags, size_t *inout_count, sta_error *err);

/* Frees the scratch; a zeroed struct is a no-op. */
void sta_katz_cells_release(sta_katz_cells *cells);

#endif
