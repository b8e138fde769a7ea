/* SPDX-License-Identifier: MIT
 * Picking (stream/pick.h) on a scene 5.4e6 m from the origin, in double: the point
 * under a pixel is the one drawn there, to the millimetre; and the measurement maths
 * (core/measure.h) and files (render/measure_file.h) against values worked out here. */
#include "test_support.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "app/view_tools.h"
#include "convert.h"
#include "core/measure.h"
#include "io/las_write.h"
#include "render/measure_file.h"
#include "stream/pick.h"

#define OX 650000.0
#define OY 5400000.0

/* A wall of points 50 m ahead (y = OY + 1000), and in front of it, 40 m from the
 * camera, two points 1 mm apart in x; scale 1 mm. Returns the scene path. */
static const char *make_scene(void)
{
    static char las[4096], scene[4096];
    snprintf(las, sizeof(las), "%s/pick.las", sta_test_tmpdir());
    snprintf(scene, sizeof(scene), "%s/pick.strata", sta_test_tmpdir());
    sta_las_write_options o = { .version_minor = 2,
                                .point_format = 1,
                                .grid = { .scale = { 0.001, 0.001, 0.001 },
                                          .offset = { OX, OY, 0.0 } } };
    sta_las_writer *w = NULL;
    sta_error err = { 0 };
    assert_int_equal(sta_las_writer_open(las, &o, &w, &err), STA_OK);
    sta_point p = { .return_number = 1, .number_of_returns = 1, .classification = 6 };
    for (int i = 0; i < 200; i++) {
        for (int k = 0; k < 200; k++) {
            p.X = 90000 + i * 100; // x 650090 .. 650110
            p.Y = 1000000;         // y OY + 1000
            p.Z = 90000 + k * 100; // z 90 .. 110
            p.intensity = (uint16_t)(i + k);
            assert_int_equal(sta_las_writer_write(w, &p, 1, &err), STA_OK);
        }
    }
    // The two targets: x 650100.123 and 650100.124, y OY + 990.456, z 100.789.
    sta_point t = { .X = 100123,
                    .Y = 990456,
                    .Z = 100789,
                    .intensity = 7,
                    .classification = 2,
                    .return_number = 2,
                    .number_of_returns = 3,
                    .gps_time = 12345.5 };
    assert_int_equal(sta_las_writer_write(w, &t, 1, &err), STA_OK);
    t.X = 100124;
    t.intensity = 8;
    assert_int_equal(sta_las_writer_write(w, &t, 1, &err), STA_OK);
    assert_int_equal(sta_las_writer_close(w, &err), STA_OK);
    const char *one[] = { las };
    sta_convert_options c = {
        .inputs = one, .input_count = 1, .output = scene, .leaf_capacity = 256, .force = true
    };
    if (sta_convert(&c, NULL, &err) != STA_OK) {
        fail_msg("convert: %s", err.message);
    }
    unlink(las);
    return scene;
}

typedef struct pick_fixture {
    sta_strata_reader *reader;
    sta_strata_decoder *decoder;
    uint32_t *nodes;
    size_t count;
} pick_fixture;

static void fixture_open(pick_fixture *f)
{
    sta_error err = { 0 };
    assert_int_equal(sta_strata_open(make_scene(), NULL, &f->reader, &err), STA_OK);
    assert_int_equal(sta_strata_decoder_create(&f->decoder, &err), STA_OK);
    f->count = sta_strata_reader_info(f->reader)->node_count;
    f->nodes = calloc(f->count, sizeof(*f->nodes));
    for (size_t i = 0; i < f->count; i++) {
        f->nodes[i] = (uint32_t)i;
    }
}

static void fixture_close(pick_fixture *f)
{
    free(f->nodes);
    sta_strata_decoder_destroy(f->decoder);
    sta_strata_close(f->reader);
}

static sta_pick_result pick_at(pick_fixture *f, const sta_camera *cam, double x, double y)
{
    sta_pick_result r;
    sta_error err = { 0 };
    assert_int_equal(
        sta_pick(f->reader, f->decoder, f->nodes, f->count, NULL, cam, x, y, 4.0, &r, &err),
        STA_OK);
    return r;
}

static void picks_the_millimetre_far_from_the_origin(void **state)
{
    (void)state;
    pick_fixture f;
    fixture_open(&f);
    // 40 m in front of the targets, looking along +y; a 0.05 degree field of view
    // spreads 1 mm over about 29 pixels (float coordinates would not tell them apart).
    sta_camera cam = { .position = { 650100.1235, OY + 950.456, 100.789 },
                       .yaw = M_PI / 2,
                       .fov_y = 0.05 * M_PI / 180,
                       .near_m = 0.5,
                       .width_px = 1000,
                       .height_px = 1000 };
    double px[2], py[2], depth;
    for (int k = 0; k < 2; k++) {
        const double target[3] = { 650100.123 + 0.001 * k, OY + 990.456, 100.789 };
        assert_true(sta_camera_project(&cam, target, &px[k], &py[k], &depth));
    }
    assert_true(px[1] - px[0] > 20.0); // the projection keeps the millimetre
    for (int k = 0; k < 2; k++) {
        sta_pick_result r = pick_at(&f, &cam, px[k] + 1.5, py[k] - 1.0);
        assert_true(r.hit);
        assert_int_equal(r.point.X, 100123 + k);
        assert_int_equal(r.point.Y, 990456);
        assert_int_equal(r.point.Z, 100789);
        assert_int_equal(r.point.intensity, 7 + k);
        assert_true(r.world[0] == 650100.123 + 0.001 * k ||
                    fabs(r.world[0] - 650100.123 - 0.001 * k) < 1e-9);
        assert_true(fabs(r.depth_m - 40.0) < 1e-6);
        assert_int_equal(r.point.return_number, 2);
        assert_true(r.point.gps_time == 12345.5);
    }
    // Between the two (beyond 4 px of both) only the wall 50 m away is under the pixel;
    // the wall is 10 m behind, far coarser than a pixel here: nothing within 4 px.
    sta_pick_result mid = pick_at(&f, &cam, (px[0] + px[1]) / 2, py[0]);
    assert_true(!mid.hit || mid.depth_m > 49.0);
    fixture_close(&f);
}

static void nearest_point_wins_and_misses_are_misses(void **state)
{
    (void)state;
    pick_fixture f;
    fixture_open(&f);
    // A wide view: the targets sit in front of the wall at the image centre.
    sta_camera cam = { .position = { 650100.1235, OY + 950.456, 100.789 },
                       .yaw = M_PI / 2,
                       .fov_y = 60 * M_PI / 180,
                       .near_m = 0.5,
                       .width_px = 640,
                       .height_px = 480 };
    sta_pick_result r = pick_at(&f, &cam, 320, 240);
    assert_true(r.hit);
    assert_int_equal(r.point.classification, 2); // a target, not the wall behind it
    assert_true(fabs(r.depth_m - 40.0) < 1e-6);
    // Off the targets but on the wall: a wall point, 49.544 m away.
    r = pick_at(&f, &cam, 250, 240); // x about 650091.7
    assert_true(r.hit);
    assert_int_equal(r.point.classification, 6);
    assert_true(fabs(r.depth_m - 49.544) < 1e-6);
    // Above the wall (z > 110): nothing.
    cam.pitch = 0.6;
    r = pick_at(&f, &cam, 320, 20);
    assert_false(r.hit);
    // A class filter hides the targets: the wall behind is picked.
    cam.pitch = 0;
    sta_clip clip = { 0 };
    sta_error err = { 0 };
    assert_int_equal(sta_clip_parse_classes(&clip, "6", &err), STA_OK);
    assert_int_equal(
        sta_pick(f.reader, f.decoder, f.nodes, f.count, &clip, &cam, 320, 240, 4.0, &r, &err),
        STA_OK);
    assert_true(r.hit && r.point.classification == 6);
    assert_string_equal(sta_pick_class_name(2), "ground");
    assert_string_equal(sta_pick_class_name(6), "building");
    assert_string_equal(sta_pick_class_name(200), "user defined");
    fixture_close(&f);
}

/* Distances, heights, lengths and areas of shapes whose values are known exactly,
 * placed at UTM coordinates: a 3-4-5 right triangle, a 2 m x 3 m rectangle tilted by
 * 30 degrees (plan area 6 cos 30), a staircase polyline. */
static void measurement_maths_in_double(void **state)
{
    (void)state;
    sta_measure_values v;
    sta_error err = { 0 };
    const double d[2][3] = { { 651234.567, 5401234.891, 100.25 },
                             { 651234.567 + 3.0, 5401234.891 + 4.0, 100.25 + 12.0 } };
    assert_int_equal(sta_measure_compute(STA_MEASURE_DISTANCE, d, 2, &v, &err), STA_OK);
    assert_true(fabs(v.distance_3d - 13.0) < 1e-9);
    assert_true(fabs(v.distance_xy - 5.0) < 1e-9);
    assert_true(fabs(v.distance_z - 12.0) < 1e-9);
    assert_int_equal(sta_measure_compute(STA_MEASURE_HEIGHT, d, 2, &v, &err), STA_OK);
    assert_true(fabs(v.distance_z - 12.0) < 1e-9);
    // The rectangle: 2 m along x, 3 m up a 30 degree slope in y-z.
    const double c = cos(M_PI / 6), s = sin(M_PI / 6);
    const double x0 = 651000.001, y0 = 5401000.002, z0 = 50.003;
    const double rect[4][3] = { { x0, y0, z0 },
                                { x0 + 2.0, y0, z0 },
                                { x0 + 2.0, y0 + 3.0 * c, z0 + 3.0 * s },
                                { x0, y0 + 3.0 * c, z0 + 3.0 * s } };
    assert_int_equal(sta_measure_compute(STA_MEASURE_AREA, rect, 4, &v, &err), STA_OK);
    assert_true(fabs(v.area_3d - 6.0) < 1e-8);
    assert_true(fabs(v.area_xy - 6.0 * c) < 1e-8);
    assert_true(fabs(v.distance_3d - 10.0) < 1e-8); // perimeter
    // Clockwise order gives the same (unsigned) areas.
    const double cw[4][3] = { { rect[3][0], rect[3][1], rect[3][2] },
                              { rect[2][0], rect[2][1], rect[2][2] },
                              { rect[1][0], rect[1][1], rect[1][2] },
                              { rect[0][0], rect[0][1], rect[0][2] } };
    sta_measure_values w;
    assert_int_equal(sta_measure_compute(STA_MEASURE_AREA, cw, 4, &w, &err), STA_OK);
    assert_true(w.area_xy == v.area_xy || fabs(w.area_xy - v.area_xy) < 1e-9);
    // A millimetre square at UTM coordinates: 1e-6 m2, which absolute-coordinate
    // shoelace sums (terms ~1e13) could not resolve.
    const double mm[4][3] = { { 651234.567, 5401234.891, 0 },
                              { 651234.568, 5401234.891, 0 },
                              { 651234.568, 5401234.892, 0 },
                              { 651234.567, 5401234.892, 0 } };
    assert_int_equal(sta_measure_compute(STA_MEASURE_AREA, mm, 4, &v, &err), STA_OK);
    assert_true(fabs(v.area_xy - 1e-6) < 1e-9);
    // Staircase: three steps of 1 m run and 0.5 m rise.
    double stairs[4][3];
    for (int i = 0; i < 4; i++) {
        stairs[i][0] = 651000.0 + i;
        stairs[i][1] = 5401000.0;
        stairs[i][2] = 10.0 + 0.5 * i;
    }
    assert_int_equal(
        sta_measure_compute(STA_MEASURE_POLYLINE, (const double(*)[3])stairs, 4, &v, &err), STA_OK);
    assert_true(fabs(v.distance_3d - 3.0 * sqrt(1.25)) < 1e-9);
    assert_true(fabs(v.distance_xy - 3.0) < 1e-9);
    // Wrong point counts and non-finite coordinates are refused.
    assert_int_equal(sta_measure_compute(STA_MEASURE_AREA, (const double(*)[3])stairs, 2, &v, &err),
                     STA_ERR_ARG);
    assert_non_null(strstr(err.message, "area"));
    stairs[1][2] = NAN;
    assert_int_equal(
        sta_measure_compute(STA_MEASURE_POLYLINE, (const double(*)[3])stairs, 4, &v, &err),
        STA_ERR_ARG);
}

static void measurements_round_trip_json_and_csv(void **state)
{
    (void)state;
    sta_measure_list list = { 0 };
    sta_error err = { 0 };
    const double a[2][3] = { { 651234.567, 5401234.891, 100.25 },
                             { 651237.567, 5401238.891, 112.25 } };
    const double tri[3][3] = { { 0.1, 0.2, 0.3 }, { 10.1, 0.2, 0.3 }, { 0.1, 5.2, 0.3 } };
    assert_int_equal(sta_measure_list_add(&list, STA_MEASURE_DISTANCE, "kerb \"A\"", a, 2, &err),
                     STA_OK);
    assert_int_equal(sta_measure_list_add(&list, STA_MEASURE_AREA, "lot", tri, 3, &err), STA_OK);
    const char *json = sta_test_tmp_path("m.json");
    char json_path[4096];
    snprintf(json_path, sizeof(json_path), "%s", json);
    assert_int_equal(sta_measure_save_json(json_path, &list, &err), STA_OK);
    sta_measure_list back = { 0 };
    assert_int_equal(sta_measure_load_json(json_path, &back, &err), STA_OK);
    assert_int_equal(back.count, 2);
    for (size_t i = 0; i < 2; i++) {
        assert_int_equal(back.items[i].kind, list.items[i].kind);
        assert_string_equal(back.items[i].name, list.items[i].name);
        assert_int_equal(back.items[i].count, list.items[i].count);
        // Coordinates come back as the same doubles (shortest exact decimals).
        assert_memory_equal(back.items[i].points, list.items[i].points,
                            list.items[i].count * sizeof(double[3]));
    }
    char csv_path[4096];
    snprintf(csv_path, sizeof(csv_path), "%s", sta_test_tmp_path("m.csv"));
    assert_int_equal(sta_measure_save_csv(csv_path, &back, &err), STA_OK);
    size_t size;
    char *csv = (char *)sta_test_read_file(csv_path, &size);
    csv = realloc(csv, size + 1);
    csv[size] = '\0';
    assert_non_null(strstr(csv, "\"kerb \"\"A\"\"\",distance,2,13,5,12,0,0,"));
    assert_non_null(strstr(csv, "651234.567 5401234.891 100.25;651237.567 5401238.891 112.25"));
    assert_non_null(strstr(csv, "\"lot\",area,3,"));
    assert_non_null(strstr(csv, ",25,25,")); // plan and 3D area of the triangle
    free(csv);
    // Broken files: named, and the list is left as it was.
    const char *angle = "{\"measurements\": [{\"kind\": \"angle\", \"points\": []}]}";
    sta_test_write_file(json_path, angle, strlen(angle));
    assert_int_equal(sta_measure_load_json(json_path, &back, &err), STA_ERR_FORMAT);
    assert_non_null(strstr(err.message, "kind"));
    const char *bad = "{\"measurements\": [{\"kind\": \"distance\", \"points\": [[1,2,3]]}]}";
    sta_test_write_file(json_path, bad, strlen(bad));
    assert_int_equal(sta_measure_load_json(json_path, &back, &err), STA_ERR_FORMAT);
    assert_non_null(strstr(err.message, "measurement 0"));
    assert_int_equal(back.count, 2);
    sta_measure_list_release(&back);
    sta_measure_list_release(&list);
    unlink(json_path);
    unlink(csv_path);
}

static sta_pick_result hit_at(double x, double y, double z)
{
    sta_pick_result r = { .hit = true, .world = { x, y, z } };
    return r;
}

/* The window's tools: distance finishes on its second pick, a miss adds nothing, a
 * polyline waits for Enter, undo drops a vertex then a measurement. */
static void measuring_tools_follow_the_clicks(void **state)
{
    (void)state;
    sta_view_tools t;
    sta_view_tools_init(&t);
    sta_error err = { 0 };
    bool done = false;
    sta_view_tools_next(&t); // point -> distance
    assert_int_equal(t.tool, STA_MEASURE_DISTANCE);
    sta_pick_result a = hit_at(OX + 1, OY + 1, 10), b = hit_at(OX + 4, OY + 5, 10);
    sta_pick_result miss = { .hit = false };
    assert_int_equal(sta_view_tools_click(&t, &a, &done, &err), STA_OK);
    assert_false(done);
    assert_int_equal(sta_view_tools_click(&t, &miss, &done, &err), STA_OK);
    assert_int_equal(t.pending_count, 1);
    assert_int_equal(sta_view_tools_click(&t, &b, &done, &err), STA_OK);
    assert_true(done);
    assert_int_equal(t.list.count, 1);
    assert_string_equal(t.list.items[0].name, "distance 1");
    sta_measure_values v;
    assert_int_equal(sta_measure_compute(t.list.items[0].kind,
                                         (const double(*)[3])t.list.items[0].points,
                                         t.list.items[0].count, &v, &err),
                     STA_OK);
    assert_true(fabs(v.distance_xy - 5.0) < 1e-9);
    sta_view_tools_next(&t); // height
    sta_view_tools_next(&t); // polyline
    assert_int_equal(t.tool, STA_MEASURE_POLYLINE);
    assert_false(sta_view_tools_finish(&t)); // nothing picked yet
    for (int i = 0; i < 3; i++) {
        sta_pick_result p = hit_at(OX + i, OY, 10);
        assert_int_equal(sta_view_tools_click(&t, &p, &done, &err), STA_OK);
        assert_false(done);
    }
    sta_view_tools_undo(&t); // drops the third vertex
    assert_int_equal(t.pending_count, 2);
    assert_true(sta_view_tools_finish(&t));
    assert_int_equal(t.list.count, 2);
    assert_int_equal(t.list.items[1].count, 2);
    sta_view_tools_undo(&t); // nothing pending: drops the polyline
    assert_int_equal(t.list.count, 1);
    char status[256];
    sta_view_tools_status(&t, status, sizeof(status));
    assert_non_null(strstr(status, "polyline"));
    sta_view_tools_release(&t);
}

static const struct CMUnitTest tests[] = {
    cmocka_unit_test(picks_the_millimetre_far_from_the_origin),
    cmocka_unit_test(nearest_point_wins_and_misses_are_misses),
    cmocka_unit_test(measurement_maths_in_double),
    cmocka_unit_test(measurements_round_trip_json_and_csv),
    cmocka_unit_test(measuring_tools_follow_the_clicks),
};

STA_TEST_MAIN(tests)
