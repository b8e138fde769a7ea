/* SPDX-License-Identifier: MIT
 * lazenc: the test suite's LAZ encoder (tests/support/lazenc) as a command, for
 * making test, fuzz-corpus and benchmark files, and for timing the decoder on them.
 * Test tooling only: it is built with the tests and never installed.
 *
 *   lazenc encode IN.las OUT.laz [--version 1|2|3|4] [--chunk N] [--pointwise]
 *                 [--channels K [--run N]]
 *   lazenc time FILE.laz...      raw record decoding speed, best of 3, one thread
 *
 * --channels K (formats 6-10) rewrites the scanner channel of the records to cycle
 * through K channels every N points (--run, default 64), as interleaved scanner heads
 * would, to exercise and time the point14 context switches.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/clock.h"
#include "core/file_map.h"
#include "io/cloud.h"
#include "io/las.h"
#include "io/las_internal.h"
#include "lazenc.h"

static int usage(void)
{
    fprintf(stderr,
            "usage: lazenc encode IN.las OUT.laz [--version 1|2|3|4] [--chunk N] [--pointwise]"
            " [--channels K [--run N]]\n"
            "       lazenc time FILE.laz...\n");
    return 2;
}

static uint8_t *read_all(const char *path, size_t *size)
{
    FILE *f = fopen(path, "rb");
    if (!f) {
        return NULL;
    }
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    uint8_t *data = n > 0 ? malloc((size_t)n) : NULL;
    if (data && fread(data, 1, (size_t)n, f) != (size_t)n) {
        free(data);
        data = NULL;
    }
    fclose(f);
    *size = (size_t)n;
    return data;
}

static int encode(int argc, char **argv)
{
    if (argc < 4) {
        return usage();
    }
    int version = 0;
    unsigned long chunk = 50000;
    bool pointwise = false;
    unsigned channels = 0;
    unsigned long run = 64;
    for (int i = 4; i < argc; i++) {
        if (!strcmp(argv[i], "--version") && i + 1 < argc) {
            version = atoi(argv[++i]);
        } else if (!strcmp(argv[i], "--chunk") && i + 1 < argc) {
            chunk = strtoul(argv[++i], NULL, 10);
        } else if (!strcmp(argv[i], "--pointwise")) {
            pointwise = true;
        } else if (!strcmp(argv[i], "--run") && i + 1 < argc) {
            run = strtoul(argv[++i], NULL, 10);
        } else if (!strcmp(argv[i], "--channels") && i + 1 < argc) {
            channels = (unsigned)atoi(argv[++i]);
        } else {
            return usage();
        }
    }
    size_t size = 0;
    uint8_t *las = read_all(argv[2], &size);
    if (!las || size < 227) {
        fprintf(stderr, "lazenc: %s: cannot read a LAS file\n", argv[2]);
        return 1;
    }
    int format = las[104] & 0x3f;
    bool layered = format >= 6;
    if (version == 0) {
        version = layered ? 3 : 2;
    }
    if (channels > 4 || (channels > 0 && !layered) || run == 0) {
        fprintf(stderr, "lazenc: --channels needs point format 6-10, 1..4 channels, --run > 0\n");
        return 1;
    }
    if (channels > 0) {
        uint32_t offset = (uint32_t)las[96] | (uint32_t)las[97] << 8 | (uint32_t)las[98] << 16 |
                          (uint32_t)las[99] << 24;
        size_t length = (size_t)las[105] | (size_t)las[106] << 8;
        for (size_t at = offset, i = 0; at + length <= size && length >= 30; at += length, i++) {
            las[at + 15] = (uint8_t)((las[at + 15] & 0xcf) | ((i / run) % channels) << 4);
        }
    }
    lazenc_options options = {
        .compressor = layered     ? STA_LAZ_COMPRESSOR_LAYERED_CHUNKED
                      : pointwise ? STA_LAZ_COMPRESSOR_POINTWISE
                                  : STA_LAZ_COMPRESSOR_POINTWISE_CHUNKED,
        .version = (uint16_t)version,
        .chunk_size = (uint32_t)chunk,
    };
    lazenc_buf out = { 0 };
    char why[160];
    if (!lazenc_from_las(las, size, &options, &out, why, sizeof(why))) {
        fprintf(stderr, "lazenc: %s: %s\n", argv[2], why);
        return 1;
    }
    FILE *f = fopen(argv[3], "wb");
    if (!f || fwrite(out.data, 1, out.size, f) != out.size || fclose(f) != 0) {
        fprintf(stderr, "lazenc: %s: cannot write\n", argv[3]);
        return 1;
    }
    printf("%s: %zu bytes (%.1f%% of the LAS file)\n", argv[3], out.size,
           100.0 * (double)out.size / (double)size);
    lazenc_buf_free(&out);
    free(las);
    return 0;
}

// Decodes every raw record of `path` once; returns the seconds taken or < 0.
static double decode_once(const char *path, uint64_t *count)
{
    sta_file_map map;
    sta_error err = { 0 };
    if (sta_file_map_open(path, &map, &err) != STA_OK) {
        fprintf(stderr, "lazenc: %s\n", err.message);
        return -1;
    }
    void *impl = NULL;
    const sta_cloud_ops *ops = NULL;
    double t0 = sta_clock_s();
    if (sta_las_open_map(&map, NULL, &impl, &ops, &err) != STA_OK) {
        fprintf(stderr, "lazenc: %s\n", err.message);
        sta_file_map_close(&map);
        return -1;
    }
    sta_las_reader *reader = impl;
    *count = reader->info.point_count;
    double seconds = -1;
    uint8_t *buffer = malloc(4096 * reader->record_length);
    if (reader->laz && buffer) {
        seconds = 0;
        for (uint64_t done = 0; done < *count;) {
            size_t step = *count - done < 4096 ? (size_t)(*count - done) : 4096;
            if (sta_laz_decode(reader->laz, buffer, step, &err) != STA_OK) {
                fprintf(stderr, "lazenc: %s\n", err.message);
                seconds = -1;
                break;
            }
            done += step;
        }
    }
    if (seconds == 0) {
        seconds = sta_clock_s() - t0;
    }
    free(buffer);
    ops->close(impl);
    sta_file_map_close(&map);
    return seconds;
}

static int time_files(int argc, char **argv)
{
    for (int i = 2; i < argc; i++) {
        double best = 1e30;
        uint64_t count = 0;
        for (int run = 0; run < 3; run++) {
            double s = decode_once(argv[i], &count);
            if (s < 0) {
                return 1;
            }
            best = s < best ? s : best;
        }
        printf("%s: %llu points, %.3f s, %.2f M points/s\n", argv[i], (unsigned long long)count,
               best, (double)count / best / 1e6);
    }
    return 0;
}

int main(int argc, char **argv)
{
    if (argc >= 2 && !strcmp(argv[1], "encode")) {
        return encode(argc, argv);
    }
    if (argc >= 3 && !strcmp(argv[1], "time")) {
        return time_files(argc, argv);
    }
    return usage();
}
