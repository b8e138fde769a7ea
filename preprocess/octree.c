/* SPDX-License-Identifier: MIT
 * Octree geometry. */
#include "octree.h"

#include "format/strata.h"

sta_status sta_octree_space_init(sta_octree_space *space, const sta_grid *grid,
                                 const int64_t min[3], const int64_t max[3], int grid_log2,
                                 sta_error *err)
{
    int32_t lo[3], hi[3];
    for (int a = 0; a < 3; a++) {
        if (min[a] < INT32_MIN || max[a] > INT32_MAX) {
            return sta_fail(err, STA_ERR_ARG, "bounds %lld..%lld leave the int32 grid",
                            (long long)min[a], (long long)max[a]);
        }
        lo[a] = (int32_t)min[a];
        hi[a] = (int32_t)max[a];
    }
    uint8_t size_log2[3];
    sta_status status = sta_strata_choose_root(grid, lo, hi, space->root_min, size_log2, err);
    if (status != STA_OK) {
        return status;
    }
    space->grid_log2 = grid_log2;
    space->max_level = STA_OCTREE_MAX_LEVEL;
    for (int a = 0; a < 3; a++) {
        space->root_log2[a] = size_log2[a];
        space->max_level = size_log2[a] < space->max_level ? size_log2[a] : space->max_level;
    }
    return STA_OK;
}

bool sta_node_contains(const sta_octree_space *s, const sta_node_key *k, const int32_t xyz[3])
{
    for (int a = 0; a < 3; a++) {
        int64_t lo = sta_node_min(s, k, a);
        int64_t hi = lo + ((int64_t)1 << sta_node_side_log2(s, k->level, a));
        if (xyz[a] < lo || xyz[a] >= hi) {
            return false;
        }
    }
    return true;
}

// Interleaves the bits of x, y, z (x lowest) into a 96-bit code held in two words.
static void morton(const sta_node_key *k, uint64_t out[2])
{
    const uint32_t c[3] = { k->x, k->y, k->z };
    out[0] = out[1] = 0;
    for (int j = 0; j < 96; j++) {
        uint64_t bit = (c[j % 3] >> (j / 3)) & 1u;
        out[j / 64] |= bit << (j % 64);
    }
}

int sta_node_key_compare(const sta_node_key *a, const sta_node_key *b)
{
    if (a->level != b->level) {
        return a->level < b->level ? -1 : 1;
    }
    uint64_t ma[2], mb[2];
    morton(a, ma);
    morton(b, mb);
    if (ma[1] != mb[1]) {
        return ma[1] < mb[1] ? -1 : 1;
    }
    if (ma[0] != mb[0]) {
        return ma[0] < mb[0] ? -1 : 1;
    }
    return 0;
}
