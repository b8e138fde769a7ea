/* SPDX-License-Identifier: MIT
 * Tests of the test-only LAZ encoder (tests/support/lazenc) and, through it, of the
 * LAZ decoder on layouts the shared data lacks.
 *
 * - The anchor: re-encoding the LAS twins of ../shared/data/laz (point10 family,
 *   version 2) with the chunk size of the LAZ file gives exactly LASzip's chunk bytes
 *   and chunk table. So the encoder writes what LASzip writes, and files it makes are
 *   fair test input for the decoder.
 * - Whole files from LAS files read back through the LAS reader to the same records:
 *   chunked and pointwise compressors, variable chunks (as COPC writes them), a
 *   missing chunk table.
 */
#include "test_support.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/bytes.h"
#include "lazenc.h"
#include "lazenc_check.h"

static uint8_t *read_shared(const char *relative, size_t *size)
{
    return sta_test_read_file(sta_test_shared_path(relative), size);
}

// The LASzip twin's chunk bytes and chunk table equal what the encoder writes for
// the LAS twin's records (version 2 items, the file's own chunk size).
static void twins_reencode_to_the_laszip_bytes(void **state)
{
    (void)state;
    STA_TEST_REQUIRE_SHARED_DATA();
    size_t matched = 0;
    size_t skipped = 0;
    for (size_t t = 0; t < lazcheck_twin_count; t++) {
        size_t laz_size = 0;
        size_t las_size = 0;
        uint8_t *laz = read_shared(lazcheck_twins[t].laz, &laz_size);
        uint8_t *las = read_shared(lazcheck_twins[t].las, &las_size);
        lazcheck_records records;
        sta_laz_vlr vlr;
        assert_true(lazcheck_las_records(las, las_size, &records));
        assert_true(lazcheck_find_vlr(laz, laz_size, &vlr));
        if (records.count == 0 || vlr.compressor == STA_LAZ_COMPRESSOR_LAYERED_CHUNKED) {
            skipped++; // no points; point14 (anchored in test_laz_p14.c)
            free(laz);
            free(las);
            continue;
        }
        lazenc_options options = { .compressor = vlr.compressor,
                                   .version = vlr.items[0].version,
                                   .chunk_size = vlr.chunk_size };
        uint64_t point_data = sta_load_u32le(laz + 96);
        lazenc_buf ours = { 0 };
        assert_true(lazenc_point_data(&options, &vlr, records.records, records.count,
                                      records.length, point_data, &ours));
        uint64_t table = sta_load_u64le(laz + point_data);
        uint64_t our_table = sta_load_u64le(ours.data) - point_data;
        assert_true(table > point_data && table <= laz_size);
        size_t chunk_bytes = (size_t)(table - point_data);
        if (chunk_bytes != our_table ||
            memcmp(laz + point_data + 8, ours.data + 8, chunk_bytes - 8) != 0) {
            size_t at = 8;
            while (at < chunk_bytes && at < our_table && laz[point_data + at] == ours.data[at]) {
                at++;
            }
            fail_msg("%s: chunk bytes differ from byte %zu of %zu (ours %llu bytes)",
                     lazcheck_twins[t].laz, at, chunk_bytes, (unsigned long long)our_table);
        }
        // The chunk table: version, count and the coded sizes (LASzip pads its end).
        size_t table_bytes = ours.size - (size_t)our_table;
        assert_true(laz_size - table >= table_bytes);
        assert_memory_equal(laz + table, ours.data + our_table, table_bytes);
        printf("%s: %llu points, %zu chunk bytes identical\n", lazcheck_twins[t].laz,
               (unsigned long long)records.count, chunk_bytes - 8);
        matched++;
        lazenc_buf_free(&ours);
        free(laz);
        free(las);
    }
    assert_int_equal(skipped, 2); // no-points-1.3.laz, 1_4_w_evlr.laz
    assert_int_equal(matched, lazcheck_twin_count - skipped);
}

// Encodes `las_relative` with `options`, reads it back, compares the records.
static void round_trip(const char *las_relative, const lazenc_options *options)
{
    size_t las_size = 0;
    uint8_t *las = read_shared(las_relative, &las_size);
    lazcheck_records records;
    assert_true(lazcheck_las_records(las, las_size, &records));
    lazenc_buf laz = { 0 };
    char why[128];
    if (!lazenc_from_las(las, las_size, options, &laz, why, sizeof(why))) {
        fail_msg("%s: %s", las_relative, why);
    }
    lazcheck_expect_records(laz.data, laz.size, las_relative, &records);
    lazenc_buf_free(&laz);
    free(las);
}

static const char *const las_files[] = {
    "las/autzen_trim.las", "las/point-time-color.las", "las/extra-bytes.las", "las/point10-1.0.las",
    "las/1815.las",
};

// Chunked (small and large chunks) and pointwise files read back to their records.
static void files_from_las_read_back(void **state)
{
    (void)state;
    STA_TEST_REQUIRE_SHARED_DATA();
    for (size_t f = 0; f < sizeof(las_files) / sizeof(las_files[0]); f++) {
        lazenc_options chunked = { .compressor = 2, .version = 2, .chunk_size = 777 };
        round_trip(las_files[f], &chunked);
        chunked.chunk_size = 50000;
        round_trip(las_files[f], &chunked);
        lazenc_options pointwise = { .compressor = 1, .version = 2, .chunk_size = 0 };
        round_trip(las_files[f], &pointwise);
    }
}

// Variable chunks (COPC writes one per octree node): 1 to 4000 points each.
static void variable_chunks_read_back(void **state)
{
    (void)state;
    STA_TEST_REQUIRE_SHARED_DATA();
    enum {
        CHUNKS = 200
    }; // more points than autzen_trim.las has; the rest go unused
    uint32_t sizes[CHUNKS];
    for (size_t i = 0; i < CHUNKS; i++) {
        sizes[i] = (uint32_t)(1 + (i * 7919) % 4000);
    }
    lazenc_options variable = { .compressor = 2,
                                .version = 2,
                                .chunk_size = UINT32_MAX,
                                .chunk_points = sizes,
                                .chunk_count = CHUNKS };
    round_trip("las/autzen_trim.las", &variable);
    round_trip("las/point-time-color.las", &variable);
}

// Without a chunk table the reader walks the chunks sequentially (with a warning).
static void missing_chunk_table_reads_sequentially(void **state)
{
    (void)state;
    STA_TEST_REQUIRE_SHARED_DATA();
    lazenc_options options = {
        .compressor = 2, .version = 2, .chunk_size = 1000, .no_chunk_table = true
    };
    round_trip("las/autzen_trim.las", &options);
}

// ---- a COPC-like file ----

enum {
    COPC_POINTS = 9000,
    COPC_RECORD = 36,
    COPC_INFO = 160,
    COPC_PAGE = 32
};

/* A LAS 1.4 PDRF 7 file laid out as COPC writes it: the "copc" info VLR first, the
 * points of each octree node together (one variable chunk per node once compressed),
 * the hierarchy as an EVLR after the points. The copc VLR contents are placeholders
 * (the reader must not need them). */
static uint8_t *copc_like_las(size_t *out_size)
{
    size_t vlr = 54 + COPC_INFO;
    size_t point_data = 375 + vlr;
    size_t evlr_at = point_data + (size_t)COPC_POINTS * COPC_RECORD;
    size_t size = evlr_at + 60 + COPC_PAGE;
    uint8_t *d = calloc(1, size);
    assert_non_null(d);
    memcpy(d, "LASF", 4);
    d[24] = 1;
    d[25] = 4;
    memcpy(d + 26, "strata tests", 12);
    memcpy(d + 58, "copc-like layout", 16);
    sta_store_u16le(d + 94, 375);
    sta_store_u32le(d + 96, point_data);
    sta_store_u32le(d + 100, 1);
    d[104] = 7;
    sta_store_u16le(d + 105, COPC_RECORD);
    for (int a = 0; a < 3; a++) {
        sta_store_f64le(d + 131 + 8 * a, 0.001);
        sta_store_f64le(d + 155 + 8 * a, a == 2 ? 100.0 : 500000.0 + 4e6 * a);
    }
    // The "copc" info VLR (record 1).
    uint8_t *v = d + 375;
    memcpy(v + 2, "copc", 4);
    sta_store_u16le(v + 18, 1);
    sta_store_u16le(v + 20, COPC_INFO);
    sta_store_f64le(v + 54, 500000.0); // centre x (placeholder values)
    double lo[3] = { 1e30, 1e30, 1e30 };
    double hi[3] = { -1e30, -1e30, -1e30 };
    for (unsigned i = 0; i < COPC_POINTS; i++) {
        uint8_t *r = d + point_data + (size_t)i * COPC_RECORD;
        unsigned node = i / 700; // points of a node stay together
        int32_t xyz[3] = { (int32_t)(node * 100000 + (i * 7919u) % 90000),
                           (int32_t)(node * 50000 + (i * 104729u) % 45000),
                           (int32_t)((i * 31u) % 20000) - 5000 };
        for (int a = 0; a < 3; a++) {
            sta_store_u32le(r + 4 * a, (uint32_t)xyz[a]);
            double c = xyz[a] * 0.001 + (a == 2 ? 100.0 : 500000.0 + 4e6 * a);
            lo[a] = c < lo[a] ? c : lo[a];
            hi[a] = c > hi[a] ? c : hi[a];
        }
        unsigned n = 1 + i % 5;
        unsigned ret = 1 + (i / 5) % n;
        sta_store_u16le(r + 12, (uint16_t)((i * 2311u) % 65536u));
        r[14] = (uint8_t)(ret | n << 4);
        r[15] = (uint8_t)((i / 97) % 4 << 4 | (i % 3 == 0) << 6); // channel, scan dir
        r[16] = (uint8_t)(i % 40 < 30 ? 2 : 6 + i % 60);
        r[17] = (uint8_t)(i / 1000);
        sta_store_u16le(r + 18, (uint16_t)(int16_t)((int)(i % 3000) - 1500));
        sta_store_u16le(r + 20, (uint16_t)(7 + i / 4000));
        sta_store_f64le(r + 22, 3.2e8 + (i / 5) * 1e-5 + node * 10.0);
        sta_store_u16le(r + 30, (uint16_t)((i * 257u) % 65536u));
        sta_store_u16le(r + 32, (uint16_t)((i * 263u) % 65536u));
        sta_store_u16le(r + 34, (uint16_t)(65535u - (i * 3u) % 65536u));
    }
    for (int a = 0; a < 3; a++) {
        sta_store_f64le(d + 179 + 16 * a, hi[a]);
        sta_store_f64le(d + 187 + 16 * a, lo[a]);
    }
    sta_store_u64le(d + 235, evlr_at);
    sta_store_u32le(d + 243, 1);
    sta_store_u64le(d + 247, COPC_POINTS);
    uint8_t *e = d + evlr_at; // the hierarchy EVLR (record 1000), one placeholder page
    memcpy(e + 2, "copc", 4);
    sta_store_u16le(e + 18, 1000);
    sta_store_u64le(e + 20, COPC_PAGE);
    *out_size = size;
    return d;
}

// A COPC-like file (LAZ 1.4, layered point14 items, one variable chunk per node, copc
// VLR and hierarchy EVLR) reads as ordinary LAZ, with its EVLR found after the chunks.
static void copc_layout_reads_as_ordinary_laz(void **state)
{
    (void)state;
    size_t las_size = 0;
    uint8_t *las = copc_like_las(&las_size);
    lazcheck_records records;
    assert_true(lazcheck_las_records(las, las_size, &records));
    uint32_t nodes[COPC_POINTS / 700 + 1];
    for (size_t i = 0; i < sizeof(nodes) / sizeof(nodes[0]); i++) {
        nodes[i] = 700;
    }
    for (uint16_t version = 3; version <= 4; version++) {
        lazenc_options options = { .compressor = STA_LAZ_COMPRESSOR_LAYERED_CHUNKED,
                                   .version = version,
                                   .chunk_size = UINT32_MAX,
                                   .chunk_points = nodes,
                                   .chunk_count = sizeof(nodes) / sizeof(nodes[0]) };
        lazenc_buf laz = { 0 };
        char why[128];
        if (!lazenc_from_las(las, las_size, &options, &laz, why, sizeof(why))) {
            fail_msg("copc-like: %s", why);
        }
        lazcheck_expect_records(laz.data, laz.size, "copc-like.copc.laz", &records);
        // The hierarchy EVLR moved behind the chunk table and is still found.
        uint64_t evlr = sta_load_u64le(laz.data + 235);
        assert_true(evlr > sta_load_u32le(laz.data + 96) && evlr + 60 <= laz.size);
        assert_memory_equal(laz.data + evlr + 2, "copc", 4);
        lazenc_buf_free(&laz);
    }
    free(las);
}

static const struct CMUnitTest tests[] = {
    cmocka_unit_test(twins_reencode_to_the_laszip_bytes),
    cmocka_unit_test(files_from_las_read_back),
    cmocka_unit_test(variable_chunks_read_back),
    cmocka_unit_test(missing_chunk_table_reads_sequentially),
    cmocka_unit_test(copc_layout_reads_as_ordinary_laz),
};

STA_TEST_MAIN(tests)
