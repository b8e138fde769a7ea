/* SPDX-License-Identifier: MIT
 * Clocks for timing: monotonic wall time and the CPU time of the calling thread or of
 * the whole process.
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

/* CPU time consumed by all threads of the process in milliseconds
 * (CLOCK_PROCESS_CPUTIME_ID): with a software GL driver, its threads' work too. */
double sta_clock_process_cpu_ms(void);

/* CPU time consumed by the calling thread in milliseconds (CLOCK_THREAD_CPUTIME_ID).
 * Non-negative and non-decreasing within one thread; compare reads from one thread only. */
double sta_clock_thread_cpu_ms(void);

#endif
