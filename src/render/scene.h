/* SPDX-License-Identifier: MIT
 * A .strata scene on screen: each frame the streamer (stream/streamer.h) decides what
 * to evict, upload and draw within the point budget and GPU cap; the GPU cache carries
 * out the evictions and uploads, the geometry pass draws, and the screen-space pipeline
 * runs after it. The frame never waits for disk. Main thread (GL) only.
 */
#ifndef STA_RENDER_SCENE_H
#define STA_RENDER_SCENE_H

#include <stdbool.h>
#include <stdint.h>

#include "core/camera.h"
#include "core/status.h"
#include "format/strata_reader.h"
#include "render/pass_geometry.h"
#include "render/pass_katz.h"
#include "render/pass_mirror.h"
#include "render/pass_splats.h"
#include "render/pipeline.h"
#include "render/target.h"
#include "stream/gpu_points.h"
#include "stream/streamer.h"

typedef struct sta_scene sta_scene;

/* Budget, GPU cap, uploads per frame, loader threads: the streamer's options. */
typedef sta_streamer_options sta_scene_options;

typedef struct sta_frame_stats {
    uint64_t points_selected; /* <= budget */
    uint64_t points_drawn;    /* <= points_selected */
    uint32_t nodes_selected;
    uint32_t nodes_drawn;
    uint32_t nodes_resident;
    uint32_t uploads;   /* nodes uploaded this frame */
    uint64_t gpu_bytes; /* resident */
    size_t loader_backlog;
    uint32_t bad_nodes;         /* nodes refused (corrupt) so far */
    uint64_t evictions;         /* nodes evicted from the GPU cache so far */
    float s0_m;                 /* sampling scale used by the screen-space passes, metres */
    double geometry_ms;         /* GPU time of the geometry pass (when timing is on) */
    double geometry_cpu_ms;     /* CPU time of the process over that pass (timing on): on
                                   llvmpipe the work of its threads, steadier than the wall
                                   time on a busy machine */
    sta_pipeline_timing timing; /* screen-space passes (when timing is on) */
    bool raster_positions;      /* the compute rasteriser wrote the camera-space positions
                                   and the pipeline skipped its unproject pass */
    bool complete;              /* every selected node is resident (or refused), and in the
                                   live Katz mode the set drawn is of this view */
    sta_katz_frame_stats katz;  /* live Katz mode (zero when off) */
} sta_frame_stats;

/* Opens `path` (maps it, validates it, starts the loader). Needs a current GL 4.5
 * context. */
sta_status sta_scene_open(const char *path, const sta_scene_options *options, sta_scene **out_scene,
                          sta_error *err);

void sta_scene_close(sta_scene *scene);

const sta_strata_info *sta_scene_info(const sta_scene *scene);

/* The scene's streamer (draw list, reader, clip: what picking needs). */
const sta_streamer *sta_scene_streamer(const sta_scene *scene);

/* Ranges of the colour ramps: elevation from `elevation_min` to `elevation_max` metres
 * (max <= min: the scene's bounds), intensity up to `intensity_max` (<= 0: the largest
 * of the root node). */
void sta_scene_set_ramps(sta_scene *scene, double elevation_min, double elevation_max,
                         double intensity_max);

/* Changes the clip and filters (sta_streamer_set_clip): nodes are reloaded. */
sta_status sta_scene_set_clip(sta_scene *scene, const sta_clip *clip, sta_error *err);

/* Bounds of where most of the scene is (sta_streamer_robust_bounds). */
void sta_scene_robust_bounds(const sta_scene *scene, double out_min[3], double out_max[3]);

/* Sets the screen-space pipeline run after the geometry pass (mode raw by default). */
void sta_scene_set_pipeline(sta_scene *scene, const sta_pipeline_options *options);

/* Sets the geometry pass's rasteriser (compute by default); it is built, and its choice
 * logged, at the next render. */
void sta_scene_set_raster(sta_scene *scene, const sta_geometry_options *options);

/* Sets the size of the points (render/point_size.h; NULL: one pixel, the default) in the
 * raw and EDL modes; the other modes, and the live Katz mode, draw one pixel per point. */
void sta_scene_set_point_size(sta_scene *scene, const sta_point_size *size);

/* The rasteriser the geometry pass runs and why; NULL before the first render. */
const sta_geometry_choice *sta_scene_raster_choice(const sta_scene *scene);

/* The splat method the scene draws with ("instanced", "geometry", "pulled"), once its
 * splat pass is built by a frame that draws splats; NULL before. */
const char *sta_scene_splat_method(const sta_scene *s);

/* Sets the splat pass's options (method, scale; render/pass_splats.h), used in the
 * splats pipeline mode; a new method is built at the next render. */
void sta_scene_set_splats(sta_scene *scene, const sta_splat_options *options);

/* Whether the scene's nodes carry normals and radii (converted with --normals). The
 * splats mode of a scene without them draws the shaded pipeline instead and says so
 * once in the log. */
bool sta_scene_has_splats(const sta_scene *scene);

/* The GPU cache (resident nodes' arenas), for reading back what was drawn. */
const sta_gpu_cache *sta_scene_gpu_cache(const sta_scene *scene);

/* Turns per-pass timing on (times in sta_frame_stats; drains the GPU around each pass). */
void sta_scene_set_timing(sta_scene *scene, bool on);

/* The clock of those times (sta_timing_clock in render/pipeline.h; default wall). */
void sta_scene_set_timing_clock(sta_scene *scene, int clock);

/* Points whose GPU flags (stream/gpu_points.h) have any of `flags` are not drawn;
 * STA_SCENE_DEFAULT_HIDE_FLAGS (mirror ghosts hidden) until set. */
#define STA_SCENE_DEFAULT_HIDE_FLAGS STA_GPU_FLAG_MIRROR_GHOST
void sta_scene_set_hide_flags(sta_scene *scene, unsigned flags);

/* Mirrors to draw by reflection (render/pass_mirror.h), borrowed until set again or
 * close; NULL or `reflect` false: none. Only vertical mirrors seen from the front are
 * drawn, at most STA_SELECT_MAX_EXTRA_VIEWS per frame (docs/MIRRORS.md). */
void sta_scene_set_mirrors(sta_scene *scene, const sta_mirror_set *mirrors, bool reflect);

/* Sets the colour mode (STA_COLOUR_* of render/bindings.h). */
void sta_scene_set_colour_mode(sta_scene *scene, int mode);

/* The screen-space pipeline of the last frame, for reading its intermediate buffers
 * (position, label, filled_position, normal textures) in benchmarks and tests. NULL
 * until a frame has run a mode other than raw. Owned by the scene; valid until the
 * next render or close. */
const sta_pipeline *sta_scene_pipeline(const sta_scene *scene);

/* The pipeline mode last set (sta_pipeline_mode). */
int sta_scene_pipeline_mode(const sta_scene *scene);

/* The live Katz HPR mode (render/pass_katz.h): on, off, options. */
void sta_scene_set_katz(sta_scene *scene, const sta_katz_view_options *options);

/* The live Katz pass (its set and origin, for the benchmark). */
const sta_pass_katz *sta_scene_katz(const sta_scene *scene);

/* Renders one frame into `target` (resized to the camera's viewport). */
sta_status sta_scene_render(sta_scene *scene, const sta_camera *camera, sta_render_target *target,
                            sta_frame_stats *out_stats, sta_error *err);

#endif
