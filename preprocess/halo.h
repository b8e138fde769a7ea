/* SPDX-License-Identifier: MIT
 * The halo of each chunk for strata-convert --normals: the positions of the points of
 * neighbouring chunks that lie within a margin of the chunk's box, so that a point
 * near a chunk border finds its nearest neighbours on both sides.
 *
 * Design: one extra pass over the distributed runs (after refine, before index): every
 * chunk's run is read (not discarded) and each point near another chunk's grown box is
 * appended, as 3 x int32, to that chunk's list in a second compressed store. Lists read
 * back in (source chunk, block) order whatever the threads, so the output stays
 * deterministic. With the moments method (the default) the margin is the reach of the
 * widest box a point may take (sta_moment_normals_reach), the same for every chunk. With
 * the kNN method the margin of a chunk is a multiple of its estimated point spacing
 * (box edge / sqrt(points): surfaces) times sqrt(K'), K' the widest neighbourhood a
 * point may be widened to (sta_normals_widest_k: 6 K, at most 64), at most its box edge; a chunk
 * receives from a neighbour the points within the smaller of their two margins (a
 * sparse chunk next to a dense one needs only a thin slice of it: its border points
 * find their K nearest there). Neighbourhoods that may reach beyond what was received
 * are counted (sta_normals_stats.beyond_halo) and reported.
 */
#ifndef STA_PREPROCESS_HALO_H
#define STA_PREPROCESS_HALO_H

#include <stdatomic.h>

#include "distribute.h"
#include "knn_normals.h"
#include "record.h"
#include "temp_runs.h"
#include "trajectory.h"

/* Halo margin in spacings per sqrt(K'): K' = 60 (K = 10 widened) gives ~23 spacings,
 * the 60th neighbour lies at ~4.4 on a surface. */
#define STA_HALO_SPACINGS_PER_SQRT_K 3.0

/* The chunk's box, the scene's bounds and the margin as sta_normals_compute wants
 * them: the margin is the smallest that any face received (up axis and trajectory
 * are left to the caller). */
void sta_halo_chunk_frame(const sta_chunk_plan *plan, const sta_grid *grid, size_t chunk, int k,
                          sta_normals_method method, sta_normals_chunk *out);

/* Fills `halo` (record size 12, one list per chunk, initialised by the caller) from the
 * chunk runs of `runs` (or, when `in_memory` is not NULL, from its array of each chunk's
 * records: no run is read), on `threads` threads. When `trajectory` is not NULL (and the
 * records have GPS time) every point is also added to it (trajectory.h) and
 * sta_trajectory_finish decides whether it is usable. `cancel` may be NULL. */
sta_status sta_halo_collect(const sta_chunk_plan *plan, const sta_grid *grid,
                            const sta_record_layout *layout, sta_temp_runs *runs,
                            uint8_t *const *in_memory, sta_temp_runs *halo,
                            sta_trajectory *trajectory, int k, sta_normals_method method,
                            int threads, atomic_bool *cancel, sta_error *err);

#endif
