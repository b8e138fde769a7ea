/* SPDX-License-Identifier: MIT
 * The CPU subsample of resident points (stream/point_sample.h): the stride from budget
 * and cap, every stride-th record kept per upload, dropped on eviction and replaced on a
 * new upload, gathered as positions relative to an origin with node/record tags, evenly
 * thinned (not cut off) over capacity; bad sizes refused. No GL. */
#include "test_support.h"

#include <string.h>

#include "core/alloc.h"
#include "stream/point_sample.h"

// count GPU records whose qx is base + index (qy = qz = 0).
static uint8_t *make_records(uint32_t count, uint16_t base)
{
    uint8_t *gpu = sta_calloc(count, STA_GPU_POINT_SIZE);
    assert_non_null(gpu);
    for (uint32_t k = 0; k < count; k++) {
        uint16_t q = (uint16_t)(base + k);
        memcpy(gpu + (size_t)k * STA_GPU_POINT_SIZE, &q, sizeof(q)); // little-endian host
    }
    return gpu;
}

static uint16_t record_qx(const uint8_t *record)
{
    uint16_t q;
    memcpy(&q, record, sizeof(q));
    return q;
}

static void keeps_every_stride_th_record(void **state)
{
    (void)state;
    sta_point_sample *s = NULL;
    assert_int_equal(sta_point_sample_create(4, 10, 100, &s, NULL), STA_OK);
    assert_int_equal(sta_point_sample_stride(s), 10);
    uint8_t *a = make_records(95, 0);
    uint8_t *b = make_records(7, 1000);
    const sta_stream_upload uploads[2] = { { 1, 95, a }, { 2, 7, b } };
    const sta_stream_frame frame = { .upload = uploads, .upload_count = 2 };
    assert_int_equal(sta_point_sample_apply(s, &frame, NULL), STA_OK);
    uint32_t count = 0;
    const uint8_t *kept = sta_point_sample_records(s, 1, &count);
    assert_int_equal(count, 10); // records 0, 10, ..., 90
    for (uint32_t k = 0; k < count; k++) {
        assert_int_equal(record_qx(kept + (size_t)k * STA_GPU_POINT_SIZE), 10 * k);
    }
    kept = sta_point_sample_records(s, 2, &count);
    assert_int_equal(count, 1);
    assert_int_equal(record_qx(kept), 1000);
    assert_null(sta_point_sample_records(s, 0, &count));
    assert_int_equal(count, 0);
    assert_null(sta_point_sample_records(s, 99, &count));

    // Gather: positions corner + q * step - origin, tags node << 32 | index.
    sta_gpu_node_frame frames[4];
    memset(frames, 0, sizeof(frames));
    for (int n = 0; n < 4; n++) {
        frames[n].corner[0] = 100.0 * n;
        frames[n].step[0] = frames[n].step[1] = frames[n].step[2] = 0.5;
    }
    const uint32_t draw[3] = { 2, 1, 3 };
    const double origin[3] = { 50.0, 0.0, 0.0 };
    float points[16][3];
    uint64_t tags[16];
    size_t n = sta_point_sample_gather(s, frames, draw, 3, origin, points, tags, 16);
    assert_int_equal(n, 11);
    assert_true(points[0][0] == (float)(200.0 + 0.5 * 1000 - 50.0));
    assert_int_equal(tags[0], (uint64_t)2 << 32);
    assert_true(points[4][0] == (float)(100.0 + 0.5 * 30 - 50.0));
    assert_int_equal(tags[4], (uint64_t)1 << 32 | 3);

    // Over capacity: evenly thinned over the whole list (node 1's late records too).
    n = sta_point_sample_gather(s, frames, draw, 3, origin, points, tags, 4);
    assert_int_equal(n, 4);
    assert_int_equal(tags[0], (uint64_t)2 << 32);     // seen 0
    assert_int_equal(tags[3], (uint64_t)1 << 32 | 8); // seen 9: step 3
    assert_int_equal(sta_point_sample_gather(s, frames, draw, 3, origin, points, tags, 0), 0);

    // Eviction drops; a new upload replaces.
    const uint32_t evict[1] = { 2 };
    uint8_t *c = make_records(20, 500);
    const sta_stream_upload again = { 1, 20, c };
    const sta_stream_frame next = {
        .evict = evict, .evict_count = 1, .upload = &again, .upload_count = 1
    };
    assert_int_equal(sta_point_sample_apply(s, &next, NULL), STA_OK);
    assert_null(sta_point_sample_records(s, 2, &count));
    kept = sta_point_sample_records(s, 1, &count);
    assert_int_equal(count, 2);
    assert_int_equal(record_qx(kept + STA_GPU_POINT_SIZE), 510);
    sta_point_sample_destroy(s);
    sta_point_sample_destroy(NULL);
    sta_free(a);
    sta_free(b);
    sta_free(c);
}

static void bad_sizes_are_refused(void **state)
{
    (void)state;
    sta_point_sample *s = NULL;
    sta_error err = { 0 };
    assert_int_equal(sta_point_sample_create(4, 0, 100, &s, &err), STA_ERR_ARG);
    assert_null(s);
    assert_non_null(strstr(err.message, "cap"));
    assert_int_equal(sta_point_sample_create(4, 10, 0, &s, &err), STA_ERR_ARG);
    // A cap above the budget keeps everything.
    assert_int_equal(sta_point_sample_create(4, 1000, 10, &s, NULL), STA_OK);
    assert_int_equal(sta_point_sample_stride(s), 1);
    sta_point_sample_destroy(s);
}

static const struct CMUnitTest tests[] = {
    cmocka_unit_test(keeps_every_stride_th_record),
    cmocka_unit_test(bad_sizes_are_refused),
};

STA_TEST_MAIN(tests)
