/* SPDX-License-Identifier: MIT
 * Tests for the packing of preprocess/normal_fit.c: a normal stored with a radius already
 * made a half float and the memo of the last octahedral map (the moments method's
 * sta_normal_store_half_at) gives sta_splat_pack's bytes, through repeats, sign flips and
 * normals that differ in one component only (a memo that compared less would reuse a
 * stale map). */
#include "test_support.h"

#include <string.h>

#include "core/octahedral.h"
#include "normal_fit.h"

static void memo_gives_the_packed_bytes(void **state)
{
    (void)state;
    sta_normals_chunk chunk;
    memset(&chunk, 0, sizeof(chunk));
    for (int a = 0; a < 3; a++) {
        chunk.scale[a] = 0.001;
        chunk.box_max[a] = chunk.scene_max[a] = 1 << 20;
    }
    chunk.up_axis = 2;
    sta_record_layout layout;
    sta_record_layout_init(&layout, STA_ATTR_SPLAT, 0);
    uint8_t record[256];
    assert_true(layout.size <= sizeof(record));
    const double normals[][3] = {
        { 0.6, 0.0, 0.8 },   { 0.6, 0.0, 0.8 },  { 0.6, 0.0, -0.8 }, { -0.6, 0.0, 0.8 },
        { 0.0, 0.6, 0.8 },   { 0.0, 0.6, 0.8 },  { 0.8, 0.6, 0.0 },  { 0.8, -0.6, 0.0 },
        { 0.8, 0.6, 0.0 },   { 0.0, 0.0, 1.0 },  { 0.0, 0.0, -1.0 }, { 0.6, 0.8, 1e-9 },
        { 0.6, 0.8, -1e-9 }, { 0.6, 0.8, 1e-9 }, { 0.6, 0.0, 0.8 },  { 0.6, 0.0, 0.1 },
        { 0.6, 0.1, 0.5 },   { 0.6, 0.1, 0.3 },  { 0.6, 0.1, 0.3 },
    };
    const float radii[] = { 0.01f, 0.02f, 0.02f, 0.5f };
    sta_normal_memo memo = { 0 };
    sta_normals_stats stats;
    memset(&stats, 0, sizeof(stats));
    for (size_t i = 0; i < sizeof(normals) / sizeof(normals[0]); i++) {
        const double p[3] = { 1000.0 * (double)i, 500.0, 20.0 }, target[3] = { 0.0, 0.0, 2000.0 };
        for (int seen = 0; seen < 2; seen++) {
            double n[3] = { normals[i][0], normals[i][1], normals[i][2] };
            float radius = radii[i % 4];
            memset(record, 0xAB, sizeof(record));
            sta_normal_store_half_at(&chunk, &layout, record, p, seen ? target : NULL, true, n,
                                     sta_half_from_float(radius), &memo, &stats);
            // n is the oriented normal now: the bytes sta_splat_pack makes of it
            const float nf[3] = { (float)n[0], (float)n[1], (float)n[2] };
            uint16_t want[3], got[3];
            sta_splat_pack(nf, radius, want);
            memcpy(got, record + layout.splat_offset, sizeof(got));
            assert_memory_equal(got, want, sizeof(want));
        }
    }
    // The degenerate fallback (up) through the memo too.
    double n[3] = { 0.3, 0.3, 0.3 };
    const double p[3] = { 0, 0, 0 };
    sta_normal_store_half_at(&chunk, &layout, record, p, NULL, false, n, 0, &memo, &stats);
    const float up[3] = { 0.0f, 0.0f, 1.0f };
    uint16_t want[3], got[3];
    sta_splat_pack(up, 0.0f, want);
    memcpy(got, record + layout.splat_offset, sizeof(got));
    assert_memory_equal(got, want, sizeof(want));
    assert_int_equal(stats.degenerate, 1);
}

static const struct CMUnitTest tests[] = {
    cmocka_unit_test(memo_gives_the_packed_bytes),
};

STA_TEST_MAIN(tests)
