/* SPDX-License-Identifier: MIT
 * Normals and splat radii of one chunk's points from cell moments only (the default of
 * strata-convert --normals; docs/CONVERTER.md "Normals").
 *
 * Design: no neighbour search. The chunk's and halo's points are sorted into the Morton
 * order of their cells (cell_order.h) and summed into the cubic cells of a power-of-two
 * grid aligned to the scene's corner (cell_moments.h: exact integer moments), from a base
 * level the whole scene shares (cells of 2-4 mean spacings), each coarser level from the
 * finer one, at most STA_MOMENTS_LEVELS_ABOVE_BASE levels up. A point's box at level L is
 * the 2 x 2 x 2 cells around its nearest grid vertex of that level (it lies in the box's
 * middle half along each axis); the box's centred moments, surface variation and plane
 * fit are computed once and shared by every point that takes it. The scale is the data's:
 * a point becomes a candidate at the finest level whose next-level cell holding it has at
 * least K points, then moves up while the next level's box is flatter (less surface
 * variation, Pauly et al.'s rule) and its normal within 20 degrees of this level's, at
 * most 2 levels (a box that is not flat compares its algebraic sphere's residual,
 * sphere_fit.h); a box whose plane is nearly linear, edge-on to the scanner or
 * degenerate takes the next level once. The default method first offers the points whose
 * base box is rough (a curb's step, a car's edge) the boxes of half-size cells (an
 * adaptive fine level, built only around them). The normal is the gradient at the point
 * of its nearest box's algebraic sphere where the box is not flat and the sphere fits it
 * clearly better than the plane (a leaf cluster), else the trilinear blend (by the
 * point's place in its cell) of the plane normals (normal_fit.h) of the boxes of its
 * cell's 8 vertices, leaving out those over 30 degrees from its nearest box's; the radius
 * 1.15 times the expected mean distance to the STA_NORMALS_RADIUS_K nearest of uniform
 * points at the density of the nearest box's points on its plane. Every sum is of
 * integers or in a fixed order, and every level and cell is the scene's, so the results
 * do not depend on the chunking or the threads (the halo reaches as far as the widest
 * boxes: sta_moment_normals_reach).
 */
#ifndef STA_PREPROCESS_MOMENT_NORMALS_H
#define STA_PREPROCESS_MOMENT_NORMALS_H

#include <stddef.h>
#include <stdint.h>

#include "core/status.h"
#include "knn_normals.h"
#include "record.h"

/* The widest boxes: cells this many levels above the base level, at most (moments-fine;
 * the default method: sta_moment_normals_levels_above). */
#define STA_MOMENTS_LEVELS_ABOVE_BASE 3

/* Computes a normal and radius for each of the `count` records (layout with
 * STA_ATTR_SPLAT) from them and the `halo_count` halo positions (3 x int32 each) by
 * chunk->method, and stores them in the records' SPLAT bytes. Adds to `stats`. A set the
 * cells cannot address (over STA_MOMENTS_MAX_POINTS points, or wider than 2^21 cells of
 * the coarsest level) takes the kNN method. */
sta_status sta_normals_compute(const sta_normals_chunk *chunk, const sta_record_layout *layout,
                               uint8_t *records, size_t count, const int32_t *halo,
                               size_t halo_count, sta_normals_stats *stats, sta_error *err);

/* The base level of `method` (a moments one) for a scene of `points` points whose bounds
 * span `extent` metres an axis, on a grid of `unit` metres (the coarsest axis): cells of
 * 2-4 (STA_NORMALS_MOMENTS_FINE: 1-2) times the spacing of points spread over the scene's
 * two widest extents. The same for every chunk of a scene. */
int sta_moment_normals_base_level(sta_normals_method method, uint64_t points,
                                  const double extent[3], double unit);

/* The points a point's cell of the next level must hold before the point takes a box at
 * a level (the scale's start, docs/CONVERTER.md "The moments method"), for `--knn` k:
 * k with moments-fine; a tenth of it, at least 1, with the default method. */
int sta_moment_normals_need(sta_normals_method method, int k);

/* The levels above the base level the boxes of `method` (a moments one) reach. */
int sta_moment_normals_levels_above(sta_normals_method method);

/* How far (metres, along any axis) the widest box of a point reaches from it, by `method`
 * (a moments one): the halo margin of the moments methods. */
double sta_moment_normals_reach(sta_normals_method method, int base_level, double unit);

/* Bytes of scratch memory sta_normals_compute needs for `points` points (own + halo). */
size_t sta_normals_memory_bytes(sta_normals_method method, size_t points);

#endif
