/* SPDX-License-Identifier: MIT
 * The full moment tensors, up to the fourth order, of the points of grid cells, and their
 * sums over the 2 x 2 x 2 cells around a grid vertex (strata-convert --normals, moments
 * method: the quadric fit of the adaptive fine level's rough boxes, quadric_fit.h).
 *
 * Design: per cell the 35 sums of d^a over its points, one for each monomial
 * x^i y^j z^k with i + j + k <= 4 (d the offset from the cell's corner, grid units), in
 * 64-bit integers modulo 2^64: order-free, exact wherever the true sum fits (a box whose
 * n (2 edge)^4 stays under 2^62; quadric_fit.c checks it), moved to a box's corner
 * exactly by the binomial expansion. Only a few cells need them (those around rough
 * points, about 5 % of a street's points), so they live in their own table, filled from
 * the points of the cells marked as wanted, beside cell_moments.h's lower sums.
 */
#ifndef STA_PREPROCESS_CELL_TENSORS_H
#define STA_PREPROCESS_CELL_TENSORS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "cell_moments.h"
#include "core/status.h"

/* Monomials of degree 0..4 in three variables. */
#define STA_TENSOR_TERMS 35

/* The exponents (x, y, z) of each term, by degree then lexicographically descending. */
extern const uint8_t sta_tensor_exponent[STA_TENSOR_TERMS][3];

/* Sums of the monomials of d over a set of points, by sta_tensor_exponent's terms. */
typedef struct sta_tensor_sums {
    uint64_t s[STA_TENSOR_TERMS];
} sta_tensor_sums;

/* Adds the monomials of one point's offset d (grid units, >= 0) to sums, modulo 2^64. */
void sta_tensor_sums_add(sta_tensor_sums *sums, const uint64_t d[3]);

typedef struct sta_cell_tensors {
    int level;             /* cells are 2^level grid units wide */
    int64_t origin[3];     /* the scene's corner, grid units */
    int64_t base[3];       /* cell coordinates below which no cell lies (packed keys) */
    size_t capacity, used; /* slots (a power of two), cells */
    uint64_t *keys;        /* 0: empty slot, else packed coordinates + 1 */
    uint32_t *cell;        /* per slot: its cell's place in `sums` */
    sta_tensor_sums *sums; /* per cell, dense (the table is at most half full) */
    size_t sums_capacity;  /* cells `sums` holds */
    int8_t index[5][5][5]; /* the term of x^i y^j z^k (i + j + k <= 4) */
} sta_cell_tensors;

/* An empty set of cells of level `level` for points inside the box lo..hi (grid units, at
 * or above the scene corner `origin`), as sta_cell_moments_init. Release with
 * sta_cell_tensors_release. */
sta_status sta_cell_tensors_init(sta_cell_tensors *t, int level, const int64_t origin[3],
                                 const int32_t lo[3], const int32_t hi[3], sta_error *err);

/* Creates cell `cell` (coordinates from the scene corner) empty: a cell wanted. False when
 * out of memory. */
bool sta_cell_tensors_mark(sta_cell_tensors *t, const int64_t cell[3]);

/* Adds the n points `grid` (grid units) to their cells: only to cells that exist (marked);
 * the others' points are left out. */
void sta_cell_tensors_add(sta_cell_tensors *t, const int32_t (*grid)[3], size_t n);

/* As sta_cell_tensors_add for the points of `count` sets, each sorted by sta_cell_order
 * at the set's level from `corner` (aligned to 2^level units from the scene corner), but
 * visiting only the marked cells' runs of points (the marked cells in the order's key
 * order, each run found by sta_cell_order_lower_near from where the last one ended): the
 * same sums (exact, so in any order). STA_ERR_NOMEM. */
sta_status sta_cell_tensors_add_sorted(sta_cell_tensors *t, const int32_t (*const *sets)[3],
                                       const size_t *counts, int count, const int32_t corner[3],
                                       sta_error *err);
/* The sums of the 2 x 2 x 2 cells around grid vertex `vertex` (cell coordinates from the
 * scene corner: the cells from vertex - 1 to vertex), as offsets from their block's
 * corner; cells not in the set are empty. */
void sta_cell_tensors_vertex(const sta_cell_tensors *t, const int64_t vertex[3],
                             sta_tensor_sums *out);

void sta_cell_tensors_release(sta_cell_tensors *t);

#endif
