/* SPDX-License-Identifier: MIT
 * Full verification of a .strata file: every payload and the nested-octree
 * invariants of every node (docs/FORMAT.md §8).
 *
 * Based on: M. Wimmer, C. Scheiblauer, "Instant Points: Fast Rendering of Unprocessed
 * Point Clouds", SPBG 2006 (nested octree: one point per cell of each node's grid).
 */
#include <inttypes.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/alloc.h"
#include "format/strata_internal.h"
#include "format/strata_reader.h"

static int compare_u64(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return x < y ? -1 : x > y;
}

static int32_t axis_value(const sta_point *p, int a)
{
    return a == 0 ? p->X : a == 1 ? p->Y : p->Z;
}

// Cell index of a point inside a node: cx + G * (cy + G * cz), below 2^48.
static uint64_t cell_key(const sta_point *p, const int64_t corner[3], const sta_strata_geometry *g,
                         unsigned level, uint32_t cell[3])
{
    for (int a = 0; a < 3; a++) {
        uint32_t rel = (uint32_t)(axis_value(p, a) - corner[a]);
        cell[a] = sta_strata_cell_of(rel, (unsigned)g->root_size_log2[a] - level, g->grid_cells);
    }
    uint64_t cells = g->grid_cells;
    return cell[0] + cells * (cell[1] + cells * (uint64_t)cell[2]);
}

// Points inside the node's box; tracks the bounds of everything seen.
static sta_status check_inside(const sta_strata_info *info, const char *label,
                               const sta_strata_points *pts, const int64_t corner[3],
                               const int64_t size[3], int64_t lo[3], int64_t hi[3], sta_error *err)
{
    for (size_t i = 0; i < pts->count; i++) {
        const sta_point *p = &pts->points[i];
        for (int a = 0; a < 3; a++) {
            int64_t v = axis_value(p, a);
            if (v < corner[a] || v >= corner[a] + size[a]) {
                return sta_fail(
                    err, STA_ERR_FORMAT,
                    "%s: %s: point %zu at grid (%" PRId32 ", %" PRId32 ", %" PRId32
                    ") lies outside the node's box [%" PRId64 ", %" PRId64 ") on axis %d",
                    info->path, label, i, p->X, p->Y, p->Z, corner[a], corner[a] + size[a], a);
            }
            lo[a] = v < lo[a] ? v : lo[a];
            hi[a] = v > hi[a] ? v : hi[a];
        }
    }
    return STA_OK;
}

// No two points in one cell of the node's grid; `keys` holds count entries.
static sta_status check_cells(const sta_strata_info *info, const char *label,
                              const sta_strata_points *pts, const int64_t corner[3], unsigned level,
                              uint64_t *keys, sta_error *err)
{
    const sta_strata_geometry *g = &info->geometry;
    uint32_t cell[3];
    for (size_t i = 0; i < pts->count; i++) {
        keys[i] = cell_key(&pts->points[i], corner, g, level, cell);
    }
    qsort(keys, pts->count, sizeof(*keys), compare_u64);
    for (size_t k = 1; k < pts->count; k++) {
        if (keys[k] != keys[k - 1]) {
            continue;
        }
        // Rare path: find the two points that share the cell.
        size_t first = SIZE_MAX;
        for (size_t i = 0; i < pts->count; i++) {
            if (cell_key(&pts->points[i], corner, g, level, cell) != keys[k]) {
                continue;
            }
            if (first == SIZE_MAX) {
                first = i;
                continue;
            }
            const sta_point *a = &pts->points[first], *b = &pts->points[i];
            return sta_fail(err, STA_ERR_FORMAT,
                            "%s: %s: points %zu (%" PRId32 ", %" PRId32 ", %" PRId32
                            ") and %zu (%" PRId32 ", %" PRId32 ", %" PRId32
                            ") share grid cell %" PRIu32 "/%" PRIu32 "/%" PRIu32 " of %" PRIu32
                            "^3 in a node not flagged overflow",
                            info->path, label, first, a->X, a->Y, a->Z, i, b->X, b->Y, b->Z,
                            cell[0], cell[1], cell[2], g->grid_cells);
        }
    }
    return STA_OK;
}

// Header bounds against the bounds of the data.
static sta_status check_bounds(const sta_strata_info *info, const int64_t lo[3],
                               const int64_t hi[3], sta_error *err)
{
    for (int a = 0; a < 3; a++) {
        int64_t want_lo = info->point_count ? lo[a] : 0, want_hi = info->point_count ? hi[a] : 0;
        if (info->grid_min[a] != want_lo || info->grid_max[a] != want_hi) {
            return sta_fail(err, STA_ERR_FORMAT,
                            "%s: header grid bounds axis %d [%" PRId32 ", %" PRId32
                            "] differ from the points' [%" PRId64 ", %" PRId64 "]",
                            info->path, a, info->grid_min[a], info->grid_max[a], want_lo, want_hi);
        }
        if (info->point_count == 0) {
            continue;
        }
        const sta_grid *grid = &info->geometry.grid;
        double real[2] = { sta_grid_apply(grid, a, (int32_t)lo[a]),
                           sta_grid_apply(grid, a, (int32_t)hi[a]) };
        double stored[2] = { info->bounds_min[a], info->bounds_max[a] };
        for (int k = 0; k < 2; k++) {
            // Allow for a fused multiply-add in either the writer or this reader.
            double tolerance = 1e-12 * (fabs(real[k] - grid->offset[a]) + fabs(grid->offset[a]));
            if (fabs(real[k] - stored[k]) > tolerance) {
                return sta_fail(err, STA_ERR_FORMAT,
                                "%s: header bounds axis %d %s %.17g differ from the points' %.17g",
                                info->path, a, k ? "max" : "min", stored[k], real[k]);
            }
        }
    }
    return STA_OK;
}

sta_status sta_strata_verify(const sta_strata_reader *reader, sta_strata_progress_fn progress,
                             void *user, sta_error *err)
{
    const sta_strata_info *info = sta_strata_reader_info(reader);
    sta_strata_decoder *decoder = NULL;
    uint64_t *keys = NULL;
    size_t key_capacity = 0;
    int64_t lo[3] = { INT64_MAX, INT64_MAX, INT64_MAX };
    int64_t hi[3] = { INT64_MIN, INT64_MIN, INT64_MIN };
    sta_status s = sta_strata_decoder_create(&decoder, err);
    for (uint32_t i = 0; i < info->node_count && s == STA_OK; i++) {
        const sta_strata_node *n = sta_strata_reader_node(reader, i);
        char label[96];
        sta_strata_node_label(label, sizeof(label), i, n->key);
        double spacing = sta_strata_node_spacing(&info->geometry, n->key.level);
        if (fabs(n->spacing - spacing) > 1e-9 * spacing) {
            s = sta_fail(err, STA_ERR_FORMAT, "%s: %s: spacing %.17g should be %.17g", info->path,
                         label, n->spacing, spacing);
            break;
        }
        sta_strata_points pts;
        s = sta_strata_decode_node(reader, i, decoder, &pts, err);
        if (s != STA_OK) {
            break;
        }
        int64_t corner[3], size[3];
        sta_strata_node_grid_bounds(&info->geometry, n->key, corner, size);
        s = check_inside(info, label, &pts, corner, size, lo, hi, err);
        if (s == STA_OK && !(n->flags & STA_STRATA_NODE_OVERFLOW) && pts.count > 1) {
            if (pts.count > key_capacity) {
                sta_free(keys);
                key_capacity = 0;
                keys = sta_alloc_array(pts.count, sizeof(*keys));
                if (!keys) {
                    s = sta_fail(err, STA_ERR_NOMEM, "%s: %s: out of memory for %zu cells",
                                 info->path, label, pts.count);
                    break;
                }
                key_capacity = pts.count;
            }
            s = check_cells(info, label, &pts, corner, n->key.level, keys, err);
        }
        if (s == STA_OK && progress && !progress(user, i + 1, info->node_count)) {
            s = sta_fail(err, STA_ERR_CANCELLED,
                         "%s: verification cancelled after %" PRIu32 " of %" PRIu32 " nodes",
                         info->path, i + 1, info->node_count);
        }
    }
    if (s == STA_OK) {
        s = check_bounds(info, lo, hi, err);
    }
    sta_free(keys);
    sta_strata_decoder_destroy(decoder);
    return s;
}
