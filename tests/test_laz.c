/* SPDX-License-Identifier: MIT
 * Tests for the LAZ decoder (src/io/laz_*.c) behind the LAS reader.
 *
 * - Every LAZ file in ../shared/data/laz decodes to exactly the point records of its
 *   uncompressed twin (the "LAS / LAZ twins" list of ../shared/data/README.md): the raw
 *   records byte for byte (through the decoder's own interface), and the points the
 *   generic reader yields field for field. Files whose items are not decoded must be
 *   refused with STA_ERR_UNSUPPORTED naming the item; the test says so on stdout.
 * - Seeking into the middle of chunks, a removed chunk table (sequential fallback),
 *   the four lasR forest tiles (counts from the README), every truncation of small
 *   files and byte flips in the chunk table and the compressed stream (error or
 *   consistent output, never a crash or hang).
 * - Speed: points per second on one core for autzen_trim.laz (printed).
 */
#include "test_support.h"

#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "convert.h"
#include "core/alloc.h"
#include "core/bytes.h"
#include "core/clock.h"
#include "core/file_map.h"
#include "core/log.h"
#include "io/cloud.h"
#include "io/las.h"
#include "io/las_internal.h"
#include "io/laz_internal.h"
#include "lazenc_check.h"

// The point records of an uncompressed LAS file (inside `map`).
typedef struct las_records {
    sta_file_map map;
    const uint8_t *records;
    uint64_t count;
    size_t length;
} las_records;

static void open_las_records(const char *relative, las_records *out)
{
    sta_error err = { 0 };
    assert_int_equal(sta_file_map_open(sta_test_shared_path(relative), &out->map, &err), STA_OK);
    const uint8_t *d = out->map.data;
    uint32_t offset =
        (uint32_t)d[96] | (uint32_t)d[97] << 8 | (uint32_t)d[98] << 16 | (uint32_t)d[99] << 24;
    out->length = (size_t)d[105] | (size_t)d[106] << 8;
    // The header's point count (the 64-bit one of LAS 1.4): EVLRs may follow the points.
    out->count = (size_t)d[107] | (size_t)d[108] << 8 | (size_t)d[109] << 16 | (size_t)d[110] << 24;
    if (d[25] >= 4) {
        out->count = sta_load_u64le(d + 247);
    }
    out->records = d + offset;
}

// A LAZ file opened through the LAS reader, with access to its decoder.
typedef struct laz_file {
    sta_file_map map;
    sta_las_reader *reader;
    const sta_cloud_ops *ops;
} laz_file;

static sta_status open_laz_bytes(const uint8_t *data, size_t size, const char *name, laz_file *out,
                                 sta_error *err)
{
    memset(out, 0, sizeof(*out));
    sta_status status = sta_file_map_wrap(data, size, name, &out->map, err);
    if (status != STA_OK) {
        return status;
    }
    void *impl = NULL;
    const sta_cloud_ops *ops = NULL;
    status = sta_las_open_map(&out->map, NULL, &impl, &ops, err);
    if (status != STA_OK) {
        sta_file_map_close(&out->map);
        return status;
    }
    out->reader = impl;
    out->ops = ops;
    return STA_OK;
}

static void close_laz(laz_file *file)
{
    if (file->reader) {
        file->ops->close(file->reader);
        file->reader = NULL;
    }
    sta_file_map_close(&file->map);
}

// Compares the raw records decoded from `file` with `expected`, starting at `first`.
static void expect_records(laz_file *file, const las_records *expected, uint64_t first,
                           uint64_t count)
{
    size_t length = file->reader->info.record_length;
    assert_int_equal(length, expected->length);
    uint8_t *buffer = malloc(4096 * length);
    assert_non_null(buffer);
    sta_error err = { 0 };
    assert_int_equal(sta_laz_seek(file->reader->laz, first, &err), STA_OK);
    uint64_t done = 0;
    while (done < count) {
        size_t step = count - done < 4096 ? (size_t)(count - done) : 4096;
        sta_status status = sta_laz_decode(file->reader->laz, buffer, step, &err);
        if (status != STA_OK) {
            fail_msg("%s: %s", file->map.path, err.message);
        }
        for (size_t i = 0; i < step; i++) {
            const uint8_t *want = expected->records + (first + done + i) * length;
            if (memcmp(buffer + i * length, want, length) != 0) {
                fail_msg("%s: record %llu differs from the LAS twin", file->map.path,
                         (unsigned long long)(first + done + i));
            }
        }
        done += step;
    }
    free(buffer);
}

static void twins_decode_to_their_las_records(void **state)
{
    (void)state;
    STA_TEST_REQUIRE_SHARED_DATA();
    for (size_t t = 0; t < lazcheck_twin_count; t++) {
        size_t size = 0;
        uint8_t *data = sta_test_read_file(sta_test_shared_path(lazcheck_twins[t].laz), &size);
        laz_file file;
        sta_error err = { 0 };
        sta_status status = open_laz_bytes(data, size, lazcheck_twins[t].laz, &file, &err);
        if (status != STA_OK) {
            fail_msg("%s: %s", lazcheck_twins[t].laz, err.message);
        }
        las_records las;
        open_las_records(lazcheck_twins[t].las, &las);
        assert_int_equal(file.reader->info.point_count, las.count);
        expect_records(&file, &las, 0, las.count);
        close_laz(&file);
        sta_file_map_close(&las.map);
        free(data);
        char laz_path[4096];
        snprintf(laz_path, sizeof(laz_path), "%s", sta_test_shared_path(lazcheck_twins[t].laz));
        lazcheck_expect_same_points(laz_path, sta_test_shared_path(lazcheck_twins[t].las));
        printf("ok: %s == %s (%llu points)\n", lazcheck_twins[t].laz, lazcheck_twins[t].las,
               (unsigned long long)las.count);
    }
}

static void seeking_decodes_from_the_chunk_start(void **state)
{
    (void)state;
    STA_TEST_REQUIRE_SHARED_DATA();
    size_t size = 0;
    uint8_t *data = sta_test_read_file(sta_test_shared_path("laz/autzen_trim.laz"), &size);
    las_records las;
    open_las_records("las/autzen_trim.las", &las);
    laz_file file;
    sta_error err = { 0 };
    assert_int_equal(open_laz_bytes(data, size, "autzen_trim.laz", &file, &err), STA_OK);
    assert_true(sta_laz_has_chunk_table(file.reader->laz));
    // Chunks of 50000: the last point of chunk 0, the first of chunk 1, backwards, the end.
    static const uint64_t at[] = { 49999, 50000, 3, 109990, 77777, 0, 100000 };
    for (size_t i = 0; i < sizeof(at) / sizeof(at[0]); i++) {
        expect_records(&file, &las, at[i], 10);
    }
    close_laz(&file);

    // The layered (point14) file: one chunk; forwards, backwards, the last points.
    size_t size14 = 0;
    uint8_t *data14 = sta_test_read_file(sta_test_shared_path("laz/1_4_w_evlr.laz"), &size14);
    las_records las14;
    open_las_records("las/1_4_w_evlr.las", &las14);
    assert_int_equal(open_laz_bytes(data14, size14, "1_4_w_evlr.laz", &file, &err), STA_OK);
    static const uint64_t at14[] = { 500, 3, 990, 0, 777 };
    for (size_t i = 0; i < sizeof(at14) / sizeof(at14[0]); i++) {
        expect_records(&file, &las14, at14[i], 10);
    }
    close_laz(&file);
    sta_file_map_close(&las14.map);
    free(data14);

    // Through the generic reader: seek then read gives the same points as the LAS file.
    sta_cloud_reader *a = NULL;
    sta_cloud_reader *b = NULL;
    assert_int_equal(sta_cloud_open(sta_test_shared_path("laz/autzen_trim.laz"), NULL, &a, &err),
                     STA_OK);
    assert_int_equal(sta_cloud_open(sta_test_shared_path("las/autzen_trim.las"), NULL, &b, &err),
                     STA_OK);
    sta_point_batch ba = { 0 };
    sta_point_batch bb = { 0 };
    assert_int_equal(sta_point_batch_init(&ba, 100, 0, &err), STA_OK);
    assert_int_equal(sta_point_batch_init(&bb, 100, 0, &err), STA_OK);
    for (size_t i = 0; i < sizeof(at) / sizeof(at[0]); i++) {
        assert_int_equal(sta_cloud_seek(a, at[i], &err), STA_OK);
        assert_int_equal(sta_cloud_seek(b, at[i], &err), STA_OK);
        assert_int_equal(sta_cloud_read(a, &ba, &err), STA_OK);
        assert_int_equal(sta_cloud_read(b, &bb, &err), STA_OK);
        assert_int_equal(ba.count, bb.count);
        assert_int_equal(ba.first_index, at[i]);
        for (size_t k = 0; k < ba.count; k++) {
            assert_true(lazcheck_same_point(&ba.points[k], &bb.points[k]));
        }
    }
    assert_int_equal(sta_cloud_seek(a, 110000, &err), STA_OK);
    assert_int_equal(sta_cloud_read(a, &ba, &err), STA_OK);
    assert_int_equal(ba.count, 0);
    assert_int_equal(sta_cloud_seek(a, 110001, &err), STA_ERR_ARG);
    sta_point_batch_release(&ba);
    sta_point_batch_release(&bb);
    sta_cloud_close(a);
    sta_cloud_close(b);
    sta_file_map_close(&las.map);
    free(data);
}

static void damaged_chunk_table_falls_back_to_sequential(void **state)
{
    (void)state;
    STA_TEST_REQUIRE_SHARED_DATA();
    size_t size = 0;
    uint8_t *data = sta_test_read_file(sta_test_shared_path("laz/autzen_trim.laz"), &size);
    las_records las;
    open_las_records("las/autzen_trim.las", &las);
    uint32_t point_data = sta_load_u32le(data + 96);
    uint64_t table_at = sta_load_u64le(data + point_data);
    static const uint64_t bad_offsets[] = { 0, 12345678901ull, UINT64_MAX - 5 };
    sta_log_set_level(STA_LOG_QUIET); // the fallback warns
    for (int variant = 0; variant < 4; variant++) {
        uint8_t *copy = malloc(size);
        memcpy(copy, data, size);
        if (variant < 3) {
            sta_store_u64le(copy + point_data, bad_offsets[variant]);
        } else {
            copy[table_at] = 7; // unknown table version
        }
        laz_file file;
        sta_error err = { 0 };
        assert_int_equal(open_laz_bytes(copy, size, "no-table.laz", &file, &err), STA_OK);
        assert_false(sta_laz_has_chunk_table(file.reader->laz));
        expect_records(&file, &las, 0, las.count);
        expect_records(&file, &las, 60000, 5); // forwards
        expect_records(&file, &las, 49998, 5); // backwards: from the first chunk again
        close_laz(&file);
        free(copy);
    }
    sta_log_set_level(STA_LOG_WARN);
    sta_file_map_close(&las.map);
    free(data);
}

static void forest_tiles_read_fully(void **state)
{
    (void)state;
    STA_TEST_REQUIRE_SHARED_DATA();
    static const struct {
        const char *path;
        uint64_t count;
    } tiles[] = {
        { "laz-tiles/bcts_1.laz", 531662 },
        { "laz-tiles/bcts_2.laz", 823945 },
        { "laz-tiles/bcts_3.laz", 887254 },
        { "laz-tiles/bcts_4.laz", 591489 },
    };
    uint64_t all = 0;
    for (size_t t = 0; t < 4; t++) {
        sta_cloud_reader *reader = NULL;
        sta_error err = { 0 };
        assert_int_equal(sta_cloud_open(sta_test_shared_path(tiles[t].path), NULL, &reader, &err),
                         STA_OK);
        const sta_cloud_info *info = sta_cloud_reader_info(reader);
        assert_int_equal(info->point_count, tiles[t].count);
        assert_int_equal(info->point_format, 1);
        sta_point_batch batch = { 0 };
        assert_int_equal(sta_point_batch_init(&batch, 65536, info->extra_size, &err), STA_OK);
        uint64_t total = 0;
        uint64_t by_return[6] = { 0 };
        for (;;) {
            sta_status status = sta_cloud_read(reader, &batch, &err);
            if (status != STA_OK) {
                fail_msg("%s: %s", tiles[t].path, err.message);
            }
            if (batch.count == 0) {
                break;
            }
            for (size_t i = 0; i < batch.count; i++) {
                uint8_t r = batch.points[i].return_number;
                by_return[r < 6 ? r : 0]++;
            }
            total += batch.count;
        }
        assert_int_equal(total, tiles[t].count);
        // The header's points-by-return must agree with the decoded return numbers.
        for (int r = 1; r <= 5; r++) {
            assert_int_equal(by_return[r], info->points_by_return[r - 1]);
        }
        all += total;
        sta_point_batch_release(&batch);
        sta_cloud_close(reader);
    }
    assert_int_equal(all, 2834350);
}

// Opens and reads everything; true when every point was read without error.
static bool read_all(const uint8_t *data, size_t size, const las_records *expected,
                     bool *out_identical)
{
    laz_file file;
    sta_error err = { 0 };
    *out_identical = false;
    if (open_laz_bytes(data, size, "damaged.laz", &file, &err) != STA_OK) {
        assert_true(err.message[0] != '\0');
        return false;
    }
    const sta_cloud_info *info = &file.reader->info;
    size_t length = info->record_length;
    uint8_t *buffer = malloc(256 * length);
    assert_non_null(buffer);
    uint64_t done = 0;
    bool ok = true;
    bool identical = info->point_count == expected->count && length == expected->length;
    while (done < info->point_count) {
        size_t step = info->point_count - done < 256 ? (size_t)(info->point_count - done) : 256;
        if (sta_laz_decode(file.reader->laz, buffer, step, &err) != STA_OK) {
            // The message names the file and the chunk.
            assert_non_null(strstr(err.message, "damaged.laz"));
            assert_non_null(strstr(err.message, "chunk"));
            ok = false;
            break;
        }
        if (identical && memcmp(buffer, expected->records + done * length, step * length) != 0) {
            identical = false;
        }
        done += step;
    }
    free(buffer);
    close_laz(&file);
    *out_identical = ok && identical;
    return ok;
}

static void every_truncation_fails_cleanly(void **state)
{
    (void)state;
    STA_TEST_REQUIRE_SHARED_DATA();
    static const lazcheck_twin small[] = {
        { "laz/point10-1.0.laz", "las/point10-1.0.las" },
        { "laz/Example.laz", "las/Example.las" },
        { "laz/autzen.laz", "las/autzen-point-format-3.las" },
        { "laz/1_4_w_evlr.laz", "las/1_4_w_evlr.las" }, // point14, layered
    };
    sta_log_set_level(STA_LOG_QUIET);
    for (size_t t = 0; t < sizeof(small) / sizeof(small[0]); t++) {
        size_t size = 0;
        uint8_t *data = sta_test_read_file(sta_test_shared_path(small[t].laz), &size);
        las_records las;
        open_las_records(small[t].las, &las);
        size_t complete = 0;
        for (size_t cut = 0; cut < size; cut++) {
            uint8_t *copy = malloc(cut ? cut : 1);
            memcpy(copy, data, cut);
            bool identical = false;
            if (read_all(copy, cut, &las, &identical)) {
                // A successful read of a truncated file must still be the right points
                // (only the chunk table was cut: sequential decoding).
                if (!identical) {
                    fail_msg("%s cut to %zu bytes: read succeeded with wrong points", small[t].laz,
                             cut);
                }
                complete++;
            }
            free(copy);
        }
        printf("%s: %zu truncations, %zu still decode fully (chunk table cut)\n", small[t].laz,
               size, complete);
        sta_file_map_close(&las.map);
        free(data);
    }
    sta_log_set_level(STA_LOG_WARN);
}

static void byte_flips_fail_cleanly(void **state)
{
    (void)state;
    STA_TEST_REQUIRE_SHARED_DATA();
    static const lazcheck_twin files[] = {
        { "laz/autzen.laz", "las/autzen-point-format-3.las" },
        { "laz/extra_byte.laz", "las/extra_byte.las" },
        { "laz/point-time-color.laz", "las/point-time-color.las" },
        { "laz/1_4_w_evlr.laz", "las/1_4_w_evlr.las" }, // point14, layered
    };
    sta_log_set_level(STA_LOG_QUIET);
    for (size_t t = 0; t < sizeof(files) / sizeof(files[0]); t++) {
        size_t size = 0;
        uint8_t *data = sta_test_read_file(sta_test_shared_path(files[t].laz), &size);
        las_records las;
        open_las_records(files[t].las, &las);
        uint32_t point_data = sta_load_u32le(data + 96);
        size_t errors = 0;
        size_t flips = 0;
        // Every byte of the chunk table pointer and the table; then the stream.
        uint64_t table_at = sta_load_u64le(data + point_data);
        for (size_t at = point_data; at < size; at++) {
            bool in_table = at < point_data + 8u || at >= table_at;
            if (!in_table && (at % 61) != 0) {
                continue;
            }
            for (int pattern = 0; pattern < 2; pattern++) {
                uint8_t *copy = malloc(size);
                memcpy(copy, data, size);
                copy[at] ^= pattern ? 0xff : 0x01;
                bool identical = false;
                if (!read_all(copy, size, &las, &identical)) {
                    errors++;
                }
                flips++;
                free(copy);
            }
        }
        printf("%s: %zu byte flips, %zu reported as errors, the rest decoded\n", files[t].laz,
               flips, errors);
        sta_file_map_close(&las.map);
        free(data);
    }
    sta_log_set_level(STA_LOG_WARN);
}

static void unsupported_and_malformed_vlrs_are_named(void **state)
{
    (void)state;
    STA_TEST_REQUIRE_SHARED_DATA();
    size_t size = 0;
    uint8_t *data = sta_test_read_file(sta_test_shared_path("laz/point-time.laz"), &size);
    // Find the LASzip VLR payload.
    size_t pos = (size_t)data[94] | (size_t)data[95] << 8;
    size_t payload = 0;
    for (uint32_t i = 0; i < sta_load_u32le(data + 100); i++) {
        size_t length = (size_t)data[pos + 20] | (size_t)data[pos + 21] << 8;
        if (memcmp(data + pos + 2, "laszip encoded", 14) == 0) {
            payload = pos + 54;
        }
        pos += 54 + length;
    }
    assert_int_not_equal(payload, 0);
    static const struct {
        size_t at;
        uint8_t value;
        sta_status code;
        const char *needle;
    } cases[] = {
        { 34 + 6 + 4, 3, STA_ERR_UNSUPPORTED, "GPSTIME11 version 3" }, // item 1 version
        { 34 + 4, 0, STA_ERR_UNSUPPORTED, "POINT10 version 0" },       // 0 = uncompressed
        { 34 + 6, 8, STA_ERR_FORMAT, "RGB12" },                        // wrong item type
        { 34 + 6 + 2, 9, STA_ERR_FORMAT, "add up to 29" },             // sizes
        { 2, 1, STA_ERR_UNSUPPORTED, "coder 1" },
        { 0, 9, STA_ERR_UNSUPPORTED, "compressor 9" },
        { 0, 3, STA_ERR_FORMAT, "compressor 3" },
        { 32, 5, STA_ERR_FORMAT, "lists 5 items" },
    };
    for (size_t c = 0; c < sizeof(cases) / sizeof(cases[0]); c++) {
        uint8_t *copy = malloc(size);
        memcpy(copy, data, size);
        copy[payload + cases[c].at] = cases[c].value;
        laz_file file;
        sta_error err = { 0 };
        assert_int_equal(open_laz_bytes(copy, size, "vlr.laz", &file, &err), cases[c].code);
        if (!strstr(err.message, cases[c].needle) || !strstr(err.message, "vlr.laz")) {
            fail_msg("case %zu: message \"%s\" lacks \"%s\"", c, err.message, cases[c].needle);
        }
        free(copy);
    }
    // A compression bit without any LASzip VLR.
    uint8_t *copy = malloc(size);
    memcpy(copy, data, size);
    memcpy(copy + payload - 54 + 2, "not laszip", 11);
    laz_file file;
    sta_error err = { 0 };
    assert_int_equal(open_laz_bytes(copy, size, "novlr.laz", &file, &err), STA_ERR_UNSUPPORTED);
    assert_non_null(strstr(err.message, "22204"));
    free(copy);
    free(data);
}

// ---- the point14 decoder driven directly ----

// Decodes all points of `data` (a LAZ file's bytes, possibly damaged) with the decoder
// itself. Returns false on an error (the message must name the file and the chunk);
// *out_identical tells whether the records equal `expected`.
static bool decode_direct(const uint8_t *data, size_t size, const sta_laz_vlr *vlr,
                          const las_records *expected, bool *out_identical)
{
    uint32_t point_data = sta_load_u32le(data + 96);
    sta_laz *laz = NULL;
    sta_error err = { 0 };
    *out_identical = false;
    if (sta_laz_open("p14.laz", data, size, point_data, vlr, expected->count, expected->length,
                     &laz, &err) != STA_OK) {
        assert_non_null(strstr(err.message, "p14.laz"));
        return false;
    }
    uint8_t *buffer = malloc(100 * expected->length);
    assert_non_null(buffer);
    bool ok = true;
    bool identical = true;
    for (uint64_t done = 0; done < expected->count; done += 100) {
        size_t step = expected->count - done < 100 ? (size_t)(expected->count - done) : 100;
        if (sta_laz_decode(laz, buffer, step, &err) != STA_OK) {
            assert_non_null(strstr(err.message, "p14.laz"));
            assert_non_null(strstr(err.message, "chunk"));
            ok = false;
            break;
        }
        identical = identical && memcmp(buffer, expected->records + done * expected->length,
                                        step * expected->length) == 0;
    }
    free(buffer);
    sta_laz_close(laz);
    *out_identical = ok && identical;
    return ok;
}

// The layered point14 decoder (POINT14 v3) reproduces the LAS twin's records byte for
// byte; every truncation of the file and a flip of every byte of the point data gives
// an error or output, never a crash (ASan) or a hang, and a truncation that decodes
// must decode right. Runs whether or not the family is switched on for readers.
static void point14_decoder_matches_its_twin(void **state)
{
    (void)state;
    STA_TEST_REQUIRE_SHARED_DATA();
    size_t size = 0;
    uint8_t *data = sta_test_read_file(sta_test_shared_path("laz/1_4_w_evlr.laz"), &size);
    las_records las;
    open_las_records("las/1_4_w_evlr.las", &las);
    assert_int_equal(las.count, 1000); // README: 1000 points, PDRF 6, 30-byte records
    assert_int_equal(las.length, 30);
    sta_laz_vlr vlr;
    assert_true(lazcheck_find_vlr(data, size, &vlr));
    assert_int_equal(vlr.compressor, STA_LAZ_COMPRESSOR_LAYERED_CHUNKED);
    assert_int_equal(vlr.items[0].type, STA_LAZ_ITEM_POINT14);
    assert_int_equal(vlr.items[0].version, 3);
    bool identical = false;
    assert_true(decode_direct(data, size, &vlr, &las, &identical));
    assert_true(identical);

    sta_log_set_level(STA_LOG_QUIET);
    uint32_t point_data = sta_load_u32le(data + 96);
    size_t complete = 0;
    // Every 8th cut, and every byte of the chunk header (first record, point count, layer
    // sizes) and the chunk table plus every 13th byte of the layers: 2 flips each.
    size_t layers_at = point_data + 8 + 30 + 4 * 10;
    uint64_t table_at = sta_load_u64le(data + point_data);
    size_t cuts = 0;
    for (size_t cut = point_data + 8; cut < size; cut += 8) {
        cuts++;
        uint8_t *copy = malloc(cut);
        memcpy(copy, data, cut);
        if (decode_direct(copy, cut, &vlr, &las, &identical)) {
            if (!identical) {
                fail_msg("1_4_w_evlr.laz cut to %zu bytes: decoded wrong points", cut);
            }
            complete++;
        }
        free(copy);
    }
    size_t errors = 0;
    size_t flips = 0;
    uint8_t *copy = malloc(size);
    for (size_t at = point_data; at < size; at++) {
        if (at >= layers_at && at < table_at && (at - layers_at) % 13 != 0) {
            continue;
        }
        for (int pattern = 0; pattern < 2; pattern++) {
            memcpy(copy, data, size);
            copy[at] ^= pattern ? 0xff : 0x01;
            errors += decode_direct(copy, size, &vlr, &las, &identical) ? 0 : 1;
            flips++;
        }
    }
    free(copy);
    sta_log_set_level(STA_LOG_WARN);
    printf("1_4_w_evlr.laz: point14 decoder byte-exact; %zu truncations (%zu decode fully: "
           "chunk table cut), %zu byte flips (%zu errors)\n",
           cuts, complete, flips, errors);
    sta_file_map_close(&las.map);
    free(data);
}

static void decoding_speed(void **state)
{
    (void)state;
    STA_TEST_REQUIRE_SHARED_DATA();
    static const char *const files[] = { "laz/autzen_trim.laz", "laz-tiles/bcts_3.laz" };
    for (size_t f = 0; f < sizeof(files) / sizeof(files[0]); f++) {
        size_t size = 0;
        uint8_t *data = sta_test_read_file(sta_test_shared_path(files[f]), &size);
        laz_file file;
        sta_error err = { 0 };
        assert_int_equal(open_laz_bytes(data, size, files[f], &file, &err), STA_OK);
        uint64_t count = file.reader->info.point_count;
        size_t length = file.reader->info.record_length;
        uint8_t *buffer = malloc(1024 * length);
        double best = 1e30;
        // Small files (the point14 one has 1000 points) are decoded many times per run.
        int repeat = count < 100000 ? 200 : 1;
        for (int run = 0; run < 3; run++) {
            double t0 = sta_clock_s();
            for (int r = 0; r < repeat; r++) {
                assert_int_equal(sta_laz_seek(file.reader->laz, 0, &err), STA_OK);
                for (uint64_t done = 0; done < count;) {
                    size_t step = count - done < 1024 ? (size_t)(count - done) : 1024;
                    assert_int_equal(sta_laz_decode(file.reader->laz, buffer, step, &err), STA_OK);
                    done += step;
                }
            }
            double dt = (sta_clock_s() - t0) / repeat;
            best = dt < best ? dt : best;
        }
        printf("LAZ decode speed: %s: %llu points in %.3f s = %.2f M points/s on one core "
               "(this build's flags)\n",
               files[f], (unsigned long long)count, best, (double)count / best / 1e6);
        free(buffer);
        close_laz(&file);
        free(data);
    }
    // The point14 (layered) file through the decoder itself: 1000 points, one chunk,
    // decoded 200 times per run (chunk start and model resets included).
    size_t size = 0;
    uint8_t *data = sta_test_read_file(sta_test_shared_path("laz/1_4_w_evlr.laz"), &size);
    las_records las;
    open_las_records("las/1_4_w_evlr.las", &las);
    sta_laz_vlr vlr;
    assert_true(lazcheck_find_vlr(data, size, &vlr));
    sta_laz *laz = NULL;
    sta_error err = { 0 };
    assert_int_equal(sta_laz_open("1_4_w_evlr.laz", data, size, sta_load_u32le(data + 96), &vlr,
                                  las.count, las.length, &laz, &err),
                     STA_OK);
    uint8_t *buffer = malloc(las.count * las.length);
    assert_non_null(buffer);
    double best = 1e30;
    for (int run = 0; run < 3; run++) {
        double t0 = sta_clock_s();
        for (int r = 0; r < 200; r++) {
            assert_int_equal(sta_laz_seek(laz, 0, &err), STA_OK);
            assert_int_equal(sta_laz_decode(laz, buffer, (size_t)las.count, &err), STA_OK);
        }
        double dt = (sta_clock_s() - t0) / 200;
        best = dt < best ? dt : best;
    }
    assert_memory_equal(buffer, las.records, las.count * las.length);
    printf("LAZ decode speed: laz/1_4_w_evlr.laz (POINT14 v3): %llu points in %.6f s = %.2f M "
           "points/s on one core (this build's flags)\n",
           (unsigned long long)las.count, best, (double)las.count / best / 1e6);
    free(buffer);
    sta_laz_close(laz);
    sta_file_map_close(&las.map);
    free(data);
}

static void forest_tiles_convert_as_one_scene(void **state)
{
    (void)state;
    STA_TEST_REQUIRE_SHARED_DATA();
    static const char *const names[] = { "laz-tiles/bcts_1.laz", "laz-tiles/bcts_2.laz",
                                         "laz-tiles/bcts_3.laz", "laz-tiles/bcts_4.laz" };
    char paths[4][4096];
    const char *inputs[4];
    for (int i = 0; i < 4; i++) {
        snprintf(paths[i], sizeof(paths[i]), "%s", sta_test_shared_path(names[i]));
        inputs[i] = paths[i];
    }
    char out[4096];
    snprintf(out, sizeof(out), "%s", sta_test_tmp_path("bcts.strata"));
    sta_convert_options options = {
        .inputs = inputs, .input_count = 4, .output = out, .threads = 2, .force = true
    };
    sta_convert_report report = { 0 };
    sta_error err = { 0 };
    sta_status status = sta_convert(&options, &report, &err);
    if (status != STA_OK) {
        fail_msg("convert: %s", err.message);
    }
    assert_int_equal(report.point_count, 2834350);
    printf("converted the 4 forest tiles: %llu points, %u nodes\n",
           (unsigned long long)report.point_count, report.node_count);
    remove(out);
}

static const struct CMUnitTest tests[] = {
    cmocka_unit_test(twins_decode_to_their_las_records),
    cmocka_unit_test(seeking_decodes_from_the_chunk_start),
    cmocka_unit_test(damaged_chunk_table_falls_back_to_sequential),
    cmocka_unit_test(forest_tiles_read_fully),
    cmocka_unit_test(forest_tiles_convert_as_one_scene),
    cmocka_unit_test(every_truncation_fails_cleanly),
    cmocka_unit_test(byte_flips_fail_cleanly),
    cmocka_unit_test(unsupported_and_malformed_vlrs_are_named),
    cmocka_unit_test(point14_decoder_matches_its_twin),
    cmocka_unit_test(decoding_speed),
};

STA_TEST_MAIN(tests)
