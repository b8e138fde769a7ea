/* SPDX-License-Identifier: MIT
 * The .strata node table: entries to and from bytes, and the structural checks that
 * make a table safe to walk (docs/FORMAT.md §6).
 *
 * The tree rules: node 0 is the root (level 0, cell 0/0/0); a node's children are
 * contiguous from first_child in ascending slot order, each with index greater than
 * its parent's, level + 1 and the cell 2 * parent + slot offset; every non-root
 * node is the child of exactly one node. Edges only point forward, so a table that
 * passes has no cycles.
 */
#include <inttypes.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/alloc.h"
#include "core/bytes.h"
#include "format/strata_internal.h"

void sta_strata_node_store(const sta_strata_node *node, uint8_t *out)
{
    memset(out, 0, STA_STRATA_NODE_ENTRY_SIZE);
    out[STA_STRATA_N_LEVEL_OFF] = node->key.level;
    out[STA_STRATA_N_CHILD_MASK_OFF] = node->child_mask;
    out[STA_STRATA_N_COMPRESSION_OFF] = node->payload.compression;
    sta_store_u32le(out + STA_STRATA_N_FLAGS_OFF, node->flags);
    sta_store_u32le(out + STA_STRATA_N_X_OFF, node->key.x);
    sta_store_u32le(out + STA_STRATA_N_Y_OFF, node->key.y);
    sta_store_u32le(out + STA_STRATA_N_Z_OFF, node->key.z);
    sta_store_u32le(out + STA_STRATA_N_FIRST_CHILD_OFF, node->first_child);
    sta_store_u64le(out + STA_STRATA_N_POINT_COUNT_OFF, node->point_count);
    sta_store_u64le(out + STA_STRATA_N_OFFSET_OFF, node->payload.offset);
    sta_store_u64le(out + STA_STRATA_N_SIZE_OFF, node->payload.stored_size);
    sta_store_u64le(out + STA_STRATA_N_RAW_SIZE_OFF, node->payload.raw_size);
    sta_store_u64le(out + STA_STRATA_N_CHECKSUM_OFF, node->payload.checksum);
    sta_store_f64le(out + STA_STRATA_N_SPACING_OFF, node->spacing);
}

void sta_strata_node_load(const uint8_t *in, sta_strata_node *out)
{
    memset(out, 0, sizeof(*out));
    out->key.level = in[STA_STRATA_N_LEVEL_OFF];
    out->child_mask = in[STA_STRATA_N_CHILD_MASK_OFF];
    out->payload.compression = in[STA_STRATA_N_COMPRESSION_OFF];
    out->flags = sta_load_u32le(in + STA_STRATA_N_FLAGS_OFF);
    out->key.x = sta_load_u32le(in + STA_STRATA_N_X_OFF);
    out->key.y = sta_load_u32le(in + STA_STRATA_N_Y_OFF);
    out->key.z = sta_load_u32le(in + STA_STRATA_N_Z_OFF);
    out->first_child = sta_load_u32le(in + STA_STRATA_N_FIRST_CHILD_OFF);
    out->point_count = sta_load_u64le(in + STA_STRATA_N_POINT_COUNT_OFF);
    out->payload.offset = sta_load_u64le(in + STA_STRATA_N_OFFSET_OFF);
    out->payload.stored_size = sta_load_u64le(in + STA_STRATA_N_SIZE_OFF);
    out->payload.raw_size = sta_load_u64le(in + STA_STRATA_N_RAW_SIZE_OFF);
    out->payload.checksum = sta_load_u64le(in + STA_STRATA_N_CHECKSUM_OFF);
    out->spacing = sta_load_f64le(in + STA_STRATA_N_SPACING_OFF);
}

// A stored payload range, for the overlap check.
typedef struct range {
    uint64_t offset;
    uint64_t size;
    uint32_t node;
} range;

static int compare_ranges(const void *a, const void *b)
{
    const range *x = a, *y = b;
    if (x->offset != y->offset) {
        return x->offset < y->offset ? -1 : 1;
    }
    return x->node < y->node ? -1 : x->node > y->node;
}

// Checks one node on its own: key, sizes, compression, payload range.
static sta_status check_node(const sta_strata_info *info, const sta_strata_node *n, uint32_t i,
                             const char *name, sta_error *err)
{
    char label[96];
    sta_strata_node_label(label, sizeof(label), i, n->key);
    uint64_t cells = (uint64_t)1 << (n->key.level <= 32 ? n->key.level : 0);
    if (n->key.level > info->max_level || n->key.x >= cells || n->key.y >= cells ||
        n->key.z >= cells) {
        return sta_fail(err, STA_ERR_FORMAT,
                        "%s: %s: key is not a cell of a level up to max_level %u", name, label,
                        info->max_level);
    }
    if (i == 0 && n->key.level != 0) {
        return sta_fail(err, STA_ERR_FORMAT, "%s: %s: the root must have level 0", name, label);
    }
    const sta_strata_payload *p = &n->payload;
    if (p->compression > STA_STRATA_COMPRESSION_ZSTD_SHUFFLE) {
        return sta_fail(err, STA_ERR_UNSUPPORTED, "%s: %s: compression code %u is unknown", name,
                        label, p->compression);
    }
    uint64_t record = info->layout.record_size;
    if (n->point_count > UINT64_MAX / record || p->raw_size != n->point_count * record) {
        return sta_fail(err, STA_ERR_FORMAT,
                        "%s: %s: raw_size %" PRIu64 " is not %" PRIu64 " points x %" PRIu64
                        " bytes",
                        name, label, p->raw_size, n->point_count, record);
    }
    if (n->point_count == 0 &&
        (p->offset != 0 || p->stored_size != 0 || p->compression != STA_STRATA_COMPRESSION_NONE)) {
        return sta_fail(err, STA_ERR_FORMAT,
                        "%s: %s: an empty node must have offset 0, size 0 and no compression", name,
                        label);
    }
    if (n->point_count > 0 && p->stored_size == 0) {
        return sta_fail(err, STA_ERR_FORMAT, "%s: %s: %" PRIu64 " points but an empty payload",
                        name, label, n->point_count);
    }
    if (p->compression == STA_STRATA_COMPRESSION_NONE && p->stored_size != p->raw_size) {
        return sta_fail(err, STA_ERR_FORMAT,
                        "%s: %s: uncompressed payload of %" PRIu64 " bytes should be %" PRIu64,
                        name, label, p->stored_size, p->raw_size);
    }
    if (p->stored_size > 0 &&
        (p->offset % info->payload_alignment != 0 || p->offset < info->data_offset ||
         p->offset > info->table_offset || p->stored_size > info->table_offset - p->offset)) {
        return sta_fail(err, STA_ERR_FORMAT,
                        "%s: %s: payload [%" PRIu64 ", +%" PRIu64 ") is not an aligned range "
                        "inside the payload area [%" PRIu64 ", %" PRIu64 ")",
                        name, label, p->offset, p->stored_size, info->data_offset,
                        info->table_offset);
    }
    if (!isfinite(n->spacing) || !(n->spacing > 0.0)) {
        return sta_fail(err, STA_ERR_FORMAT, "%s: %s: spacing %g is not positive", name, label,
                        n->spacing);
    }
    if ((n->flags & STA_STRATA_NODE_OVERFLOW) && n->child_mask != 0) {
        return sta_fail(err, STA_ERR_FORMAT,
                        "%s: %s: an overflow node must be a leaf but has children (mask 0x%02x)",
                        name, label, n->child_mask);
    }
    return STA_OK;
}

// Checks node i's child links and marks its children in `claimed` (bit per node).
static sta_status check_children(const sta_strata_info *info, const sta_strata_node *nodes,
                                 uint32_t i, uint8_t *claimed, const char *name, sta_error *err)
{
    const sta_strata_node *n = &nodes[i];
    char label[96];
    sta_strata_node_label(label, sizeof(label), i, n->key);
    if (n->child_mask == 0) {
        if (n->first_child != 0) {
            return sta_fail(err, STA_ERR_FORMAT,
                            "%s: %s: first_child is %" PRIu32 " but the node has no children", name,
                            label, n->first_child);
        }
        return STA_OK;
    }
    unsigned count = (unsigned)__builtin_popcount(n->child_mask);
    if (n->first_child <= i) {
        return sta_fail(err, STA_ERR_FORMAT,
                        "%s: %s: first child %" PRIu32 " is not after its parent (a cycle or "
                        "an order that is neither breadth- nor depth-first)",
                        name, label, n->first_child);
    }
    if ((uint64_t)n->first_child + count > info->node_count) {
        return sta_fail(
            err, STA_ERR_FORMAT,
            "%s: %s: children %" PRIu32 "..%" PRIu64 " are out of range (%" PRIu32 " nodes)", name,
            label, n->first_child, (uint64_t)n->first_child + count - 1, info->node_count);
    }
    uint32_t j = n->first_child;
    for (unsigned slot = 0; slot < 8; slot++) {
        if (!(n->child_mask & (1u << slot))) {
            continue;
        }
        const sta_strata_node *c = &nodes[j];
        if (claimed[j / 8] & (1u << (j % 8))) {
            return sta_fail(err, STA_ERR_FORMAT,
                            "%s: %s: child %" PRIu32 " already belongs to another node", name,
                            label, j);
        }
        claimed[j / 8] |= (uint8_t)(1u << (j % 8));
        uint64_t x = 2 * (uint64_t)n->key.x + (slot & 1);
        uint64_t y = 2 * (uint64_t)n->key.y + ((slot >> 1) & 1);
        uint64_t z = 2 * (uint64_t)n->key.z + ((slot >> 2) & 1);
        if (c->key.level != n->key.level + 1 || c->key.x != x || c->key.y != y || c->key.z != z) {
            char child[96];
            sta_strata_node_label(child, sizeof(child), j, c->key);
            return sta_fail(err, STA_ERR_FORMAT,
                            "%s: %s: child in slot %u is %s, expected level %u cell %" PRIu64
                            "/%" PRIu64 "/%" PRIu64,
                            name, label, slot, child, n->key.level + 1, x, y, z);
        }
        j++;
    }
    return STA_OK;
}

// Payload ranges must not overlap (each stored byte belongs to one node).
static sta_status check_overlaps(const sta_strata_info *info, const sta_strata_node *nodes,
                                 const char *name, sta_error *err)
{
    range *ranges = sta_alloc_array(info->node_count, sizeof(*ranges));
    if (!ranges) {
        return sta_fail(err, STA_ERR_NOMEM, "%s: out of memory checking %" PRIu32 " nodes", name,
                        info->node_count);
    }
    size_t count = 0;
    for (uint32_t i = 0; i < info->node_count; i++) {
        if (nodes[i].payload.stored_size > 0) {
            ranges[count++] = (range){ nodes[i].payload.offset, nodes[i].payload.stored_size, i };
        }
    }
    qsort(ranges, count, sizeof(*ranges), compare_ranges);
    sta_status s = STA_OK;
    for (size_t k = 1; k < count; k++) {
        if (ranges[k].offset < ranges[k - 1].offset + ranges[k - 1].size) {
            char a[96], b[96];
            sta_strata_node_label(a, sizeof(a), ranges[k - 1].node, nodes[ranges[k - 1].node].key);
            sta_strata_node_label(b, sizeof(b), ranges[k].node, nodes[ranges[k].node].key);
            s = sta_fail(err, STA_ERR_FORMAT,
                         "%s: payloads of %s [%" PRIu64 ", +%" PRIu64 ") and %s [%" PRIu64
                         ", +%" PRIu64 ") overlap",
                         name, a, ranges[k - 1].offset, ranges[k - 1].size, b, ranges[k].offset,
                         ranges[k].size);
            break;
        }
    }
    sta_free(ranges);
    return s;
}

sta_status sta_strata_table_check(const sta_strata_info *info, const sta_strata_node *nodes,
                                  const char *name, sta_error *err)
{
    uint8_t *claimed = sta_calloc((size_t)info->node_count / 8 + 1, 1);
    if (!claimed) {
        return sta_fail(err, STA_ERR_NOMEM, "%s: out of memory checking %" PRIu32 " nodes", name,
                        info->node_count);
    }
    sta_status s = STA_OK;
    uint64_t points = 0;
    unsigned deepest = 0;
    for (uint32_t i = 0; i < info->node_count && s == STA_OK; i++) {
        s = check_node(info, &nodes[i], i, name, err);
        if (s == STA_OK) {
            s = check_children(info, nodes, i, claimed, name, err);
        }
        if (s == STA_OK && i > 0 && !(claimed[i / 8] & (1u << (i % 8)))) {
            // Children come after parents, so by now node i's parent has claimed it.
            char label[96];
            s = sta_fail(err, STA_ERR_FORMAT, "%s: %s is not the child of any node", name,
                         sta_strata_node_label(label, sizeof(label), i, nodes[i].key));
        }
        if (s == STA_OK && nodes[i].point_count > UINT64_MAX - points) {
            s = sta_fail(err, STA_ERR_FORMAT, "%s: node point counts overflow", name);
        }
        points += nodes[i].point_count;
        if (nodes[i].key.level > deepest) {
            deepest = nodes[i].key.level;
        }
    }
    sta_free(claimed);
    if (s != STA_OK) {
        return s;
    }
    if (points != info->point_count) {
        return sta_fail(err, STA_ERR_FORMAT,
                        "%s: nodes hold %" PRIu64 " points but the header says %" PRIu64, name,
                        points, info->point_count);
    }
    if (deepest != info->max_level) {
        return sta_fail(err, STA_ERR_FORMAT,
                        "%s: deepest node has level %u but the header's max_level is %u", name,
                        deepest, info->max_level);
    }
    return check_overlaps(info, nodes, name, err);
}
