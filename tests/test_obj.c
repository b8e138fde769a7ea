/* SPDX-License-Identifier: MIT
 * Tests for src/io/obj.c: Wavefront OBJ meshes (vertices, faces, every reference form),
 * errors that name the file and line, the mesh loader by content, and a strata-synth mesh
 * scene from an OBJ (the Stanford dragon of the shared data is OBJ only).
 */
#include "test_support.h"

#include <stdio.h>
#include <string.h>

#include "io/obj.h"
#include "synth/synth.h"

static sta_mesh load_text(const char *text, sta_status expect, sta_error *err)
{
    sta_mesh mesh;
    sta_status s =
        sta_obj_load_mesh_memory((const uint8_t *)text, strlen(text), "t.obj", &mesh, err);
    if (s != expect) {
        fail_msg("status %d, expected %d (%s) for:\n%s", (int)s, (int)expect, err->message, text);
    }
    return mesh;
}

static void dragon_loads_from_the_shared_data(void **state)
{
    (void)state;
    sta_mesh mesh;
    sta_error err = { 0 };
    const char *path = sta_test_shared_path("models/dragon_vrip_res3.obj");
    assert_int_equal(sta_mesh_load(path, &mesh, &err), STA_OK);
    // The data's README: 22 998 vertices, 47 794 triangular faces.
    assert_int_equal(mesh.vertex_count, 22998);
    assert_int_equal(mesh.triangle_count, 47794);
    double lo[3] = { 1e300, 1e300, 1e300 }, hi[3] = { -1e300, -1e300, -1e300 };
    for (size_t i = 0; i < mesh.vertex_count; i++) {
        for (int a = 0; a < 3; a++) {
            double v = mesh.positions[3 * i + (size_t)a];
            lo[a] = v < lo[a] ? v : lo[a];
            hi[a] = v > hi[a] ? v : hi[a];
        }
    }
    for (size_t i = 0; i < 3 * mesh.triangle_count; i++) {
        assert_true(mesh.triangles[i] < mesh.vertex_count);
    }
    // The dragon is y-up and longest along x (about 0.2 x 0.14 x 0.09 units).
    assert_true(hi[0] - lo[0] > hi[1] - lo[1] && hi[1] - lo[1] > hi[2] - lo[2]);
    sta_mesh_release(&mesh);
}

static void references_polygons_and_other_statements(void **state)
{
    (void)state;
    sta_error err = { 0 };
    const char *text = "# comment\r\n"
                       "mtllib a.mtl\r\n"
                       "o thing\n"
                       "v 0 0 0\n"
                       "v 1 0 0 0.5 0.5 0.5\n" // a colour after the position
                       "v 1 1 0 1.0\n"         // a w
                       "\tv  0   1  0  \n"     // blanks around
                       "vt 0 0\nvn 0 0 1\ng side\ns 1\nusemtl red\n"
                       "f 1/1/1 2/1/1 3/1/1 4/1/1\n" // a quad: two triangles, fanned
                       "f -4//1 -3//1 -1//1\n"       // counting back from vertex 4
                       "f 2/1 3/1 4/1\n"
                       "f 1 2\n"  // fewer than 3: none
                       "l 1 2\n"; // a line: skipped
    sta_mesh m = load_text(text, STA_OK, &err);
    assert_int_equal(m.vertex_count, 4);
    assert_int_equal(m.triangle_count, 4);
    const uint32_t expect[] = { 0, 1, 2, 0, 2, 3, 0, 1, 3, 1, 2, 3 };
    assert_memory_equal(m.triangles, expect, sizeof(expect));
    assert_true(m.positions[3] == 1.0 && m.positions[4] == 0.0 && m.positions[11] == 0.0);
    sta_mesh_release(&m);
    // A face may come before its vertices (positive references are checked at the end).
    m = load_text("f 1 2 3\nv 0 0 0\nv 1 0 0\nv 0 1 0\n", STA_OK, &err);
    assert_int_equal(m.triangle_count, 1);
    sta_mesh_release(&m);
    // No vertices, no faces: an empty mesh (the synth says it has nothing to sample).
    m = load_text("# nothing\n", STA_OK, &err);
    assert_int_equal(m.vertex_count, 0);
    assert_int_equal(m.triangle_count, 0);
}

static void bad_files_name_the_line(void **state)
{
    (void)state;
    static const struct {
        const char *text, *message;
    } cases[] = {
        { "v 1 2\n", "t.obj: line 1: a vertex needs three coordinates" },
        { "v 0 0 0\nv 1 2 nan\n", "t.obj: line 2: coordinate is not finite: \"nan\"" },
        { "v 1 2 1e999\n", "line 1: coordinate is not finite" },
        { "v 1 2 x3\n", "line 1: coordinate is not a number: \"x3\"" },
        { "v 1 2 3,5\n", "line 1: coordinate is not a number: \"3,5\"" },
        { "v 0 0 0\nf 0 1 1\n", "line 2: vertex reference 0" },
        { "v 0 0 0\nf 1 a 1\n", "line 2: vertex reference is not a number: \"a\"" },
        { "v 0 0 0\nf -2 1 1\n", "line 2: vertex reference before the first vertex" },
        { "v 0 0 0\nf 1 2 3\n", "t.obj: face 1 refers to vertex 2, but the file has 1" },
        { "v 0 0 0\nf 1 1 99999999999\n", "line 2: vertex reference beyond 2^32 vertices" },
        { "v 1 2 \\\n3\n", "line 1: lines continued with a backslash are not supported" },
    };
    for (size_t i = 0; i < sizeof(cases) / sizeof(cases[0]); i++) {
        sta_error err = { 0 };
        sta_mesh m = load_text(cases[i].text, STA_ERR_FORMAT, &err);
        if (!strstr(err.message, cases[i].message)) {
            fail_msg("case %zu: \"%s\" lacks \"%s\"", i, err.message, cases[i].message);
        }
        assert_null(m.positions);
        assert_null(m.triangles);
    }
    // A NUL byte inside a line.
    static const char nul[] = "v 1 2\0 3\n";
    sta_mesh m;
    sta_error err = { 0 };
    assert_int_equal(
        sta_obj_load_mesh_memory((const uint8_t *)nul, sizeof(nul) - 1, "t.obj", &m, &err),
        STA_ERR_FORMAT);
    assert_non_null(strstr(err.message, "line 1: a NUL byte"));
}

static void mesh_load_picks_the_format_by_content(void **state)
{
    (void)state;
    char ply[4096], obj[4096], las[4096];
    snprintf(ply, sizeof(ply), "%s", sta_test_tmp_path("tri.ply"));
    snprintf(obj, sizeof(obj), "%s", sta_test_tmp_path("tri.mesh")); // no .obj needed
    snprintf(las, sizeof(las), "%s", sta_test_tmp_path("not_a_mesh.obj"));
    const char ply_text[] = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                            "property float y\nproperty float z\nelement face 1\n"
                            "property list uchar int vertex_indices\nend_header\n"
                            "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    sta_test_write_file(ply, ply_text, sizeof(ply_text) - 1);
    const char obj_text[] = "\n\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    sta_test_write_file(obj, obj_text, sizeof(obj_text) - 1);
    sta_test_write_file(las, "LASF\0\0\0\0", 8);
    const char *meshes[] = { ply, obj };
    for (int i = 0; i < 2; i++) {
        sta_mesh m;
        sta_error err = { 0 };
        assert_int_equal(sta_mesh_load(meshes[i], &m, &err), STA_OK);
        assert_int_equal(m.vertex_count, 3);
        assert_int_equal(m.triangle_count, 1);
        sta_mesh_release(&m);
    }
    sta_mesh m;
    sta_error err = { 0 };
    assert_int_equal(sta_mesh_load(las, &m, &err), STA_ERR_FORMAT);
    assert_non_null(strstr(err.message, "not_a_mesh.obj: neither a PLY mesh"));
    assert_int_equal(sta_mesh_load(sta_test_tmp_path("missing.obj"), &m, &err), STA_ERR_IO);
}

// The dragon as a strata-synth mesh scene, and a broken OBJ refused by the synth.
static void synth_mesh_scene_from_an_obj(void **state)
{
    (void)state;
    char las[4096], bad[4096];
    snprintf(las, sizeof(las), "%s", sta_test_tmp_path("dragon.las"));
    snprintf(bad, sizeof(bad), "%s", sta_test_tmp_path("bad.obj"));
    sta_synth_params p = { .kind = STA_SYNTH_MESH,
                           .seed = 1,
                           .point_count = 20000,
                           .mesh_path = sta_test_shared_path("models/dragon_vrip_res3.obj") };
    sta_error err = { 0 };
    if (sta_synth_generate(&p, las, NULL, NULL, &err) != STA_OK) {
        fail_msg("%s", err.message);
    }
    sta_test_write_file(bad, "v 0 0 0\nf 1 2 3\n", 16);
    p.mesh_path = bad;
    assert_int_equal(sta_synth_generate(&p, las, NULL, NULL, &err), STA_ERR_FORMAT);
    assert_non_null(strstr(err.message, "bad.obj: face 1 refers to vertex 2"));
}

int main(int argc, char **argv)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(dragon_loads_from_the_shared_data),
        cmocka_unit_test(references_polygons_and_other_statements),
        cmocka_unit_test(bad_files_name_the_line),
        cmocka_unit_test(mesh_load_picks_the_format_by_content),
        cmocka_unit_test(synth_mesh_scene_from_an_obj),
    };
    return sta_test_run("obj", tests, sizeof(tests) / sizeof(tests[0]), argc, argv);
}
