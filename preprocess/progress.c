/* SPDX-License-Identifier: MIT
 * Progress line on stderr. */
#include "progress.h"

#include <stdio.h>

#include "core/clock.h"

void sta_progress_begin(sta_progress *progress, const char *phase, uint64_t total, bool enabled)
{
    progress->phase = phase;
    progress->total = total;
    atomic_store(&progress->done, 0);
    progress->start_s = sta_clock_s();
    progress->last_print_s = progress->start_s;
    progress->enabled = enabled;
}

void sta_progress_add(sta_progress *progress, uint64_t amount)
{
    atomic_fetch_add(&progress->done, amount);
}

void sta_progress_draw(sta_progress *progress)
{
    if (!progress->enabled) {
        return;
    }
    double now = sta_clock_s();
    if (now - progress->last_print_s < 0.25) {
        return;
    }
    progress->last_print_s = now;
    uint64_t done = atomic_load(&progress->done);
    double elapsed = now - progress->start_s;
    double rate = elapsed > 0 ? (double)done / elapsed : 0.0;
    double fraction = progress->total ? (double)done / (double)progress->total : 0.0;
    double eta = rate > 0 && progress->total > done ? (double)(progress->total - done) / rate : 0;
    fprintf(stderr, "\r%-12s %5.1f%%  %7.2f M points/s  ETA %d:%02d   ", progress->phase,
            100.0 * fraction, rate * 1e-6, (int)(eta / 60), (int)eta % 60);
    fflush(stderr);
}

double sta_progress_end(sta_progress *progress)
{
    if (progress->enabled) {
        fprintf(stderr, "\r%60s\r", "");
        fflush(stderr);
    }
    return sta_clock_s() - progress->start_s;
}
