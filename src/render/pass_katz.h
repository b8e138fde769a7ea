/* SPDX-License-Identifier: MIT
 * The live Katz HPR mode (`strata-view --hpr katz`, key K): a CPU subsample of the drawn
 * points (stream/point_sample.h) goes to the Katz worker threads (visibility/
 * katz_worker.h); the frame draws the points of the latest complete visibility set that
 * are visible, with the geometry pass's shaders (same colours, one pixel per point, same
 * depth), instead of the whole draw list. The frame never waits for a hull; the set's
 * age in frames is reported. Main thread (GL) only.
 *
 * Design: the subsample (every stride-th GPU record, stride = ceil(points drawn /
 * (sample points x STA_KATZ_VIEW_OVERSAMPLE))) is made on the first enabled frame from the
 * nodes then resident, read back from the GPU cache once, and from then on kept in step
 * with every frame's uploads and evictions, on or off; no reload is needed to turn the
 * mode on. A submission hands these candidates with the camera to the worker, whose
 * thread keeps the nearest in each screen cell, about sample points of them
 * (visibility/katz_cells.h), before the hull; R is the one-point-per-pixel rule's.
 * A new submission is made when the camera or the draw list changed since the last one;
 * a newer submission replaces one that no thread has started. When a new set arrives,
 * its visible records are copied (grouped by node) into one vertex buffer, so nodes
 * evicted since still draw until the next set.
 * Based on: Braga et al., section 5 (front and back buffers, the hull on its own thread).
 */
#ifndef STA_RENDER_PASS_KATZ_H
#define STA_RENDER_PASS_KATZ_H

#include <epoxy/gl.h>
#include <stdbool.h>
#include <stdint.h>

#include "core/camera.h"
#include "core/status.h"
#include "render/gpu_cache.h"
#include "render/pass_geometry.h"
#include "render/target.h"
#include "stream/gpu_points.h"
#include "stream/point_sample.h"
#include "stream/streamer.h"
#include "visibility/katz_worker.h"

/* Default depth tolerance of Katz's radius rule, in units of the scene's spacing s0. */
#define STA_KATZ_VIEW_DEFAULT_TOLERANCE 3.0
/* Candidates gathered per point handed to the hull: the screen cells keep the nearest. */
#define STA_KATZ_VIEW_OVERSAMPLE        8.0

/* Options. Zero means default (sta_katz_view_options_defaults). */
typedef struct sta_katz_view_options {
    bool enabled;           /* draw the live Katz set instead of the whole draw list */
    uint64_t sample_points; /* points per hull (screen cells); 0: STA_DEFAULT_KATZ_SAMPLE_POINTS */
    int threads;            /* hull threads; 0: STA_KATZ_WORKER_DEFAULT_THREADS */
    double perturbation;    /* Braga's perturbation (sta_katz_params); 0: none */
    double tolerance;       /* R's depth tolerance in the scene's spacing s0; 0: default */
    double oversample;      /* candidates per hull point; 0: STA_KATZ_VIEW_OVERSAMPLE */
    bool compare_plain;     /* also time the plain hull on each input (with perturbation) */
} sta_katz_view_options;

/* The live set as a frame sees it. */
typedef struct sta_katz_frame_stats {
    uint64_t generation;  /* of the set drawn (0: none yet) */
    uint64_t age_frames;  /* frames since its points were submitted */
    uint64_t points;      /* points of the set */
    uint64_t visible;     /* of those, visible (drawn) */
    double hull_ms;       /* its hull's wall time */
    double plain_hull_ms; /* compare_plain: the plain hull's on the same input; else 0 */
    double radius_m;      /* Katz's R used */
    bool current;         /* the set is of the last submission (nothing newer pending) */
} sta_katz_frame_stats;

typedef struct sta_pass_katz {
    sta_katz_view_options options;
    uint32_t node_count;
    sta_point_sample *sample; /* from the first enabled frame, then kept in step */
    sta_katz_worker *worker;  /* from the first enabled frame */
    double origin[3];         /* sample positions are relative to this, metres */
    float (*points)[3];       /* gather scratch, `capacity` */
    uint64_t *tags;
    size_t capacity;
    uint64_t frame;          /* frames seen */
    uint64_t submitted;      /* generation of the last submission (0: none) */
    sta_camera last_camera;  /* of the last submission */
    uint64_t last_signature; /* of the last submission's draw list */
    double last_radius_m;
    uint64_t drawn_generation;     /* of the set in `buffer` */
    uint64_t last_frame_of_set;    /* the frame its points were submitted in */
    const sta_katz_set *drawn_set; /* the worker's front set, drawn from `buffer` */
    sta_katz_frame_stats last;     /* of the set in `buffer` */
    uint8_t *records;              /* staged visible records */
    size_t records_capacity;       /* in records */
    struct sta_katz_range {
        uint32_t node, first, count;
    } * ranges; /* runs of one node's records in `buffer` */
    size_t range_count, range_capacity;
    sta_pass_geometry geometry; /* the geometry pass's program, for drawing the set */
    GLuint buffer;
} sta_pass_katz;

/* Fills the zero fields of `options` with defaults, in place. */
void sta_katz_view_options_defaults(sta_katz_view_options *options);

/* A pass for a scene of `node_count` nodes, positions relative to `origin`; nothing is
 * allocated and no GL is called until the first enabled frame. options: NULL for
 * defaults (off). */
void sta_pass_katz_init(sta_pass_katz *pass, uint32_t node_count, const double origin[3],
                        const sta_katz_view_options *options);

/* Stops the threads and frees everything (GL objects too: the context must be current if
 * the mode was ever on). A zeroed pass is a no-op. */
void sta_pass_katz_release(sta_pass_katz *pass);

/* Turns the mode on or off and sets the other options (a new sample_points remakes the
 * subsample on the next enabled frame). */
void sta_pass_katz_set_options(sta_pass_katz *pass, const sta_katz_view_options *options);

/* Keeps the subsample in step with a streamer frame; call with every frame. */
sta_status sta_pass_katz_apply(sta_pass_katz *pass, const sta_stream_frame *frame, sta_error *err);

/* One frame of the mode: submits the draw list's subsample when the camera or the list
 * changed, takes the newest set, and draws its visible points into `target` (cleared
 * first). s0_m: the full draw list's sampling scale (metres). */
sta_status sta_pass_katz_frame(sta_pass_katz *pass, const sta_camera *camera,
                               const sta_geometry_colours *colours,
                               const sta_gpu_node_frame *frames, const sta_stream_frame *frame,
                               const sta_gpu_cache *cache, double s0_m, sta_render_target *target,
                               sta_katz_frame_stats *out_stats, sta_error *err);

/* The set last drawn (NULL before the first), its positions relative to sta_pass_katz's
 * origin; valid until the next frame. For the benchmark. */
const sta_katz_set *sta_pass_katz_set(const sta_pass_katz *pass);

#endif
