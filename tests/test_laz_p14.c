/* SPDX-License-Identifier: MIT
 * Tests of the point14 family LAZ decoder (layered chunks, item versions 3 and 4,
 * formats 6-10) against the test-only LAZ encoder (tests/support/lazenc).
 *
 * Design: the encoder is first anchored to LASzip itself: it re-encodes the records of
 * ../shared/data/las/1_4_w_evlr.las into exactly the chunk bytes LASzip wrote in
 * ../shared/data/laz/1_4_w_evlr.laz. Then synthetic records exercise what no real file
 * here has (four scanner channels switching back and forth, returns, classes above 31,
 * flags, user data, point source, scan angle, GPS time jumps, RGB, NIR, wave packets,
 * extra bytes): written as a LAS file, turned into LAZ by lazenc_from_las with items of
 * version 3 and of version 4, read back through the LAS reader's LAZ decoder and
 * compared byte for byte with the records.
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

enum {
    HEADER_SIZE = 375, // LAS 1.4
    VLR_HEADER = 54,
    SYNTH_POINTS = 4500,
    SYNTH_CHUNK = 1000, // 5 chunks, the last one partial
};

static size_t base_size(int pdrf)
{
    static const size_t sizes[] = { 30, 36, 38, 59, 67 };
    return sizes[pdrf - 6];
}

// An uncompressed LAS 1.4 file of `count` records (no VLRs).
static void build_las(int pdrf, const uint8_t *records, size_t count, size_t length,
                      lazenc_buf *out)
{
    uint8_t header[HEADER_SIZE] = { 0 };
    memcpy(header, "LASF", 4);
    header[24] = 1;
    header[25] = 4;
    memcpy(header + 26, "strata test", 11);
    memcpy(header + 58, "test_laz_p14", 12);
    sta_store_u16le(header + 94, HEADER_SIZE);
    sta_store_u32le(header + 96, HEADER_SIZE);
    header[104] = (uint8_t)pdrf;
    sta_store_u16le(header + 105, (uint16_t)length);
    for (int axis = 0; axis < 3; axis++) {
        sta_store_f64le(header + 131 + 8 * axis, 0.01);
        sta_store_f64le(header + 179 + 16 * axis, 1e7);      // max
        sta_store_f64le(header + 179 + 16 * axis + 8, -1e7); // min
    }
    sta_store_u64le(header + 247, count);
    lazenc_buf_put(out, header, sizeof(header));
    lazenc_buf_put(out, records, count * length);
}

// The LAZ file (lazenc_from_las) of the records, items of `version`, fixed chunks.
static void build_laz(int pdrf, uint16_t version, uint32_t chunk_size, const uint8_t *records,
                      size_t count, size_t length, lazenc_buf *out)
{
    lazenc_buf las = { 0 };
    build_las(pdrf, records, count, length, &las);
    lazenc_options options = { .compressor = STA_LAZ_COMPRESSOR_LAYERED_CHUNKED,
                               .version = version,
                               .chunk_size = chunk_size };
    char why[160];
    if (!lazenc_from_las(las.data, las.size, &options, out, why, sizeof(why))) {
        fail_msg("PDRF %d v%u: %s", pdrf, version, why);
    }
    lazenc_buf_free(&las);
}

// ---- synthetic records ----

static uint64_t rng_state;

static uint32_t rnd(void)
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return (uint32_t)(rng_state >> 16);
}

static uint32_t below(uint32_t n)
{
    return rnd() % n;
}

// `count` records of `pdrf` with `extra` extra bytes: four scanner channels whose runs
// come back to channels used before, each channel with its own colour, time and
// position trends, so that predicting from the wrong context costs bits.
static uint8_t *synth_records(int pdrf, size_t extra, size_t count, uint64_t seed,
                              size_t *out_length)
{
    size_t length = base_size(pdrf) + extra;
    uint8_t *recs = calloc(count, length);
    assert_non_null(recs);
    rng_state = seed;
    uint32_t x[4] = { 1000, 50000, (uint32_t)-3000, 7 }; // coordinates wrap (unsigned)
    uint32_t y[4] = { 0, 100, 200, 300 };
    uint32_t z[4] = { 500, 600, 700, 800 };
    double t[4] = { 1000.0, 2000.5, 3.25e8, 77.0 };
    uint16_t rgb[4][4] = {
        { 100, 100, 100, 9 }, { 65000, 200, 3, 1000 }, { 4000, 4100, 4200, 0 }, { 7, 7, 7, 7 }
    };
    uint64_t wp_offset[4] = { 0, 1u << 20, 5000000000ull, 12 };
    uint32_t channel = 1;
    uint32_t n = 1;
    uint32_t r = 1;
    uint16_t source = 17;
    uint8_t user = 3;
    int16_t angle = -300;
    for (size_t i = 0; i < count; i++) {
        uint8_t *p = recs + i * length;
        if (r >= n) { // a new pulse: maybe another channel, always a new time
            if (below(4) == 0) {
                channel = below(4);
            }
            n = 1 + below(5);
            r = 1;
            uint32_t jump = below(50);
            t[channel] += jump == 0   ? 1e6 + below(1000)              // a big jump
                          : jump == 1 ? -(double)below(100) * 1e-3     // backwards
                                      : 1e-5 * (double)(1 + below(3)); // regular
        } else {
            r++;
        }
        uint32_t pn = n;
        uint32_t pr = r;
        if (below(200) == 0) { // odd return numbering
            pr = below(16);
            pn = below(16);
        }
        x[channel] += below(2001) - 1000u;
        y[channel] += below(101) - 50u;
        z[channel] += below(21) - 10u;
        if (below(300) == 0) {
            x[channel] += 1u << 28; // a far point
        }
        sta_store_u32le(p, x[channel]);
        sta_store_u32le(p + 4, y[channel]);
        sta_store_u32le(p + 8, z[channel]);
        sta_store_u16le(p + 12, (uint16_t)(below(4) ? 1000 + below(50) * pr : below(65536)));
        p[14] = (uint8_t)(pr | pn << 4);
        uint32_t class_flags = below(10) == 0 ? below(16) : 0;
        uint32_t scan_dir = (uint32_t)(i / 37) & 1;
        uint32_t edge = below(100) == 0;
        p[15] = (uint8_t)(class_flags | channel << 4 | scan_dir << 6 | edge << 7);
        static const uint8_t classes[] = { 1, 2, 2, 2, 5, 6, 40, 64, 200, 255 };
        p[16] = below(3) ? classes[(channel + pr) % 4] : classes[below(10)];
        if (below(20) == 0) {
            user = (uint8_t)below(256);
        }
        p[17] = user;
        if (below(25) == 0) {
            angle = (int16_t)((int32_t)below(60001) - 30000);
        }
        sta_store_u16le(p + 18, (uint16_t)angle);
        if (below(500) == 0) {
            source = (uint16_t)below(65536);
        }
        sta_store_u16le(p + 20, source);
        sta_store_f64le(p + 22, t[channel]);
        size_t at = 30;
        if (pdrf == 7 || pdrf == 8 || pdrf == 10) {
            uint16_t *c = rgb[channel];
            if (below(3) == 0) {
                c[0] = (uint16_t)(c[0] + below(600) - 300);
                c[1] = below(5) == 0 ? c[0] : (uint16_t)(c[1] + below(9) - 4);
                c[2] = below(5) == 0 ? c[0] : (uint16_t)(c[2] + below(300));
            }
            if (below(4) == 0) {
                c[3] = (uint16_t)(c[3] + below(2000) - 1000);
            }
            for (int k = 0; k < 3; k++) {
                sta_store_u16le(p + at + 2 * k, c[k]);
            }
            at += 6;
            if (pdrf != 7) {
                sta_store_u16le(p + at, c[3]);
                at += 2;
            }
        }
        if (pdrf == 9 || pdrf == 10) {
            uint32_t size = 64 + 16 * (channel + 1);
            uint32_t kind = below(10);
            uint64_t *o = &wp_offset[channel];
            *o = kind < 6   ? *o + size                           // back to back
                 : kind < 7 ? *o                                  // same packet
                 : kind < 9 ? *o + below(100000)                  // a gap
                            : *o + ((uint64_t)below(1000) << 33); // a huge jump
            p[at] = (uint8_t)(1 + channel + (below(50) == 0));
            sta_store_u64le(p + at + 1, *o);
            sta_store_u32le(p + at + 9, below(30) ? size : below(100000));
            sta_store_u32le(p + at + 13, rnd());          // return point (f32 bits)
            sta_store_u32le(p + at + 17, 0x3f800000u);    // x(t) = 1.0f
            sta_store_u32le(p + at + 21, rnd() & 0xffff); // y(t)
            sta_store_u32le(p + at + 25, below(2) ? 0 : rnd());
            at += 29;
        }
        for (size_t e = 0; e < extra; e++) {
            // byte 0 constant (empty layer), byte 1 the channel, others vary
            p[at + e] = e == 0 ? 42 : e == 1 ? (uint8_t)channel : (uint8_t)(below(4) ? e : rnd());
        }
    }
    *out_length = length;
    return recs;
}

// Reads `data` through the LAS reader's LAZ decoder; compares raw records with
// `expected`. Returns false (message checked) when the reader reports an error.
static bool read_back(const uint8_t *data, size_t size, const uint8_t *expected, size_t count,
                      size_t length, bool *out_identical)
{
    lazcheck_records want = { .records = expected, .count = count, .length = length };
    char message[512];
    if (!lazcheck_try_decode(data, size, "synth.laz", &want, out_identical, message,
                             sizeof(message))) {
        assert_non_null(strstr(message, "synth.laz"));
        return false;
    }
    return true;
}

// Encodes synthetic `pdrf` records as version 3 and 4 and reads them back exactly.
static void round_trip(int pdrf, size_t extra)
{
    size_t length = 0;
    uint8_t *recs =
        synth_records(pdrf, extra, SYNTH_POINTS, 0x9e3779b97f4a7c15ull + (uint64_t)pdrf, &length);
    for (uint16_t version = 3; version <= 4; version++) {
        lazenc_buf file = { 0 };
        build_laz(pdrf, version, SYNTH_CHUNK, recs, SYNTH_POINTS, length, &file);
        bool identical = false;
        assert_true(read_back(file.data, file.size, recs, SYNTH_POINTS, length, &identical));
        if (!identical) {
            fail_msg("PDRF %d (+%zu extra bytes) version %u: decoded records differ", pdrf, extra,
                     version);
        }
        printf("PDRF %d + %zu extra bytes, v%u: %d points in %zu bytes (%zu raw) round-trip\n",
               pdrf, extra, version, SYNTH_POINTS, file.size, (size_t)SYNTH_POINTS * length);
        lazenc_buf_free(&file);
    }
    free(recs);
}

// ---- cases ----

// The encoder re-creates LASzip's chunk bytes of 1_4_w_evlr.laz from its LAS twin.
static void encoder_reproduces_laszip_chunks(void **state)
{
    (void)state;
    STA_TEST_REQUIRE_SHARED_DATA();
    size_t laz_size = 0;
    size_t las_size = 0;
    uint8_t *laz = sta_test_read_file(sta_test_shared_path("laz/1_4_w_evlr.laz"), &laz_size);
    uint8_t *las = sta_test_read_file(sta_test_shared_path("las/1_4_w_evlr.las"), &las_size);
    // The LASzip VLR's items and chunk size, as in the file.
    sta_laz_vlr vlr = { 0 };
    assert_true(lazcheck_find_vlr(laz, laz_size, &vlr));
    assert_int_equal(vlr.compressor, STA_LAZ_COMPRESSOR_LAYERED_CHUNKED);
    lazcheck_records records;
    assert_true(lazcheck_las_records(las, las_size, &records));
    size_t length = records.length;
    uint64_t count = records.count;

    // Walk the chunks from offset_to_point_data + 8 to the chunk table.
    uint32_t laz_data = sta_load_u32le(laz + 96);
    uint64_t table = sta_load_u64le(laz + laz_data);
    size_t pos = laz_data + 8;
    size_t matched = 0;
    size_t chunks = 0;
    for (uint64_t first = 0; first < count; first += vlr.chunk_size) {
        size_t n = count - first < vlr.chunk_size ? (size_t)(count - first) : vlr.chunk_size;
        lazenc_buf chunk = { 0 };
        assert_true(
            lazenc_point14_chunk(&vlr, records.records + first * length, n, length, &chunk));
        assert_true(pos + chunk.size <= table);
        for (size_t i = 0; i < chunk.size; i++) {
            if (chunk.data[i] != laz[pos + i]) {
                fail_msg(
                    "chunk %zu byte %zu (file offset %zu): encoder wrote 0x%02x, LASzip 0x%02x "
                    "(chunk of %zu bytes)",
                    chunks, i, pos + i, chunk.data[i], laz[pos + i], chunk.size);
            }
        }
        matched += chunk.size;
        pos += chunk.size;
        chunks++;
        lazenc_buf_free(&chunk);
    }
    assert_int_equal(pos, table); // the chunks end exactly where the table starts
    printf("1_4_w_evlr.laz: %zu chunk(s), %zu bytes re-encoded identically from %llu records\n",
           chunks, matched, (unsigned long long)count);
    free(las);
    free(laz);
}

static void pdrf6_round_trips(void **state)
{
    (void)state;
    round_trip(6, 0);
}

static void pdrf6_extra_bytes_round_trip(void **state)
{
    (void)state;
    round_trip(6, 11); // more than 8 bytes: the decoder's wide per-context buffer
}

static void pdrf7_rgb_round_trips(void **state)
{
    (void)state;
    round_trip(7, 3);
}

static void pdrf8_rgbnir_round_trips(void **state)
{
    (void)state;
    round_trip(8, 0);
}

static void pdrf9_wave_packets_round_trip(void **state)
{
    (void)state;
    round_trip(9, 2);
}

static void pdrf10_rgbnir_wave_packets_round_trip(void **state)
{
    (void)state;
    round_trip(10, 5);
}

// The context-switch rule of version 4 is exercised: the two encodings of multi-channel
// RGB differ, in the RGB layer only; single-channel data encodes identically; and a v4
// file read as v3 does not give the records.
static void v3_and_v4_differ_on_channel_switches(void **state)
{
    (void)state;
    size_t length = 0;
    uint8_t *recs = synth_records(7, 0, SYNTH_POINTS, 12345, &length);
    lazenc_buf f3 = { 0 };
    lazenc_buf f4 = { 0 };
    build_laz(7, 3, SYNTH_CHUNK, recs, SYNTH_POINTS, length, &f3);
    build_laz(7, 4, SYNTH_CHUNK, recs, SYNTH_POINTS, length, &f4);
    // Chunk by chunk: the first record, the count and the nine POINT14 layers are the
    // same in both versions; the RGB14 layer differs in some chunk.
    size_t at3 = sta_load_u32le(f3.data + 96) + 8;
    size_t at4 = sta_load_u32le(f4.data + 96) + 8;
    size_t rgb_differs = 0;
    for (size_t c = 0; c < (SYNTH_POINTS + SYNTH_CHUNK - 1) / SYNTH_CHUNK; c++) {
        enum {
            SIZES = 36 + 4,
            LAYERS = 10
        };
        const uint8_t *c3 = f3.data + at3;
        const uint8_t *c4 = f4.data + at4;
        assert_memory_equal(c3, c4, SIZES + 4 * (LAYERS - 1));
        size_t point14 = 0;
        for (int l = 0; l < LAYERS - 1; l++) {
            point14 += sta_load_u32le(c3 + SIZES + 4 * l);
        }
        size_t head = SIZES + 4 * LAYERS;
        assert_memory_equal(c3 + head, c4 + head, point14);
        uint32_t rgb3 = sta_load_u32le(c3 + SIZES + 4 * (LAYERS - 1));
        uint32_t rgb4 = sta_load_u32le(c4 + SIZES + 4 * (LAYERS - 1));
        rgb_differs += rgb3 != rgb4 || memcmp(c3 + head + point14, c4 + head + point14, rgb3) != 0;
        at3 += head + point14 + rgb3;
        at4 += head + point14 + rgb4;
        assert_true(at3 <= f3.size && at4 <= f4.size);
    }
    assert_true(rgb_differs > 0);
    // Single-channel data encodes identically in both versions (bar the VLR's versions).
    uint8_t *one = malloc(SYNTH_POINTS * length);
    assert_non_null(one);
    memcpy(one, recs, SYNTH_POINTS * length);
    for (size_t i = 0; i < SYNTH_POINTS; i++) {
        one[i * length + 15] &= 0xcf; // channel 0 everywhere
    }
    lazenc_buf s3 = { 0 };
    lazenc_buf s4 = { 0 };
    build_laz(7, 3, SYNTH_CHUNK, one, SYNTH_POINTS, length, &s3);
    build_laz(7, 4, SYNTH_CHUNK, one, SYNTH_POINTS, length, &s4);
    uint32_t data3 = sta_load_u32le(s3.data + 96);
    assert_int_equal(s3.size, s4.size);
    assert_memory_equal(s3.data + data3, s4.data + data3, s3.size - data3);
    // The v4 file's VLR relabelled as version 3: the decoder must not reproduce the points.
    uint8_t *relabelled = malloc(f4.size);
    assert_non_null(relabelled);
    memcpy(relabelled, f4.data, f4.size);
    sta_laz_vlr v4;
    assert_true(lazcheck_find_vlr(f4.data, f4.size, &v4));
    size_t vlr_at = HEADER_SIZE; // the LASzip VLR is the file's only VLR
    assert_memory_equal(relabelled + vlr_at + 2, "laszip encoded", 14);
    size_t items = vlr_at + VLR_HEADER + 34;
    for (uint16_t i = 0; i < v4.item_count; i++) {
        sta_store_u16le(relabelled + items + 6 * i + 4, 3);
    }
    sta_log_set_level(STA_LOG_QUIET);
    bool identical = true;
    (void)read_back(relabelled, f4.size, recs, SYNTH_POINTS, length, &identical);
    sta_log_set_level(STA_LOG_WARN);
    assert_false(identical);
    printf("PDRF 7, 4 channels: v3 %zu bytes, v4 %zu bytes, RGB layer differs in %zu of %d "
           "chunks; one channel: identical point data\n",
           f3.size, f4.size, rgb_differs, (SYNTH_POINTS + SYNTH_CHUNK - 1) / SYNTH_CHUNK);
    free(relabelled);
    free(one);
    lazenc_buf_free(&s3);
    lazenc_buf_free(&s4);
    lazenc_buf_free(&f3);
    lazenc_buf_free(&f4);
    free(recs);
}

// Every 97th truncation and two flips of every 61st byte of the point data of a PDRF 10
// file (both versions): a named error or decoded records (the right ones after a cut that
// left all chunks), never a crash or a hang.
static void damaged_files_fail_cleanly(void **state)
{
    (void)state;
    enum {
        POINTS = 1200,
        CHUNK = 500
    };
    size_t length = 0;
    uint8_t *recs = synth_records(10, 4, POINTS, 777, &length);
    sta_log_set_level(STA_LOG_QUIET);
    for (uint16_t version = 3; version <= 4; version++) {
        lazenc_buf file = { 0 };
        build_laz(10, version, CHUNK, recs, POINTS, length, &file);
        uint32_t point_data = sta_load_u32le(file.data + 96);
        size_t cuts = 0;
        size_t cut_ok = 0;
        bool identical = false;
        for (size_t cut = point_data; cut < file.size; cut += 97) {
            uint8_t *copy = malloc(cut);
            assert_non_null(copy);
            memcpy(copy, file.data, cut);
            if (read_back(copy, cut, recs, POINTS, length, &identical)) {
                if (!identical) {
                    fail_msg("v%u cut to %zu bytes: decoded wrong records", version, cut);
                }
                cut_ok++;
            }
            cuts++;
            free(copy);
        }
        size_t flips = 0;
        size_t errors = 0;
        uint8_t *copy = malloc(file.size);
        assert_non_null(copy);
        for (size_t at = point_data; at < file.size; at += 61) {
            for (int pattern = 0; pattern < 2; pattern++) {
                memcpy(copy, file.data, file.size);
                copy[at] ^= pattern ? 0xff : 0x10;
                errors += read_back(copy, file.size, recs, POINTS, length, &identical) ? 0 : 1;
                flips++;
            }
        }
        free(copy);
        printf("PDRF 10 v%u: %zu truncations (%zu decode fully), %zu flips (%zu errors)\n", version,
               cuts, cut_ok, flips, errors);
        lazenc_buf_free(&file);
    }
    sta_log_set_level(STA_LOG_WARN);
    free(recs);
}

static const struct CMUnitTest tests[] = {
    cmocka_unit_test(encoder_reproduces_laszip_chunks),
    cmocka_unit_test(pdrf6_round_trips),
    cmocka_unit_test(pdrf6_extra_bytes_round_trip),
    cmocka_unit_test(pdrf7_rgb_round_trips),
    cmocka_unit_test(pdrf8_rgbnir_round_trips),
    cmocka_unit_test(pdrf9_wave_packets_round_trip),
    cmocka_unit_test(pdrf10_rgbnir_wave_packets_round_trip),
    cmocka_unit_test(v3_and_v4_differ_on_channel_switches),
    cmocka_unit_test(damaged_files_fail_cleanly),
};

STA_TEST_MAIN(tests)
