/* SPDX-License-Identifier: MIT
 * Live Katz HPR: worker threads run the flip + hull (katz_hpr.h) on the latest submitted
 * points while the caller keeps drawing with the last complete visibility set. No GL: the
 * caller submits positions and reads flags; render/ draws them.
 *
 * Design: one mutex guards only pointer swaps and counters; copying, allocation and the
 * hull run outside it, so neither side ever waits for the other's work.
 *   request: the caller fills its staging buffer, then swaps it with the pending slot
 *            (a newer submission replaces a pending one that no thread has started);
 *            a free thread swaps the pending slot with its own work buffer.
 *   result:  each thread computes into its back set, then swaps it with the ready slot
 *            if its request is newer than the ready and the front sets (an older result
 *            that finishes late is dropped); the caller's acquire swaps ready with its
 *            front set. A set is only ever written by the one thread that holds it, so
 *            the caller never sees a torn set (Braga et al.'s front and back buffers,
 *            with a third slot so that publishing never waits for the reader).
 * Lock order: only `lock`. Threads are named "sta-katz-<n>".
 *
 * Based on: R. Braga et al., "Evaluating the visibility algorithm of point-based graphics
 * for real-time applications", section 5 (an auxiliary thread computes HPR into a back
 * buffer; a flag tells the main thread to take it as the front buffer).
 */
#ifndef STA_VISIBILITY_KATZ_WORKER_H
#define STA_VISIBILITY_KATZ_WORKER_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "core/camera.h"
#include "core/status.h"
#include "visibility/katz_cells.h"
#include "visibility/katz_hpr.h"

/* Default number of hull threads. */
#define STA_KATZ_WORKER_DEFAULT_THREADS 1
/* Most hull threads. */
#define STA_KATZ_WORKER_MAX_THREADS     16

/* Configuration. Zero means default (sta_katz_worker_config_defaults). */
typedef struct sta_katz_worker_config {
    int thread_count;       /* hull threads, 1..STA_KATZ_WORKER_MAX_THREADS; 0: default */
    sta_katz_params params; /* operator parameters (zero: the exact operator); a request's
                               radius_m, when above 0, replaces params.radius_m */
    bool compare_plain;     /* when params.perturbation > 0: also run the plain hull on the
                               same input and report its time (sta_katz_set.plain_hull_ms) */
} sta_katz_worker_config;

/* One complete visibility set. Owned by the worker; read-only to the caller. */
typedef struct sta_katz_set {
    uint64_t generation;      /* the request's submission number (1, 2, ...); 0: no set yet */
    uint64_t frame;           /* the caller's frame number given with the request */
    size_t count;             /* points of the request (after the cells, when used) */
    size_t candidates;        /* points submitted (before the cells) */
    double cell_px;           /* sta_katz_worker_submit_view: the cells' side; else 0 */
    float (*points)[3];       /* count positions as submitted (those the cells kept) */
    uint64_t *tags;           /* count tags as submitted (the index when none were given) */
    uint8_t *visible;         /* count flags: 1 visible */
    size_t visible_count;     /* flags set */
    double viewpoint[3];      /* as submitted */
    sta_katz_stats stats;     /* of the hull that made the flags */
    double plain_hull_ms;     /* compare_plain: wall time of the plain hull; else 0 */
    double plain_hull_cpu_ms; /* compare_plain: its CPU time; else 0 */
    size_t capacity;          /* allocated points (worker private) */
} sta_katz_set;

/* What the worker has done (sta_katz_worker_counters). */
typedef struct sta_katz_worker_counters {
    uint64_t submitted; /* requests submitted */
    uint64_t replaced;  /* requests replaced by a newer one before any thread took them */
    uint64_t computed;  /* hulls finished */
    uint64_t dropped;   /* results older than the published set, not published */
    uint64_t published; /* sets made ready */
    uint64_t failed;    /* hulls that failed (the error: sta_katz_worker_take_error) */
} sta_katz_worker_counters;

typedef struct sta_katz_worker sta_katz_worker;

/* Fills the zero fields of `config` with defaults, in place (thread_count; params through
 * sta_katz_params_defaults). */
void sta_katz_worker_config_defaults(sta_katz_worker_config *config);

/* Starts the threads. config: NULL for defaults. *out: owned by the caller
 * (sta_katz_worker_destroy). Returns STA_ERR_ARG for a bad configuration, STA_ERR_NOMEM,
 * or STA_ERR_IO when a thread cannot be started. */
sta_status sta_katz_worker_create(const sta_katz_worker_config *config, sta_katz_worker **out,
                                  sta_error *err);

/* Stops and joins the threads (a hull in progress finishes first) and frees everything,
 * including the sets handed out. NULL is a no-op. */
void sta_katz_worker_destroy(sta_katz_worker *worker);

/* Hands `count` positions and their tags (copied; borrowed for the call; tags may be
 * NULL, then a point's tag is its index; the caller's way back from a set to its points)
 * and the viewpoint to the threads; radius_m > 0 replaces the configured R (sta_katz_view_radius),
 * 0 keeps it. frame: the caller's frame number, returned in the set (for its age). Never waits for
 * a hull. Returns STA_ERR_ARG for NULL or non-finite input, STA_ERR_NOMEM. One caller thread only
 * (the same that acquires). */
sta_status sta_katz_worker_submit(sta_katz_worker *worker, const float (*points)[3],
                                  const uint64_t *tags, size_t count, const double viewpoint[3],
                                  double radius_m, uint64_t frame, sta_error *err);

/* As sta_katz_worker_submit for the points of a view: `camera` in world coordinates,
 * points relative to `origin`; the thread first keeps the nearest point of each screen
 * cell, at most `cell_cap` (> 0) of them (katz_cells.h), then runs the hull on those, so
 * the caller's frame does not pay for the selection. STA_ERR_ARG also for a camera that is
 * no view (size, fov in (0, pi), near > 0). */
sta_status sta_katz_worker_submit_view(sta_katz_worker *worker, const float (*points)[3],
                                       const uint64_t *tags, size_t count, const sta_camera *camera,
                                       const double origin[3], size_t cell_cap, double radius_m,
                                       uint64_t frame, sta_error *err);

/* The newest complete set: *out points to the caller's front set, valid until the next
 * acquire or destroy; generation 0 until the first result. Returns true when the set is
 * newer than the one the last acquire returned. Never waits for a hull. Caller thread. */
bool sta_katz_worker_acquire(sta_katz_worker *worker, const sta_katz_set **out);

/* Whether a request is pending or being computed. */
bool sta_katz_worker_is_busy(sta_katz_worker *worker);

/* Copies the counters. Any thread. */
void sta_katz_worker_counters_get(sta_katz_worker *worker, sta_katz_worker_counters *out);

/* The error of the last failed hull since the previous call: returns its status and sets
 * err, or STA_OK when none failed. */
sta_status sta_katz_worker_take_error(sta_katz_worker *worker, sta_error *err);

#endif
