/* SPDX-License-Identifier: MIT
 * The integer geometry of the converter's octree: node keys, node corners, cells.
 *
 * Everything is exact integer arithmetic on the output grid. The root is a box whose
 * side on each axis is a power of two in grid units (equal sides when the scales
 * are equal), so children halve each axis exactly and every node's corner is an
 * integer.
 */
#ifndef STA_PREPROCESS_OCTREE_H
#define STA_PREPROCESS_OCTREE_H

#include <stdbool.h>
#include <stdint.h>

#include "core/point.h"
#include "core/status.h"

enum {
    STA_OCTREE_MAX_LEVEL = 30
};

/* Which part of space the tree covers and how finely nodes sample it. */
typedef struct sta_octree_space {
    int64_t root_min[3]; /* corner of the root in grid units */
    int root_log2[3];    /* root side per axis is 2^root_log2 grid units */
    int grid_log2;       /* each node has 2^grid_log2 cells per axis */
    int max_level;       /* deepest level: nodes there are one grid unit wide or less
                            than STA_OCTREE_MAX_LEVEL */
} sta_octree_space;

/* A node: its level and its integer coordinates among the 2^level nodes per axis. */
typedef struct sta_node_key {
    uint32_t x, y, z;
    uint8_t level;
} sta_node_key;

/* Chooses the root box for integer bounds [min, max] (inclusive) on `grid` with the
 * .strata rule (sta_strata_choose_root: cubic in metres, centred, inside int32), and
 * 2^grid_log2 cells per node axis. */
sta_status sta_octree_space_init(sta_octree_space *space, const sta_grid *grid,
                                 const int64_t min[3], const int64_t max[3], int grid_log2,
                                 sta_error *err);

/* Corner of a node in grid units. */
static inline int64_t sta_node_min(const sta_octree_space *s, const sta_node_key *k, int axis)
{
    const uint32_t c = axis == 0 ? k->x : axis == 1 ? k->y : k->z;
    return s->root_min[axis] + ((int64_t)c << (s->root_log2[axis] - k->level));
}

/* log2 of a node's side on an axis, in grid units (>= 0 for valid levels). */
static inline int sta_node_side_log2(const sta_octree_space *s, int level, int axis)
{
    return s->root_log2[axis] - level;
}

/* Cell index (0 .. 8^grid_log2 - 1) of an integer position inside the node. */
static inline uint32_t sta_node_cell(const sta_octree_space *s, const sta_node_key *k,
                                     const int32_t xyz[3])
{
    uint32_t cell = 0;
    for (int a = 0; a < 3; a++) {
        int64_t rel = (int64_t)xyz[a] - sta_node_min(s, k, a);
        int shift = sta_node_side_log2(s, k->level, a) - s->grid_log2;
        uint32_t c = shift >= 0 ? (uint32_t)(rel >> shift) : (uint32_t)(rel << -shift);
        cell = (cell << s->grid_log2) | c;
    }
    return cell;
}

/* Child slot 0..7 (bit 0 x, bit 1 y, bit 2 z) of a position inside the node. */
static inline int sta_node_octant(const sta_octree_space *s, const sta_node_key *k,
                                  const int32_t xyz[3])
{
    int octant = 0;
    for (int a = 0; a < 3; a++) {
        int64_t rel = (int64_t)xyz[a] - sta_node_min(s, k, a);
        int half = sta_node_side_log2(s, k->level, a) - 1;
        octant |= (int)((rel >> half) & 1) << a;
    }
    return octant;
}

/* The child key in slot `octant`. */
static inline sta_node_key sta_node_child(const sta_node_key *k, int octant)
{
    sta_node_key c = { (k->x << 1) | (uint32_t)(octant & 1),
                       (k->y << 1) | (uint32_t)((octant >> 1) & 1),
                       (k->z << 1) | (uint32_t)((octant >> 2) & 1), (uint8_t)(k->level + 1) };
    return c;
}

/* The parent key (level must be > 0). */
static inline sta_node_key sta_node_parent(const sta_node_key *k)
{
    sta_node_key p = { k->x >> 1, k->y >> 1, k->z >> 1, (uint8_t)(k->level - 1) };
    return p;
}

/* True when the node contains the position. */
bool sta_node_contains(const sta_octree_space *s, const sta_node_key *k, const int32_t xyz[3]);

/* Orders keys by level, then Morton code (breadth-first, children of one parent
 * adjacent and in slot order). For qsort-style use. */
int sta_node_key_compare(const sta_node_key *a, const sta_node_key *b);

#endif
