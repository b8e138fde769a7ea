/* SPDX-License-Identifier: MIT
 * Tests for the LAZ decoder's version 1 items (LASzip 1.x files): POINT10, GPSTIME11,
 * RGB12, BYTE and WAVEPACKET13 version 1 (src/io/laz_point10_v1.c).
 *
 * No file in ../shared/data uses version 1 items, so the files are made by the test
 * encoder (tests/support/lazenc, version 1 items written from LASzip's writer rules,
 * separately from the decoder): real LAS files of point formats 0-4 and synthetic
 * records of formats 0-5 are compressed with compressor 1 (pointwise) and 2 (chunked),
 * written to a temporary file and read back through the LAS reader; the records must
 * be the originals byte for byte, and the points the same as the LAS file's.
 * Wave packets (formats 4, 5) exist only as version 1 items, so they are also tested
 * next to version 2 items. Damaged files (every truncation, byte flips) give an error
 * naming the file (and the chunk, when the point data is damaged) or output, never a
 * crash or hang.
 */
#include "test_support.h"

#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/bytes.h"
#include "core/file_map.h"
#include "core/log.h"
#include "io/cloud.h"
#include "io/las.h"
#include "io/las_internal.h"
#include "io/laz_internal.h"
#include "lazenc.h"
#include "lazenc_check.h"

// The LAS twins of ../shared/data/laz (formats 0-3, extra bytes) and a few more.
static const char *const las_files[] = {
    "las/simple.las",           "las/autzen_trim.las",   "las/autzen-point-format-3.las",
    "las/point10.las",          "las/point-time.las",    "las/point-color.las",
    "las/point-time-color.las", "las/extra-bytes.las",   "las/1815.las",
    "las/point10-1.0.las",      "las/no-points-1.3.las", "las/Megaplot.las",
    "las/MixedConifer.las",     "las/Example.las",       "las/extra_byte.las",
    "las/epsg_4326.las",        "las/sample_c.las",      "las/vegetation_1_3.las",
    "las/warsaw_small.las",     "las/mvk-thin.las",      "las/TO_core_last_clip.las",
    "las/liblas_1.2_2.las",     "las/gps-time-nan.las",
};

static const lazenc_options pointwise_v1 = { .compressor = STA_LAZ_COMPRESSOR_POINTWISE,
                                             .version = 1 };
static const lazenc_options chunked_v1 = { .compressor = STA_LAZ_COMPRESSOR_POINTWISE_CHUNKED,
                                           .version = 1,
                                           .chunk_size = 5000 };

// LAZ bytes for `las` (test failure if the encoder refuses).
static void make_laz(const uint8_t *las, size_t size, const lazenc_options *options,
                     const char *name, lazenc_buf *out)
{
    char why[200] = "";
    *out = (lazenc_buf){ 0 };
    if (!lazenc_from_las(las, size, options, out, why, sizeof(why))) {
        fail_msg("%s: the test encoder refused it: %s", name, why);
    }
}

// Compresses `las` with `options`, writes it as `name` in the temp folder, reads it back
// (raw records byte for byte, then points against `las_path`). Returns the point count.
static uint64_t round_trip(const uint8_t *las, size_t size, const char *las_path,
                           const lazenc_options *options, const char *name)
{
    lazcheck_records expected;
    if (!lazcheck_las_records(las, size, &expected)) {
        fail_msg("%s: not a complete LAS file", las_path);
    }
    lazenc_buf laz;
    make_laz(las, size, options, name, &laz);
    char path[1024];
    snprintf(path, sizeof(path), "%s", sta_test_tmp_path(name));
    sta_test_write_file(path, laz.data, laz.size);
    lazenc_buf_free(&laz);

    sta_file_map map;
    sta_error err = { 0 };
    assert_int_equal(sta_file_map_open(path, &map, &err), STA_OK);
    sta_laz_vlr vlr;
    assert_true(lazcheck_find_vlr(map.data, map.size, &vlr));
    assert_int_equal(vlr.compressor, options->compressor);
    lazcheck_expect_records(map.data, map.size, path, &expected);
    sta_file_map_close(&map);
    lazcheck_expect_same_points(path, las_path);
    return expected.count;
}

static void real_files_round_trip(const lazenc_options *options, const char *tag)
{
    uint64_t points = 0;
    size_t files = 0;
    for (size_t f = 0; f < sizeof(las_files) / sizeof(las_files[0]); f++) {
        const char *las_path = sta_test_shared_path(las_files[f]);
        size_t size = 0;
        uint8_t *las = sta_test_read_file(las_path, &size);
        char name[128];
        snprintf(name, sizeof(name), "%s-%zu.laz", tag, f);
        points += round_trip(las, size, las_path, options, name);
        files++;
        free(las);
    }
    printf("%s: %zu LAS files, %llu points round-tripped byte for byte\n", tag, files,
           (unsigned long long)points);
}

static void real_files_round_trip_pointwise(void **state)
{
    (void)state;
    STA_TEST_REQUIRE_SHARED_DATA();
    real_files_round_trip(&pointwise_v1, "v1-pointwise");
}

static void real_files_round_trip_chunked(void **state)
{
    (void)state;
    STA_TEST_REQUIRE_SHARED_DATA();
    real_files_round_trip(&chunked_v1, "v1-chunked");
}

// simple1_3.las (LAS 1.3, format 4, 999 real wave packet records) without its
// waveform data record, which the test encoder does not carry over.
static uint8_t *wave_packet_las(size_t *out_size)
{
    uint8_t *las = sta_test_read_file(sta_test_shared_path("las/simple1_3.las"), out_size);
    lazcheck_records r;
    assert_true(lazcheck_las_records(las, *out_size, &r));
    assert_int_equal(r.format, 4);
    *out_size = (size_t)(r.records - las) + r.count * r.length;
    las[6] &= (uint8_t)~2u;  // global encoding: no internal waveform data
    memset(las + 227, 0, 8); // start_of_waveform_data
    return las;
}

static void real_wave_packets_round_trip(void **state)
{
    (void)state;
    STA_TEST_REQUIRE_SHARED_DATA();
    size_t size = 0;
    uint8_t *las = wave_packet_las(&size);
    char las_path[1024];
    snprintf(las_path, sizeof(las_path), "%s", sta_test_tmp_path("simple1_3-nowave.las"));
    sta_test_write_file(las_path, las, size);
    const lazenc_options v2_chunked = { .compressor = STA_LAZ_COMPRESSOR_POINTWISE_CHUNKED,
                                        .version = 2,
                                        .chunk_size = 300 };
    const lazenc_options *options[] = { &pointwise_v1, &chunked_v1, &v2_chunked };
    uint64_t points = 0;
    for (size_t o = 0; o < 3; o++) {
        char name[64];
        snprintf(name, sizeof(name), "wave-real-%zu.laz", o);
        points += round_trip(las, size, las_path, options[o], name);
    }
    printf("simple1_3.las (format 4): %llu points round-tripped (v1 pointwise, v1 chunked, "
           "v2 items + WAVEPACKET13 v1)\n",
           (unsigned long long)points);
    free(las);
}

// ---- synthetic records ----

typedef struct rng {
    uint64_t s;
} rng;

static uint32_t next_u32(rng *r)
{
    r->s = r->s * 6364136223846793005ull + 1442695040888963407ull;
    return (uint32_t)(r->s >> 32);
}

static bool one_in(rng *r, uint32_t n)
{
    return next_u32(r) % n == 0;
}

static const size_t base_record[6] = { 20, 28, 26, 34, 57, 63 };

// A LAS 1.3 file of `count` synthetic records of `format` (0-5) with `extra` extra
// bytes: every field changes now and then, including the cases the version 1
// predictors treat specially (GPS time unchanged, 32-bit and huge jumps, multiples of
// the last difference; wave packet offsets unchanged, following the last packet,
// coded differences and huge jumps; 32-bit coordinate wrap).
static uint8_t *synthetic_las(int format, size_t extra, size_t count, uint64_t seed,
                              size_t *out_size)
{
    size_t length = base_record[format] + extra;
    size_t header = 235;
    size_t size = header + count * length;
    uint8_t *las = calloc(1, size);
    assert_non_null(las);
    memcpy(las, "LASF", 4);
    las[24] = 1;
    las[25] = 3;
    memcpy(las + 26, "strata", 6);
    memcpy(las + 58, "test_laz_v1", 11);
    sta_store_u16le(las + 94, (uint16_t)header);
    sta_store_u32le(las + 96, (uint32_t)header);
    las[104] = (uint8_t)format;
    sta_store_u16le(las + 105, (uint16_t)length);
    sta_store_u32le(las + 107, (uint32_t)count);
    for (int axis = 0; axis < 3; axis++) {
        sta_store_f64le(las + 131 + 8 * axis, 0.01);
        sta_store_f64le(las + 179 + 16 * axis, 1e9);  // max
        sta_store_f64le(las + 187 + 16 * axis, -1e9); // min
    }
    rng r = { seed };
    int32_t xyz[3] = { 100000, 200000, 3000 };
    int32_t step[3] = { 7, -3, 1 };
    uint8_t fixed[20] = { 0 };
    uint64_t time_bits = 0x41d0000000000000ull;
    int64_t time_step = 1000;
    uint16_t rgb[3] = { 30000, 20000, 10000 };
    uint64_t offset = 1000;
    uint32_t packet = 256;
    float wave_xyz[4] = { 0.5f, -1.25f, 3.0f, 250.0f };
    for (size_t i = 0; i < count; i++) {
        uint8_t *p = las + header + i * length;
        for (int a = 0; a < 3; a++) {
            if (one_in(&r, 40)) {
                step[a] = (int32_t)(next_u32(&r) % 2001) - 1000;
            }
            xyz[a] += step[a] + (int32_t)(next_u32(&r) % 5) - 2;
            if (one_in(&r, 500)) {
                xyz[a] = (int32_t)next_u32(&r); // anywhere, the difference wraps
            }
            sta_store_i32le(p + 4 * a, xyz[a]);
        }
        if (one_in(&r, 3)) {
            sta_store_u16le(fixed + 12, (uint16_t)next_u32(&r));
        }
        if (one_in(&r, 4)) {
            uint32_t n = 1 + next_u32(&r) % 5;
            uint32_t rn = 1 + next_u32(&r) % n;
            fixed[14] = (uint8_t)(rn | n << 3 | (next_u32(&r) & 0xc0));
        }
        if (one_in(&r, 9)) {
            fixed[15] = (uint8_t)(next_u32(&r) % 20);
        }
        if (one_in(&r, 6)) {
            fixed[16] = (uint8_t)((int32_t)(next_u32(&r) % 181) - 90);
        }
        if (one_in(&r, 17)) {
            fixed[17] = (uint8_t)next_u32(&r);
        }
        if (one_in(&r, 50)) {
            sta_store_u16le(fixed + 18, (uint16_t)next_u32(&r));
        }
        memcpy(p + 12, fixed + 12, 8);
        size_t at = 20;
        if (format == 1 || format >= 3) {
            uint32_t kind = next_u32(&r) % 20;
            if (kind == 0) {
                // unchanged
            } else if (kind == 1) {
                time_bits += (uint64_t)1 << 40; // beyond 32 bits
            } else if (kind == 2) {
                time_step = (int64_t)(next_u32(&r) % 100000) - 50000;
                time_bits += (uint64_t)time_step;
            } else if (kind == 3) {
                time_bits += (uint64_t)(time_step * (int64_t)(2 + next_u32(&r) % 600));
            } else if (kind == 4) {
                time_bits -= (uint64_t)(time_step / 3);
            } else {
                time_bits += (uint64_t)time_step;
            }
            sta_store_u64le(p + at, time_bits);
            at += 8;
        }
        if (format == 2 || format == 3 || format == 5) {
            for (int c = 0; c < 3; c++) {
                if (one_in(&r, 3)) {
                    rgb[c] = (uint16_t)(one_in(&r, 2) ? next_u32(&r) : rgb[c] + next_u32(&r) % 9);
                }
                sta_store_u16le(p + at + 2 * c, rgb[c]);
            }
            at += 6;
        }
        if (format >= 4) {
            p[at] = (uint8_t)(one_in(&r, 5) ? next_u32(&r) : 1);
            uint32_t kind = next_u32(&r) % 8;
            if (kind == 0) {
                // same offset
            } else if (kind <= 3) {
                offset += packet; // right behind the last packet
            } else if (kind <= 5) {
                offset += (uint64_t)(int64_t)((int32_t)(next_u32(&r) % 200001) - 100000);
            } else if (kind == 6) {
                offset += (uint64_t)next_u32(&r) << 8; // beyond 32 bits
            } else {
                offset = (uint64_t)next_u32(&r) << 32 | next_u32(&r);
            }
            if (one_in(&r, 4)) {
                packet = next_u32(&r) % 0x10000000u; // below 2^31, see the encoder
            }
            sta_store_u64le(p + at + 1, offset);
            sta_store_u32le(p + at + 9, packet);
            for (int c = 0; c < 4; c++) {
                if (one_in(&r, 3)) {
                    wave_xyz[c] = (float)((int32_t)(next_u32(&r) % 20001) - 10000) / 64.0f;
                }
                sta_store_f32le(p + at + 13 + 4 * c, wave_xyz[c]);
            }
            at += 29;
        }
        for (size_t e = 0; e < extra; e++) {
            p[at + e] = (uint8_t)(one_in(&r, 3) ? next_u32(&r) : (e * 7 + i / 50));
        }
    }
    *out_size = size;
    return las;
}

static void synthetic_records_round_trip(void **state)
{
    (void)state;
    const lazenc_options small_chunks = { .compressor = STA_LAZ_COMPRESSOR_POINTWISE_CHUNKED,
                                          .version = 1,
                                          .chunk_size = 777 };
    const lazenc_options *options[] = { &pointwise_v1, &small_chunks };
    uint64_t points = 0;
    size_t files = 0;
    for (int format = 0; format <= 5; format++) {
        for (size_t extra = 0; extra <= 3; extra += 3) {
            size_t size = 0;
            uint8_t *las = synthetic_las(format, extra, 3000, 17 + (uint64_t)format, &size);
            char las_path[1024];
            char name[64];
            snprintf(name, sizeof(name), "synthetic-%d-%zu.las", format, extra);
            snprintf(las_path, sizeof(las_path), "%s", sta_test_tmp_path(name));
            sta_test_write_file(las_path, las, size);
            for (size_t o = 0; o < 2; o++) {
                snprintf(name, sizeof(name), "synthetic-%d-%zu-%zu.laz", format, extra, o);
                points += round_trip(las, size, las_path, options[o], name);
                files++;
            }
            free(las);
        }
    }
    printf("synthetic formats 0-5 (+/- 3 extra bytes): %zu files, %llu points round-tripped\n",
           files, (unsigned long long)points);
}

static void synthetic_wave_packets_next_to_version2_items(void **state)
{
    (void)state;
    const lazenc_options options[] = {
        { .compressor = STA_LAZ_COMPRESSOR_POINTWISE, .version = 2 },
        { .compressor = STA_LAZ_COMPRESSOR_POINTWISE_CHUNKED, .version = 2, .chunk_size = 1000 },
    };
    for (int format = 4; format <= 5; format++) {
        size_t size = 0;
        uint8_t *las = synthetic_las(format, 2, 2500, 99 + (uint64_t)format, &size);
        char las_path[1024];
        char name[64];
        snprintf(name, sizeof(name), "mixed-%d.las", format);
        snprintf(las_path, sizeof(las_path), "%s", sta_test_tmp_path(name));
        sta_test_write_file(las_path, las, size);
        for (size_t o = 0; o < 2; o++) {
            lazenc_buf laz;
            make_laz(las, size, &options[o], name, &laz);
            sta_laz_vlr vlr;
            assert_true(lazcheck_find_vlr(laz.data, laz.size, &vlr));
            // POINT10, GPSTIME11, [RGB12], WAVEPACKET13, BYTE: only the wave packet is v1.
            for (size_t i = 0; i < vlr.item_count; i++) {
                bool wave = vlr.items[i].type == STA_LAZ_ITEM_WAVEPACKET13;
                assert_int_equal(vlr.items[i].version, wave ? 1 : 2);
            }
            lazenc_buf_free(&laz);
            snprintf(name, sizeof(name), "mixed-%d-%zu.laz", format, o);
            round_trip(las, size, las_path, &options[o], name);
        }
        free(las);
    }
}

// Seeks into the middle of chunks of a chunked version 1 file and backwards.
static void seeking_into_version1_chunks(void **state)
{
    (void)state;
    size_t size = 0;
    uint8_t *las = synthetic_las(5, 1, 2000, 5, &size);
    lazcheck_records expected;
    assert_true(lazcheck_las_records(las, size, &expected));
    const lazenc_options options = { .compressor = STA_LAZ_COMPRESSOR_POINTWISE_CHUNKED,
                                     .version = 1,
                                     .chunk_size = 300 };
    lazenc_buf laz;
    make_laz(las, size, &options, "seek.laz", &laz);
    sta_file_map map;
    sta_error err = { 0 };
    assert_int_equal(sta_file_map_wrap(laz.data, laz.size, "seek.laz", &map, &err), STA_OK);
    void *impl = NULL;
    const sta_cloud_ops *ops = NULL;
    assert_int_equal(sta_las_open_map(&map, NULL, &impl, &ops, &err), STA_OK);
    sta_las_reader *reader = impl;
    assert_true(sta_laz_has_chunk_table(reader->laz));
    static const uint64_t targets[] = { 1999, 0, 299, 300, 301, 1234, 5, 600, 1998 };
    uint8_t record[200];
    for (size_t t = 0; t < sizeof(targets) / sizeof(targets[0]); t++) {
        assert_int_equal(sta_laz_seek(reader->laz, targets[t], &err), STA_OK);
        assert_int_equal(sta_laz_decode(reader->laz, record, 1, &err), STA_OK);
        assert_memory_equal(record, expected.records + targets[t] * expected.length,
                            expected.length);
    }
    ops->close(impl);
    sta_file_map_close(&map);
    lazenc_buf_free(&laz);
    free(las);
}

// ---- damaged files ----

// Decodes `data`; an error must name the file, and the chunk when it is about the
// point data. Returns whether it decoded; *identical as lazcheck_try_decode.
static bool decode_damaged(const uint8_t *data, size_t size, const lazcheck_records *expected,
                           bool *identical)
{
    char message[512];
    if (lazcheck_try_decode(data, size, "damaged.laz", expected, identical, message,
                            sizeof(message))) {
        return true;
    }
    if (!strstr(message, "damaged.laz")) {
        fail_msg("error without the file name: %s", message);
    }
    return false;
}

// Every truncation: an error, or (only the chunk table cut) exactly the right records.
static void truncations_of(const uint8_t *las, size_t las_size, const lazenc_options *options,
                           const char *tag)
{
    lazcheck_records expected;
    assert_true(lazcheck_las_records(las, las_size, &expected));
    lazenc_buf laz;
    make_laz(las, las_size, options, tag, &laz);
    size_t decoded = 0;
    for (size_t cut = 0; cut < laz.size; cut++) {
        uint8_t *copy = malloc(cut ? cut : 1);
        assert_non_null(copy);
        memcpy(copy, laz.data, cut);
        bool identical = false;
        if (decode_damaged(copy, cut, &expected, &identical)) {
            if (!identical) {
                fail_msg("%s cut to %zu of %zu bytes: decoded wrong records", tag, cut, laz.size);
            }
            decoded++;
        }
        free(copy);
    }
    printf("%s: %zu truncations, %zu decode fully (chunk table cut)\n", tag, laz.size, decoded);
    lazenc_buf_free(&laz);
}

static void truncated_version1_files_fail_cleanly(void **state)
{
    (void)state;
    sta_log_set_level(STA_LOG_QUIET);
    size_t size = 0;
    uint8_t *las = synthetic_las(5, 2, 60, 3, &size);
    const lazenc_options chunked = { .compressor = STA_LAZ_COMPRESSOR_POINTWISE_CHUNKED,
                                     .version = 1,
                                     .chunk_size = 25 };
    truncations_of(las, size, &pointwise_v1, "format 5 v1 pointwise");
    truncations_of(las, size, &chunked, "format 5 v1 chunked");
    free(las);
    las = synthetic_las(1, 0, 120, 4, &size);
    truncations_of(las, size, &chunked, "format 1 v1 chunked");
    free(las);
    sta_log_set_level(STA_LOG_WARN);
}

// Byte flips in the point data (both compressors): error or output, never a crash.
static void flipped_version1_files_fail_cleanly(void **state)
{
    (void)state;
    sta_log_set_level(STA_LOG_QUIET);
    const lazenc_options chunked = { .compressor = STA_LAZ_COMPRESSOR_POINTWISE_CHUNKED,
                                     .version = 1,
                                     .chunk_size = 70 };
    const lazenc_options *options[] = { &pointwise_v1, &chunked };
    for (int format = 3; format <= 5; format += 2) {
        size_t size = 0;
        uint8_t *las = synthetic_las(format, 1, 200, 11, &size);
        lazcheck_records expected;
        assert_true(lazcheck_las_records(las, size, &expected));
        for (size_t o = 0; o < 2; o++) {
            lazenc_buf laz;
            make_laz(las, size, options[o], "flip.laz", &laz);
            uint32_t point_data = sta_load_u32le(laz.data + 96);
            size_t flips = 0;
            size_t errors = 0;
            for (size_t at = point_data; at < laz.size; at += 7) {
                for (int pattern = 0; pattern < 2; pattern++) {
                    uint8_t *copy = malloc(laz.size);
                    assert_non_null(copy);
                    memcpy(copy, laz.data, laz.size);
                    copy[at] ^= pattern ? 0xff : 0x10;
                    bool identical = false;
                    char message[512];
                    if (!lazcheck_try_decode(copy, laz.size, "flip.laz", &expected, &identical,
                                             message, sizeof(message))) {
                        if (!strstr(message, "flip.laz") || !strstr(message, "chunk")) {
                            fail_msg("flip at %zu: message lacks the file or the chunk: %s", at,
                                     message);
                        }
                        errors++;
                    }
                    flips++;
                    free(copy);
                }
            }
            printf("format %d, compressor %u: %zu flips, %zu reported as errors\n", format,
                   options[o]->compressor, flips, errors);
            lazenc_buf_free(&laz);
        }
        free(las);
    }
    sta_log_set_level(STA_LOG_WARN);
}

static const struct CMUnitTest tests[] = {
    cmocka_unit_test(real_files_round_trip_pointwise),
    cmocka_unit_test(real_files_round_trip_chunked),
    cmocka_unit_test(real_wave_packets_round_trip),
    cmocka_unit_test(synthetic_records_round_trip),
    cmocka_unit_test(synthetic_wave_packets_next_to_version2_items),
    cmocka_unit_test(seeking_into_version1_chunks),
    cmocka_unit_test(truncated_version1_files_fail_cleanly),
    cmocka_unit_test(flipped_version1_files_fail_cleanly),
};

STA_TEST_MAIN(tests)
