/* SPDX-License-Identifier: MIT
 * Clocks for timing. */
#include "core/clock.h"

#include <time.h>

static struct timespec read_clock(clockid_t clock)
{
    struct timespec ts;
    // Both clocks exist on every POSIX system we build on; a failure would be our bug.
    if (clock_gettime(clock, &ts) != 0) {
        ts.tv_sec = 0;
        ts.tv_nsec = 0;
    }
    return ts;
}

double sta_clock_s(void)
{
    struct timespec ts = read_clock(CLOCK_MONOTONIC);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

double sta_clock_ms(void)
{
    struct timespec ts = read_clock(CLOCK_MONOTONIC);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

double sta_clock_process_cpu_ms(void)
{
    struct timespec ts = read_clock(CLOCK_PROCESS_CPUTIME_ID);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

double sta_clock_thread_cpu_ms(void)
{
    struct timespec ts = read_clock(CLOCK_THREAD_CPUTIME_ID);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}
