/* SPDX-License-Identifier: MIT
 * Samples of a scene's points for its default view: the root node's points as stored,
 * and a sample spread as the file's points are (the coarse levels' points, each weighted
 * by how many of the file's points it stands for).
 */
#ifndef STA_APP_VIEW_SAMPLE_H
#define STA_APP_VIEW_SAMPLE_H

#include <stdbool.h>
#include <stddef.h>

#include "format/strata_reader.h"

#define STA_VIEW_SAMPLE_DECODE_POINTS 262144 /* points decoded at most (the root at least) */
#define STA_VIEW_SAMPLE_POINTS        8192   /* points in the weighted sample at most */

/* World metres; arrays owned by the sample (sta_view_sample_release). */
typedef struct sta_view_sample {
    double (*root)[3]; /* the root node's points inside the box, unweighted */
    size_t root_count;
    double (*weighted)[3]; /* the density-weighted resample */
    size_t weighted_count;
} sta_view_sample;

/* Decodes the first nodes of the table (breadth first: the coarse levels,
 * STA_VIEW_SAMPLE_DECODE_POINTS at most, the root whatever its size) and keeps their
 * points inside box_min..box_max. `root` gets the root node's; `weighted` all of them
 * resampled by weight into up to STA_VIEW_SAMPLE_POINTS points (systematic resampling: a
 * point appears about as often as its weight asks). A decoded point stands for itself
 * and for its share of the first undecoded node on its way down the tree: that node's
 * subtree's points shared among the decoded points inside its box. A coarse level is a
 * sample even in space (one point per cell), so without the weights a sparse spread — a
 * mobile scan's ground streaks, a hundred metres and more down the cross streets —
 * counts as much as the dense street it came from. false, with both empty, when the
 * nodes cannot be decoded or memory is short; when the node table is unusable (a child
 * index out of order) the points come unweighted. */
bool sta_view_sample_build(const sta_strata_reader *reader, const double box_min[3],
                           const double box_max[3], sta_view_sample *out);

/* Frees both arrays; a zeroed sample is a no-op. */
void sta_view_sample_release(sta_view_sample *sample);

#endif
