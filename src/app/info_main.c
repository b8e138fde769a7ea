/* SPDX-License-Identifier: MIT
 * strata-info: what a LAS or PLY file holds (summary, JSON, or points as CSV).
 */
#include <errno.h>
#include <inttypes.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app/info_print.h"
#include "app/info_strata.h"
#include "app/info_strata_points.h"
#include "core/cli.h"
#include "core/log.h"

static const char usage_text[] =
    "usage: strata-info [options] FILE...\n"
    "\n"
    "Prints what a LAS (1.0-1.4, point formats 0-10) or PLY file holds: header,\n"
    "VLRs/EVLRs, extra dimensions, CRS, and facts from a full scan of the points\n"
    "(actual bounds, classes, returns, GPS time range, colour depth).\n"
    "For a .strata file: tree statistics (nodes, points and spacing per level,\n"
    "compression, bounds), or its points with --points.\n";

static const char exit_text[] =
    "exit status: 0 when every file was read, 1 when any file failed, 2 on bad usage\n";

typedef struct info_args {
    bool json;
    bool points;
    uint64_t points_start;
    uint64_t points_count;
    bool salvage;
    bool verify;
    bool decode_speed;
} info_args;

// --points START:COUNT (dest: info_args).
static sta_status parse_range(const sta_cli_option *option, const char *text, sta_error *err)
{
    info_args *args = option->dest;
    char *end = NULL;
    errno = 0;
    unsigned long long a = text[0] != '-' ? strtoull(text, &end, 10) : 0;
    bool ok = end && errno == 0 && end != text && *end == ':';
    const char *second = ok ? end + 1 : "";
    ok = ok && second[0] != '-' && second[0] != '\0';
    unsigned long long b = ok ? strtoull(second, &end, 10) : 0;
    if (!ok || errno || *end != '\0') {
        return sta_cli_fail_value(err, option, text, "START:COUNT (e.g. 0:10)");
    }
    args->points_start = a;
    args->points_count = b;
    args->points = true;
    return STA_OK;
}

static int report_file(const char *path, const info_args *args)
{
    sta_error err = { 0 };
    if (sta_info_is_strata(path)) {
        sta_status s =
            args->points
                ? sta_info_strata_points(stdout, path, args->points_start, args->points_count, &err)
            : args->decode_speed ? sta_info_strata_decode_speed(stdout, path, &err)
                                 : sta_info_strata(stdout, path, args->json, args->verify,
                                                   sta_log_is_terminal(), &err);
        if (s != STA_OK) {
            fflush(stdout);
            fprintf(stderr, "strata-info: %s\n", err.message);
            return 1;
        }
        return 0;
    }
    sta_cloud_reader *reader = NULL;
    sta_read_options options = { .salvage_truncated = args->salvage };
    sta_status status = sta_cloud_open(path, &options, &reader, &err);
    if (status == STA_OK) {
        const sta_cloud_info *info = sta_cloud_reader_info(reader);
        if (info->skipped_point_count) {
            sta_log_warn("%s: truncated: read %" PRIu64 " complete points, %" PRIu64 " missing",
                         path, info->point_count, info->skipped_point_count);
        }
        if (args->points) {
            status =
                sta_info_print_points(stdout, reader, args->points_start, args->points_count, &err);
        } else {
            sta_cloud_stats stats;
            status = sta_cloud_scan_stats(reader, &stats, &err);
            if (status == STA_OK && args->json) {
                sta_info_print_json(stdout, info, &stats);
            } else if (status == STA_OK) {
                sta_info_print_text(stdout, info, &stats);
            }
        }
    }
    sta_cloud_close(reader);
    if (status != STA_OK) {
        fflush(stdout);
        fprintf(stderr, "strata-info: %s\n", err.message);
        return 1;
    }
    return 0;
}

int main(int argc, char **argv)
{
    info_args args = { 0 };
    bool quiet = false;
    const sta_cli_option options[] = {
        { .name = "json",
          .kind = STA_CLI_FLAG,
          .dest = &args.json,
          .help = "print one JSON object per file instead of text" },
        { .name = "points",
          .kind = STA_CLI_CALLBACK,
          .dest = &args,
          .metavar = "START:COUNT",
          .parse = parse_range,
          .help = "print COUNT points from index START as CSV:\n"
                  "x,y,z,intensity,return_number,number_of_returns,\n"
                  "classification,gps_time,red,green,blue\n"
                  "(real-world coordinates; empty where the format lacks a field);\n"
                  ".strata: in file order (nodes breadth-first, coarse points first)" },
        { .name = "verify",
          .kind = STA_CLI_FLAG,
          .dest = &args.verify,
          .help = "(.strata) check every checksum and the octree rules (points inside their "
                  "node, one per cell); exit 1 on the first violation" },
        { .name = "decode-speed",
          .kind = STA_CLI_FLAG,
          .dest = &args.decode_speed,
          .help = "(.strata) time decompression alone and the viewer's whole per-node load "
                  "(decode + GPU layout), one thread" },
        { .name = "salvage",
          .kind = STA_CLI_FLAG,
          .dest = &args.salvage,
          .help = "read the complete points of a truncated file and report how many were "
                  "missing (default: refuse it)" },
        { .name = "quiet",
          .short_name = 'q',
          .kind = STA_CLI_FLAG,
          .dest = &quiet,
          .help = "no warnings" },
        { .name = NULL },
    };
    const sta_cli cli = {
        .program = "strata-info", .usage = usage_text, .epilog = exit_text, .options = options
    };
    // Options may come before or after the files; files keep their order.
    sta_cli_result r;
    int rc = sta_cli_parse_main(&cli, argc, argv, &r);
    if (rc >= 0) {
        return rc;
    }
    if (quiet) {
        sta_log_set_level(STA_LOG_QUIET);
    }
    if (r.positional_count == 0) {
        sta_cli_print_help(&cli, stderr);
        return 2;
    }
    int failed = 0;
    for (int i = 0; i < r.positional_count; i++) {
        failed |= report_file(r.positional[i], &args);
    }
    return failed;
}
