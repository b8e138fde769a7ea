/* SPDX-License-Identifier: MIT
 * The exact K nearest neighbours of each point of a set (one chunk and its halo, for
 * strata-convert --normals).
 *
 * Design: the points go into one uniform grid whose cell edge is tuned until a point's
 * cell holds about 1.5 K points (surfaces and volumes alike). Cells are hashed (a table
 * sized to the occupied cells, and a 16-bit-a-cell occupancy filter so that probing the
 * empty cells around a surface costs no cache miss) and walked in key order. Each cell
 * gathers the points of its 27 cells once (own cell first, then by distance); a point
 * whose K-th neighbour is not provably inside them continues in shells of cells,
 * skipping cells farther than its current K-th distance. Distance ties are broken by
 * coordinates, so a point's neighbourhood is the same set whatever else the set holds
 * beyond it and in whatever order cells are visited.
 */
#ifndef STA_PREPROCESS_KNN_GRID_H
#define STA_PREPROCESS_KNN_GRID_H

#include <stddef.h>

#include "core/status.h"

#define STA_KNN_MAX 64 /* largest K */

/* A neighbourhood: `size` points (k + 1 when the set has as many), ascending distance;
 * p[0] is the query point itself (or a duplicate of it). */
typedef struct sta_knn {
    int size, capacity;
    float d2[STA_KNN_MAX + 1];       /* squared distances */
    const float *p[STA_KNN_MAX + 1]; /* the points (into the library's copies) */
} sta_knn;

/* Called for each of the first `queries` points, in no particular order. Returns 0 when
 * done with the point, or a wider K (up to STA_KNN_MAX): then it is called again for the
 * same point with its exact K + 1 nearest (adaptive neighbourhoods: only the points that
 * ask pay for the wider search). */
typedef int (*sta_knn_visit)(void *user, size_t index, const sta_knn *neighbours);

/* Finds the k + 1 nearest of xyz[0 .. n) (a neighbourhood wider than 12 cells gets what
 * those hold) for each point i < queries and calls visit(user, i, ...), again with more
 * neighbours while it asks for them. */
sta_status sta_knn_each(const float (*xyz)[3], size_t n, size_t queries, int k, sta_knn_visit visit,
                        void *user, sta_error *err);

/* Bytes of scratch memory sta_knn_each needs for `points` points. */
size_t sta_knn_memory_bytes(size_t points);

#endif
