/* SPDX-License-Identifier: MIT
 * Reading test-encoded LAZ files back through the product reader (lazenc_check.h).
 */
#include "test_support.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/bytes.h"
#include "core/file_map.h"
#include "core/point.h"
#include "io/cloud.h"
#include "io/las.h"
#include "io/las_internal.h"
#include "lazenc_check.h"

// From ../shared/data/README.md, "LAS / LAZ twins".
const lazcheck_twin lazcheck_twins[] = {
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
    { "laz/no-points-1.3.laz", "las/no-points-1.3.las" },
    { "laz/Megaplot.laz", "las/Megaplot.las" },
    { "laz/MixedConifer.laz", "las/MixedConifer.las" },
    { "laz/Example.laz", "las/Example.las" },
    { "laz/extra_byte.laz", "las/extra_byte.las" },
    { "laz/1_4_w_evlr.laz", "las/1_4_w_evlr.las" },
};

const size_t lazcheck_twin_count = sizeof(lazcheck_twins) / sizeof(lazcheck_twins[0]);

bool lazcheck_las_records(const uint8_t *las, size_t size, lazcheck_records *out)
{
    if (size < 227 || memcmp(las, "LASF", 4) != 0) {
        return false;
    }
    uint32_t offset = sta_load_u32le(las + 96);
    out->length = sta_load_u16le(las + 105);
    out->format = las[104] & 0x3f;
    out->count = sta_load_u32le(las + 107);
    if (las[25] >= 4 && size >= 255) {
        out->count = sta_load_u64le(las + 247);
    }
    if (offset > size || out->length == 0 || out->count > (size - offset) / out->length) {
        return false;
    }
    out->records = las + offset;
    return true;
}

bool lazcheck_find_vlr(const uint8_t *d, size_t size, sta_laz_vlr *out)
{
    size_t at = sta_load_u16le(d + 94);
    uint32_t vlrs = sta_load_u32le(d + 100);
    for (uint32_t v = 0; v < vlrs && at + 54 <= size; v++) {
        uint16_t id = sta_load_u16le(d + at + 18);
        uint16_t length = sta_load_u16le(d + at + 20);
        const uint8_t *p = d + at + 54;
        if (memcmp(d + at + 2, "laszip encoded", 14) == 0 && id == 22204 && length >= 34 &&
            at + 54 + length <= size) {
            *out = (sta_laz_vlr){ .compressor = sta_load_u16le(p),
                                  .chunk_size = sta_load_u32le(p + 12),
                                  .item_count = sta_load_u16le(p + 32) };
            if (out->item_count > STA_LAZ_MAX_ITEMS || 34u + 6u * out->item_count > length) {
                return false;
            }
            for (uint16_t i = 0; i < out->item_count; i++) {
                const uint8_t *it = p + 34 + 6 * i;
                out->items[i] = (sta_laz_item){ sta_load_u16le(it), sta_load_u16le(it + 2),
                                                sta_load_u16le(it + 4) };
            }
            return true;
        }
        at += 54u + length;
    }
    return false;
}

bool lazcheck_try_decode(const uint8_t *laz, size_t size, const char *name,
                         const lazcheck_records *expected, bool *identical, char *message,
                         size_t message_size)
{
    sta_file_map map;
    sta_error err = { 0 };
    *identical = false;
    message[0] = '\0';
    if (sta_file_map_wrap(laz, size, name, &map, &err) != STA_OK) {
        snprintf(message, message_size, "%s", err.message);
        return false;
    }
    void *impl = NULL;
    const sta_cloud_ops *ops = NULL;
    if (sta_las_open_map(&map, NULL, &impl, &ops, &err) != STA_OK) {
        snprintf(message, message_size, "%s", err.message);
        sta_file_map_close(&map);
        return false;
    }
    sta_las_reader *reader = impl;
    bool ok = reader->laz && reader->record_length == expected->length &&
              reader->info.point_count == expected->count;
    if (!ok) {
        snprintf(message, message_size, "%s: not read as LAZ with %llu records of %zu bytes", name,
                 (unsigned long long)expected->count, expected->length);
    }
    bool same = ok;
    size_t step_max = 997; // not a divisor of typical chunk sizes
    uint8_t *buffer = malloc(step_max * expected->length + 1);
    for (uint64_t done = 0; ok && buffer && done < expected->count;) {
        size_t step =
            expected->count - done < step_max ? (size_t)(expected->count - done) : step_max;
        if (sta_laz_decode(reader->laz, buffer, step, &err) != STA_OK) {
            snprintf(message, message_size, "%s", err.message);
            ok = false;
            break;
        }
        same = same && memcmp(buffer, expected->records + done * expected->length,
                              step * expected->length) == 0;
        done += step;
    }
    free(buffer);
    ops->close(impl);
    sta_file_map_close(&map);
    *identical = ok && same;
    return ok;
}

void lazcheck_expect_records(const uint8_t *laz, size_t size, const char *name,
                             const lazcheck_records *expected)
{
    bool identical = false;
    char message[512];
    if (!lazcheck_try_decode(laz, size, name, expected, &identical, message, sizeof(message))) {
        fail_msg("%s: %s", name, message);
    }
    if (!identical) {
        fail_msg("%s: decoded records differ from the records encoded", name);
    }
}

bool lazcheck_same_point(const sta_point *a, const sta_point *b)
{
    bool same_time = memcmp(&a->gps_time, &b->gps_time, sizeof(double)) == 0;
    return a->X == b->X && a->Y == b->Y && a->Z == b->Z && a->intensity == b->intensity &&
           a->return_number == b->return_number && a->number_of_returns == b->number_of_returns &&
           a->classification == b->classification &&
           a->classification_flags == b->classification_flags &&
           a->scanner_channel == b->scanner_channel &&
           a->scan_direction_flag == b->scan_direction_flag &&
           a->edge_of_flight_line == b->edge_of_flight_line && a->user_data == b->user_data &&
           a->scan_angle == b->scan_angle && a->point_source_id == b->point_source_id &&
           a->red == b->red && a->green == b->green && a->blue == b->blue && a->nir == b->nir &&
           same_time && a->wave_packet_size == b->wave_packet_size;
}

void lazcheck_expect_same_points(const char *laz_path, const char *las_path)
{
    sta_cloud_reader *a = NULL;
    sta_cloud_reader *b = NULL;
    sta_error err = { 0 };
    if (sta_cloud_open(laz_path, NULL, &a, &err) != STA_OK) {
        fail_msg("%s", err.message);
    }
    assert_int_equal(sta_cloud_open(las_path, NULL, &b, &err), STA_OK);
    const sta_cloud_info *ia = sta_cloud_reader_info(a);
    const sta_cloud_info *ib = sta_cloud_reader_info(b);
    assert_int_equal(ia->point_count, ib->point_count);
    assert_int_equal(ia->point_format, ib->point_format);
    assert_int_equal(ia->extra_size, ib->extra_size);
    assert_int_equal(ia->attributes, ib->attributes);
    assert_int_equal(ia->extra_dim_count, ib->extra_dim_count);
    sta_point_batch ba = { 0 };
    sta_point_batch bb = { 0 };
    assert_int_equal(sta_point_batch_init(&ba, 777, ia->extra_size, &err), STA_OK);
    assert_int_equal(sta_point_batch_init(&bb, 777, ib->extra_size, &err), STA_OK);
    uint64_t total = 0;
    for (;;) {
        assert_int_equal(sta_cloud_read(a, &ba, &err), STA_OK);
        assert_int_equal(sta_cloud_read(b, &bb, &err), STA_OK);
        assert_int_equal(ba.count, bb.count);
        assert_int_equal(ba.first_index, bb.first_index);
        if (ba.count == 0) {
            break;
        }
        for (size_t i = 0; i < ba.count; i++) {
            if (!lazcheck_same_point(&ba.points[i], &bb.points[i])) {
                fail_msg("%s: point %llu differs from %s", laz_path,
                         (unsigned long long)(total + i), las_path);
            }
        }
        assert_memory_equal(ba.extra, bb.extra, ba.count * ia->extra_size);
        total += ba.count;
    }
    assert_int_equal(total, ia->point_count);
    sta_point_batch_release(&ba);
    sta_point_batch_release(&bb);
    sta_cloud_close(a);
    sta_cloud_close(b);
}
