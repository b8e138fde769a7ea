/* SPDX-License-Identifier: MIT
 * strata-convert: LAS / PLY files in, one .strata LOD hierarchy out.
 */
#include <errno.h>
#include <inttypes.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "convert.h"
#include "core/alloc.h"
#include "core/log.h"

static atomic_bool cancel_requested;

static void on_signal(int signal_number)
{
    (void)signal_number;
    atomic_store(&cancel_requested, true);
}

static void print_usage(FILE *out)
{
    fputs("usage: strata-convert [options] INPUT... -o OUTPUT.strata\n"
          "\n"
          "Builds a nested-octree LOD hierarchy (one memory-mappable .strata file) from\n"
          "LAS 1.0-1.4 and PLY files, out of core and in bounded memory. Several inputs\n"
          "(tiles of one survey) merge into one scene. Every input point is stored exactly\n"
          "once, on the input's integer grid (lossless).\n"
          "\n"
          "options:\n"
          "  -o, --output FILE      the .strata file to write (required)\n"
          "  --threads N            worker threads (default: all cores)\n"
          "  --memory MIB           memory budget for the whole process (default 2048)\n"
          "  --tmp DIR              folder for the temporary file (default: the output's)\n"
          "  --compress LEVEL       zstd level 1-19, 0 = store uncompressed (default 3)\n"
          "  --grid CELLS           grid cells per node axis, power of two 16-1024\n"
          "                         (default 128)\n"
          "  --leaf POINTS          points a leaf holds before it splits (default 32768)\n"
          "  --attributes extra     also keep LAS extra dimensions (extra bytes)\n"
          "  --salvage              convert the complete points of truncated inputs\n"
          "  --force                overwrite OUTPUT if it exists\n"
          "  -q, --quiet            no progress line, no summary, no warnings\n"
          "  -h, --help             this text\n"
          "\n"
          "exit status: 0 done, 1 failed (nothing written), 2 bad usage, 130 interrupted\n",
          out);
}

static int parse_long(const char *option, const char *text, long lo, long hi, long *out)
{
    char *end = NULL;
    errno = 0;
    long v = text ? strtol(text, &end, 10) : 0;
    if (!text || errno || end == text || *end != '\0' || v < lo || v > hi) {
        fprintf(stderr, "strata-convert: %s needs a whole number from %ld to %ld, got '%s'\n",
                option, lo, hi, text ? text : "");
        return 0;
    }
    *out = v;
    return 1;
}

int main(int argc, char **argv)
{
    sta_convert_options options = { .compress_level = 3, .progress = true };
    const char **inputs = sta_calloc((size_t)argc, sizeof(*inputs));
    if (!inputs) {
        return 1;
    }
    size_t input_count = 0;
    bool quiet = false;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        const char *value = i + 1 < argc ? argv[i + 1] : NULL;
        long v = 0;
        if (strcmp(a, "-h") == 0 || strcmp(a, "--help") == 0) {
            print_usage(stdout);
            sta_free(inputs);
            return 0;
        } else if (strcmp(a, "-o") == 0 || strcmp(a, "--output") == 0) {
            if (!value) {
                fprintf(stderr, "strata-convert: %s needs a file name\n", a);
                goto usage_error;
            }
            options.output = value;
            i++;
        } else if (strcmp(a, "--threads") == 0) {
            if (!parse_long(a, value, 1, 256, &v)) {
                goto usage_error;
            }
            options.threads = (int)v;
            i++;
        } else if (strcmp(a, "--memory") == 0) {
            if (!parse_long(a, value, 64, 1 << 24, &v)) {
                goto usage_error;
            }
            options.memory_mib = (size_t)v;
            i++;
        } else if (strcmp(a, "--tmp") == 0) {
            if (!value) {
                fprintf(stderr, "strata-convert: --tmp needs a folder\n");
                goto usage_error;
            }
            options.tmp_dir = value;
            i++;
        } else if (strcmp(a, "--compress") == 0) {
            if (!parse_long(a, value, 0, 19, &v)) {
                goto usage_error;
            }
            options.compress_level = (int)v;
            i++;
        } else if (strcmp(a, "--grid") == 0) {
            if (!parse_long(a, value, 16, 1024, &v)) {
                goto usage_error;
            }
            if ((v & (v - 1)) != 0) {
                fprintf(stderr, "strata-convert: --grid must be a power of two, got %ld\n", v);
                goto usage_error;
            }
            options.grid_cells = (int)v;
            i++;
        } else if (strcmp(a, "--leaf") == 0) {
            if (!parse_long(a, value, 16, 1 << 24, &v)) {
                goto usage_error;
            }
            options.leaf_capacity = (size_t)v;
            i++;
        } else if (strcmp(a, "--attributes") == 0) {
            if (!value || strcmp(value, "extra") != 0) {
                fprintf(stderr, "strata-convert: --attributes takes 'extra'\n");
                goto usage_error;
            }
            options.keep_extra = true;
            i++;
        } else if (strcmp(a, "--salvage") == 0) {
            options.salvage = true;
        } else if (strcmp(a, "--force") == 0) {
            options.force = true;
        } else if (strcmp(a, "-q") == 0 || strcmp(a, "--quiet") == 0) {
            quiet = true;
        } else if (a[0] == '-' && a[1] != '\0') {
            fprintf(stderr, "strata-convert: unknown option %s (see --help)\n", a);
            goto usage_error;
        } else {
            inputs[input_count++] = a;
        }
    }
    if (input_count == 0 || !options.output) {
        fprintf(stderr, "strata-convert: %s\n",
                input_count == 0 ? "no input files" : "no output file (-o OUTPUT.strata)");
        goto usage_error;
    }
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

    sta_convert_report report;
    sta_error err = { 0 };
    sta_status status = sta_convert(&options, &report, &err);
    sta_free(inputs);
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
                "finish %.2f s; %zu chunks, %.0f MiB temporary\n",
                report.seconds_count, report.seconds_distribute, report.seconds_index,
                report.seconds_merge, report.seconds_finish, report.chunk_count,
                (double)report.temp_bytes / 1048576.0);
    }
    return 0;
usage_error:
    sta_free(inputs);
    return 2;
}
