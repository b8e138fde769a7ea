/* SPDX-License-Identifier: MIT
 * A sample of a scene's points for its default view, spread as the points are: the
 * root node's points, each weighted by how many of the file's points it stands for.
 */
#ifndef STA_APP_VIEW_SAMPLE_H
#define STA_APP_VIEW_SAMPLE_H

#include <stddef.h>

#include "format/strata_reader.h"

#define STA_VIEW_SAMPLE_DECODE_POINTS 262144 /* points decoded at most (the root at least) */
#define STA_VIEW_SAMPLE_POINTS        8192   /* points in the sample at most */

/* The points inside box_min..box_max (world metres) of the first nodes of the table
 * (breadth first: the coarse levels, STA_VIEW_SAMPLE_DECODE_POINTS at most, the root
 * whatever its size), resampled by weight into up to STA_VIEW_SAMPLE_POINTS points
 * (systematic resampling: a point appears about as often as its weight asks). A
 * decoded point's weight is the number of the file's points around it: the points of
 * the deepest node whose box holds it, and of that node's subtrees that hold no decoded
 * point, shared among the decoded points it holds. A coarse level is a sample even in
 * space (one point per cell), so without the weights a sparse spread — a mobile scan's
 * ground streaks, hundreds of metres long down the cross streets — counts as much as
 * the dense street it came from. *out (owned by the caller) is NULL and 0 is returned
 * when the root cannot be read; when the node table is unusable (a child index out of
 * order) the points come unweighted. */
size_t sta_view_density_sample(const sta_strata_reader *reader, const double box_min[3],
                               const double box_max[3], double (**out)[3]);

#endif
