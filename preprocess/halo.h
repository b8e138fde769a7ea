/* SPDX-License-Identifier: MIT
 * The halo of each chunk for strata-convert --normals: the positions of the points of
 * neighbouring chunks that lie within a margin of the chunk's box, so that a point
 * near a chunk border finds its nearest neighbours on both sides.
 *
 * Design: one extra pass over the distributed runs (after refine, before index): every
 * chunk's run is read (not discarded) and each point near another chunk's grown box is
 * appended, as 3 x int32, to that chunk's list in a second compressed store. Lists read
 * back in (source chunk, block) order whatever the threads, so the output stays
 * deterministic. The margin of a chunk is a multiple of its estimated point spacing
 * (box edge / sqrt(points): surfaces), times sqrt(K); neighbourhoods that still reach
 * beyond it are counted (sta_normals_stats.beyond_halo) and reported.
 */
#ifndef STA_PREPROCESS_HALO_H
#define STA_PREPROCESS_HALO_H

#include <stdatomic.h>

#include "distribute.h"
#include "knn_normals.h"
#include "record.h"
#include "temp_runs.h"
#include "trajectory.h"

/* Halo margin in spacings per sqrt(K): K = 10 gives ~9.5 spacings, the 10th neighbour
 * lies at ~1.8 on a surface. */
#define STA_HALO_SPACINGS_PER_SQRT_K 3.0

/* The chunk's box and margin as sta_normals_compute wants them (k, up axis and scene
 * centre are left to the caller). */
void sta_halo_chunk_frame(const sta_chunk_plan *plan, const sta_grid *grid, size_t chunk, int k,
                          sta_normals_chunk *out);

/* Fills `halo` (record size 12, one list per chunk, initialised by the caller) from the
 * chunk runs of `runs`, on `threads` threads. When `trajectory` is not NULL (and the
 * records have GPS time) every point is also added to it (trajectory.h) and
 * sta_trajectory_finish decides whether it is usable. `cancel` may be NULL. */
sta_status sta_halo_collect(const sta_chunk_plan *plan, const sta_grid *grid,
                            const sta_record_layout *layout, sta_temp_runs *runs,
                            sta_temp_runs *halo, sta_trajectory *trajectory, int k, int threads,
                            atomic_bool *cancel, sta_error *err);

#endif
