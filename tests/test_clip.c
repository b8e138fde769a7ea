/* SPDX-License-Identifier: MIT
 * Clipping and filters in the streamer (stream/clip.h through select.c and
 * strata_source.c): nodes outside the clip are neither selected nor loaded, the
 * budget goes to the nodes that can show points, and loaded nodes hold exactly the
 * points that pass (counted here from the source LAS without the clip code). */
#include "test_support.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "convert.h"
#include "core/alloc.h"
#include "io/cloud.h"
#include "stream/clip.h"
#include "stream/lod_tree.h"
#include "stream/select.h"
#include "stream/strata_source.h"
#include "stream/streamer.h"

static const char *convert_autzen(char *scene, size_t size)
{
    static char source[4096];
    snprintf(source, sizeof(source), "%s", sta_test_shared_path("las/autzen_trim.las"));
    snprintf(scene, size, "%s/clip.strata", sta_test_tmpdir());
    const char *one[] = { source };
    sta_convert_options o = {
        .inputs = one, .input_count = 1, .output = scene, .leaf_capacity = 500, .force = true
    };
    sta_error err = { 0 };
    if (sta_convert(&o, NULL, &err) != STA_OK) {
        fail_msg("convert: %s", err.message);
    }
    return source;
}

// Above the scene, looking down at it whole.
static sta_camera overview(const sta_strata_info *info)
{
    sta_camera c = { .yaw = 0.3,
                     .pitch = -1.2,
                     .fov_y = 60 * M_PI / 180,
                     .near_m = 0.1,
                     .width_px = 1280,
                     .height_px = 720 };
    sta_camera_frame_box(&c, info->bounds_min, info->bounds_max);
    return c;
}

static bool box_overlaps(const sta_lod_node *n, const double lo[3], const double hi[3])
{
    for (int a = 0; a < 3; a++) {
        if (n->max[a] < lo[a] || n->min[a] > hi[a]) {
            return false;
        }
    }
    return true;
}

/* With a clip box, every selected node meets the box; under the same budget the
 * clipped cut holds more points of nodes meeting the box than the unclipped one. */
static void selection_skips_nodes_outside_the_box(void **state)
{
    (void)state;
    STA_TEST_REQUIRE_SHARED_DATA();
    char scene[4096];
    convert_autzen(scene, sizeof(scene));
    sta_strata_reader *r = NULL;
    sta_error err = { 0 };
    assert_int_equal(sta_strata_open(scene, NULL, &r, &err), STA_OK);
    sta_lod_tree tree;
    assert_int_equal(sta_lod_tree_init(&tree, r, &err), STA_OK);
    sta_camera cam = overview(sta_strata_reader_info(r));
    const double lo[3] = { 636300.0, 849000.0, 0.0 }, hi[3] = { 636700.0, 849250.0, 1000.0 };
    sta_clip clip = { .has_box = true };
    memcpy(clip.box_min, lo, sizeof(lo));
    memcpy(clip.box_max, hi, sizeof(hi));
    sta_selection plain = { 0 }, clipped = { 0 };
    sta_select_params p = { .budget_points = 20000 };
    assert_int_equal(sta_select(&tree, &cam, &p, &plain, &err), STA_OK);
    p.clip = &clip;
    assert_int_equal(sta_select(&tree, &cam, &p, &clipped, &err), STA_OK);
    uint64_t plain_inside = 0, clipped_inside = 0;
    for (size_t i = 0; i < plain.count; i++) {
        const sta_lod_node *n = &tree.nodes[plain.nodes[i]];
        plain_inside += box_overlaps(n, lo, hi) ? n->point_count : 0;
    }
    assert_true(clipped.count > 0);
    for (size_t i = 0; i < clipped.count; i++) {
        const sta_lod_node *n = &tree.nodes[clipped.nodes[i]];
        assert_true(box_overlaps(n, lo, hi));
        clipped_inside += n->point_count;
    }
    assert_true(clipped.point_count <= 20000);
    assert_true(clipped_inside > plain_inside);
    // A level limit: nothing deeper is selected, even with budget to spare.
    sta_clip shallow = { .has_max_level = true, .max_level = 1 };
    sta_select_params q = { .budget_points = 10000000, .clip = &shallow };
    assert_int_equal(sta_select(&tree, &cam, &q, &clipped, &err), STA_OK);
    for (size_t i = 0; i < clipped.count; i++) {
        assert_true(tree.nodes[clipped.nodes[i]].level <= 1);
    }
    sta_selection_release(&plain);
    sta_selection_release(&clipped);
    sta_lod_tree_release(&tree);
    sta_strata_close(r);
    unlink(scene);
}

/* Nodes loaded through the .strata node source with a class and return filter hold
 * exactly the passing points: the total equals a count made from the LAS input. */
static void loaded_nodes_hold_only_passing_points(void **state)
{
    (void)state;
    STA_TEST_REQUIRE_SHARED_DATA();
    char scene[4096];
    const char *source = convert_autzen(scene, sizeof(scene));
    uint64_t want = 0, total = 0;
    sta_cloud_reader *cr = NULL;
    sta_error err = { 0 };
    assert_int_equal(sta_cloud_open(source, NULL, &cr, &err), STA_OK);
    sta_point_batch batch;
    assert_int_equal(sta_point_batch_init(&batch, 65536, 0, &err), STA_OK);
    for (;;) {
        assert_int_equal(sta_cloud_read(cr, &batch, &err), STA_OK);
        if (batch.count == 0) {
            break;
        }
        for (size_t i = 0; i < batch.count; i++) {
            const sta_point *p = &batch.points[i];
            want += p->classification == 2 && p->return_number == p->number_of_returns;
            total++;
        }
    }
    sta_point_batch_release(&batch);
    sta_cloud_close(cr);
    assert_true(want > 0 && want < total);

    sta_strata_reader *r = NULL;
    assert_int_equal(sta_strata_open(scene, NULL, &r, &err), STA_OK);
    sta_clip clip = { 0 };
    assert_int_equal(sta_clip_parse_classes(&clip, "2", &err), STA_OK);
    assert_int_equal(sta_clip_parse_returns(&clip, "last", &err), STA_OK);
    sta_strata_source src;
    sta_strata_source_init(&src, r, 0);
    src.clip = &clip;
    void *worker = NULL;
    assert_int_equal(src.source.worker_begin(src.source.context, &worker, &err), STA_OK);
    uint64_t got = 0;
    for (uint32_t n = 0; n < src.source.node_count; n++) {
        uint8_t *gpu = NULL;
        size_t count = 0;
        assert_int_equal(src.source.load(src.source.context, worker, n, &gpu, &count, &err),
                         STA_OK);
        assert_true((count == 0) == (gpu == NULL));
        got += count;
        sta_free(gpu);
    }
    src.source.worker_end(src.source.context, worker);
    assert_int_equal(got, want);
    sta_strata_close(r);
    unlink(scene);
}

// Frames until the streamer reports a complete cut (at most 2000); the last frame.
static sta_stream_frame run_until_complete(sta_streamer *s, const sta_camera *cam)
{
    sta_stream_frame f;
    sta_error err = { 0 };
    for (int i = 0; i < 2000; i++) {
        assert_int_equal(sta_streamer_update(s, cam, &f, &err), STA_OK);
        if (f.complete) {
            return f;
        }
        usleep(2000);
    }
    fail_msg("the streamer never completed its cut");
    return f;
}

/* Changing the clip at run time: every resident node is evicted with the next frame
 * and the cut is reloaded holding only the passing points. */
static void changing_the_clip_reloads_the_cut(void **state)
{
    (void)state;
    STA_TEST_REQUIRE_SHARED_DATA();
    char scene[4096];
    const char *source = convert_autzen(scene, sizeof(scene));
    uint64_t ground = 0;
    sta_cloud_reader *cr = NULL;
    sta_error err = { 0 };
    assert_int_equal(sta_cloud_open(source, NULL, &cr, &err), STA_OK);
    sta_point_batch batch;
    assert_int_equal(sta_point_batch_init(&batch, 65536, 0, &err), STA_OK);
    for (;;) {
        assert_int_equal(sta_cloud_read(cr, &batch, &err), STA_OK);
        if (batch.count == 0) {
            break;
        }
        for (size_t i = 0; i < batch.count; i++) {
            ground += batch.points[i].classification == 2;
        }
    }
    sta_point_batch_release(&batch);
    sta_cloud_close(cr);

    sta_streamer_options o = { .budget_points = 1000000, .loader_threads = 2 };
    sta_streamer *s = NULL;
    assert_int_equal(sta_streamer_open(scene, &o, &s, &err), STA_OK);
    const sta_strata_info *info = sta_strata_reader_info(sta_streamer_reader(s));
    sta_camera cam = overview(info);
    // A close look would not select every node: take a budget and view that do.
    cam.width_px = 4096;
    cam.height_px = 4096;
    sta_stream_frame f = run_until_complete(s, &cam);
    uint32_t resident = f.nodes_resident;
    assert_true(resident > 0);
    sta_clip clip = { 0 };
    assert_int_equal(sta_clip_parse_classes(&clip, "2", &err), STA_OK);
    assert_int_equal(sta_streamer_set_clip(s, &clip, &err), STA_OK);
    assert_int_equal(sta_streamer_update(s, &cam, &f, &err), STA_OK);
    assert_true(f.evict_count >= resident); // all of them, with this frame's own
    f = run_until_complete(s, &cam);
    assert_int_equal(f.points_selected, info->point_count); // the whole scene is in the cut
    assert_int_equal(f.points_drawn, ground);
    sta_streamer_close(s);
    unlink(scene);
}

static const struct CMUnitTest tests[] = {
    cmocka_unit_test(selection_skips_nodes_outside_the_box),
    cmocka_unit_test(loaded_nodes_hold_only_passing_points),
    cmocka_unit_test(changing_the_clip_reloads_the_cut),
};

STA_TEST_MAIN(tests)
