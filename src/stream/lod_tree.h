/* SPDX-License-Identifier: MIT
 * The node hierarchy as the streaming code sees it: real-world boxes, point counts,
 * spacing and children, taken once from an open .strata file. No GL.
 */
#ifndef STA_STREAM_LOD_TREE_H
#define STA_STREAM_LOD_TREE_H

#include <stdint.h>

#include "core/status.h"
#include "format/strata_reader.h"

typedef struct sta_lod_node {
    double min[3], max[3]; /* real-world box of the node, metres */
    double spacing;        /* metres between points of the node's grid */
    uint64_t point_count;
    uint32_t first_child; /* valid when child_mask != 0 */
    uint8_t child_mask;   /* children are first_child .. + popcount(mask) - 1 */
    uint8_t level;
} sta_lod_node;

typedef struct sta_lod_tree {
    sta_lod_node *nodes; /* owned; node 0 is the root */
    uint32_t count;
} sta_lod_tree;

/* Copies the table of `reader` (which may be closed afterwards). */
sta_status sta_lod_tree_init(sta_lod_tree *tree, const sta_strata_reader *reader, sta_error *err);

void sta_lod_tree_release(sta_lod_tree *tree);

#endif
