/* SPDX-License-Identifier: MIT
 * Choosing which nodes to draw this frame (the LOD cut), within a point budget.
 *
 * Design: nodes are visited from the root in order of their projected spacing (how
 * far apart, in pixels, the node's points appear): the coarsest-looking first. A node
 * is taken when it is in the view frustum and its points still fit the budget; its
 * children become candidates only while its spacing on screen is above
 * `min_spacing_px` (finer detail would not show). A nested octree's children refine
 * their parent, so any selection closed under "parent first" draws no point twice
 * and a missing child is stood in for by its parent. Cost: O(selected log selected),
 * independent of the scene size.
 */
#ifndef STA_STREAM_SELECT_H
#define STA_STREAM_SELECT_H

#include <stddef.h>
#include <stdint.h>

#include "core/camera.h"
#include "stream/clip.h"
#include "stream/lod_tree.h"

/* The point budget per frame when none is given (DESIGN.md: 30 M points per frame). */
#define STA_DEFAULT_BUDGET_POINTS UINT64_C(30000000)

/* On-screen spacing below which a node is not refined when none is given, pixels. */
#define STA_DEFAULT_MIN_SPACING_PX 0.75

#define STA_SELECT_MAX_EXTRA_VIEWS 8 /* further cameras a cut may serve (mirror reflections) */

typedef struct sta_select_params {
    uint64_t budget_points;        /* 0: STA_DEFAULT_BUDGET_POINTS */
    double min_spacing_px;         /* 0: STA_DEFAULT_MIN_SPACING_PX; stop refining below this */
    const sta_clip *clip;          /* borrowed or NULL: nodes it rejects are not selected, so
                                      the budget goes to the nodes that can show points */
    const sta_camera *extra_views; /* borrowed: the cut serves these too (a node's priority
                                      is its largest over all views); up to
                                      STA_SELECT_MAX_EXTRA_VIEWS are used */
    size_t extra_view_count;
} sta_select_params;

/* Fills the zero fields of `params` with their defaults. */
void sta_select_params_defaults(sta_select_params *params);

/* The cut, in priority order (highest first). Reused frame to frame; zero-initialise,
 * release with sta_selection_release. */
typedef struct sta_selection {
    uint32_t *nodes;  /* selected node indices, parents before children */
    double *priority; /* on-screen spacing of each, pixels */
    size_t count;
    uint64_t point_count; /* sum over selected nodes, <= budget */
    size_t capacity;
    /* candidate heap (internal) */
    uint32_t *heap_nodes;
    double *heap_keys;
    size_t heap_count;
    size_t heap_capacity;
} sta_selection;

sta_status sta_select(const sta_lod_tree *tree, const sta_camera *camera,
                      const sta_select_params *params, sta_selection *selection, sta_error *err);

void sta_selection_release(sta_selection *selection);

/* On-screen spacing (pixels) of a node seen from `camera`; 0 when outside the
 * frustum. Exposed for tests and the loader's priorities. */
double sta_select_node_priority(const sta_lod_node *node, const sta_camera *camera,
                                const sta_frustum *frustum);

#endif
