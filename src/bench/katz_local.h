/* SPDX-License-Identifier: MIT
 * Katz's operator with R chosen per region of a view (strata-bench --katz-local): one
 * hull with the view's R (sta_katz_view_radius at the pixel's angle) and one with R /
 * STA_KATZ_LOCAL_DIVISOR; a point takes the second's flag where the input is sparse
 * around it (fewer than STA_KATZ_LOCAL_SPARSE of the pixels within STA_KATZ_LOCAL_WINDOW_PX
 * hold a point). With one R, the tolerance R * a^2 grows with the square of the local
 * spacing, so points behind holes in a sparse surface stay on the hull (docs/KATZ.md,
 * "Where the last 0.002 at 1080p goes"). CPU only, no GL.
 */
#ifndef STA_BENCH_KATZ_LOCAL_H
#define STA_BENCH_KATZ_LOCAL_H

#include <stddef.h>
#include <stdint.h>

#include "core/status.h"
#include "visibility/katz_hpr.h"

/* Half the side of the square window the occupancy is counted in, pixels (7 x 7). */
#define STA_KATZ_LOCAL_WINDOW_PX 3
/* Occupancy below which a point's region counts as sparse (spacing above ~2.2 pixels). */
#define STA_KATZ_LOCAL_SPARSE    0.2
/* R of the sparse regions: the view's R over this (the rule's R for a 2-pixel spacing). */
#define STA_KATZ_LOCAL_DIVISOR   4.0

/* Flags of `count` points (relative to the viewpoint at the origin) drawn in `pixel`
 * (y * width + x, one point per pixel of a width x height view) into out_visible;
 * params->radius_m is the view's R (> 0). out_sparse: how many points took the small
 * R's flag; stats: of the view's R hull, with hull_ms and total_ms the sum of both.
 * Errors: those of sta_katz_visible, STA_ERR_ARG for a pixel outside the view,
 * STA_ERR_NOMEM. */
sta_status sta_katz_local_visible(const double (*relative)[3], const uint32_t *pixel, size_t count,
                                  int width, int height, const sta_katz_params *params,
                                  uint8_t *out_visible, size_t *out_sparse, sta_katz_stats *stats,
                                  sta_error *err);

#endif
