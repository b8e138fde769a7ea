/* SPDX-License-Identifier: MIT
 * Tests for the LAS writer (src/io/las_write.c): every field written is read back
 * through sta_cloud_open; header counts and bounds; the temporary-file protocol;
 * errors naming the file. */
#include "test_support.h"

#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/alloc.h"
#include "core/bytes.h"
#include "io/cloud.h"
#include "io/las_write.h"

static uint64_t mix(uint64_t *state)
{
    uint64_t z = (*state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

/* Points with every field drawn at random within what `point_format` can hold. */
static sta_point *random_points(size_t count, int point_format, uint64_t seed)
{
    sta_point *pts = sta_calloc(count, sizeof(*pts));
    assert_non_null(pts);
    bool legacy = point_format < 6;
    for (size_t i = 0; i < count; i++) {
        sta_point *p = &pts[i];
        p->X = (int32_t)(mix(&seed) % 2000001u) - 1000000;
        p->Y = (int32_t)(mix(&seed) % 2000001u) - 1000000;
        p->Z = (int32_t)(mix(&seed) % 200001u) - 100000;
        p->intensity = (uint16_t)mix(&seed);
        p->number_of_returns = (uint8_t)(1 + mix(&seed) % (legacy ? 7u : 15u));
        p->return_number = (uint8_t)(1 + mix(&seed) % p->number_of_returns);
        p->classification = (uint8_t)(mix(&seed) % (legacy ? 32u : 256u));
        p->classification_flags = (uint8_t)(mix(&seed) % (legacy ? 8u : 16u));
        p->scanner_channel = (uint8_t)(legacy ? 0 : mix(&seed) % 4u);
        p->scan_direction_flag = (uint8_t)(mix(&seed) & 1u);
        p->edge_of_flight_line = (uint8_t)(mix(&seed) & 1u);
        p->user_data = (uint8_t)mix(&seed);
        // Legacy formats hold whole degrees: draw those (as 0.006 degree units).
        if (legacy) {
            p->scan_angle = (int16_t)lround((double)((int)(mix(&seed) % 181u) - 90) / 0.006);
        } else {
            p->scan_angle = (int16_t)((int)(mix(&seed) % 60001u) - 30000);
        }
        p->point_source_id = (uint16_t)mix(&seed);
        p->red = (uint16_t)mix(&seed);
        p->green = (uint16_t)mix(&seed);
        p->blue = (uint16_t)mix(&seed);
        p->nir = (uint16_t)mix(&seed);
        p->gps_time = 388102418.0 + (double)(mix(&seed) % 1000000000u) * 1e-6;
        p->wave_descriptor_index = (uint8_t)mix(&seed);
        p->wave_byte_offset = mix(&seed);
        p->wave_packet_size = (uint32_t)mix(&seed);
        p->wave_return_location = (float)(mix(&seed) % 100000u) * 0.5f;
        p->wave_xt = (float)(mix(&seed) % 1000u) * 0.25f;
        p->wave_yt = -(float)(mix(&seed) % 1000u) * 0.25f;
        p->wave_zt = (float)(mix(&seed) % 1000u) * 0.125f;
    }
    return pts;
}

static const sta_grid test_grid = { { 0.001, 0.001, 0.01 }, { 650000.0, 5400000.0, 100.0 } };

static void write_file(const char *path, int minor, int format, const char *wkt,
                       const sta_point *pts, size_t count)
{
    sta_las_write_options opt = {
        .version_minor = minor,
        .point_format = format,
        .grid = test_grid,
        .system_identifier = "test system",
        .generating_software = "test_las_write",
        .wkt = wkt,
        .gps_time_adjusted = true,
        .file_source_id = 77,
        .creation_day = 32,
        .creation_year = 2024,
    };
    sta_error err = { 0 };
    sta_las_writer *w = NULL;
    assert_int_equal(sta_las_writer_open(path, &opt, &w, &err), STA_OK);
    // Several calls, so records cross both call and buffer boundaries.
    size_t done = 0, step = 7;
    while (done < count) {
        size_t n = count - done < step ? count - done : step;
        assert_int_equal(sta_las_writer_write(w, pts + done, n, &err), STA_OK);
        done += n;
        step = step * 3 + 1;
    }
    assert_int_equal(sta_las_writer_point_count(w), count);
    if (sta_las_writer_close(w, &err) != STA_OK) {
        fail_msg("%s", err.message);
    }
}

static bool has_gps(int f)
{
    return f == 1 || f >= 3;
}

static bool has_rgb(int f)
{
    return f == 2 || f == 3 || f == 5 || f == 7 || f == 8 || f == 10;
}

static bool has_wave(int f)
{
    return f == 4 || f == 5 || f == 9 || f == 10;
}

/* Reads `path` back and compares every field the format holds. */
static void check_points(const char *path, int format, const sta_point *pts, size_t count)
{
    sta_error err = { 0 };
    sta_cloud_reader *r = NULL;
    if (sta_cloud_open(path, NULL, &r, &err) != STA_OK) {
        fail_msg("%s", err.message);
    }
    const sta_cloud_info *info = sta_cloud_reader_info(r);
    assert_int_equal(info->point_format, format);
    assert_int_equal(info->point_count, count);
    sta_point_batch batch = { 0 };
    assert_int_equal(sta_point_batch_init(&batch, 4096, info->extra_size, &err), STA_OK);
    size_t seen = 0;
    bool legacy = format < 6;
    for (;;) {
        assert_int_equal(sta_cloud_read(r, &batch, &err), STA_OK);
        if (batch.count == 0) {
            break;
        }
        for (size_t i = 0; i < batch.count; i++, seen++) {
            const sta_point *a = &pts[seen], *b = &batch.points[i];
            assert_int_equal(a->X, b->X);
            assert_int_equal(a->Y, b->Y);
            assert_int_equal(a->Z, b->Z);
            assert_int_equal(a->intensity, b->intensity);
            assert_int_equal(a->return_number, b->return_number);
            assert_int_equal(a->number_of_returns, b->number_of_returns);
            assert_int_equal(a->classification, b->classification);
            assert_int_equal(legacy ? (a->classification_flags & 7) : a->classification_flags,
                             b->classification_flags);
            assert_int_equal(legacy ? 0 : a->scanner_channel, b->scanner_channel);
            assert_int_equal(a->scan_direction_flag, b->scan_direction_flag);
            assert_int_equal(a->edge_of_flight_line, b->edge_of_flight_line);
            assert_int_equal(a->user_data, b->user_data);
            if (legacy) {
                // Whole degrees on disk: the same degree comes back.
                assert_int_equal(lround(a->scan_angle * 0.006), lround(b->scan_angle * 0.006));
            } else {
                assert_int_equal(a->scan_angle, b->scan_angle);
            }
            assert_int_equal(a->point_source_id, b->point_source_id);
            if (has_gps(format)) {
                assert_true(a->gps_time == b->gps_time);
            }
            if (has_rgb(format)) {
                assert_int_equal(a->red, b->red);
                assert_int_equal(a->green, b->green);
                assert_int_equal(a->blue, b->blue);
            }
            if (format == 8 || format == 10) {
                assert_int_equal(a->nir, b->nir);
            }
            if (has_wave(format)) {
                assert_int_equal(a->wave_descriptor_index, b->wave_descriptor_index);
                assert_true(a->wave_byte_offset == b->wave_byte_offset);
                assert_int_equal(a->wave_packet_size, b->wave_packet_size);
                assert_true(a->wave_return_location == b->wave_return_location);
                assert_true(a->wave_xt == b->wave_xt && a->wave_yt == b->wave_yt &&
                            a->wave_zt == b->wave_zt);
            }
        }
    }
    assert_int_equal(seen, count);
    sta_point_batch_release(&batch);
    sta_cloud_close(r);
}

/* Header facts: counts by return, bounds from the points, identification. */
static void check_header(const char *path, int minor, int format, const sta_point *pts,
                         size_t count, const char *wkt)
{
    sta_error err = { 0 };
    sta_cloud_reader *r = NULL;
    if (sta_cloud_open(path, NULL, &r, &err) != STA_OK) {
        fail_msg("%s", err.message);
    }
    const sta_cloud_info *info = sta_cloud_reader_info(r);
    static const uint16_t sizes[11] = { 20, 28, 26, 34, 57, 63, 30, 36, 38, 59, 67 };
    assert_int_equal(info->kind, STA_CLOUD_LAS);
    assert_int_equal(info->version_major, 1);
    assert_int_equal(info->version_minor, minor);
    assert_int_equal(info->header_size, minor == 4 ? 375 : 227);
    assert_int_equal(info->record_length, sizes[format]);
    assert_int_equal(info->header_point_count, count);
    bool legacy_fits = format < 6;
    assert_int_equal(info->legacy_point_count, legacy_fits ? count : 0);
    uint64_t by_return[15] = { 0 };
    int32_t lo[3] = { INT32_MAX, INT32_MAX, INT32_MAX },
            hi[3] = { INT32_MIN, INT32_MIN, INT32_MIN };
    for (size_t i = 0; i < count; i++) {
        by_return[pts[i].return_number - 1]++;
        const int32_t xyz[3] = { pts[i].X, pts[i].Y, pts[i].Z };
        for (int a = 0; a < 3; a++) {
            lo[a] = xyz[a] < lo[a] ? xyz[a] : lo[a];
            hi[a] = xyz[a] > hi[a] ? xyz[a] : hi[a];
        }
    }
    int returns = minor == 4 ? 15 : 5;
    for (int k = 0; k < returns; k++) {
        assert_int_equal(info->points_by_return[k], by_return[k]);
    }
    for (int a = 0; a < 3; a++) {
        assert_true(info->grid.scale[a] == test_grid.scale[a]);
        assert_true(info->grid.offset[a] == test_grid.offset[a]);
        if (count > 0) {
            assert_true(info->header_min[a] == sta_grid_apply(&test_grid, a, lo[a]));
            assert_true(info->header_max[a] == sta_grid_apply(&test_grid, a, hi[a]));
        } else {
            assert_true(info->header_min[a] == 0.0 && info->header_max[a] == 0.0);
        }
    }
    assert_string_equal(info->system_identifier, "test system");
    assert_string_equal(info->generating_software, "test_las_write");
    assert_int_equal(info->file_source_id, 77);
    assert_int_equal(info->creation_day, 32);
    assert_int_equal(info->creation_year, 2024);
    assert_true(info->global_encoding & 1u);
    if (wkt) {
        assert_non_null(info->crs_wkt);
        assert_string_equal(info->crs_wkt, wkt);
        assert_int_equal(info->vlr_count, 1);
        assert_string_equal(info->vlrs[0].user_id, "LASF_Projection");
        assert_int_equal(info->vlrs[0].record_id, 2112);
        assert_int_equal((info->global_encoding >> 4) & 1u, minor == 4 ? 1u : 0u);
        assert_int_equal(info->offset_to_point_data, info->header_size + 54 + strlen(wkt) + 1);
    } else {
        assert_null(info->crs_wkt);
        assert_int_equal(info->vlr_count, 0);
        assert_int_equal(info->offset_to_point_data, info->header_size);
    }
    sta_cloud_close(r);
}

static const char test_wkt[] = "LOCAL_CS[\"test\",UNIT[\"metre\",1]]";

static void v12_format3_round_trip(void **state)
{
    (void)state;
    // 150 000 records of 34 bytes pass the writer's 4 MiB buffer.
    const size_t n = 150000;
    sta_point *pts = random_points(n, 3, 1);
    const char *path = sta_test_tmp_path("v12_f3.las");
    write_file(path, 2, 3, test_wkt, pts, n);
    check_points(path, 3, pts, n);
    check_header(path, 2, 3, pts, n, test_wkt);
    struct stat st;
    assert_int_equal(stat(path, &st), 0);
    assert_int_equal(st.st_size, 227 + 54 + sizeof(test_wkt) + n * 34);
    sta_free(pts);
}

static void v14_format7_round_trip(void **state)
{
    (void)state;
    const size_t n = 150000;
    sta_point *pts = random_points(n, 7, 2);
    const char *path = sta_test_tmp_path("v14_f7.las");
    write_file(path, 4, 7, test_wkt, pts, n);
    check_points(path, 7, pts, n);
    check_header(path, 4, 7, pts, n, test_wkt);
    struct stat st;
    assert_int_equal(stat(path, &st), 0);
    assert_int_equal(st.st_size, 375 + 54 + sizeof(test_wkt) + n * 36);
    sta_free(pts);
}

static void every_format_round_trips(void **state)
{
    (void)state;
    const size_t n = 3000;
    for (int minor = 2; minor <= 4; minor += 2) {
        for (int format = 0; format <= (minor == 2 ? 3 : 10); format++) {
            sta_point *pts = random_points(n, format, (uint64_t)(100 + format));
            char name[64];
            snprintf(name, sizeof(name), "v1%d_f%d.las", minor, format);
            char path[4096];
            snprintf(path, sizeof(path), "%s", sta_test_tmp_path(name));
            write_file(path, minor, format, NULL, pts, n);
            check_points(path, format, pts, n);
            check_header(path, minor, format, pts, n, NULL);
            sta_free(pts);
        }
    }
}

static void empty_file_has_zero_counts_and_bounds(void **state)
{
    (void)state;
    const char *path = sta_test_tmp_path("empty.las");
    write_file(path, 4, 7, NULL, NULL, 0);
    check_header(path, 4, 7, NULL, 0, NULL);
    check_points(path, 7, NULL, 0);
}

static void legacy_scan_angle_is_rounded_and_clamped(void **state)
{
    (void)state;
    // 0.006 degree units: 14.994 deg -> 15; -30000 (-180 deg) -> -128; 30000 -> 127.
    const int16_t angles[4] = { 2499, -30000, 30000, -83 };
    const long degrees[4] = { 15, -128, 127, 0 };
    sta_point pts[4];
    memset(pts, 0, sizeof(pts));
    for (int i = 0; i < 4; i++) {
        pts[i].scan_angle = angles[i];
        pts[i].return_number = 1;
        pts[i].number_of_returns = 1;
    }
    const char *path = sta_test_tmp_path("angles.las");
    write_file(path, 2, 1, NULL, pts, 4);
    size_t size = 0;
    uint8_t *bytes = sta_test_read_file(path, &size);
    assert_int_equal(size, 227 + 4 * 28);
    for (int i = 0; i < 4; i++) {
        assert_int_equal((int8_t)bytes[227 + 28 * i + 16], degrees[i]);
    }
    free(bytes);
}

static void legacy_counts_in_v14_follow_the_format(void **state)
{
    (void)state;
    // LAS 1.4 with a legacy format keeps the legacy count and first five returns.
    const size_t n = 500;
    sta_point *pts = random_points(n, 1, 9);
    const char *path = sta_test_tmp_path("v14_f1.las");
    write_file(path, 4, 1, NULL, pts, n);
    size_t size = 0;
    uint8_t *h = sta_test_read_file(path, &size);
    assert_int_equal(sta_load_u32le(h + 107), n);
    assert_int_equal(sta_load_u64le(h + 247), n);
    uint64_t sum = 0;
    for (int k = 0; k < 5; k++) {
        assert_int_equal(sta_load_u32le(h + 111 + 4 * k), sta_load_u64le(h + 255 + 8 * k));
        sum += sta_load_u64le(h + 255 + 8 * k);
    }
    for (int k = 5; k < 15; k++) {
        sum += sta_load_u64le(h + 255 + 8 * k);
    }
    assert_int_equal(sum, n); // every point has return_number >= 1
    free(h);
    sta_free(pts);
}

static int count_entries_with(const char *dir, const char *part)
{
    DIR *d = opendir(dir);
    assert_non_null(d);
    int n = 0;
    for (struct dirent *e = readdir(d); e; e = readdir(d)) {
        if (strstr(e->d_name, part)) {
            n++;
        }
    }
    closedir(d);
    return n;
}

static void output_appears_only_when_closed(void **state)
{
    (void)state;
    const char *dir = sta_test_tmpdir();
    char path[4096];
    snprintf(path, sizeof(path), "%s/atomic.las", dir);
    sta_las_write_options opt = { .point_format = 7, .grid = test_grid };
    sta_error err = { 0 };
    sta_las_writer *w = NULL;
    sta_point *pts = random_points(10, 7, 3);
    assert_int_equal(sta_las_writer_open(path, &opt, &w, &err), STA_OK);
    assert_int_equal(sta_las_writer_write(w, pts, 10, &err), STA_OK);
    assert_int_equal(access(path, F_OK), -1);
    assert_int_equal(count_entries_with(dir, "atomic.las.tmp-"), 1);
    assert_int_equal(sta_las_writer_close(w, &err), STA_OK);
    assert_int_equal(access(path, F_OK), 0);
    assert_int_equal(count_entries_with(dir, "atomic.las.tmp-"), 0);

    // Abort leaves neither the temporary nor a new file, and keeps an old one.
    size_t old_size = 0;
    uint8_t *old = sta_test_read_file(path, &old_size);
    assert_int_equal(sta_las_writer_open(path, &opt, &w, &err), STA_OK);
    assert_int_equal(sta_las_writer_write(w, pts, 5, &err), STA_OK);
    sta_las_writer_abort(w);
    assert_int_equal(count_entries_with(dir, "atomic.las.tmp-"), 0);
    size_t now_size = 0;
    uint8_t *now = sta_test_read_file(path, &now_size);
    assert_int_equal(now_size, old_size);
    assert_memory_equal(now, old, old_size);
    free(old);
    free(now);
    sta_free(pts);
    sta_las_writer_abort(NULL);
    assert_int_equal(sta_las_writer_close(NULL, &err), STA_OK);
}

static void bad_options_are_refused(void **state)
{
    (void)state;
    const char *path = sta_test_tmp_path("bad.las");
    sta_error err = { 0 };
    sta_las_writer *w = NULL;
    sta_las_write_options opt = { .version_minor = 2, .point_format = 7, .grid = test_grid };
    assert_int_equal(sta_las_writer_open(path, &opt, &w, &err), STA_ERR_ARG);
    assert_null(w);
    assert_non_null(strstr(err.message, "bad.las"));
    assert_non_null(strstr(err.message, "point format 7"));
    opt = (sta_las_write_options){ .version_minor = 3, .point_format = 1, .grid = test_grid };
    assert_int_equal(sta_las_writer_open(path, &opt, &w, &err), STA_ERR_ARG);
    opt = (sta_las_write_options){ .point_format = 11, .grid = test_grid };
    assert_int_equal(sta_las_writer_open(path, &opt, &w, &err), STA_ERR_ARG);
    opt = (sta_las_write_options){ .point_format = 6, .grid = { { 0.0, 1, 1 }, { 0, 0, 0 } } };
    assert_int_equal(sta_las_writer_open(path, &opt, &w, &err), STA_ERR_ARG);
    assert_non_null(strstr(err.message, "scale"));
    opt = (sta_las_write_options){ .point_format = 6,
                                   .grid = test_grid,
                                   .system_identifier = "0123456789012345678901234567890123" };
    assert_int_equal(sta_las_writer_open(path, &opt, &w, &err), STA_ERR_ARG);
    assert_non_null(strstr(err.message, "system identifier"));
    assert_int_equal(access(path, F_OK), -1);
}

static void unwritable_path_names_the_file(void **state)
{
    (void)state;
    char path[4096];
    snprintf(path, sizeof(path), "%s/no/such/dir/x.las", sta_test_tmpdir());
    sta_las_write_options opt = { .point_format = 7, .grid = test_grid };
    sta_error err = { 0 };
    sta_las_writer *w = NULL;
    assert_int_equal(sta_las_writer_open(path, &opt, &w, &err), STA_ERR_IO);
    assert_null(w);
    assert_non_null(strstr(err.message, path));
}

static void values_the_format_cannot_hold_are_refused(void **state)
{
    (void)state;
    const char *dir = sta_test_tmpdir();
    const char *path = sta_test_tmp_path("refuse.las");
    char copy[4096];
    snprintf(copy, sizeof(copy), "%s", path);
    sta_error err = { 0 };
    sta_las_writer *w = NULL;
    sta_point p;
    memset(&p, 0, sizeof(p));
    p.return_number = 1;
    p.number_of_returns = 1;
    p.classification = 40; // not in 5 bits
    sta_las_write_options opt = { .version_minor = 2, .point_format = 3, .grid = test_grid };
    assert_int_equal(sta_las_writer_open(copy, &opt, &w, &err), STA_OK);
    assert_int_equal(sta_las_writer_write(w, &p, 1, &err), STA_ERR_ARG);
    assert_non_null(strstr(err.message, "refuse.las"));
    assert_non_null(strstr(err.message, "classification 40"));
    // A writer that failed cannot be finished: close fails and removes the temporary.
    assert_int_equal(sta_las_writer_close(w, &err), STA_ERR_ARG);
    assert_int_equal(access(copy, F_OK), -1);
    assert_int_equal(count_entries_with(dir, "refuse.las.tmp-"), 0);

    p.classification = 2;
    p.return_number = 9;
    p.number_of_returns = 9;
    assert_int_equal(sta_las_writer_open(copy, &opt, &w, &err), STA_OK);
    assert_int_equal(sta_las_writer_write(w, &p, 1, &err), STA_ERR_ARG);
    assert_non_null(strstr(err.message, "return 9 of 9"));
    sta_las_writer_abort(w);

    opt = (sta_las_write_options){ .point_format = 7, .grid = test_grid };
    p.return_number = 1;
    p.number_of_returns = 1;
    p.scanner_channel = 4;
    assert_int_equal(sta_las_writer_open(copy, &opt, &w, &err), STA_OK);
    assert_int_equal(sta_las_writer_write(w, &p, 1, &err), STA_ERR_ARG);
    assert_non_null(strstr(err.message, "scanner channel 4"));
    sta_las_writer_abort(w);
    assert_int_equal(count_entries_with(dir, "refuse.las.tmp-"), 0);
}

static void failed_allocations_leave_nothing(void **state)
{
    (void)state;
    const char *dir = sta_test_tmpdir();
    const char *path = sta_test_tmp_path("nomem.las");
    sta_las_write_options opt = { .point_format = 7, .grid = test_grid, .wkt = test_wkt };
    for (long k = 0; k < 5; k++) {
        sta_error err = { 0 };
        sta_las_writer *w = NULL;
        sta_alloc_fail_after(k);
        sta_status s = sta_las_writer_open(path, &opt, &w, &err);
        sta_alloc_fail_after(-1);
        if (s == STA_OK) {
            sta_las_writer_abort(w);
            continue;
        }
        assert_int_equal(s, STA_ERR_NOMEM);
        assert_null(w);
        assert_non_null(strstr(err.message, "nomem.las"));
    }
    assert_int_equal(count_entries_with(dir, "nomem.las"), 0);
}

static const struct CMUnitTest tests[] = {
    cmocka_unit_test(v12_format3_round_trip),
    cmocka_unit_test(v14_format7_round_trip),
    cmocka_unit_test(every_format_round_trips),
    cmocka_unit_test(empty_file_has_zero_counts_and_bounds),
    cmocka_unit_test(legacy_scan_angle_is_rounded_and_clamped),
    cmocka_unit_test(legacy_counts_in_v14_follow_the_format),
    cmocka_unit_test(output_appears_only_when_closed),
    cmocka_unit_test(bad_options_are_refused),
    cmocka_unit_test(unwritable_path_names_the_file),
    cmocka_unit_test(values_the_format_cannot_hold_are_refused),
    cmocka_unit_test(failed_allocations_leave_nothing),
};

STA_TEST_MAIN(tests)
