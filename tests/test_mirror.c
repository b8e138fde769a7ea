/* SPDX-License-Identifier: MIT
 * Mirror planes (src/mirror): reflection of points, directions and the matrix in
 * double precision 6.4e6 m from the origin, point-in-polygon on a concave outline,
 * ray and segment crossings, planarity, the mirror file (round trip and every kind of
 * bad input, each error naming file and mirror) and both ghost models on cases worked
 * out by hand. */
#include "test_support.h"

#include <math.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "convert.h"
#include "format/strata_reader.h"
#include "mirror/mirror_camera.h"
#include "mirror/mirror_set.h"
#include "synth/mirror_eval.h"
#include "synth/synth.h"

/* An ECEF-like centre: 6.4e6 m from the origin, not a round number of metres. */
static const double far_centre[3] = { 4201345.125, 171234.5, 4780123.75 };

/* A regular hexagon of radius 1.5 m about far_centre in the plane with unit normal
 * n (tilted, not axis-aligned), counter-clockwise seen from the front. */
static void far_hexagon(double out[6][3], double normal[3])
{
    double n[3] = { 0.48, -0.6, 0.64 }; // unit: 0.2304 + 0.36 + 0.4096 = 1
    double u[3] = { 0.8, 0.64, 0.0 };   // n.u = 0.384 - 0.384 + 0 = 0, |u| = sqrt(1.0496)
    double lu = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    for (int a = 0; a < 3; a++) {
        u[a] /= lu;
    }
    double v[3] = { n[1] * u[2] - n[2] * u[1], n[2] * u[0] - n[0] * u[2],
                    n[0] * u[1] - n[1] * u[0] };
    for (int i = 0; i < 6; i++) {
        double angle = 2.0 * 3.14159265358979323846 * i / 6.0;
        for (int a = 0; a < 3; a++) {
            out[i][a] = far_centre[a] + 1.5 * (cos(angle) * u[a] + sin(angle) * v[a]);
        }
    }
    memcpy(normal, n, sizeof(n));
}

static void reflection_is_exact_far_from_the_origin(void **state)
{
    (void)state;
    double hex[6][3], n[3];
    far_hexagon(hex, n);
    sta_mirror m;
    sta_error err = { 0 };
    assert_int_equal(sta_mirror_init(&m, "far", (const double(*)[3])hex, 6, 1e-6, &err), STA_OK);
    for (int a = 0; a < 3; a++) {
        assert_true(fabs(m.normal[a] - n[a]) < 1e-8); // Newell's normal, winding kept
    }
    assert_true(m.max_off_plane_m < 1e-8);
    // A point 7.25 m in front, 0.4 m aside: its image is 7.25 m behind, same foot.
    double p[3], q[3], back[3];
    for (int a = 0; a < 3; a++) {
        p[a] = far_centre[a] + 7.25 * n[a] + 0.4 * m.axis_u[a];
    }
    assert_true(fabs(sta_mirror_signed_distance(&m, p) - 7.25) < 1e-8);
    sta_mirror_reflect_point(&m, p, q);
    assert_true(fabs(sta_mirror_signed_distance(&m, q) + 7.25) < 1e-8);
    for (int a = 0; a < 3; a++) {
        double expected = far_centre[a] - 7.25 * n[a] + 0.4 * m.axis_u[a];
        assert_true(fabs(q[a] - expected) < 1e-8); // 10 nm at 6.4e6 m
    }
    sta_mirror_reflect_point(&m, q, back);
    for (int a = 0; a < 3; a++) {
        assert_true(fabs(back[a] - p[a]) < 1e-8);
    }
    // The matrix maps p as the function does (to 1e-7: it holds 2(n.c)n, ~1e7 m).
    double M[16];
    sta_mirror_reflection_matrix(&m, M);
    for (int row = 0; row < 3; row++) {
        double x = M[12 + row];
        for (int col = 0; col < 3; col++) {
            x += M[col * 4 + row] * p[col];
        }
        assert_true(fabs(x - q[row]) < 1e-6);
    }
    assert_true(M[15] == 1.0 && M[3] == 0.0 && M[7] == 0.0 && M[11] == 0.0);
    // Directions: the normal flips, in-plane directions stay, length is kept.
    double d[3];
    sta_mirror_reflect_direction(&m, m.normal, d);
    for (int a = 0; a < 3; a++) {
        assert_true(fabs(d[a] + m.normal[a]) < 1e-15);
    }
    sta_mirror_reflect_direction(&m, m.axis_v, d);
    for (int a = 0; a < 3; a++) {
        assert_true(fabs(d[a] - m.axis_v[a]) < 1e-15);
    }
}

static void axis_plane_reflects_to_the_millimetre_grid(void **state)
{
    (void)state;
    // Plane x = 4201345.125 facing +x (vertices counter-clockwise seen from +x).
    const double x0 = 4201345.125;
    const double sq[4][3] = { { x0, 171234.0, 4780123.0 },
                              { x0, 171236.0, 4780123.0 },
                              { x0, 171236.0, 4780125.0 },
                              { x0, 171234.0, 4780125.0 } };
    sta_mirror m;
    assert_int_equal(sta_mirror_init(&m, NULL, sq, 4, 1e-9, NULL), STA_OK);
    assert_true(m.normal[0] == 1.0 && m.normal[1] == 0.0 && m.normal[2] == 0.0);
    double p[3] = { x0 + 3.501, 171235.25, 4780124.5 }, q[3];
    sta_mirror_reflect_point(&m, p, q);
    assert_true(fabs(q[0] - (x0 - 3.501)) < 1e-9);
    assert_true(q[1] == p[1] && q[2] == p[2]);
}

static void concave_outline_contains_and_distances(void **state)
{
    (void)state;
    // An L in the plane z = 2 (normal +z): [0,2]x[0,1] plus [0,1]x[1,2].
    const double l_shape[6][3] = { { 0, 0, 2 }, { 2, 0, 2 }, { 2, 1, 2 },
                                   { 1, 1, 2 }, { 1, 2, 2 }, { 0, 2, 2 } };
    sta_mirror m;
    assert_int_equal(sta_mirror_init(&m, "L", l_shape, 6, 1e-9, NULL), STA_OK);
    assert_true(fabs(m.normal[2] - 1.0) < 1e-15);
    struct {
        double p[3];
        bool inside;
        double distance;
    } cases[] = {
        { { 0.5, 0.5, 2 }, true, 0.0 },  { { 1.5, 0.5, 2 }, true, 0.0 },
        { { 0.5, 1.5, 2 }, true, 0.0 },  { { 1.5, 1.5, 2 }, false, 0.5 }, // the notch
        { { 3.0, 0.5, 2 }, false, 1.0 }, { { -0.5, -0.5, 7 }, false, sqrt(0.5) },
        { { 0.5, 1.5, -9 }, true, 0.0 }, // projection along the normal
    };
    for (size_t i = 0; i < sizeof(cases) / sizeof(cases[0]); i++) {
        double uv[2];
        sta_mirror_project(&m, cases[i].p, uv);
        assert_int_equal(sta_mirror_contains_uv(&m, uv), cases[i].inside);
        assert_true(fabs(sta_mirror_distance_uv(&m, uv) - cases[i].distance) < 1e-12);
    }
    // Rays: from the front into the L hit, into the notch miss, from behind miss.
    double t = 0.0;
    const double down[3] = { 0, 0, -2 };
    assert_true(sta_mirror_ray_hit(&m, (double[3]){ 0.5, 1.5, 6 }, down, 0.0, 100.0, &t));
    assert_true(fabs(t - 2.0) < 1e-12); // dir has length 2: 4 m is t = 2
    assert_false(sta_mirror_ray_hit(&m, (double[3]){ 1.5, 1.5, 6 }, down, 0.0, 100.0, &t));
    assert_false(sta_mirror_ray_hit(&m, (double[3]){ 0.5, 0.5, 6 }, down, 0.0, 1.5, &t));
    const double up[3] = { 0, 0, 1 };
    assert_false(sta_mirror_ray_hit(&m, (double[3]){ 0.5, 0.5, -1 }, up, 0.0, 100.0, &t));
    // Segments: front to behind through the L, but not when ending within behind_m.
    assert_true(sta_mirror_segment_crosses(&m, (double[3]){ 0.5, 0.5, 3 },
                                           (double[3]){ 0.5, 0.5, 1 }, 0.05));
    assert_false(sta_mirror_segment_crosses(&m, (double[3]){ 0.5, 0.5, 3 },
                                            (double[3]){ 0.5, 0.5, 1.97 }, 0.05));
    assert_false(sta_mirror_segment_crosses(&m, (double[3]){ 0.5, 0.5, 1 },
                                            (double[3]){ 0.5, 0.5, 3 }, 0.05));
    assert_false(sta_mirror_segment_crosses(&m, (double[3]){ 1.5, 1.5, 3 },
                                            (double[3]){ 1.5, 1.5, 1 }, 0.05));
}

static void outline_errors_name_the_vertex(void **state)
{
    (void)state;
    sta_mirror m;
    sta_error err = { 0 };
    const double bent[4][3] = { { 0, 0, 0 }, { 1, 0, 0 }, { 1, 1, 0.2 }, { 0, 1, 0 } };
    assert_int_equal(sta_mirror_init(&m, "b", bent, 4, 0.01, &err), STA_ERR_FORMAT);
    // A twisted quad: each vertex about h/4 = 0.05 m off the best plane; the message
    // names the worst one.
    assert_non_null(strstr(err.message, "not planar: vertex 3 is 0.0495"));
    assert_non_null(strstr(err.message, "m off the plane (tolerance 0.01 m)"));
    assert_int_equal(sta_mirror_init(&m, "b", bent, 4, 0.06, &err), STA_OK);
    assert_true(m.max_off_plane_m > 0.049 && m.max_off_plane_m < 0.05);
    const double line[3][3] = { { 0, 0, 0 }, { 1, 1, 1 }, { 2, 2, 2 } };
    assert_int_equal(sta_mirror_init(&m, "l", line, 3, 0.01, &err), STA_ERR_FORMAT);
    assert_non_null(strstr(err.message, "degenerate"));
    assert_int_equal(sta_mirror_init(&m, "l", line, 2, 0.01, &err), STA_ERR_FORMAT);
    assert_non_null(strstr(err.message, "at least 3"));
    const double nan_vertex[3][3] = { { 0, 0, 0 }, { 1, NAN, 0 }, { 0, 1, 0 } };
    assert_int_equal(sta_mirror_init(&m, "n", nan_vertex, 3, 0.01, &err), STA_ERR_FORMAT);
    assert_non_null(strstr(err.message, "vertex 2: coordinate 2 is not finite"));
}

static void file_round_trips_bit_exactly(void **state)
{
    (void)state;
    double hex[6][3], n[3];
    far_hexagon(hex, n);
    const double tri[3][3] = { { 0.1, 0.2, 0.3 }, { 1.7, 0.2, 0.3 }, { 0.1, 0.2, 2.9 } };
    sta_mirror_set set = { .max_incidence_deg = 70.0 };
    sta_error err = { 0 };
    assert_int_equal(sta_mirror_set_add(&set, "hall", (const double(*)[3])hex, 6, &err), STA_OK);
    assert_int_equal(sta_mirror_set_add(&set, "bath \"2\"", tri, 3, &err), STA_OK);
    const double station[3] = { 650244.375, 5401876.625, 104.85 };
    assert_int_equal(sta_mirror_set_add_station(&set, 7, station, &err), STA_OK);
    const char *path = sta_test_tmp_path("round.mirrors.json");
    assert_int_equal(sta_mirror_set_save(path, &set, &err), STA_OK);
    sta_mirror_set back;
    assert_int_equal(sta_mirror_set_load(path, &back, &err), STA_OK);
    assert_int_equal(back.count, 2);
    assert_string_equal(back.mirrors[0].name, "hall");
    assert_string_equal(back.mirrors[1].name, "bath \"2\"");
    assert_true(back.max_incidence_deg == 70.0);
    assert_true(back.tolerance_m == STA_MIRROR_DEFAULT_TOLERANCE_M);
    assert_int_equal(back.mirrors[0].vertex_count, 6);
    assert_memory_equal(back.mirrors[0].vertices, set.mirrors[0].vertices, 6 * 3 * sizeof(double));
    assert_memory_equal(back.mirrors[1].vertices, tri, sizeof(tri));
    assert_int_equal(back.station_count, 1);
    assert_int_equal(back.stations[0].point_source_id, 7);
    assert_memory_equal(back.stations[0].position, station, sizeof(station));
    sta_mirror_set_release(&back);
    sta_mirror_set_release(&set);
    assert_int_equal(sta_mirror_set_load(sta_test_tmp_path("absent.json"), &back, &err),
                     STA_ERR_IO);
    assert_non_null(strstr(err.message, "absent.json"));
}

#define HEAD "{\"format\": \"strata-mirrors\", \"version\": 1, "
#define GOOD "{\"name\": \"ok\", \"polygon\": [[0,0,0],[1,0,0],[1,1,0],[0,1,0]]}"

static void bad_files_name_file_and_mirror(void **state)
{
    (void)state;
    struct {
        const char *text;
        const char *expect; /* in the message after "bad.json: " */
    } cases[] = {
        { HEAD "\"mirrors\": [" GOOD ", {\"name\": \"tri\", \"polygon\": [[0,0,0],[1,0,0]]}]}",
          "mirror 2 'tri': 2 vertices, a mirror needs at least 3" },
        { HEAD "\"mirrors\": [" GOOD ", {\"name\": \"bent\", \"polygon\": "
               "[[0,0,0],[1,0,0],[1,1,0.5],[0,1,0]]}]}",
          "mirror 2 'bent': not planar: vertex 1 is 0.1179 m off the plane (tolerance 0.05 m)" },
        { HEAD "\"mirrors\": [{\"name\": \"nan\", \"polygon\": [[0,0,0],[1,NaN,0],[0,1,0]]}]}",
          "not valid JSON" },
        { HEAD "\"mirrors\": [{\"name\": \"inf\", \"polygon\": [[0,0,0],[1,1e999,0],[0,1,0]]}]}",
          "mirror 1 'inf': vertex 2: coordinate 2 is not a finite number" },
        { HEAD "\"mirrors\": [{\"name\": \"null\", \"polygon\": [[0,0,0],[1,null,0],[0,1,0]]}]}",
          "mirror 1 'null': vertex 2: coordinate 2 is not a finite number" },
        { HEAD "\"mirrors\": [" GOOD ", {\"name\": \"k\", \"colour\": 1, \"polygon\": "
               "[[0,0,0],[1,0,0],[0,1,0]]}]}",
          "mirror 2 'k': unknown key \"colour\"" },
        { HEAD "\"mirors\": []}", "unknown key \"mirors\"" },
        { HEAD "\"tolerance_m\": -1, \"mirrors\": []}", "\"tolerance_m\" must be a number" },
        { "{\"format\": \"las\", \"version\": 1, \"mirrors\": []}", "\"format\" must be" },
        { "{\"format\": \"strata-mirrors\", \"version\": 2, \"mirrors\": []}",
          "\"version\" must be 1" },
        { HEAD "\"mirrors\": [{\"name\": \"p\"}]}", "mirror 1 'p': \"polygon\"" },
        { HEAD "\"mirrors\": [{\"name\": \"v\", \"polygon\": [[0,0,0],[1,0],[0,1,0]]}]}",
          "mirror 1 'v': vertex 2 is not [x, y, z]" },
        { HEAD "\"mirrors\": [7]}", "mirror 1: not an object" },
        { "{\"format\": \"strata-mirrors\", \"version\": 1}", "\"mirrors\" (an array) is missing" },
        { HEAD "\"mirrors\": [], \"stations\": {}}", "\"stations\" must be an array" },
        { HEAD "\"mirrors\": [], \"stations\": [{\"point_source_id\": 1}]}",
          "station 1: \"position\" must be [x, y, z], finite" },
        { HEAD "\"mirrors\": [], \"stations\": [{\"point_source_id\": 1.5, \"position\": "
               "[0,0,0]}]}",
          "station 1: \"point_source_id\" must be an integer 0..65535" },
        { HEAD "\"mirrors\": [], \"stations\": [{\"point_source_id\": 70000, \"position\": "
               "[0,0,0]}]}",
          "station 1: \"point_source_id\" must be an integer 0..65535" },
        { HEAD "\"mirrors\": [], \"stations\": [{\"point_source_id\": 2, \"position\": "
               "[0,0,0], \"yaw\": 1}]}",
          "station 1: unknown key \"yaw\"" },
        { HEAD "\"mirrors\": [], \"stations\": [{\"point_source_id\": 2, \"position\": "
               "[0,0,0]}, {\"point_source_id\": 2, \"position\": [1,0,0]}]}",
          "station 2: point source ID 2 is already station 1" },
        { HEAD "\"mirrors\": [], \"stations\": [{\"point_source_id\": 2, \"position\": "
               "[0,1e999,0]}]}",
          "station 1: \"position\" must be [x, y, z], finite" },
        { "[1, 2]", "not a JSON object" },
        { "", "not valid JSON" },
    };
    for (size_t i = 0; i < sizeof(cases) / sizeof(cases[0]); i++) {
        sta_mirror_set set;
        sta_error err = { 0 };
        sta_status s =
            sta_mirror_set_parse(cases[i].text, strlen(cases[i].text), "bad.json", &set, &err);
        if (s == STA_OK || strncmp(err.message, "bad.json: ", 10) != 0 ||
            !strstr(err.message, cases[i].expect)) {
            fail_msg("case %zu: status %d, message '%s', expected '%s'", i, (int)s, err.message,
                     cases[i].expect);
        }
        assert_int_equal(set.count, 0);
        assert_null(set.mirrors);
        assert_null(set.stations);
    }
}

static void ghost_models_by_hand(void **state)
{
    (void)state;
    // A 2 x 2 m mirror in the plane x = 0 facing +x, centred on (0, 0, 1).
    const double sq[4][3] = { { 0, -1, 0 }, { 0, 1, 0 }, { 0, 1, 2 }, { 0, -1, 2 } };
    sta_mirror_set set = { 0 };
    assert_int_equal(sta_mirror_set_add(&set, "m", sq, 4, NULL), STA_OK);
    const double scanner[3] = { 5, 0, 1 };
    // Straight behind: ghost in both models.
    double p[3] = { -3, 0, 1 };
    assert_int_equal(sta_mirror_ghost_from_scanner(&set, scanner, p), 1);
    assert_int_equal(sta_mirror_ghost_in_volume(&set, p), 1);
    // Behind but off to the side: the scanner's ray passes beside the mirror (crosses
    // the plane at y = 3.125); the volume model's view rays up to 80 deg reach it.
    double q[3] = { -3, 5, 1 };
    assert_int_equal(sta_mirror_ghost_from_scanner(&set, scanner, q), 0);
    assert_int_equal(sta_mirror_ghost_in_volume(&set, q), 1);
    // Far to the side at shallow depth: beyond 80 deg (4 m off the outline, 0.5 m deep).
    double r[3] = { -0.5, 5, 1 };
    assert_int_equal(sta_mirror_ghost_in_volume(&set, r), 0);
    // Within behind_m of the plane, and in front: real.
    double s[3] = { -0.04, 0, 1 }, f[3] = { 2, 0, 1 };
    assert_int_equal(sta_mirror_ghost_from_scanner(&set, scanner, s), 0);
    assert_int_equal(sta_mirror_ghost_in_volume(&set, s), 0);
    assert_int_equal(sta_mirror_ghost_from_scanner(&set, scanner, f), 0);
    assert_int_equal(sta_mirror_ghost_in_volume(&set, f), 0);
    // A second mirror: labels are its index + 1; the first match wins.
    const double sq2[4][3] = { { 10, 1, 0 }, { 10, -1, 0 }, { 10, -1, 2 }, { 10, 1, 2 } };
    assert_int_equal(sta_mirror_set_add(&set, "m2", sq2, 4, NULL), STA_OK); // faces -x
    double g[3] = { 13, 0, 1 };
    assert_int_equal(sta_mirror_ghost_from_scanner(&set, scanner, g), 2);
    assert_int_equal(sta_mirror_ghost_in_volume(&set, g), 2);
    // With a station for point source ID 4, its points follow the scanner model; points
    // of other IDs fall back to the volume model.
    assert_int_equal(sta_mirror_set_add_station(&set, 4, scanner, NULL), STA_OK);
    assert_int_equal(sta_mirror_ghost_of(&set, 4, q), 0);
    assert_int_equal(sta_mirror_ghost_of(&set, 5, q), 1);
    assert_int_equal(sta_mirror_ghost_of(&set, 4, p), 1);
    sta_mirror_set_release(&set);
    assert_int_equal(set.station_count, 0);
}

/* The synthetic mirror room (strata-synth mirror), 6.4e6 m from the origin: both
 * models against the truth labels. The scanner model must reach 0.99 everywhere; the
 * volume model on the wall mirrors, and its recall on all (docs/MIRRORS.md explains
 * the leaning mirror's false positives, which only the scanner model avoids). */
static void ghosts_match_the_synthetic_truth(void **state)
{
    (void)state;
    sta_synth_params p = {
        .kind = STA_SYNTH_MIRROR, .point_count = 400000, .seed = 7, .origin = STA_SYNTH_ORIGIN_ECEF
    };
    char las[4096];
    snprintf(las, sizeof(las), "%s", sta_test_tmp_path("room.las"));
    sta_error err = { 0 };
    if (sta_synth_generate(&p, las, NULL, NULL, &err) != STA_OK) {
        fail_msg("%s", err.message);
    }
    // The mirror file written beside it is the scene's, in world coordinates.
    sta_mirror_set file;
    assert_int_equal(sta_mirror_set_load(sta_test_tmp_path("room.mirrors.json"), &file, &err),
                     STA_OK);
    assert_int_equal(file.count, 3);
    assert_true(file.mirrors[0].centre[0] > 4.2e6);
    sta_ghost_eval e;
    assert_int_equal(sta_synth_ghost_evaluate(las, &p, &file, &e, &err), STA_OK);
    assert_int_equal(e.points, 400000);
    assert_true(e.truth_ghosts > 4000); // about 3.4 %
    const sta_ghost_score *scanner = &e.models[STA_GHOST_MODEL_SCANNER];
    const sta_ghost_score *volume = &e.models[STA_GHOST_MODEL_VOLUME];
    printf("scanner model: precision %.5f recall %.5f; volume model: precision %.5f recall "
           "%.5f (%llu ghosts of %llu points)\n",
           sta_ghost_precision(scanner), sta_ghost_recall(scanner), sta_ghost_precision(volume),
           sta_ghost_recall(volume), (unsigned long long)e.truth_ghosts,
           (unsigned long long)e.points);
    assert_true(sta_ghost_precision(scanner) >= 0.99 && sta_ghost_recall(scanner) >= 0.99);
    assert_true(scanner->wrong_mirror <= scanner->true_positive / 100);
    assert_true(sta_ghost_recall(volume) >= 0.99);
    for (int k = 0; k < 3; k++) {
        const sta_ghost_score *sk = &e.mirrors[STA_GHOST_MODEL_SCANNER][k];
        const sta_ghost_score *vk = &e.mirrors[STA_GHOST_MODEL_VOLUME][k];
        assert_true(sk->true_positive + sk->false_negative > 500); // every mirror has ghosts
        assert_true(sta_ghost_precision(sk) >= 0.99 && sta_ghost_recall(sk) >= 0.99);
        assert_true(sta_ghost_recall(vk) >= 0.99);
        if (k < 2) { // on the walls
            assert_true(sta_ghost_precision(vk) >= 0.99);
        }
    }
    sta_mirror_set_release(&file);
}

/* strata-convert --mirrors: every point kept, the MIRROR attribute stored (after the
 * other columns) and matching the truth on every mirror (the scene's mirror file lists
 * its stations, so each point is judged by the scanner model from the station of its
 * point source ID); a bad mirror file fails the conversion with the file and mirror
 * named and leaves no output. */
static void convert_flags_ghosts_and_keeps_every_point(void **state)
{
    (void)state;
    sta_synth_params p = { .kind = STA_SYNTH_MIRROR, .point_count = 150000, .seed = 3 };
    char las[4096], mirrors[4096], out[4096];
    snprintf(las, sizeof(las), "%s", sta_test_tmp_path("conv.las"));
    snprintf(mirrors, sizeof(mirrors), "%s", sta_test_tmp_path("conv.mirrors.json"));
    snprintf(out, sizeof(out), "%s", sta_test_tmp_path("conv.strata"));
    sta_error err = { 0 };
    assert_int_equal(sta_synth_generate(&p, las, NULL, NULL, &err), STA_OK);
    const char *inputs[] = { las };
    sta_convert_options o = {
        .inputs = inputs,
        .input_count = 1,
        .output = out,
        .threads = 2,
        .force = true,
        .mirrors = mirrors,
    };
    if (sta_convert(&o, NULL, &err) != STA_OK) {
        fail_msg("%s", err.message);
    }
    sta_strata_reader *r = NULL;
    sta_strata_decoder *dec = NULL;
    assert_int_equal(sta_strata_open(out, NULL, &r, &err), STA_OK);
    assert_int_equal(sta_strata_decoder_create(&dec, &err), STA_OK);
    const sta_strata_info *info = sta_strata_reader_info(r);
    assert_int_equal(info->version_minor, 3);
    assert_true(info->layout.attributes & STA_STRATA_ATTR_MIRROR);
    assert_int_equal(info->layout.attr_size[15], 1);
    uint64_t points = 0, truth = 0, flagged = 0;
    sta_ghost_score all = { 0 };
    for (uint32_t n = 0; n < info->node_count; n++) {
        sta_strata_points pts;
        if (sta_strata_decode_node(r, n, dec, &pts, &err) != STA_OK) {
            fail_msg("%s", err.message);
        }
        for (size_t i = 0; i < pts.count; i++) {
            const sta_point *q = &pts.points[i];
            points++;
            truth += q->user_data != 0;
            flagged += q->mirror != 0;
            assert_true(q->mirror <= 3);
            bool t = q->user_data != 0, f = q->mirror != 0;
            all.true_positive += t && f && q->user_data == q->mirror;
            all.false_positive += f && !t;
            all.false_negative += t && !f;
        }
    }
    assert_int_equal(points, 150000);
    assert_true(truth > 3000);
    printf("stored: %llu flagged, %llu truth ghosts; all mirrors precision %.5f recall %.5f\n",
           (unsigned long long)flagged, (unsigned long long)truth, sta_ghost_precision(&all),
           sta_ghost_recall(&all));
    assert_true(sta_ghost_precision(&all) >= 0.99 && sta_ghost_recall(&all) >= 0.99);
    sta_strata_decoder_destroy(dec);
    sta_strata_close(r);
    // A bad mirror file: the conversion fails naming it and the mirror; no output.
    char bad[4096];
    snprintf(bad, sizeof(bad), "%s", sta_test_tmp_path("bad.mirrors.json"));
    const char text[] = "{\"format\": \"strata-mirrors\", \"version\": 1, \"mirrors\": "
                        "[{\"name\": \"w\", \"polygon\": [[0,0,0],[1,0,0]]}]}";
    sta_test_write_file(bad, text, sizeof(text) - 1);
    char bad_out[4096];
    snprintf(bad_out, sizeof(bad_out), "%s", sta_test_tmp_path("bad.strata"));
    o.output = bad_out;
    o.mirrors = bad;
    assert_int_equal(sta_convert(&o, NULL, &err), STA_ERR_FORMAT);
    assert_non_null(strstr(err.message, "bad.mirrors.json: mirror 1 'w': 2 vertices"));
    assert_int_equal(access(bad_out, F_OK), -1);
}

/* The reflected camera: a point x seen in the mirror (its image R(x) through the real
 * camera) lands on the reflected view's pixel W - x, same row, in double, for a vertical
 * mirror 5.4e6 m from the origin; tilted mirrors and cameras behind are refused. */
static void reflected_camera_sees_the_mirror_image(void **state)
{
    (void)state;
    const double x0 = 650010.25, y0 = 5400000.5;
    // The wall x = x0 facing -x (counter-clockwise seen from -x).
    const double wall[4][3] = {
        { x0, y0 + 2, 100 }, { x0, y0, 100 }, { x0, y0, 102 }, { x0, y0 + 2, 102 }
    };
    sta_mirror m;
    assert_int_equal(sta_mirror_init(&m, "w", wall, 4, 1e-6, NULL), STA_OK);
    assert_true(m.normal[0] < -0.999);
    sta_camera c = { .position = { x0 - 6.0, y0 + 0.3, 101.2 },
                     .yaw = 0.35,
                     .pitch = -0.1,
                     .fov_y = 1.0,
                     .near_m = 0.1,
                     .width_px = 640,
                     .height_px = 400 };
    sta_camera r;
    assert_true(sta_mirror_reflect_camera(&m, &c, &r));
    assert_true(fabs(r.position[0] - (x0 + 6.0)) < 1e-9);
    const double points[3][3] = { { x0 - 3.0, y0 + 1.0, 100.4 },
                                  { x0 - 9.0, y0 - 2.5, 101.0 }, // behind the camera
                                  { x0 - 0.5, y0 + 1.9, 101.9 } };
    for (int i = 0; i < 3; i++) {
        double image[3], px, py, depth, rx, ry, rdepth;
        sta_mirror_reflect_point(&m, points[i], image);
        bool seen = sta_camera_project(&c, image, &px, &py, &depth);
        bool seen_r = sta_camera_project(&r, points[i], &rx, &ry, &rdepth);
        assert_int_equal(seen, seen_r);
        if (!seen) {
            continue;
        }
        assert_true(fabs(rx - (640.0 - px)) < 1e-6);
        assert_true(fabs(ry - py) < 1e-6);
        assert_true(fabs(rdepth - depth) < 1e-6);
    }
    // Behind the mirror, or a tilted mirror: no reflected camera.
    sta_camera behind = c;
    behind.position[0] = x0 + 1.0;
    assert_false(sta_mirror_reflect_camera(&m, &behind, &r));
    const double tilted[3][3] = { { x0, y0, 100 }, { x0, y0 + 2, 100 }, { x0 - 0.4, y0 + 1, 102 } };
    sta_mirror t;
    assert_int_equal(sta_mirror_init(&t, "t", tilted, 3, 1e-6, NULL), STA_OK);
    if (sta_mirror_signed_distance(&t, c.position) < 0) {
        const double flipped[3][3] = { { x0, y0 + 2, 100 },
                                       { x0, y0, 100 },
                                       { x0 - 0.4, y0 + 1, 102 } };
        assert_int_equal(sta_mirror_init(&t, "t", flipped, 3, 1e-6, NULL), STA_OK);
    }
    assert_false(sta_mirror_reflect_camera(&t, &c, &r));
}

static const struct CMUnitTest tests[] = {
    cmocka_unit_test(reflection_is_exact_far_from_the_origin),
    cmocka_unit_test(axis_plane_reflects_to_the_millimetre_grid),
    cmocka_unit_test(concave_outline_contains_and_distances),
    cmocka_unit_test(outline_errors_name_the_vertex),
    cmocka_unit_test(file_round_trips_bit_exactly),
    cmocka_unit_test(bad_files_name_file_and_mirror),
    cmocka_unit_test(ghost_models_by_hand),
    cmocka_unit_test(reflected_camera_sees_the_mirror_image),
    cmocka_unit_test(ghosts_match_the_synthetic_truth),
    cmocka_unit_test(convert_flags_ghosts_and_keeps_every_point),
};

STA_TEST_MAIN(tests)
