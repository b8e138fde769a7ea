/* SPDX-License-Identifier: MIT
 * LOD tree from a .strata table. */
#include "stream/lod_tree.h"

#include <string.h>

#include "core/alloc.h"

sta_status sta_lod_tree_init(sta_lod_tree *tree, const sta_strata_reader *reader, sta_error *err)
{
    memset(tree, 0, sizeof(*tree));
    const sta_strata_info *info = sta_strata_reader_info(reader);
    tree->nodes = sta_calloc(info->node_count, sizeof(*tree->nodes));
    if (!tree->nodes) {
        return sta_fail(err, STA_ERR_NOMEM, "%s: out of memory for %u nodes", info->path,
                        info->node_count);
    }
    tree->count = info->node_count;
    for (uint32_t i = 0; i < info->node_count; i++) {
        const sta_strata_node *n = sta_strata_reader_node(reader, i);
        sta_lod_node *out = &tree->nodes[i];
        sta_strata_node_real_bounds(&info->geometry, n->key, out->min, out->max);
        out->spacing = n->spacing;
        out->point_count = n->point_count;
        out->first_child = n->first_child;
        out->child_mask = n->child_mask;
        out->level = n->key.level;
    }
    return STA_OK;
}

void sta_lod_tree_release(sta_lod_tree *tree)
{
    sta_free(tree->nodes);
    memset(tree, 0, sizeof(*tree));
}
