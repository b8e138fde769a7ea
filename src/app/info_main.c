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
#include "core/log.h"

static void print_usage(FILE *out)
{
    fputs("usage: strata-info [options] FILE...\n"
          "\n"
          "Prints what a LAS (1.0-1.4, point formats 0-10) or PLY file holds: header,\n"
          "VLRs/EVLRs, extra dimensions, CRS, and facts from a full scan of the points\n"
          "(actual bounds, classes, returns, GPS time range, colour depth).\n"
          "For a .strata file: tree statistics (nodes, points and spacing per level,\n"
          "compression, bounds).\n"
          "\n"
          "options:\n"
          "  --json                 print one JSON object per file instead of text\n"
          "  --points START:COUNT   print COUNT points from index START as CSV:\n"
          "                         x,y,z,intensity,return_number,number_of_returns,\n"
          "                         classification,gps_time,red,green,blue\n"
          "                         (real-world coordinates; empty where the format\n"
          "                         lacks a field)\n"
          "  --verify               (.strata) check every checksum and the octree rules\n"
          "                         (points inside their node, one per cell); exit 1 on\n"
          "                         the first violation\n"
          "  --decode-speed         (.strata) time decompression alone and the viewer's\n"
          "                         whole per-node load (decode + GPU layout), one thread\n"
          "  --salvage              read the complete points of a truncated file and\n"
          "                         report how many were missing (default: refuse it)\n"
          "  -q, --quiet            no warnings\n"
          "  -h, --help             this text\n"
          "\n"
          "exit status: 0 when every file was read, 1 when any file failed, 2 on bad usage\n",
          out);
}

typedef struct info_args {
    bool json;
    bool points;
    uint64_t points_start;
    uint64_t points_count;
    bool salvage;
    bool verify;
    bool decode_speed;
} info_args;

static bool parse_range(const char *text, uint64_t *start, uint64_t *count)
{
    char *end = NULL;
    errno = 0;
    if (text[0] == '-') {
        return false;
    }
    unsigned long long a = strtoull(text, &end, 10);
    if (errno || end == text || *end != ':') {
        return false;
    }
    const char *second = end + 1;
    if (second[0] == '-' || second[0] == '\0') {
        return false;
    }
    unsigned long long b = strtoull(second, &end, 10);
    if (errno || *end != '\0') {
        return false;
    }
    *start = a;
    *count = b;
    return true;
}

static int report_file(const char *path, const info_args *args)
{
    sta_error err = { 0 };
    if (sta_info_is_strata(path)) {
        if (args->points) {
            fprintf(stderr, "strata-info: %s: --points is for LAS and PLY files\n", path);
            return 1;
        }
        sta_status s = args->decode_speed ? sta_info_strata_decode_speed(stdout, path, &err)
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
    // Options may come before or after the files; files keep their order.
    int file_count = 0;
    bool options_done = false;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (options_done || a[0] != '-' || a[1] == '\0') {
            argv[1 + file_count++] = argv[i];
        } else if (strcmp(a, "-h") == 0 || strcmp(a, "--help") == 0) {
            print_usage(stdout);
            return 0;
        } else if (strcmp(a, "--json") == 0) {
            args.json = true;
        } else if (strcmp(a, "--verify") == 0) {
            args.verify = true;
        } else if (strcmp(a, "--decode-speed") == 0) {
            args.decode_speed = true;
        } else if (strcmp(a, "--salvage") == 0) {
            args.salvage = true;
        } else if (strcmp(a, "-q") == 0 || strcmp(a, "--quiet") == 0) {
            sta_log_set_level(STA_LOG_QUIET);
        } else if (strcmp(a, "--points") == 0) {
            if (i + 1 >= argc ||
                !parse_range(argv[i + 1], &args.points_start, &args.points_count)) {
                fprintf(stderr, "strata-info: --points needs START:COUNT (e.g. 0:10)\n");
                return 2;
            }
            args.points = true;
            i++;
        } else if (strcmp(a, "--") == 0) {
            options_done = true;
        } else {
            fprintf(stderr, "strata-info: unknown option %s (see --help)\n", a);
            return 2;
        }
    }
    if (file_count == 0) {
        print_usage(stderr);
        return 2;
    }
    int failed = 0;
    for (int i = 1; i <= file_count; i++) {
        failed |= report_file(argv[i], &args);
    }
    return failed;
}
