/* SPDX-License-Identifier: MIT
 * The streamer: the per-frame streaming policy of a scene, without GL. It owns the node
 * source (the .strata reader), the LOD tree, the cut selection, the loader threads, the
 * GPU residency model and the list of nodes that cannot be shown. Each frame, given the
 * camera, it says what to evict from the GPU, what to upload and what to draw; render/
 * (gpu_cache.c, pass_geometry.c) carries that out.
 *
 * Design: sta_streamer_update (1) starts a residency frame, (2) selects the LOD cut within
 * min(budget, GPU cap / bytes per point) points, (3) marks the cut's resident nodes used so the
 * frame's own uploads cannot evict them, (4) takes finished nodes from the loader up to
 * the per-frame upload bytes, admitting each into the residency model (evicting least
 * recently used nodes of earlier frames) or, for a node that failed, recording it as bad
 * and logging it once, (5) asks the loader for the cut's nodes that are neither resident
 * nor bad, in priority order, and (6) lists the cut's resident nodes to draw. The frame
 * never waits for the loader: a missing child is absent and its parent, selected first,
 * stands in for it. Main thread only; the loader's workers never call back.
 */
#ifndef STA_STREAM_STREAMER_H
#define STA_STREAM_STREAMER_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "core/camera.h"
#include "core/status.h"
#include "format/strata_reader.h"
#include "mirror/mirror_set.h"
#include "stream/clip.h"
#include "stream/lod_tree.h"
#include "stream/node_source.h"
#include "stream/select.h"

/* GPU memory for resident nodes when none is given. */
#define STA_DEFAULT_GPU_BYTES_CAP (UINT64_C(1) << 30)

typedef struct sta_streamer sta_streamer;

typedef struct sta_streamer_options {
    uint64_t budget_points;          /* 0: STA_DEFAULT_BUDGET_POINTS per frame */
    uint64_t gpu_bytes_cap;          /* 0: STA_DEFAULT_GPU_BYTES_CAP */
    uint64_t upload_bytes_per_frame; /* 0: 64 MiB */
    int loader_threads;              /* 0: cores - 1 (at least 1) */
    double min_spacing_px;           /* 0: 0.75 (sta_select_params) */
    sta_clip clip;                   /* zero: everything; nodes outside it are neither
                                        selected nor loaded, and loaded nodes keep only
                                        the points that pass (its polygon is borrowed
                                        and must outlive the streamer) */
    const sta_mirror_set *mirrors;   /* NULL, or mirrors whose ghosts are flagged at load in
                                        files without a MIRROR attribute (borrowed, must
                                        outlive the streamer) */
} sta_streamer_options;

/* Fills the zero fields of `options` with their defaults. */
void sta_streamer_options_defaults(sta_streamer_options *options);

/* A finished node to upload this frame: `gpu` holds count points of the GPU layout
 * (stream/gpu_points.h), followed, when the scene has splats (sta_streamer_has_splats),
 * by count splat records (stream/gpu_splats.h); it stays valid until the next
 * sta_streamer_update or close. */
typedef struct sta_stream_upload {
    uint32_t node;
    uint32_t count;
    const uint8_t *gpu;
} sta_stream_upload;

/* What one frame must do, in this order: free `evict`, upload `upload`, draw `draw`.
 * The lists are owned by the streamer and valid until the next update or close. */
typedef struct sta_stream_frame {
    const uint32_t *evict; /* nodes to free on the GPU */
    size_t evict_count;
    const sta_stream_upload *upload; /* nodes to upload, after the evictions */
    size_t upload_count;
    const uint32_t *draw; /* resident nodes of the cut, highest priority first */
    size_t draw_count;
    const uint32_t *new_bad; /* nodes refused for the first time this frame (logged) */
    size_t new_bad_count;
    uint64_t points_selected; /* the cut's points, <= budget and <= GPU cap / bytes per
                                 point (16, or 24 with splats) */
    uint64_t points_drawn;    /* points of the draw list */
    uint32_t nodes_selected;
    uint32_t nodes_resident;
    uint64_t resident_bytes; /* GPU bytes of resident nodes after this frame, <= cap
                                (splat sections included) */
    size_t loader_backlog;   /* nodes wanted but not finished */
    uint32_t bad_nodes;      /* nodes refused so far */
    uint64_t evictions;      /* nodes evicted so far */
    bool complete;           /* every node of the cut is drawn (or refused), none loading */
} sta_stream_frame;

/* Opens the .strata file at `path` (maps and validates it), reads its tree and starts
 * the loader. `options` may be NULL. */
sta_status sta_streamer_open(const char *path, const sta_streamer_options *options,
                             sta_streamer **out_streamer, sta_error *err);

/* A streamer over any node source (tests use a fake one). `tree` is copied; `source` is
 * borrowed and must outlive the streamer; its node_count must equal tree->count. */
sta_status sta_streamer_create(const sta_lod_tree *tree, const sta_node_source *source,
                               const sta_streamer_options *options, sta_streamer **out_streamer,
                               sta_error *err);

/* Stops the loader and frees everything; NULL is a no-op. */
void sta_streamer_close(sta_streamer *streamer);

/* One frame's decisions for `camera` (see Design). */
/* Further views the next cuts must serve as well (mirror reflections: render/pass_mirror.h);
 * copied, at most STA_SELECT_MAX_EXTRA_VIEWS; count 0 for none. */
void sta_streamer_set_extra_views(sta_streamer *streamer, const sta_camera *views, size_t count);

sta_status sta_streamer_update(sta_streamer *streamer, const sta_camera *camera,
                               sta_stream_frame *out_frame, sta_error *err);

/* The options in use, defaults resolved. */
const sta_streamer_options *sta_streamer_options_used(const sta_streamer *streamer);

const sta_lod_tree *sta_streamer_tree(const sta_streamer *streamer);

/* The nodes drawn by the last update (its draw list, valid until the next update),
 * for picking. */
const uint32_t *sta_streamer_last_draw(const sta_streamer *streamer, size_t *out_count);

/* The clip in use (zeroed: none). */
const sta_clip *sta_streamer_clip(const sta_streamer *streamer);

/* Changes the clip between frames (its polygon is borrowed as in the options): the
 * loader is restarted and every resident node is evicted with the next frame (its
 * points were filtered by the old clip), then reloaded as the new cut wants it. Main
 * thread, after the last frame's lists were carried out. Errors: STA_ERR_NOMEM (the
 * loader could not restart; the streamer then must be closed). */
sta_status sta_streamer_set_clip(sta_streamer *streamer, const sta_clip *clip, sta_error *err);

/* Whether the source's nodes carry a splat section (normals and radii, issue 12): then
 * the GPU cap, the upload bytes per frame and the loader's queue count 24 bytes per
 * point instead of 16, so splats cost budget the way the points do. */
bool sta_streamer_has_splats(const sta_streamer *streamer);

/* The .strata reader (owned by the streamer), or NULL for a streamer over another source. */
const sta_strata_reader *sta_streamer_reader(const sta_streamer *streamer);

/* The scene's name in messages: its path, or "nodes" for another source. */
const char *sta_streamer_name(const sta_streamer *streamer);

/* 1 / the largest intensity in the root node (a uniform subsample of the scene), for the
 * intensity colour ramp; 1 / 65535 when unknown. */
float sta_streamer_intensity_scale(const sta_streamer *streamer);

/* Bounds of where most of the scene is: the 1st and 99th percentiles per axis of the
 * root node's points, so a few far stray points do not make the default view tiny.
 * Falls back to the header bounds (or the root's box without a reader). */
void sta_streamer_robust_bounds(const sta_streamer *streamer, double out_min[3], double out_max[3]);

/* Bouchiba's s0 for the last cut, metres: the typical distance between neighbouring
 * points where refinement stops (see docs/DECISIONS.md); 0 for an empty cut. */
double sta_streamer_surface_spacing(sta_streamer *streamer);

#endif
