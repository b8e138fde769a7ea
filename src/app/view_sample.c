/* SPDX-License-Identifier: MIT
 * The default view's samples of points: the root's, and all decoded ones weighted by the
 * density they stand for. */
#include "app/view_sample.h"

#include <stdbool.h>
#include <stdint.h>
#include <string.h>

#include "core/alloc.h"

typedef struct decoded_point {
    double world[3];
    int32_t grid[3];   /* the file's integers */
    uint32_t frontier; /* first node not decoded on its way down, or NO_FRONTIER */
} decoded_point;

#define NO_FRONTIER UINT32_MAX
#define BAD_TABLE   (UINT32_MAX - 1)

// Walking down from the root to the deepest node whose box holds grid position xyz:
// the first node with an index of at least `decoded` (not decoded: the table is
// breadth first, so the decoded nodes are its first ones), NO_FRONTIER when the walk
// ends among decoded nodes, BAD_TABLE when a child index is out of order.
static uint32_t frontier_node(const sta_strata_reader *reader, const int64_t xyz[3],
                              uint32_t decoded)
{
    const sta_strata_info *info = sta_strata_reader_info(reader);
    uint32_t index = 0;
    for (;;) {
        if (index >= decoded) {
            return index;
        }
        const sta_strata_node *node = sta_strata_reader_node(reader, index);
        if (!node->child_mask) {
            return NO_FRONTIER;
        }
        int64_t corner[3], size[3];
        sta_strata_node_grid_bounds(&info->geometry, node->key, corner, size);
        unsigned slot = 0;
        for (int a = 0; a < 3; a++) {
            slot |= (unsigned)(xyz[a] - corner[a] >= size[a] / 2) << a;
        }
        if (!(node->child_mask & (1u << slot))) {
            return NO_FRONTIER;
        }
        unsigned before = (unsigned)__builtin_popcount(node->child_mask & ((1u << slot) - 1u));
        uint64_t child = (uint64_t)node->first_child + before;
        if (child <= index || child >= info->node_count) {
            return BAD_TABLE;
        }
        index = (uint32_t)child;
    }
}

// Each decoded point's weight: itself, plus the points of the subtree of its frontier
// node (none decoded) shared among the decoded points inside that node's box. A
// frontier node with no decoded point in its box is left out (the coarse levels keep
// a point in nearly every occupied part of their box). false when the table is unusable.
static bool point_weights(const sta_strata_reader *reader, const decoded_point *points,
                          size_t count, double *out_weights)
{
    const sta_strata_info *info = sta_strata_reader_info(reader);
    uint32_t n = info->node_count;
    uint64_t *subtree = sta_calloc(n, sizeof(*subtree));
    uint32_t *held = sta_calloc(n, sizeof(*held));
    bool ok = subtree && held;
    for (size_t i = 0; ok && i < count; i++) {
        ok = points[i].frontier != BAD_TABLE;
        if (ok && points[i].frontier != NO_FRONTIER) {
            held[points[i].frontier]++;
        }
    }
    // Children come after their parents, so one pass from the end sums the subtrees.
    for (uint32_t i = n; ok && i-- > 0;) {
        const sta_strata_node *node = sta_strata_reader_node(reader, i);
        subtree[i] += node->point_count;
        unsigned children = (unsigned)__builtin_popcount(node->child_mask);
        for (unsigned c = 0; ok && c < children; c++) {
            uint64_t child = (uint64_t)node->first_child + c;
            ok = child > i && child < n;
            if (ok) {
                subtree[i] += subtree[child];
            }
        }
    }
    for (size_t i = 0; ok && i < count; i++) {
        uint32_t u = points[i].frontier;
        out_weights[i] = u == NO_FRONTIER ? 1.0 : 1.0 + (double)subtree[u] / held[u];
    }
    sta_free(subtree);
    sta_free(held);
    return ok;
}

// Appends node `index`'s points inside box_min..box_max to *points (grown as needed).
static bool append_node(const sta_strata_reader *reader, uint32_t index,
                        sta_strata_decoder *decoder, const double box_min[3],
                        const double box_max[3], decoded_point **points, size_t *count,
                        size_t *capacity)
{
    const sta_grid *grid = &sta_strata_reader_info(reader)->geometry.grid;
    sta_strata_points decoded;
    if (sta_strata_decode_node(reader, index, decoder, &decoded, NULL) != STA_OK) {
        return false;
    }
    if (*count + decoded.count > *capacity) {
        size_t grown = 2 * (*count + decoded.count);
        decoded_point *more = sta_realloc_array(*points, grown, sizeof(**points));
        if (!more) {
            return false;
        }
        *points = more;
        *capacity = grown;
    }
    for (size_t i = 0; i < decoded.count; i++) {
        const int64_t xyz[3] = { decoded.points[i].X, decoded.points[i].Y, decoded.points[i].Z };
        decoded_point *p = &(*points)[*count];
        bool inside = true;
        for (int a = 0; a < 3; a++) {
            p->grid[a] = (int32_t)xyz[a];
            p->world[a] = sta_grid_apply(grid, a, p->grid[a]);
            inside = inside && p->world[a] >= box_min[a] && p->world[a] <= box_max[a];
        }
        *count += inside;
    }
    return true;
}

// Copies `count` points' world coordinates into a new array (NULL when count is 0 or
// memory is short).
static double (*world_copy(const decoded_point *points, size_t count))[3]
{
    double(*out)[3] = count ? sta_alloc_array(count, sizeof(*out)) : NULL;
    for (size_t i = 0; out && i < count; i++) {
        for (int a = 0; a < 3; a++) {
            out[i][a] = points[i].world[a];
        }
    }
    return out;
}

// Resamples `points` by `weights` (systematic: sample j at (j + 1/2) total / want along
// the weights' sum) into out[want].
static void resample(const decoded_point *points, const double *weights, size_t count, size_t want,
                     double (*out)[3])
{
    double total = 0.0;
    for (size_t i = 0; i < count; i++) {
        total += weights[i];
    }
    size_t source = 0;
    double reached = weights[0];
    for (size_t j = 0; j < want; j++) {
        double at = ((double)j + 0.5) * total / (double)want;
        while (reached < at && source + 1 < count) {
            reached += weights[++source];
        }
        for (int a = 0; a < 3; a++) {
            out[j][a] = points[source].world[a];
        }
    }
}

void sta_view_sample_release(sta_view_sample *sample)
{
    sta_free(sample->root);
    sta_free(sample->weighted);
    memset(sample, 0, sizeof(*sample));
}

bool sta_view_sample_build(const sta_strata_reader *reader, const double box_min[3],
                           const double box_max[3], sta_view_sample *out)
{
    memset(out, 0, sizeof(*out));
    const sta_strata_info *info = sta_strata_reader_info(reader);
    sta_strata_decoder *decoder = NULL;
    decoded_point *points = NULL;
    double *weights = NULL;
    size_t kept = 0, capacity = 0, decoded = 0, root_kept = 0;
    bool ok = sta_strata_decoder_create(&decoder, NULL) == STA_OK;
    // The nodes in table order (breadth first: the coarse levels) within the budget.
    uint32_t nodes = 0;
    for (uint32_t i = 0; ok && i < info->node_count; i++, nodes++) {
        uint64_t n = sta_strata_reader_node(reader, i)->point_count;
        if (i > 0 && decoded + n > STA_VIEW_SAMPLE_DECODE_POINTS) {
            break;
        }
        ok = append_node(reader, i, decoder, box_min, box_max, &points, &kept, &capacity);
        decoded += n;
        root_kept = i == 0 ? kept : root_kept;
    }
    size_t want = kept < STA_VIEW_SAMPLE_POINTS ? kept : STA_VIEW_SAMPLE_POINTS;
    if (ok && kept > 0) {
        weights = sta_alloc_array(kept, sizeof(*weights));
        out->root = world_copy(points, root_kept);
        out->weighted = sta_alloc_array(want, sizeof(*out->weighted));
        ok = weights && out->weighted && (out->root || root_kept == 0);
    }
    if (ok && kept > 0) {
        for (size_t i = 0; i < kept; i++) {
            const int64_t xyz[3] = { points[i].grid[0], points[i].grid[1], points[i].grid[2] };
            points[i].frontier = frontier_node(reader, xyz, nodes);
        }
        if (!point_weights(reader, points, kept, weights)) {
            for (size_t i = 0; i < kept; i++) {
                weights[i] = 1.0;
            }
        }
        resample(points, weights, kept, want, out->weighted);
        out->root_count = root_kept;
        out->weighted_count = want;
    }
    if (!ok) {
        sta_view_sample_release(out);
    }
    sta_free(points);
    sta_free(weights);
    if (decoder) {
        sta_strata_decoder_destroy(decoder);
    }
    return ok;
}
