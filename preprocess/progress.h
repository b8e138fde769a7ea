/* SPDX-License-Identifier: MIT
 * A progress line on the terminal: phase, percentage, points/s, ETA.
 * Quiet when stderr is not a terminal or when disabled.
 */
#ifndef STA_PREPROCESS_PROGRESS_H
#define STA_PREPROCESS_PROGRESS_H

#include <stdatomic.h>
#include <stdbool.h>
#include <stdint.h>

typedef struct sta_progress {
    const char *phase;     /* shown first, e.g. "counting" */
    uint64_t total;        /* units of work in the phase (points) */
    _Atomic uint64_t done; /* atomic: workers add to it */
    double start_s;        /* monotonic clock at phase start */
    double last_print_s;   /* main only */
    bool enabled;          /* draw at all */
} sta_progress;

/* Starts a phase (prints nothing yet). */
void sta_progress_begin(sta_progress *progress, const char *phase, uint64_t total, bool enabled);

/* Adds finished work (any thread). */
void sta_progress_add(sta_progress *progress, uint64_t amount);

/* Redraws the line if 0.25 s have passed (call from one thread only). */
void sta_progress_draw(sta_progress *progress);

/* Ends the phase: erases the line. Returns the phase's duration in seconds. */
double sta_progress_end(sta_progress *progress);

#endif
