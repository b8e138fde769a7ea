/* SPDX-License-Identifier: MIT
 * strata-convert: LAS / PLY files in, one .strata LOD hierarchy out.
 */
#include <inttypes.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "convert.h"
#include "core/cli.h"
#include "core/log.h"
#include "format/layout.h"
#include "format/strata_writer.h"
#include "knn_normals.h"
#include "moment_normals.h"

static atomic_bool cancel_requested;

static void on_signal(int signal_number)
{
    (void)signal_number;
    atomic_store(&cancel_requested, true);
}

static const char usage_text[] =
    "usage: strata-convert [options] INPUT... -o OUTPUT.strata\n"
    "\n"
    "Builds a nested-octree LOD hierarchy (one memory-mappable .strata file) from\n"
    "LAS 1.0-1.4 and PLY files, out of core and in bounded memory. Several inputs\n"
    "(tiles of one survey) merge into one scene. Every input point is stored exactly\n"
    "once, on the input's integer grid (lossless).\n";

static const char exit_text[] =
    "exit status: 0 done, 1 failed (nothing written), 2 bad usage, 130 interrupted\n";

int main(int argc, char **argv)
{
    // The defaults, shown by --help from here (convert.c resolves 0 to the same values).
    sta_convert_options options = { .compress_level = STA_CONVERT_DEFAULT_ZSTD_LEVEL,
                                    .grid_cells = (int)STA_STRATA_DEFAULT_CELLS,
                                    .progress = true };
    int memory_mib = 0; // the machine's default (sta_convert_default_memory_mib)
    int leaf_capacity = STA_CONVERT_DEFAULT_LEAF_CAPACITY;
    options.knn = STA_NORMALS_DEFAULT_K;
    int attributes = -1; // index into attribute_names
    bool quiet = false;
    static const char *const attribute_names[] = { "extra", NULL };
    static const char *const method_names[] = { "moments", "knn", "moments-fine", NULL };
    int method = STA_NORMALS_MOMENTS; // index into method_names = sta_normals_method
    const sta_cli_option table[] = {
        { .name = "output",
          .short_name = 'o',
          .kind = STA_CLI_STRING,
          .dest = &options.output,
          .metavar = "FILE",
          .help = "the .strata file to write (required)" },
        { .name = "threads",
          .kind = STA_CLI_INT,
          .dest = &options.threads,
          .metavar = "N",
          .int_min = 1,
          .int_max = 256,
          .help = "worker threads",
          .default_text = "all cores" },
        { .name = "memory",
          .kind = STA_CLI_INT,
          .dest = &memory_mib,
          .metavar = "MIB",
          .int_min = 64,
          .int_max = 1 << 24,
          .help = "memory budget for the whole process (points that fit skip the "
                  "temporary file; with --normals, chunks too rough to share it run alone, "
                  "and one that cannot fit even alone stops with the --memory it needs)",
          .default_text = "a quarter of the RAM, 2048 to 16384" },
        { .name = "tmp",
          .kind = STA_CLI_STRING,
          .dest = &options.tmp_dir,
          .metavar = "DIR",
          .help = "folder for the temporary file",
          .default_text = "the output's" },
        { .name = "compress",
          .kind = STA_CLI_INT,
          .dest = &options.compress_level,
          .metavar = "LEVEL",
          .int_min = 0,
          .int_max = 19,
          .help = "zstd level, 0 = store uncompressed" },
        { .name = "grid",
          .kind = STA_CLI_INT,
          .dest = &options.grid_cells,
          .metavar = "CELLS",
          .int_min = 16,
          .int_max = 1024,
          .help = "grid cells per node axis, a power of two" },
        { .name = "leaf",
          .kind = STA_CLI_INT,
          .dest = &leaf_capacity,
          .metavar = "POINTS",
          .int_min = 16,
          .int_max = 1 << 24,
          .help = "points a leaf holds before it splits" },
        { .name = "attributes",
          .kind = STA_CLI_CHOICE,
          .dest = &attributes,
          .metavar = "extra",
          .choices = attribute_names,
          .help = "also keep LAS extra dimensions (extra bytes)" },
        { .name = "mirrors",
          .kind = STA_CLI_STRING,
          .dest = &options.mirrors,
          .metavar = "FILE",
          .help = "mirror file (docs/MIRRORS.md): flag the ghost points behind its mirrors in "
                  "the MIRROR attribute; every point is kept" },
        { .name = "normals",
          .kind = STA_CLI_FLAG,
          .dest = &options.normals,
          .help = "compute a normal and a splat radius per point (plane fit)" },
        { .name = "normals-method",
          .kind = STA_CLI_CHOICE,
          .dest = &method,
          .metavar = "moments|knn|moments-fine",
          .choices = method_names,
          .help = "--normals from boxes of cell moments sized by the data, from the exact K "
                  "nearest (slower), or from moments with cells half as wide everywhere "
                  "(~1.4x the CPU); docs/CONVERTER.md" },
        { .name = "knn",
          .kind = STA_CLI_INT,
          .dest = &options.knn,
          .metavar = "K",
          .int_min = 3,
          .int_max = STA_NORMALS_MAX_K,
          .help = "neighbours of each point for --normals (moments: a point starts where its "
                  "cells hold K/10 points, at least 1; moments-fine: K)" },
        { .name = "salvage",
          .kind = STA_CLI_FLAG,
          .dest = &options.salvage,
          .help = "convert the complete points of truncated inputs" },
        { .name = "force",
          .kind = STA_CLI_FLAG,
          .dest = &options.force,
          .help = "overwrite OUTPUT if it exists" },
        { .name = "quiet",
          .short_name = 'q',
          .kind = STA_CLI_FLAG,
          .dest = &quiet,
          .help = "no progress line, no summary, no warnings" },
        { .name = NULL },
    };
    const sta_cli cli = {
        .program = "strata-convert", .usage = usage_text, .epilog = exit_text, .options = table
    };
    sta_cli_result r;
    int rc = sta_cli_parse_main(&cli, argc, argv, &r);
    if (rc >= 0) {
        return rc;
    }
    if ((options.grid_cells & (options.grid_cells - 1)) != 0) {
        return sta_cli_usage_error(&cli, "--grid must be a power of two, got %d",
                                   options.grid_cells);
    }
    if (options.compress_level == 0) {
        options.compress_level = STA_CONVERT_STORE; // "--compress 0": zero means default below
    }
    options.memory_mib = (size_t)memory_mib;
    options.leaf_capacity = (size_t)leaf_capacity;
    options.keep_extra = attributes == 0;
    options.normals_method = (sta_normals_method)method;
    if (r.positional_count == 0 || !options.output) {
        return sta_cli_usage_error(&cli, "%s",
                                   r.positional_count == 0 ? "no input files"
                                                           : "no output file (-o OUTPUT.strata)");
    }
    size_t input_count = (size_t)r.positional_count;
    const char *const *inputs = (const char *const *)r.positional;
    if (quiet) {
        sta_log_set_level(STA_LOG_QUIET);
    }
    options.inputs = inputs;
    options.input_count = input_count;
    options.progress = !quiet && sta_log_is_terminal();
    options.cancel = &cancel_requested;
    struct sigaction action;
    memset(&action, 0, sizeof(action));
    action.sa_handler = on_signal;
    sigaction(SIGINT, &action, NULL);
    sigaction(SIGTERM, &action, NULL);
    sigaction(SIGHUP, &action, NULL);

    sta_convert_keep_heap(); // (refused: the same output, only slower)
    sta_convert_report report;
    sta_error err = { 0 };
    sta_convert_options_defaults(&options); // the machine's threads and memory, for the summary
    sta_status status = sta_convert(&options, &report, &err);
    if (status == STA_ERR_CANCELLED) {
        fprintf(stderr, "strata-convert: interrupted; nothing written\n");
        return 130;
    }
    if (status != STA_OK) {
        fprintf(stderr, "strata-convert: %s\n", err.message);
        return 1;
    }
    if (!quiet) {
        double ratio =
            report.stored_bytes ? (double)report.raw_bytes / (double)report.stored_bytes : 1.0;
        fprintf(stderr,
                "%s: %" PRIu64 " points, %" PRIu32 " nodes, %d levels, %.1f MiB "
                "(compression %.2fx), %.2f s (%.2f M points/s)\n",
                options.output, report.point_count, report.node_count, report.max_level + 1,
                (double)report.stored_bytes / 1048576.0, ratio, report.seconds_total,
                report.seconds_total > 0 ? (double)report.point_count / report.seconds_total * 1e-6
                                         : 0.0);
        fprintf(stderr,
                "  phases: count %.2f s, distribute %.2f s, index %.2f s, merge %.2f s, "
                "finish %.2f s; %zu chunks, %.0f MiB temporary%s\n",
                report.seconds_count, report.seconds_distribute, report.seconds_index,
                report.seconds_merge, report.seconds_finish, report.chunk_count,
                (double)report.temp_bytes / 1048576.0,
                report.records_in_memory ? " (records kept in memory)" : "");
        fprintf(stderr, "  budget: --memory %zu MiB, %d threads\n", options.memory_mib,
                options.threads);
        fprintf(stderr,
                "  CPU (all threads): count %.2f s, distribute %.2f s, index %.2f s, merge "
                "%.2f s, finish %.2f s\n",
                report.cpu_count, report.cpu_distribute, report.cpu_index, report.cpu_merge,
                report.cpu_finish);
        fprintf(stderr, "  up axis: %s\n", report.up_why);
        if (options.normals && options.normals_method != STA_NORMALS_KNN) {
            fprintf(stderr,
                    "  normals: cell moments, start at cells of %d+ points (K = %d), halo pass "
                    "%.2f s; %" PRIu64 " fallback (degenerate), %" PRIu64
                    " boxes grown (nearly linear, edge-on or degenerate), %" PRIu64
                    " boxes wider than the halo; walls face %s\n",
                    sta_moment_normals_need(options.normals_method, options.knn), options.knn,
                    report.seconds_halo, report.normals_degenerate, report.normals_widened,
                    report.normals_beyond_halo,
                    report.normals_trajectory ? "the scanner path (GPS time)"
                                              : "away from the scene's vertical centre line");
        } else if (options.normals) {
            fprintf(stderr,
                    "  normals: K = %d, halo pass %.2f s; %" PRIu64
                    " fallback (degenerate), %" PRIu64
                    " widened (nearly linear, thick or edge-on; %" PRIu64
                    " to the %d nearest, the others to a box of cells), %" PRIu64
                    " neighbourhoods wider than the halo; walls face %s\n",
                    options.knn, report.seconds_halo, report.normals_degenerate,
                    report.normals_widened, report.normals_widened_exact,
                    sta_normals_widest_k(options.knn), report.normals_beyond_halo,
                    report.normals_trajectory ? "the scanner path (GPS time)"
                                              : "away from the scene's vertical centre line");
        }
        if (options.normals) {
            fprintf(stderr,
                    "  normals memory: %.0f MiB for all workers' normals, %.0f MiB the most "
                    "a chunk took; %zu chunks ran alone; workers waited %.2f s\n",
                    (double)report.normals_pool_bytes / 1048576.0,
                    (double)report.normals_chunk_peak_bytes / 1048576.0, report.normals_alone,
                    report.normals_waited_s);
        }
    }
    return 0;
}
