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

typedef struct twin {
    const char *laz;
    const char *las;
} twin;

// Point10-family twins from ../shared/data/README.md whose LAZ LASzip wrote.
static const twin twins[] = {
    { "laz/simple.laz", "las/simple.las" },
    { "laz/laszip-generated_with2bytespadding.laz", "las/simple.las" },
    { "laz/liblas-generated.laz", "las/simple.las" },
    { "laz/autzen_trim.laz", "las/autzen_trim.las" },
    { "laz/autzen.laz", "las/autzen-point-format-3.las" },
    { "laz/point10.laz", "las/point10.las" },
    { "laz/point-time.laz", "las/point-time.las" },
    { "laz/point-color.laz", "las/point-color.las" },
    { "laz/point-time-color.laz", "las/point-time-color.las" },
    { "laz/extra-bytes.laz", "las/extra-bytes.las" },
    { "laz/point-time-1.4.las.laz", "las/point-time.las" },
    { "laz/1815.laz", "las/1815.las" },
    { "laz/point10-1.0.laz", "las/point10-1.0.las" },
    { "laz/Megaplot.laz", "las/Megaplot.las" },
    { "laz/MixedConifer.laz", "las/MixedConifer.las" },
    { "laz/Example.laz", "las/Example.las" },
    { "laz/extra_byte.laz", "las/extra_byte.las" },
};

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
    for (size_t t = 0; t < sizeof(twins) / sizeof(twins[0]); t++) {
        size_t laz_size = 0;
        size_t las_size = 0;
        uint8_t *laz = read_shared(twins[t].laz, &laz_size);
        uint8_t *las = read_shared(twins[t].las, &las_size);
        lazcheck_records records;
        sta_laz_vlr vlr;
        assert_true(lazcheck_las_records(las, las_size, &records));
        assert_true(lazcheck_find_vlr(laz, laz_size, &vlr));
        if (records.count == 0) {
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
            fail_msg("%s: chunk bytes differ from byte %zu of %zu (ours %llu bytes)", twins[t].laz,
                     at, chunk_bytes, (unsigned long long)our_table);
        }
        // The chunk table: version, count and the coded sizes (LASzip pads its end).
        size_t table_bytes = ours.size - (size_t)our_table;
        assert_true(laz_size - table >= table_bytes);
        assert_memory_equal(laz + table, ours.data + our_table, table_bytes);
        printf("%s: %llu points, %zu chunk bytes identical\n", twins[t].laz,
               (unsigned long long)records.count, chunk_bytes - 8);
        matched++;
        lazenc_buf_free(&ours);
        free(laz);
        free(las);
    }
    assert_int_equal(matched, sizeof(twins) / sizeof(twins[0]));
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

static const struct CMUnitTest tests[] = {
    cmocka_unit_test(twins_reencode_to_the_laszip_bytes),
    cmocka_unit_test(files_from_las_read_back),
    cmocka_unit_test(variable_chunks_read_back),
    cmocka_unit_test(missing_chunk_table_reads_sequentially),
};

STA_TEST_MAIN(tests)
