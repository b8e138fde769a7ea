/* SPDX-License-Identifier: MIT
 * The points of a set in the Morton (Z) order of their cells of one power-of-two level
 * (strata-convert --normals, moment_normals.c): the points of any cell of that level or a
 * coarser one come together, so a pass in this order meets each cell once and its
 * neighbours soon after.
 *
 * Design: a key per point (its cell's coordinates from the set's lowest cell, bits
 * interleaved x, y, z) sorted by a stable radix sort: one pass by the keys' top 11 bits
 * (the only pass over all points, which misses the caches), then each of its buckets by
 * the bits below, 8 a pass (or by insertion where it holds few), in cache. Ties keep the
 * input order, so the order is a function of the points alone.
 */
#ifndef STA_PREPROCESS_CELL_ORDER_H
#define STA_PREPROCESS_CELL_ORDER_H

#include <stddef.h>
#include <stdint.h>

#include "core/status.h"

/* Cells an axis the keys address (3 x 21 bits in a 64-bit key). */
#define STA_CELL_ORDER_AXIS_BITS 21

/* Fills order[n] with the indices 0..n-1 of the points `grid` (grid units) sorted by
 * their cells of edge 2^level units counted from `lo` (at or below every point). Fails
 * (STA_ERR_ARG) when the points span more than 2^STA_CELL_ORDER_AXIS_BITS cells an axis
 * or n does not fit 32 bits; STA_ERR_NOMEM. */
sta_status sta_cell_order(const int32_t (*grid)[3], size_t n, const int32_t lo[3], int level,
                          uint32_t *order, sta_error *err);

/* The key of a cell (coordinates from `lo` in cells of the order's level, each below
 * 2^STA_CELL_ORDER_AXIS_BITS): the cells of any coarser aligned cell have consecutive
 * keys. */
uint64_t sta_cell_order_key(const int64_t cell[3]);

/* The first of the n points `sorted` (in the order sta_cell_order gave for lo and level)
 * whose cell's key is at least `key` (n when none), searched outwards from index `hint`
 * first (a few steps where the answer lies near it), then by bisection. */
size_t sta_cell_order_lower_near(const int32_t (*sorted)[3], size_t n, const int32_t lo[3],
                                 int level, uint64_t key, size_t hint);

#endif
