/* SPDX-License-Identifier: MIT
 * Which pixels and points strata-bench's truth metrics score (bench/pixel_masks.h,
 * issue 15, fourteenth round): the true surfaces of volumetric classes left out of the
 * fill metrics, the face rule (a point on the pixel's own true face) and the HPR rules
 * (an occluder no point samples; a room behind window glass), on hand-made views. */
#include <math.h>
#include <stdbool.h>
#include <string.h>

#include "bench/pixel_masks.h"
#include "bench/view_eval.h"
#include "render/ref/screen_space.h"
#include "test_support.h"

enum {
    W = 8,
    H = 8,
    N = W * H
};

typedef struct hand_view {
    float depth[N], glass[N], normal[3 * N];
    uint8_t classification[N];
    sta_view_truth truth;
    sta_camera camera;
    uint32_t pixel[N];
    double world[N][3];
    uint8_t visible[N];
    sta_view_points points;
} hand_view;

// Every pixel's ray hits a surface at 10 m facing the camera (class 6); no glass.
static void hand_view_init(hand_view *v)
{
    memset(v, 0, sizeof(*v));
    for (int i = 0; i < N; i++) {
        v->depth[i] = v->glass[i] = 10.0f;
        v->normal[3 * i + 2] = 1.0f;
        v->classification[i] = 6;
    }
    v->truth = (sta_view_truth){ .width = W,
                                 .height = H,
                                 .depth_m = v->depth,
                                 .normal = v->normal,
                                 .glass_depth_m = v->glass,
                                 .classification = v->classification };
    v->camera =
        (sta_camera){ .fov_y = 60.0 * M_PI / 180.0, .near_m = 0.1, .width_px = W, .height_px = H };
    v->points = (sta_view_points){ .pixel = v->pixel, .world = v->world, .visible = v->visible };
}

// A drawn point on pixel (x, y)'s ray at `depth` along the view axis.
static void add_point(hand_view *v, int x, int y, double depth, bool visible)
{
    double dir[3], cosine;
    sta_bench_pixel_ray(&v->camera, x, y, dir, &cosine);
    size_t k = v->points.count++;
    for (int a = 0; a < 3; a++) {
        v->world[k][a] = v->camera.position[a] + dir[a] * (depth / cosine);
    }
    v->pixel[k] = (uint32_t)(y * W + x);
    v->visible[k] = visible;
}

static void volumetric_truth_is_left_out_of_the_fill(void **state)
{
    (void)state;
    hand_view v;
    hand_view_init(&v);
    v.classification[1] = 5; // high vegetation
    v.classification[2] = 3; // low vegetation
    v.classification[3] = 5;
    v.depth[3] = NAN; // a miss is never left out
    uint32_t set[1] = { (1u << 3) | (1u << 4) | (1u << 5) };
    uint8_t counted[N], sampled[N];
    memset(sampled, 1, sizeof(sampled));
    assert_int_equal(sta_view_truth_leave_out_classes(&v.truth, set, 1, counted, sampled), 2);
    for (int i = 0; i < N; i++) {
        bool out = i == 1 || i == 2;
        assert_int_equal(counted[i], !out);
        assert_int_equal(sampled[i], !out);
    }
    // A class beyond the set's words, or no classification: nothing left out.
    v.classification[1] = 200;
    assert_int_equal(sta_view_truth_leave_out_classes(&v.truth, set, 1, counted, NULL), 1);
    v.truth.classification = NULL;
    assert_int_equal(sta_view_truth_leave_out_classes(&v.truth, set, 1, counted, NULL), 0);
    assert_int_equal(counted[1], 1);
}

// Columns 0-3 face the camera, 4-7 face sideways (a window reveal, a car's back seen
// edge-on by the scanner); points lie only on columns 0-3. Within a 2 m radius (the
// columns are 1.44 m apart at 10 m), column 4 is sampled by column 3's points but its
// face is not; a point off its own pixel's surface samples no face.
static void face_rule_needs_a_point_on_the_face(void **state)
{
    (void)state;
    hand_view v;
    hand_view_init(&v);
    for (int y = 0; y < H; y++) {
        for (int x = 4; x < W; x++) {
            float *n = v.normal + 3 * (y * W + x);
            n[0] = 1.0f;
            n[2] = 0.0f;
        }
        for (int x = 0; x < 4; x++) {
            add_point(&v, x, y, 10.0, true);
        }
    }
    uint8_t sampled[N], face[N];
    sta_error err = { 0 };
    assert_int_equal(sta_view_truth_sampled(&v.truth, &v.camera, &v.points, 2.0, sampled, &err),
                     STA_OK);
    assert_int_equal(sta_view_truth_face_sampled(&v.truth, &v.camera, &v.points, 2.0, face, &err),
                     STA_OK);
    for (int y = 0; y < H; y++) {
        for (int x = 0; x < W; x++) {
            assert_int_equal(sampled[y * W + x], x <= 4);
            assert_int_equal(face[y * W + x], x <= 3);
        }
    }
    // Column 3's rays now pass to a wall at 30 m, and its points float at 10.3 m: within
    // the radius of column 2's hits (so column 2 is "sampled"), but on no pixel's true
    // surface, so no face is sampled.
    hand_view_init(&v);
    for (int y = 0; y < H; y++) {
        v.depth[y * W + 3] = 30.0f;
        add_point(&v, 3, y, 10.3, false);
    }
    assert_int_equal(sta_view_truth_sampled(&v.truth, &v.camera, &v.points, 2.0, sampled, &err),
                     STA_OK);
    assert_int_equal(sta_view_truth_face_sampled(&v.truth, &v.camera, &v.points, 2.0, face, &err),
                     STA_OK);
    for (int i = 0; i < N; i++) {
        assert_int_equal(sampled[i], i % W == 2 || i % W == 4);
        assert_int_equal(face[i], 0);
    }
}

// Row 4: a visible point (column 0, labelled visible: tp); a truly hidden point behind
// an unsampled surface (column 2, labelled visible: fp, left out by the face rule); a
// hidden point behind a sampled one (column 5, hidden: tn); a visible point (column 6:
// tp); a room point behind window glass (column 7, labelled hidden: fn, left out by the
// glass rule). Column 1 is a volumetric class: left out of the fill's masks only.
static void hpr_rules_leave_out_what_the_data_cannot_show(void **state)
{
    (void)state;
    hand_view v;
    hand_view_init(&v);
    const int y = 4;
    v.glass[y * W + 7] = 5.0f;
    v.classification[y * W + 1] = 5;
    add_point(&v, 0, y, 10.0, true);
    add_point(&v, 2, y, 20.0, false);
    add_point(&v, 5, y, 20.0, false);
    add_point(&v, 6, y, 10.0, true);
    add_point(&v, 7, y, 10.0, true);
    uint32_t set[1] = { 1u << 5 };
    sta_pixel_masks m;
    sta_error err = { 0 };
    assert_int_equal(sta_pixel_masks_compute(&v.truth, &v.camera, &v.points, 2.0, set, 1, &m, &err),
                     STA_OK);
    assert_int_equal(m.left_out, 1);
    assert_int_equal(m.counted[y * W + 1], 0);
    assert_int_equal(m.sampled_counted[y * W + 1], 0);
    assert_int_equal(m.sampled[y * W + 1], 1); // column 0's point is 1.44 m away
    assert_int_equal(m.face_counted[y * W + 1], 0);
    assert_int_equal(m.hpr_face[y * W + 2], 0);
    assert_int_equal(m.hpr_face[y * W + 5], 1);
    assert_int_equal(m.hpr_face[y * W + 7], 1);
    assert_int_equal(m.hpr_face_glass[y * W + 7], 0);
    assert_int_equal(m.hpr_face_glass[y * W + 0], 1);
    sta_image label = { 0 };
    assert_int_equal(sta_image_init(&label, W, H, 1, &err), STA_OK);
    const float labels[W] = {
        STA_LABEL_VISIBLE, 0, STA_LABEL_VISIBLE, 0, 0, STA_LABEL_HIDDEN, STA_LABEL_VISIBLE,
        STA_LABEL_HIDDEN
    };
    memcpy(sta_image_at(&label, 0, y), labels, sizeof(labels));
    sta_confusion raw, face, glass;
    sta_eval_hpr_masked(&v.points, &label, NULL, &raw);
    sta_eval_hpr_masked(&v.points, &label, m.hpr_face, &face);
    sta_eval_hpr_masked(&v.points, &label, m.hpr_face_glass, &glass);
    assert_true(raw.tp == 2 && raw.fp == 1 && raw.fn == 1 && raw.tn == 1);
    assert_true(face.tp == 2 && face.fp == 0 && face.fn == 1 && face.tn == 1);
    assert_true(glass.tp == 2 && glass.fp == 0 && glass.fn == 0 && glass.tn == 1);
    // Without a class set every pixel counts for the fill.
    sta_pixel_masks_release(&m);
    assert_int_equal(
        sta_pixel_masks_compute(&v.truth, &v.camera, &v.points, 2.0, NULL, 1, &m, &err), STA_OK);
    assert_null(m.counted);
    assert_int_equal(m.left_out, 0);
    assert_int_equal(m.face_counted[y * W + 0], 1);
    sta_pixel_masks_release(&m);
    sta_image_release(&label);
}

// Row 3: a visible point on the wall (column 0, labelled visible: tp); a point behind a
// crown (column 1, class 5: truly hidden, labelled visible: fp, left out by the volumetric
// rule); a crown's own point (column 2, truly visible, labelled hidden: fn, kept: visible
// points are always scored); a point behind the wall (column 5, class 6: truly hidden,
// labelled visible: fp, kept).
static void volumetric_rule_leaves_out_points_hidden_by_vegetation(void **state)
{
    (void)state;
    hand_view v;
    hand_view_init(&v);
    const int y = 3;
    v.classification[y * W + 1] = 5;
    v.classification[y * W + 2] = 5;
    add_point(&v, 0, y, 10.0, true);
    add_point(&v, 1, y, 20.0, false);
    add_point(&v, 2, y, 10.0, true);
    add_point(&v, 5, y, 20.0, false);
    uint32_t set[1] = { (1u << 3) | (1u << 4) | (1u << 5) };
    sta_pixel_masks m;
    sta_error err = { 0 };
    assert_int_equal(sta_pixel_masks_compute(&v.truth, &v.camera, &v.points, 2.0, set, 1, &m, &err),
                     STA_OK);
    assert_non_null(m.hpr_volumetric);
    for (int x = 0; x < W; x++) {
        assert_int_equal(m.hpr_volumetric[y * W + x], x != 1);
    }
    sta_image label = { 0 };
    assert_int_equal(sta_image_init(&label, W, H, 1, &err), STA_OK);
    const float labels[W] = {
        STA_LABEL_VISIBLE, STA_LABEL_VISIBLE, STA_LABEL_HIDDEN, 0, 0, STA_LABEL_VISIBLE, 0, 0
    };
    memcpy(sta_image_at(&label, 0, y), labels, sizeof(labels));
    sta_confusion raw, ruled;
    sta_eval_hpr_masked(&v.points, &label, NULL, &raw);
    sta_eval_hpr_masked(&v.points, &label, m.hpr_volumetric, &ruled);
    assert_true(raw.tp == 1 && raw.fp == 2 && raw.fn == 1 && raw.tn == 0);
    assert_true(ruled.tp == 1 && ruled.fp == 1 && ruled.fn == 1 && ruled.tn == 0);
    // Without classes (--fill-every-class) every point is scored.
    sta_pixel_masks_release(&m);
    assert_int_equal(
        sta_pixel_masks_compute(&v.truth, &v.camera, &v.points, 2.0, NULL, 1, &m, &err), STA_OK);
    assert_null(m.hpr_volumetric);
    sta_pixel_masks_release(&m);
    sta_image_release(&label);
}

static const struct CMUnitTest tests[] = {
    cmocka_unit_test(volumetric_rule_leaves_out_points_hidden_by_vegetation),
    cmocka_unit_test(volumetric_truth_is_left_out_of_the_fill),
    cmocka_unit_test(face_rule_needs_a_point_on_the_face),
    cmocka_unit_test(hpr_rules_leave_out_what_the_data_cannot_show),
};

STA_TEST_MAIN(tests)
