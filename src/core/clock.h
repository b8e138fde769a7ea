/* SPDX-License-Identifier: MIT
 * Clocks for timing: monotonic wall time, the calling thread's and the process's CPU time.
 *
 * Values are only meaningful as differences between two reads of the same clock; the
 * origin is unspecified. All functions are thread-safe.
 */
#ifndef STA_CORE_CLOCK_H
#define STA_CORE_CLOCK_H

/* Monotonic wall-clock time in seconds (CLOCK_MONOTONIC): never goes back, not changed by
 * setting the system time. Non-negative. */
double sta_clock_s(void);

/* The same clock as sta_clock_s in milliseconds. Non-negative. */
double sta_clock_ms(void);

/* CPU time consumed by the calling thread in milliseconds (CLOCK_THREAD_CPUTIME_ID).
 * Non-negative and non-decreasing within one thread; compare reads from one thread only. */
double sta_clock_thread_cpu_ms(void);

/* CPU time consumed by all threads of the process in milliseconds
 * (CLOCK_PROCESS_CPUTIME_ID). Around a drained GPU pass on a software rasteriser whose
 * worker threads run in the process (llvmpipe), the difference is the work the pass
 * took, which a busy machine does not inflate as it does wall time. Non-negative. */
double sta_clock_process_cpu_ms(void);

#endif
