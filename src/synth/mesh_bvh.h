/* SPDX-License-Identifier: MIT
 * Internal: a bounding volume hierarchy over a triangle mesh for exact ray casts.
 *
 * Built once (median split on the longest centroid axis, leaves of up to 4
 * triangles), then read-only: traversal is thread-safe.
 */
#ifndef STA_SYNTH_MESH_BVH_H
#define STA_SYNTH_MESH_BVH_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "core/status.h"

typedef struct sta_bvh_node {
    double lo[3], hi[3]; /* bounds of the node's triangles */
    uint32_t first;      /* leaf: first index into order; inner: left child (right = +1) */
    uint32_t count;      /* leaf: triangle count (> 0); inner: 0 */
} sta_bvh_node;

typedef struct sta_bvh {
    const double *positions;   /* borrowed: 3 doubles per vertex */
    const uint32_t *triangles; /* borrowed: 3 indices per triangle */
    uint32_t *order;           /* triangle indices in leaf order (owned) */
    sta_bvh_node *nodes;       /* nodes[0] is the root (owned) */
    size_t node_count;
} sta_bvh;

/* Builds a BVH over `triangle_count` triangles (positions and triangles are
 * borrowed and must outlive the BVH). Zero-initialise `bvh` first. */
sta_status sta_bvh_build(sta_bvh *bvh, const double *positions, const uint32_t *triangles,
                         size_t triangle_count, sta_error *err);

/* Frees the arrays; a zeroed BVH is a no-op. */
void sta_bvh_release(sta_bvh *bvh);

/* Nearest triangle hit with min_t < t < max_t (two-sided). On a hit returns true with
 * *out_t and *out_triangle. */
bool sta_bvh_raycast(const sta_bvh *bvh, const double origin[3], const double dir[3], double min_t,
                     double max_t, double *out_t, uint32_t *out_triangle);

#endif
