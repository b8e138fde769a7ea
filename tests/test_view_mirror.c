/* SPDX-License-Identifier: MIT
 * The mirror-marking tool's state machine (src/app/view_mirror_tool.c): picks become
 * vertices, misses do nothing, undo drops vertices then mirrors, closing turns the
 * front towards the camera and writes a file that reads back; bad outlines are
 * refused with the vertices kept. */
#include "test_support.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "app/view_mirror_tool.h"

static sta_pick_result hit_at(double x, double y, double z)
{
    sta_pick_result p = { .hit = true };
    p.world[0] = x;
    p.world[1] = y;
    p.world[2] = z;
    return p;
}

static void picks_close_save_and_undo(void **state)
{
    (void)state;
    char path[4096];
    snprintf(path, sizeof(path), "%s", sta_test_tmp_path("marked.mirrors.json"));
    remove(path);
    sta_view_mirror_tool tool;
    sta_error err = { 0 };
    assert_int_equal(sta_view_mirror_tool_init(&tool, path, &err), STA_OK);
    assert_int_equal(tool.set.count, 0);
    // A mirror on the wall x = 650010 (UTM-like coordinates), seen from x < 650010:
    // picked counter-clockwise as seen from +x, i.e. clockwise from the camera.
    const double x0 = 650010.25, y0 = 5400000.5;
    const sta_pick_result corners[4] = { hit_at(x0, y0, 100.5), hit_at(x0, y0 + 1.5, 100.5),
                                         hit_at(x0, y0 + 1.5, 102.0), hit_at(x0, y0, 102.0) };
    const sta_pick_result miss = { .hit = false };
    for (int i = 0; i < 4; i++) {
        assert_int_equal(sta_view_mirror_tool_click(&tool, &corners[i], &err), STA_OK);
        assert_int_equal(sta_view_mirror_tool_click(&tool, &miss, &err), STA_OK); // no vertex
    }
    assert_int_equal(tool.pending_count, 4);
    // A stray fifth pick off the plane, undone before closing.
    sta_pick_result stray = hit_at(x0 - 0.7, y0 + 0.7, 101.0);
    assert_int_equal(sta_view_mirror_tool_click(&tool, &stray, &err), STA_OK);
    char line[256];
    sta_view_mirror_tool_status(&tool, line, sizeof(line));
    assert_non_null(strstr(line, "5 of 3+ vertices, 0 mirrors"));
    const double eye[3] = { x0 - 6.0, y0 + 0.7, 101.6 };
    assert_int_equal(sta_view_mirror_tool_close(&tool, eye, &err), STA_ERR_FORMAT);
    assert_non_null(strstr(err.message, "mirror 1 'mirror 1': not planar: vertex"));
    assert_int_equal(tool.pending_count, 5); // kept for undo
    assert_int_equal(sta_view_mirror_tool_undo(&tool, &err), STA_OK);
    assert_int_equal(sta_view_mirror_tool_close(&tool, eye, &err), STA_OK);
    assert_int_equal(tool.pending_count, 0);
    assert_int_equal(tool.set.count, 1);
    // The front faces the camera although the clicks went the other way round.
    const sta_mirror *m = &tool.set.mirrors[0];
    assert_true(sta_mirror_signed_distance(m, eye) > 5.9);
    assert_true(fabs(m->normal[0] + 1.0) < 1e-9);
    // The file reads back with the same outline (reversed, bit for bit).
    sta_mirror_set back;
    assert_int_equal(sta_mirror_set_load(path, &back, &err), STA_OK);
    assert_int_equal(back.count, 1);
    assert_string_equal(back.mirrors[0].name, "mirror 1");
    assert_int_equal(back.mirrors[0].vertex_count, 4);
    for (int i = 0; i < 4; i++) {
        assert_memory_equal(back.mirrors[0].vertices[i], corners[3 - i].world, 3 * sizeof(double));
    }
    sta_mirror_set_release(&back);
    // Too few vertices: refused, nothing added.
    assert_int_equal(sta_view_mirror_tool_click(&tool, &corners[0], &err), STA_OK);
    assert_int_equal(sta_view_mirror_tool_click(&tool, &corners[1], &err), STA_OK);
    assert_int_equal(sta_view_mirror_tool_close(&tool, eye, &err), STA_ERR_FORMAT);
    assert_non_null(strstr(err.message, "2 vertices, a mirror needs at least 3"));
    // Undo: two vertices, then the mirror itself (the file follows).
    for (int i = 0; i < 3; i++) {
        assert_int_equal(sta_view_mirror_tool_undo(&tool, &err), STA_OK);
    }
    assert_int_equal(tool.set.count, 0);
    assert_int_equal(sta_mirror_set_load(path, &back, &err), STA_OK);
    assert_int_equal(back.count, 0);
    sta_mirror_set_release(&back);
    sta_view_mirror_tool_release(&tool);
}

static void existing_file_is_loaded_and_extended(void **state)
{
    (void)state;
    char path[4096];
    snprintf(path, sizeof(path), "%s", sta_test_tmp_path("existing.mirrors.json"));
    const char text[] = "{\"format\": \"strata-mirrors\", \"version\": 1, \"mirrors\": "
                        "[{\"name\": \"hall\", \"polygon\": [[0,0,0],[1,0,0],[1,0,1]]}]}";
    sta_test_write_file(path, text, sizeof(text) - 1);
    sta_view_mirror_tool tool;
    sta_error err = { 0 };
    assert_int_equal(sta_view_mirror_tool_init(&tool, path, &err), STA_OK);
    assert_int_equal(tool.set.count, 1);
    const sta_pick_result tri[3] = { hit_at(5, 0, 0), hit_at(5, 1, 0), hit_at(5, 1, 1) };
    for (int i = 0; i < 3; i++) {
        assert_int_equal(sta_view_mirror_tool_click(&tool, &tri[i], &err), STA_OK);
    }
    const double eye[3] = { 9, 0.5, 0.5 };
    assert_int_equal(sta_view_mirror_tool_close(&tool, eye, &err), STA_OK);
    sta_mirror_set back;
    assert_int_equal(sta_mirror_set_load(path, &back, &err), STA_OK);
    assert_int_equal(back.count, 2);
    assert_string_equal(back.mirrors[0].name, "hall");
    assert_string_equal(back.mirrors[1].name, "mirror 2");
    assert_true(sta_mirror_signed_distance(&back.mirrors[1], eye) > 0.0);
    sta_mirror_set_release(&back);
    sta_view_mirror_tool_release(&tool);
    // A broken file is an error at start, naming it.
    const char bad[] = "{\"format\": \"strata-mirrors\", \"version\": 1, \"mirror\": []}";
    sta_test_write_file(path, bad, sizeof(bad) - 1);
    assert_int_equal(sta_view_mirror_tool_init(&tool, path, &err), STA_ERR_FORMAT);
    assert_non_null(strstr(err.message, "existing.mirrors.json: unknown key \"mirror\""));
    sta_view_mirror_tool_release(&tool);
}

static const struct CMUnitTest tests[] = {
    cmocka_unit_test(picks_close_save_and_undo),
    cmocka_unit_test(existing_file_is_loaded_and_extended),
};

STA_TEST_MAIN(tests)
