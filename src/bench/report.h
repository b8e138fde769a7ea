/* SPDX-License-Identifier: MIT
 * Benchmark output: results.csv (one header line, one line per row) and results.json
 * (an object with the run's context and an array of rows), the same columns in both,
 * in the order of docs/BENCH.md.
 */
#ifndef STA_BENCH_REPORT_H
#define STA_BENCH_REPORT_H

#include "bench/sweep.h"
#include "core/status.h"

/* Writes `results` as CSV. Numbers in shortest round-trip form; NaN (not measured)
 * as an empty field; infinite PSNR as "inf". */
sta_status sta_bench_write_csv(const char *path, const sta_bench_results *results, sta_error *err);

/* Writes {"tool": "strata-bench", "renderer": ..., "rows": [ {column: value} ]}; NaN
 * and infinities are null (psnr_db is null for identical images: see identical). */
sta_status sta_bench_write_json(const char *path, const char *renderer,
                                const sta_bench_results *results, sta_error *err);

/* Creates `dir` (and parents) and writes results.csv and results.json in it. */
sta_status sta_bench_write_reports(const char *dir, const char *renderer,
                                   const sta_bench_results *results, sta_error *err);

#endif
