/* SPDX-License-Identifier: MIT
 * One level's exact cell moments (cell_moments.h's sums) stored densely, grouped in
 * aligned blocks of 4 x 4 x 4 cells: the levels the moments normals fit their vertex boxes
 * from (moment_normals.c).
 *
 * Design: the cells' sums lie in one array, the cells of a block together and in the
 * Morton order of their place in it; a small open-addressing table maps a block to a
 * 64-bit mask of the cells it holds and the index of its first cell, so a cell is one
 * probe of that table and a popcount, and a vertex box's 8 cells mostly share one block
 * (one probe, neighbouring sums). Points added in the Morton order of their cells
 * (cell_order.h, from a corner aligned to 4 cells) append cells in that order, and so do
 * the parents a coarser level gets from such a set: no hashing of cells, no rehash, no
 * random writes. Cells that come in any other order are kept loose (with their keys) and
 * sorted into blocks when the set is sealed, so every order gives the same set.
 */
#ifndef STA_PREPROCESS_CELL_BLOCKS_H
#define STA_PREPROCESS_CELL_BLOCKS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "cell_moments.h"
#include "core/status.h"

/* One block of 4 x 4 x 4 cells, a slot of the block table. */
typedef struct sta_cell_block {
    uint64_t key;   /* 0: empty slot, else packed block coordinates + 1 */
    uint64_t mask;  /* bit b: the block's cell of Morton index b exists */
    uint32_t first; /* the index of the block's first cell in the sums */
} sta_cell_block;

/* One level's cells. */
typedef struct sta_cell_blocks {
    int level;                  /* cells are 2^level grid units wide */
    bool higher;                /* also the sphere fit's sums s3, s4 (else they stay 0) */
    int64_t origin[3];          /* the scene's corner, grid units */
    int64_t base[3];            /* cell coordinates of the set's first block corner (a
                                   multiple of 4 below the lowest cell minus one) */
    size_t used, cell_capacity; /* cells, room for cells */
    sta_cell_sums *sums;        /* per cell, by block and Morton place in it */
    sta_higher_sums *high;      /* per cell, only when `higher` */
    size_t capacity, blocks;    /* slots (a power of two), blocks */
    sta_cell_block *slots;      /* the block table */
    uint32_t *block_order;      /* the blocks' slots in the order of their cells */
    uint64_t *loose;            /* while cells came out of order: each cell's block key
                                   << 6 | its place; NULL when grouped */
    size_t current;             /* the slot cells are appended to (SIZE_MAX: none) */
} sta_cell_blocks;

/* An empty level `level` (0..STA_MOMENTS_MAX_LEVEL) for points inside the box lo..hi
 * (grid units, at or above the scene corner `origin`), with the higher sums when
 * `higher`. Fails (STA_ERR_ARG) when the box spans more cells than
 * STA_MOMENTS_AXIS_BITS hold. Release with sta_cell_blocks_release. */
sta_status sta_cell_blocks_init(sta_cell_blocks *m, int level, bool higher, const int64_t origin[3],
                                const int32_t lo[3], const int32_t hi[3], sta_error *err);

/* Room for `cells` cells (and a block each) without growing. False when out of memory. */
bool sta_cell_blocks_reserve(sta_cell_blocks *m, size_t cells);

/* Adds the n points `grid` (grid units, inside the box; at most STA_MOMENTS_MAX_POINTS in
 * all) to their cells, in the order `order` (indices into grid; NULL: 0..n-1), and seals
 * the set. Any order gives the same set; the Morton order of the cells (cell_order.h, its
 * corner a multiple of 4 cells from the scene corner) is the fast one. */
sta_status sta_cell_blocks_add(sta_cell_blocks *m, const int32_t (*grid)[3], size_t n,
                               const uint32_t *order, sta_error *err);

/* Adds the cells of `fine` to `coarse`, a set one level coarser over the same box (the
 * sums moved to the parents' corners, exactly), and seals it. */
sta_status sta_cell_blocks_coarsen(const sta_cell_blocks *fine, sta_cell_blocks *coarse,
                                   sta_error *err);

/* Adds the points of the lists a[na] and b[nb] (grid units, inside the box), each in the
 * Morton order of their cells one level up (m->level + 1) counted from `corner` (at or
 * below every point; a multiple of 2 such cells from the scene corner keeps the blocks in
 * order), whose cell one level up `wanted` (a hashed set of that level; NULL: all) holds,
 * and seals the set: a parent's children are summed together and appended in their
 * blocks' order (no sort), whichever list its points are in. */
sta_status sta_cell_blocks_add_children(sta_cell_blocks *m, const int32_t (*a)[3], size_t na,
                                        const int32_t (*b)[3], size_t nb, const int32_t corner[3],
                                        const sta_cell_moments *wanted, sta_error *err);

/* Adds the cells of the hashed set `cells` (same level and scene corner, a box inside
 * m's) to m, and seals it. */
sta_status sta_cell_blocks_add_moments(sta_cell_blocks *m, const sta_cell_moments *cells,
                                       sta_error *err);

void sta_cell_blocks_release(sta_cell_blocks *m);

/* The sums of cell `cell` (coordinates from the scene corner), NULL when it does not
 * exist; *index: its index in m->sums (and m->high). */
const sta_cell_sums *sta_cell_blocks_find(const sta_cell_blocks *m, const int64_t cell[3],
                                          size_t *index);

/* The number of points in cell `cell` (0 when it does not exist). */
int64_t sta_cell_blocks_count(const sta_cell_blocks *m, const int64_t cell[3]);

/* The summed moments of the 2 x 2 x 2 cells around grid vertex `vertex` (cell
 * coordinates from the scene corner: the cells from vertex - 1 to vertex), as offsets
 * from their block's corner, as sta_cell_moments_vertex gives them: `lower` sets n, s1
 * and s2 and zeroes s3 and s4; `higher` sets only s3 and s4 (0 unless m->higher). */
void sta_cell_blocks_vertex_lower(const sta_cell_blocks *m, const int64_t vertex[3],
                                  sta_moment_sums *out);
void sta_cell_blocks_vertex_higher(const sta_cell_blocks *m, const int64_t vertex[3],
                                   sta_moment_sums *out);

#endif
