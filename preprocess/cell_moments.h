/* SPDX-License-Identifier: MIT
 * Exact moments (count, sum of offsets, sum of their products) of the points in the
 * cubic cells of one level of a power-of-two grid, and the moments of blocks of 2 x 2 x 2
 * or 3 x 3 x 3 such cells (the wide plane fits of strata-convert --normals).
 *
 * Design: level L's cells are 2^L grid units wide, aligned to the scene's corner, so a
 * cell and its points are the same whatever chunk computes it (given the chunk's halo).
 * A cell keeps its sums in int64 over its points' offsets from its own corner; a block
 * translates them to its corner exactly (integers again), so a block's moments are the
 * same bits in any order the points came in. Cells are hashed (open addressing) by their
 * coordinates relative to the lowest cell of the set, 21 bits an axis.
 */
#ifndef STA_PREPROCESS_CELL_MOMENTS_H
#define STA_PREPROCESS_CELL_MOMENTS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "core/status.h"

/* Coarsest level and most points: 4 x 2^16 units a block keeps s2 of 2^26 points in int64. */
#define STA_MOMENTS_MAX_LEVEL  16
#define STA_MOMENTS_MAX_POINTS ((size_t)1 << 26)
#define STA_MOMENTS_AXIS_BITS  21 /* cell coordinates an axis, relative to the set's lowest */

/* The sums of a set of points' offsets d from a corner: n, sum d, sum d d^T (xx xy xz yy
 * yz zz), in grid units; and the higher sums of the algebraic sphere fit (sphere_fit.h),
 * sum d |d|^2 and sum |d|^4, modulo 2^64 (two's complement): they equal the true sums
 * where these fit an int64 (n |d|^4 < 2^63, sta_sphere_sums_exact), whatever overflowed
 * on the way. */
typedef struct sta_moment_sums {
    int64_t n;
    int64_t s1[3];
    int64_t s2[6];
    uint64_t s3[3];
    uint64_t s4;
} sta_moment_sums;

/* A cell's own sums: n, s1, s2 of sta_moment_sums (kept apart from the higher ones: a
 * set without them stays 80 bytes a cell). */
typedef struct sta_cell_sums {
    int64_t n;
    int64_t s1[3];
    int64_t s2[6];
} sta_cell_sums;

/* A cell's higher sums: s3, s4 of sta_moment_sums. */
typedef struct sta_higher_sums {
    uint64_t s3[3];
    uint64_t s4;
} sta_higher_sums;

/* Adds the higher sums h of a cell whose own sums are c, moved by o grid units (d + o: to
 * a corner o below the cell's), to dst, modulo 2^64 like the sums themselves. */
void sta_higher_sums_add_moved(sta_higher_sums *dst, const sta_cell_sums *c,
                               const sta_higher_sums *h, const int64_t o[3]);

/* One level's cells. */
typedef struct sta_cell_moments {
    int level;             /* cells are 2^level grid units wide */
    bool higher;           /* also the sphere fit's sums s3, s4 (else they stay 0); false
                              after sta_cell_moments_init: set it before adding */
    int64_t origin[3];     /* the scene's corner, grid units */
    int64_t base[3];       /* the lowest cell of the set, cell coordinates */
    size_t capacity, used; /* slots (a power of two), cells */
    uint64_t *keys;        /* 0: empty slot, else packed coordinates + 1 */
    sta_cell_sums *sums;   /* per slot (NULL in a set of marks: sta_cell_moments_init_marks) */
    sta_higher_sums *high; /* per slot, only when `higher` (else NULL) */
} sta_cell_moments;

/* An empty level `level` (0..STA_MOMENTS_MAX_LEVEL) for points inside the box lo..hi
 * (grid units, at or above the scene corner `origin`). Fails (STA_ERR_ARG) when the box
 * spans more cells than STA_MOMENTS_AXIS_BITS hold. Release with
 * sta_cell_moments_release. */
sta_status sta_cell_moments_init(sta_cell_moments *m, int level, const int64_t origin[3],
                                 const int32_t lo[3], const int32_t hi[3], sta_error *err);

/* As sta_cell_moments_init, a set that only records which cells exist: for
 * sta_cell_moments_mark, _has and as `only` of sta_cell_moments_add, never given points (8
 * bytes a slot where the sums take 88: the wanted cells around every rough point of a noisy
 * chunk were its largest table). */
sta_status sta_cell_moments_init_marks(sta_cell_moments *m, int level, const int64_t origin[3],
                                       const int32_t lo[3], const int32_t hi[3], sta_error *err);

/* Room for `cells` cells without growing (the table grows by doubling, rehashing every
 * cell: a set whose size is known roughly starts near it). False when out of memory. */
bool sta_cell_moments_reserve(sta_cell_moments *m, size_t cells);

/* Creates cell `cell` (coordinates from the scene corner) empty: a set of wanted cells.
 * False when out of memory. */
bool sta_cell_moments_mark(sta_cell_moments *m, const int64_t cell[3]);

/* Whether cell `cell` exists. */
bool sta_cell_moments_has(const sta_cell_moments *m, const int64_t cell[3]);

/* The number of points in cell `cell` (0 when it does not exist). */
int64_t sta_cell_moments_count(const sta_cell_moments *m, const int64_t cell[3]);

/* Adds the n points `grid` (grid units, inside the box; at most STA_MOMENTS_MAX_POINTS
 * in all) to their cells, in the order `order` (indices into grid; NULL: 0..n-1; an
 * order that keeps each cell's points together, cell_order.h, looks each cell up once);
 * when `only` is not NULL, only the points whose cell of only's (coarser or equal) level
 * exists there. */
sta_status sta_cell_moments_add(sta_cell_moments *m, const int32_t (*grid)[3], size_t n,
                                const uint32_t *order, const sta_cell_moments *only,
                                sta_error *err);

/* Adds the cells of `fine` to `coarse`, a set one level coarser over the same box (its
 * parents: the sums moved to the parents' corners, exactly). */
sta_status sta_cell_moments_coarsen(const sta_cell_moments *fine, sta_cell_moments *coarse,
                                    sta_error *err);

void sta_cell_moments_release(sta_cell_moments *m);

/* The moments of each of the cells x cells x cells cells from `anchor` (cell coordinates
 * from the scene corner; x fastest, then y, z) into out[cells^3], as offsets from the
 * block's corner (anchor x 2^level + origin); cells beyond the set are empty. */
void sta_cell_moments_block(const sta_cell_moments *m, const int64_t anchor[3], int cells,
                            sta_moment_sums *out);

/* The summed moments of the 2 x 2 x 2 cells around grid vertex `vertex` (cell
 * coordinates from the scene corner: the cells from vertex - 1 to vertex), as offsets from
 * their block's corner: sta_cell_moments_block's 8 cells added up, in one pass. */
void sta_cell_moments_vertex(const sta_cell_moments *m, const int64_t vertex[3],
                             sta_moment_sums *out);

#endif
