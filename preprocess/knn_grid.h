/* SPDX-License-Identifier: MIT
 * The exact K nearest neighbours of each point of a set (one chunk and its halo, for
 * strata-convert --normals).
 *
 * Design: the points go into one uniform grid whose cell edge is tuned until a point's
 * cell holds about 1.5 K points (surfaces and volumes alike). Cells are hashed (a table
 * sized to the occupied cells, and a 16-bit-a-cell occupancy filter so that probing the
 * empty cells around a surface costs no cache miss) and walked in key order. Each cell
 * gathers the points of its 27 cells once (own cell first, then by distance), and of its
 * 125 cells when one of its points asks for a wider neighbourhood. For each point the
 * squared distances to the block are computed in one vectorised loop (a wider search
 * of the same point only adds the outer ring's); the candidates under a bound are kept
 * (the previous point's K-th distance x 1.25, else the triangle inequality's bound from
 * it, else all: any bound that keeps K + 1 gives the exact set) and the K-th smallest
 * distance among them is found by quickselect (knn_select.h): the neighbours are taken
 * as a set, with no sorted list to insert into. A point whose K-th neighbour is not
 * provably inside the 27 cells tries the 125, then continues in shells of cells,
 * skipping cells farther than its current K-th distance. Distance ties are broken by
 * integer coordinates, so a point's neighbourhood is the same set whatever else the set
 * holds beyond it and in whatever order cells are visited.
 */
#ifndef STA_PREPROCESS_KNN_GRID_H
#define STA_PREPROCESS_KNN_GRID_H

#include <stddef.h>
#include <stdint.h>

#include "core/status.h"

#define STA_KNN_MAX 64 /* largest K */

/* A neighbourhood: `size` points (k + 1 when the set has as many), the nearest under
 * the order (squared distance, then integer coordinates), in no particular order; the
 * query point itself (or a duplicate of it) is among them. Consumers that sum over it
 * must not depend on the order (knn_normals.c sums integers). */
typedef struct sta_knn {
    int size, capacity;
    float d2[STA_KNN_MAX + 1];        /* squared distances (of the float positions) */
    int32_t grid[STA_KNN_MAX + 1][3]; /* the integer positions */
} sta_knn;

/* Called for each of the first `queries` points, in no particular order. Returns 0 when
 * done with the point, or a wider K (up to STA_KNN_MAX): then it is called again for the
 * same point with its exact K + 1 nearest (adaptive neighbourhoods: only the points that
 * ask pay for the wider search). */
typedef int (*sta_knn_visit)(void *user, size_t index, const sta_knn *neighbours);

/* Finds the k + 1 nearest of xyz[0 .. n) (a neighbourhood wider than 12 cells gets what
 * those hold) for each point i < queries and calls visit(user, i, ...), again with more
 * neighbours while it asks for them. grid[i]: point i's integer position (the one xyz[i]
 * was computed from: same order), handed back in the neighbourhoods and the tie-break. */
sta_status sta_knn_each(const float (*xyz)[3], const int32_t (*grid)[3], size_t n, size_t queries,
                        int k, sta_knn_visit visit, void *user, sta_error *err);

/* Bytes of scratch memory sta_knn_each needs for `points` points. */
size_t sta_knn_memory_bytes(size_t points);

#endif
