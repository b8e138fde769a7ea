/* SPDX-License-Identifier: MIT
 * The geometry pass's two rasterisers (compute shader and GL_POINTS) against the C twin
 * render/ref/raster_ref.h on small hand-made node sets, exactly: the id of the point
 * kept per pixel and its depth bits. Depth order, ties, points outside the frustum,
 * empty nodes, a node larger than one workgroup's batch, many points contending for a
 * few pixels, the arena after repacking;
 * both rasterisers on a converted scene through sta_scene; the choice of the atomics
 * path (the 32-bit fallback when 64-bit atomics are absent or switched off). Points
 * wider than a pixel (render/point_size.h), fixed and adaptive, the same way; the
 * footprint's shape and paraboloid depth on the twin. */
#include "scene_fixture.h"
#include "test_support.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/camera.h"
#include "render/bindings.h"
#include "render/gl.h"
#include "render/gpu_cache.h"
#include "render/pass_geometry.h"
#include "render/point_size.h"
#include "render/ref/raster_ref.h"
#include "render/scene.h"
#include "stream/gpu_points.h"

enum {
    W = 96,
    H = 64,
    MAX_NODES = 16
};

/* A node as the test builds it: corner relative to the camera (which sits at the
 * origin), step, points in the GPU layout. */
typedef struct test_node {
    double corner[3];
    double step;
    double spacing; /* metres, for the adaptive size */
    uint8_t *points;
    uint32_t count;
} test_node;

typedef struct test_set {
    test_node nodes[MAX_NODES];
    uint32_t node_count;
    uint32_t draw[MAX_NODES]; /* draw order (node ids) */
    uint32_t draw_count;
} test_set;

static uint32_t rng_state = 12345;
static uint8_t hide_flags;  /* GPU point flags not drawn (mirror ghosts), both sides */
static float clip_plane[4]; /* camera-relative clip plane (mirror pass), both sides */

static uint32_t rng(void)
{
    rng_state = rng_state * 1664525u + 1013904223u;
    return rng_state >> 8;
}

static void put_point(uint8_t *p, uint32_t qx, uint32_t qy, uint32_t qz, uint32_t colour)
{
    const uint32_t q[3] = { qx, qy, qz };
    memset(p, 0, STA_GPU_POINT_SIZE);
    for (int a = 0; a < 3; a++) {
        p[2 * a] = (uint8_t)(q[a] & 0xFF);
        p[2 * a + 1] = (uint8_t)(q[a] >> 8);
    }
    p[8] = (uint8_t)(colour & 0xFF);
    p[9] = (uint8_t)(colour >> 8);
    p[10] = (uint8_t)(colour >> 16);
    p[12] = p[13] = 1;
}

// A node of `count` random points in the box [corner, corner + extent * step).
static test_node *add_node(test_set *set, double x, double y, double z, uint32_t count,
                           uint32_t extent)
{
    assert_true(set->node_count < MAX_NODES);
    test_node *n = &set->nodes[set->node_count];
    n->corner[0] = x;
    n->corner[1] = y;
    n->corner[2] = z;
    n->step = 1.0 / 1024.0;
    n->count = count;
    n->points = calloc(count ? count : 1, STA_GPU_POINT_SIZE);
    assert_non_null(n->points);
    for (uint32_t i = 0; i < count; i++) {
        put_point(n->points + (size_t)i * STA_GPU_POINT_SIZE, rng() % extent, rng() % extent,
                  rng() % extent, rng() & 0xFFFFFF);
    }
    set->draw[set->draw_count++] = set->node_count;
    set->node_count++;
    return n;
}

static void free_set(test_set *set)
{
    for (uint32_t i = 0; i < set->node_count; i++) {
        free(set->nodes[i].points);
    }
}

static sta_camera test_camera(void)
{
    sta_camera c = { .position = { 0, 0, 0 },
                     .yaw = 0,
                     .pitch = 0,
                     .fov_y = 60.0 * M_PI / 180.0,
                     .near_m = 0.5,
                     .width_px = W,
                     .height_px = H };
    return c;
}

typedef struct raster_out {
    float depth[W * H];      /* GL order: rows from the bottom */
    uint32_t ids[2 * W * H]; /* GL order */
    size_t drawn;            /* pixels with a point */
} raster_out;

// The twin of rasteriser `method` (the compute one projects one-pixel points by node rows).
static void twin(const test_set *set, const sta_camera *camera, const sta_point_size *size,
                 int method, raster_out *out)
{
    sta_raster_ref_view view = { .width_px = W,
                                 .height_px = H,
                                 .hide_flags = hide_flags,
                                 .node_rows = method == STA_RASTER_COMPUTE };
    memcpy(view.clip_plane, clip_plane, sizeof(clip_plane));
    if (size) {
        sta_point_size_footprint(size, camera, &view.footprint);
    }
    sta_camera_view_rotation(camera, view.view);
    sta_camera_projection(camera, view.projection);
    glGetIntegerv(GL_SUBPIXEL_BITS, &view.subpixel_bits);
    sta_raster_ref_node nodes[MAX_NODES];
    for (uint32_t k = 0; k < set->draw_count; k++) {
        const test_node *n = &set->nodes[set->draw[k]];
        for (int a = 0; a < 3; a++) {
            nodes[k].origin[a] = (float)(n->corner[a] - camera->position[a]);
            nodes[k].step[a] = (float)n->step;
        }
        nodes[k].points = n->points;
        nodes[k].count = n->count;
        nodes[k].slot = set->draw[k];
        nodes[k].spacing = (float)n->spacing;
    }
    sta_raster_ref_draw(&view, nodes, set->draw_count, out->depth, out->ids);
    out->drawn = 0;
    for (int i = 0; i < W * H; i++) {
        out->drawn += out->ids[2 * i] != STA_TARGET_NO_POINT;
    }
}

// Uploads the set (node i = its index) into a fresh cache, in `upload_order` when given.
static void upload(sta_gpu_cache *cache, const test_set *set)
{
    sta_error err = { 0 };
    assert_int_equal(sta_gpu_cache_init(cache, set->node_count, &err), STA_OK);
    sta_stream_upload uploads[MAX_NODES];
    for (uint32_t i = 0; i < set->node_count; i++) {
        uploads[i] = (sta_stream_upload){ i, set->nodes[i].count, set->nodes[i].points };
    }
    sta_stream_frame frame = { .upload = uploads, .upload_count = set->node_count };
    assert_int_equal(sta_gpu_cache_apply(cache, &frame, &err), STA_OK);
}

static void frames_of(const test_set *set, sta_gpu_node_frame *frames)
{
    memset(frames, 0, sizeof(*frames) * MAX_NODES);
    for (uint32_t i = 0; i < set->node_count; i++) {
        for (int a = 0; a < 3; a++) {
            frames[i].corner[a] = set->nodes[i].corner[a];
            frames[i].step[a] = set->nodes[i].step;
        }
        frames[i].spacing = set->nodes[i].spacing;
    }
}

static void flip_rows(void *data, size_t row_bytes)
{
    uint8_t *bytes = data, row[2 * W * sizeof(uint32_t)];
    assert_true(row_bytes <= sizeof(row));
    for (int y = 0; y < H / 2; y++) {
        memcpy(row, bytes + y * row_bytes, row_bytes);
        memcpy(bytes + y * row_bytes, bytes + (H - 1 - y) * row_bytes, row_bytes);
        memcpy(bytes + (H - 1 - y) * row_bytes, row, row_bytes);
    }
}

static void gpu(const test_set *set, const sta_gpu_cache *cache, const sta_camera *camera,
                const sta_geometry_options *options, const sta_point_size *size, raster_out *out)
{
    sta_error err = { 0 };
    sta_pass_geometry pass;
    assert_int_equal(sta_pass_geometry_init(&pass, options, &err), STA_OK);
    sta_pass_geometry_set_point_size(&pass, size);
    sta_gpu_node_frame frames[MAX_NODES];
    frames_of(set, frames);
    sta_geometry_colours colours = { STA_COLOUR_RGB, 0, 1, 1.0f, NULL, hide_flags, { 0 } };
    memcpy(colours.clip_plane, clip_plane, sizeof(clip_plane));
    sta_render_target target = { 0 };
    assert_int_equal(sta_render_target_resize(&target, W, H, &err), STA_OK);
    if (sta_pass_geometry_draw(&pass, camera, &colours, cache, frames, set->draw, set->draw_count,
                               &target, &err) != STA_OK) {
        fail_msg("%s", err.message);
    }
    sta_render_target_read_depth(&target, out->depth);
    sta_render_target_read_ids(&target, out->ids);
    flip_rows(out->depth, W * sizeof(float));
    flip_rows(out->ids, 2 * W * sizeof(uint32_t));
    assert_int_equal(sta_gl_check("the geometry pass", &err), STA_OK);
    sta_render_target_release(&target);
    sta_pass_geometry_release(&pass);
    out->drawn = 0;
    for (int i = 0; i < W * H; i++) {
        out->drawn += out->ids[2 * i] != STA_TARGET_NO_POINT;
    }
}

// Both rasterisers equal the twin with points of `size` (NULL: one pixel), id for id
// and depth bit for bit; returns the pixels drawn.
static size_t check_set_sized(const test_set *set, const sta_point_size *size)
{
    sta_camera camera = test_camera();
    static raster_out expected, got;
    sta_gpu_cache cache;
    upload(&cache, set);
    const int methods[2] = { STA_RASTER_COMPUTE, STA_RASTER_POINTS };
    for (int m = 0; m < 2; m++) {
        twin(set, &camera, size, methods[m], &expected);
        sta_geometry_options options = { .raster = methods[m] };
        gpu(set, &cache, &camera, &options, size, &got);
        size_t id_differ = 0, depth_differ = 0;
        for (int i = 0; i < W * H; i++) {
            id_differ += memcmp(&expected.ids[2 * i], &got.ids[2 * i], 8) != 0;
            depth_differ += memcmp(&expected.depth[i], &got.depth[i], 4) != 0;
        }
        printf("%s: %zu pixels drawn (twin %zu), %zu ids and %zu depths differ\n",
               sta_raster_method_name(methods[m]), got.drawn, expected.drawn, id_differ,
               depth_differ);
        assert_int_equal(id_differ, 0);
        assert_int_equal(depth_differ, 0);
    }
    sta_gpu_cache_release(&cache);
    return expected.drawn;
}

static size_t check_set(const test_set *set)
{
    return check_set_sized(set, NULL);
}

static void twin_matches_on_random_nodes(void **state)
{
    (void)state;
    test_set set = { 0 };
    // Boxes 4 m wide between 3 m and 40 m ahead (+X), some overlapping on screen.
    for (int k = 0; k < 8; k++) {
        add_node(&set, 3.0 + 5.0 * k, -2.0 + 0.3 * k, -2.0 + 0.2 * k, 3000, 4096);
    }
    size_t drawn = check_set(&set);
    assert_true(drawn > W * H / 4);
    free_set(&set);
}

static sta_point_size fixed_size(double px)
{
    sta_point_size size;
    sta_point_size_defaults(&size);
    size.size_px = px;
    return size;
}

/* Mirror ghosts (flags byte bit 0) are not drawn by either rasteriser when hidden: the
 * points behind them show instead, as in the twin; shown, they are drawn again. */
static void flagged_points_are_hidden(void **state)
{
    (void)state;
    test_set set = { 0 };
    for (int k = 0; k < 6; k++) {
        test_node *n = add_node(&set, 3.0 + 4.0 * k, -2.0, -2.0 + 0.3 * k, 4000, 4096);
        for (uint32_t i = 0; i < n->count; i += 3) {
            n->points[(size_t)i * STA_GPU_POINT_SIZE + STA_GPU_POINT_FLAGS_BYTE] =
                STA_GPU_FLAG_MIRROR_GHOST;
        }
    }
    hide_flags = STA_GPU_FLAG_MIRROR_GHOST;
    size_t hidden = check_set(&set);
    sta_camera camera = test_camera();
    static raster_out out;
    twin(&set, &camera, NULL, STA_RASTER_COMPUTE, &out);
    for (int i = 0; i < W * H; i++) {
        if (out.ids[2 * i] != STA_TARGET_NO_POINT) {
            assert_true(out.ids[2 * i + 1] % 3 != 0); // never a flagged point
        }
    }
    sta_point_size wide = fixed_size(3.0); // the wide paths hide them too
    size_t hidden_wide = check_set_sized(&set, &wide);
    hide_flags = 0;
    size_t shown_wide = check_set_sized(&set, &wide);
    assert_true(shown_wide > hidden_wide);
    size_t shown = check_set(&set);
    printf("pixels drawn: %zu with ghosts hidden, %zu shown\n", hidden, shown);
    assert_true(hidden > W * H / 8 && shown > hidden);
    free_set(&set);
}

/* The mirror pass's clip plane: points on its negative side are not drawn, by either
 * rasteriser, as in the twin. */
static void clip_plane_cuts_like_the_twin(void **state)
{
    (void)state;
    test_set set = { 0 };
    for (int k = 0; k < 6; k++) {
        add_node(&set, 3.0 + 4.0 * k, -2.0, -2.0 + 0.3 * k, 4000, 4096);
    }
    size_t whole = check_set(&set);
    // Keep x + 0.25 y >= 12.3 (camera-relative): the nearer nodes go, partly or wholly.
    clip_plane[0] = 1.0f;
    clip_plane[1] = 0.25f;
    clip_plane[3] = -12.3f;
    size_t cut = check_set(&set);
    sta_point_size wide = fixed_size(3.0); // the wide paths cut by the plane too
    size_t cut_wide = check_set_sized(&set, &wide);
    memset(clip_plane, 0, sizeof(clip_plane));
    size_t whole_wide = check_set_sized(&set, &wide);
    assert_true(cut_wide > 100 && cut_wide < whole_wide);
    printf("pixels drawn: %zu whole, %zu behind the plane\n", whole, cut);
    assert_true(cut > 100 && cut < whole);
    free_set(&set);
}

static void nearest_point_wins_in_any_draw_order(void **state)
{
    (void)state;
    test_set set = { 0 };
    // A far wall drawn first, then a near one covering the middle: and the reverse.
    test_node *far = add_node(&set, 30.0, -20.0, -15.0, 0, 1);
    test_node *near = add_node(&set, 5.0, -1.0, -0.7, 0, 1);
    far->count = near->count = 128 * 96;
    far->points = realloc(far->points, (size_t)far->count * STA_GPU_POINT_SIZE);
    near->points = realloc(near->points, (size_t)near->count * STA_GPU_POINT_SIZE);
    assert_true(far->points && near->points);
    for (uint32_t i = 0; i < 128 * 96; i++) {
        uint32_t u = i % 128, v = i / 128;
        put_point(far->points + (size_t)i * STA_GPU_POINT_SIZE, 0, u * 320 + 7, v * 320 + 5,
                  0x0000FF);
        put_point(near->points + (size_t)i * STA_GPU_POINT_SIZE, 0, u * 16 + 3, v * 16 + 1,
                  0xFF0000);
    }
    size_t drawn = check_set(&set);
    set.draw[0] = 1;
    set.draw[1] = 0;
    assert_int_equal(check_set(&set), drawn);
    // The near node really hides part of the far one in the twin.
    sta_camera camera = test_camera();
    static raster_out out;
    twin(&set, &camera, NULL, STA_RASTER_COMPUTE, &out);
    size_t near_pixels = 0;
    for (int i = 0; i < W * H; i++) {
        near_pixels += out.ids[2 * i] == 1;
    }
    assert_true(near_pixels > 100 && near_pixels < drawn);
    free_set(&set);
}

static void equal_depths_keep_the_first_drawn(void **state)
{
    (void)state;
    test_set set = { 0 };
    // Three nodes with the same points (same corner, step): every pixel ties three ways,
    // and within each node some points repeat.
    for (int k = 0; k < 3; k++) {
        rng_state = 99;
        test_node *n = add_node(&set, 6.0, -2.0, -1.5, 2000, 4096);
        memcpy(n->points + 1000 * STA_GPU_POINT_SIZE, n->points, 1000 * STA_GPU_POINT_SIZE);
    }
    set.draw[0] = 2;
    set.draw[1] = 0;
    set.draw[2] = 1;
    check_set(&set);
    sta_camera camera = test_camera();
    static raster_out out;
    twin(&set, &camera, NULL, STA_RASTER_COMPUTE, &out);
    for (int i = 0; i < W * H; i++) {
        if (out.ids[2 * i] != STA_TARGET_NO_POINT) {
            assert_int_equal(out.ids[2 * i], 2);    // the first node drawn
            assert_true(out.ids[2 * i + 1] < 1000); // not the repeat in its second half
        }
    }
    free_set(&set);
}

// Many points, from many workgroups at once, into a few pixels: the atomics contend
// within SIMD groups and between threads, and most points tie in depth with others (a
// 6x6x6 grid of positions 1 mm apart, 20 m ahead), so many are payload candidates.
static void many_points_contend_for_few_pixels(void **state)
{
    (void)state;
    test_set set = { 0 };
    for (int k = 0; k < 8; k++) {
        add_node(&set, 20.0 + 0.002 * k, 0.001 * k, -0.001 * k, 20000, 6);
    }
    size_t drawn = check_set(&set);
    printf("%zu pixels drawn by %d points\n", drawn, 8 * 20000);
    assert_true(drawn >= 1 && drawn <= 16);
    free_set(&set);
}

static void points_outside_the_frustum_are_not_drawn(void **state)
{
    (void)state;
    test_set set = { 0 };
    add_node(&set, -20.0, -2.0, -2.0, 2000, 4096); // behind the camera
    add_node(&set, 0.1, -0.05, -0.05, 2000, 100);  // before the near plane (0.5 m)
    add_node(&set, 5.0, 30.0, -2.0, 2000, 4096);   // far to the left
    add_node(&set, 5.0, -40.0, -2.0, 2000, 4096);  // far to the right
    add_node(&set, 5.0, -2.0, 30.0, 2000, 4096);   // above
    add_node(&set, 5.0, -2.0, -40.0, 2000, 4096);  // below
    assert_int_equal(check_set(&set), 0);
    // One node straddling the left edge of the view: only part of it is drawn.
    add_node(&set, 4.0, 0.0, -1.0, 4000, 8192);
    size_t drawn = check_set(&set);
    assert_true(drawn > 50);
    free_set(&set);
}

static void empty_nodes_are_skipped(void **state)
{
    (void)state;
    test_set set = { 0 };
    add_node(&set, 4.0, -1.0, -1.0, 0, 1);
    add_node(&set, 5.0, -2.0, -1.0, 1500, 4096);
    add_node(&set, 4.0, -1.0, -1.0, 0, 1);
    add_node(&set, 4.0, -1.0, -1.0, 0, 1);
    add_node(&set, 7.0, -1.0, -2.0, 1500, 4096);
    add_node(&set, 4.0, -1.0, -1.0, 0, 1);
    assert_true(check_set(&set) > 500);
    free_set(&set);
}

static void node_larger_than_a_batch(void **state)
{
    (void)state;
    test_set set = { 0 };
    add_node(&set, 4.0, -1.0, -1.0, 100, 2048);
    add_node(&set, 5.0, -3.0, -2.0, 3 * STA_RASTER_BATCH_POINTS + 17, 6000);
    add_node(&set, 3.0, -1.0, -1.0, 100, 2048);
    size_t drawn = check_set(&set);
    assert_true(drawn > W * H / 4);
    // Points of the last batch of the big node are kept too.
    sta_camera camera = test_camera();
    static raster_out out;
    twin(&set, &camera, NULL, STA_RASTER_COMPUTE, &out);
    size_t last_batch = 0;
    for (int i = 0; i < W * H; i++) {
        last_batch += out.ids[2 * i] == 1 && out.ids[2 * i + 1] >= 3 * STA_RASTER_BATCH_POINTS;
    }
    assert_true(last_batch > 0);
    free_set(&set);
}

// Round 0 uploads every node of `set`; round 1 evicts nodes 1 and 3 and uploads them
// again: with six nodes of 20 000 points in a 65 536-point first arena this repacks.
static void apply_repack_round(sta_gpu_cache *cache, const test_set *set, int round)
{
    sta_error err = { 0 };
    sta_stream_upload uploads[MAX_NODES];
    size_t n = 0;
    for (uint32_t i = 0; i < set->node_count; i++) {
        if (round == 0 || i == 1 || i == 3) {
            uploads[n++] = (sta_stream_upload){ i, set->nodes[i].count, set->nodes[i].points };
        }
    }
    const uint32_t evicted[2] = { 1, 3 };
    sta_stream_frame frame = { .evict = round ? evicted : NULL,
                               .evict_count = round ? 2 : 0,
                               .upload = uploads,
                               .upload_count = n };
    assert_int_equal(sta_gpu_cache_apply(cache, &frame, &err), STA_OK);
}

static void arena_repack_keeps_every_node(void **state)
{
    (void)state;
    test_set set = { 0 };
    for (int k = 0; k < 6; k++) {
        add_node(&set, 4.0 + 3.0 * k, -2.0, -1.5, 20000, 4096);
    }
    sta_error err = { 0 };
    sta_gpu_cache cache;
    assert_int_equal(sta_gpu_cache_init(&cache, set.node_count, &err), STA_OK);
    // The holes of 1 and 3 go in the repack.
    apply_repack_round(&cache, &set, 0);
    apply_repack_round(&cache, &set, 1);
    assert_true(cache.compactions >= 1);
    assert_int_equal(cache.live, 6 * 20000);
    sta_camera camera = test_camera();
    static raster_out expected, got;
    twin(&set, &camera, NULL, STA_RASTER_COMPUTE, &expected);
    sta_geometry_options options = { .raster = STA_RASTER_COMPUTE };
    gpu(&set, &cache, &camera, &options, NULL, &got);
    assert_memory_equal(expected.ids, got.ids, sizeof(got.ids));
    sta_gpu_cache_release(&cache);
    free_set(&set);
}

// A repacked arena is a new buffer; the driver may give it the name of an arena deleted
// before (NVIDIA's does; Mesa's never reuses names), and the compute rasteriser's texture
// view must follow it anyway: a view that still held the deleted arena drew points at
// their old offsets (a garbled street on an H100, docs/BENCHMARKS.md). The reuse is
// simulated: after the repack the view's buffer name is set to the new arena's.
static void arena_view_follows_a_repack_under_a_reused_name(void **state)
{
    (void)state;
    test_set set = { 0 };
    for (int k = 0; k < 6; k++) {
        add_node(&set, 6.0, -6.0 + 2.0 * k, -1.0, 20000, 2048); // side by side: all seen
    }
    sta_error err = { 0 };
    sta_gpu_cache cache;
    assert_int_equal(sta_gpu_cache_init(&cache, set.node_count, &err), STA_OK);
    apply_repack_round(&cache, &set, 0);
    sta_geometry_options options = { .raster = STA_RASTER_COMPUTE, .force_32bit_atomics = true };
    sta_pass_geometry pass;
    assert_int_equal(sta_pass_geometry_init(&pass, &options, &err), STA_OK);
    sta_gpu_node_frame frames[MAX_NODES];
    frames_of(&set, frames);
    sta_geometry_colours colours = { STA_COLOUR_RGB, 0, 1, 1.0f, NULL, 0, { 0 } };
    sta_render_target target = { 0 };
    assert_int_equal(sta_render_target_resize(&target, W, H, &err), STA_OK);
    sta_camera camera = test_camera();
    assert_int_equal(sta_pass_geometry_draw(&pass, &camera, &colours, &cache, frames, set.draw,
                                            set.draw_count, &target, &err),
                     STA_OK);
    uint32_t generation = cache.generation;
    apply_repack_round(&cache, &set, 1);
    assert_true(cache.generation > generation);
    pass.compute.arena_viewed = cache.buffer; // as if the new arena had the old one's name
    assert_int_equal(sta_pass_geometry_draw(&pass, &camera, &colours, &cache, frames, set.draw,
                                            set.draw_count, &target, &err),
                     STA_OK);
    static raster_out expected, got;
    sta_render_target_read_ids(&target, got.ids);
    flip_rows(got.ids, 2 * W * sizeof(uint32_t));
    twin(&set, &camera, NULL, STA_RASTER_COMPUTE, &expected);
    assert_memory_equal(expected.ids, got.ids, sizeof(got.ids));
    sta_render_target_release(&target);
    sta_pass_geometry_release(&pass);
    sta_gpu_cache_release(&cache);
    free_set(&set);
}

static void fallback_without_64bit_atomics(void **state)
{
    (void)state;
    sta_geometry_choice c;
    sta_geometry_choose(NULL, false, &c);
    assert_int_equal(c.raster, STA_RASTER_COMPUTE); // the default
    assert_false(c.packed);
    assert_non_null(strstr(c.reason, "no 64-bit ones"));
    sta_geometry_choose(NULL, true, &c);
    assert_true(c.packed);
    sta_geometry_options forced = { .force_32bit_atomics = true };
    sta_geometry_choose(&forced, true, &c);
    assert_int_equal(c.raster, STA_RASTER_COMPUTE);
    assert_false(c.packed);
    sta_geometry_options points = { .raster = STA_RASTER_POINTS };
    sta_geometry_choose(&points, true, &c);
    assert_int_equal(c.raster, STA_RASTER_POINTS);
    assert_false(c.packed);
    assert_int_equal(sta_raster_method_from_name("compute"), STA_RASTER_COMPUTE);
    assert_int_equal(sta_raster_method_from_name("points"), STA_RASTER_POINTS);
    assert_int_equal(sta_raster_method_from_name("splat"), -1);
    // This driver: the pass takes the path the extension allows, and it draws.
    sta_error err = { 0 };
    sta_pass_geometry pass;
    assert_int_equal(sta_pass_geometry_init(&pass, NULL, &err), STA_OK);
    assert_int_equal(pass.choice.packed, sta_raster_int64_extensions() != NULL);
    printf("%s\n", pass.choice.reason);
    sta_pass_geometry_release(&pass);
}

// Renders a converted scene until loaded with one rasteriser.
static void render_scene(const char *path, int raster, uint8_t *rgba, uint32_t *ids)
{
    sta_scene *scene = NULL;
    sta_error err = { 0 };
    sta_scene_options options = { .loader_threads = 2 };
    assert_int_equal(sta_scene_open(path, &options, &scene, &err), STA_OK);
    sta_geometry_options raster_options = { .raster = raster };
    sta_scene_set_raster(scene, &raster_options);
    sta_scene_set_colour_mode(scene, STA_COLOUR_RGB);
    const double origin[3] = { 0, 0, 0 };
    sta_camera camera = sta_fixture_camera(origin, 320, 240);
    sta_render_target target = { 0 };
    sta_fixture_render_complete(scene, &camera, &target);
    assert_int_equal(sta_scene_raster_choice(scene)->raster, raster);
    sta_render_target_read_rgba(&target, rgba);
    sta_render_target_read_ids(&target, ids);
    sta_render_target_release(&target);
    sta_scene_close(scene);
}

static void both_rasterisers_render_a_scene_alike(void **state)
{
    (void)state;
    const double origin[3] = { 0, 0, 0 };
    char path[4096];
    sta_fixture_build_scene("raster", 30000, origin, path, sizeof(path));
    enum {
        PIXELS = 320 * 240
    };
    uint8_t *rgba[2] = { malloc(PIXELS * 4), malloc(PIXELS * 4) };
    uint32_t *ids[2] = { malloc(PIXELS * 8), malloc(PIXELS * 8) };
    assert_true(rgba[0] && rgba[1] && ids[0] && ids[1]);
    render_scene(path, STA_RASTER_POINTS, rgba[0], ids[0]);
    render_scene(path, STA_RASTER_COMPUTE, rgba[1], ids[1]);
    size_t covered = 0, differ = 0;
    for (int i = 0; i < PIXELS; i++) {
        covered += ids[0][2 * i] != STA_TARGET_NO_POINT;
        differ += memcmp(rgba[0] + 4 * i, rgba[1] + 4 * i, 4) != 0 ||
                  memcmp(ids[0] + 2 * i, ids[1] + 2 * i, 8) != 0;
    }
    printf("%zu covered pixels, %zu differ between GL_POINTS and compute\n", covered, differ);
    assert_true(covered > 5000);
    // Stated tolerance (docs/PIPELINE.md, "The compute rasteriser's pixel rule"): at most
    // 0.5 % of the covered pixels. The compute path projects by per-node rows rounded to
    // float, GL_POINTS by two matrix products: a point within a few 1e-7 of a sub-pixel
    // boundary may snap to the neighbouring pixel, or a near tie of depths flip (1 of
    // 13801 pixels here when written).
    assert_true(differ * 200 <= covered);
    for (int k = 0; k < 2; k++) {
        free(rgba[k]);
        free(ids[k]);
    }
}

static void wide_points_match_the_twin(void **state)
{
    (void)state;
    test_set set = { 0 };
    // Sparse nodes (so that disks overlap without hiding everything), one straddling the
    // left edge of the view: footprints are cut at the border, not dropped.
    for (int k = 0; k < 6; k++) {
        add_node(&set, 3.0 + 6.0 * k, -2.0 + 0.4 * k, -2.0 + 0.3 * k, 150, 4096);
    }
    add_node(&set, 4.0, 0.0, -1.0, 300, 8192);
    size_t one = check_set(&set), previous = one;
    const double sizes[] = { 2.0, 3.0, 5.5, 9.0 };
    for (size_t s = 0; s < sizeof(sizes) / sizeof(sizes[0]); s++) {
        sta_point_size size = fixed_size(sizes[s]);
        size_t drawn = check_set_sized(&set, &size);
        printf("%g px: %zu pixels drawn (1 px: %zu)\n", sizes[s], drawn, one);
        assert_true(drawn > previous); // larger points cover more
        previous = drawn;
    }
    free_set(&set);
}

static void adaptive_points_match_the_twin(void **state)
{
    (void)state;
    test_set set = { 0 };
    // The same spacing near and far: near points get larger disks than far ones, within
    // [min, max].
    add_node(&set, 3.0, -1.0, -1.0, 200, 2048)->spacing = 0.05;
    add_node(&set, 30.0, -8.0, -6.0, 200, 16384)->spacing = 0.05;
    add_node(&set, 8.0, -2.0, -2.0, 200, 4096)->spacing = 0.0; // no spacing: the minimum
    sta_point_size size;
    sta_point_size_defaults(&size);
    size.mode = STA_POINT_SIZE_ADAPTIVE;
    size.min_px = 1.5;
    size.max_px = 6.0;
    size_t adaptive = check_set_sized(&set, &size);
    size_t one = check_set(&set);
    printf("adaptive: %zu pixels drawn (1 px: %zu)\n", adaptive, one);
    assert_true(adaptive > one);
    free_set(&set);
}

// One point 10 m ahead on the axis in the twin: the pixels it covers with a diameter
// of 9 px form a disk (area near pi 4.5^2, symmetric), the nearest depth in the middle,
// the point's own depth at the rim.
static void wide_point_is_a_disk_with_a_paraboloid(void **state)
{
    (void)state;
    sta_camera camera = test_camera();
    sta_raster_ref_view view = { .width_px = W, .height_px = H, .subpixel_bits = 8 };
    sta_camera_view_rotation(&camera, view.view);
    sta_camera_projection(&camera, view.projection);
    sta_point_size size = fixed_size(9.0);
    sta_point_size_footprint(&size, &camera, &view.footprint);
    uint8_t point[STA_GPU_POINT_SIZE] = { 0 };
    put_point(point, 0, 0, 0, 0xFFFFFF);
    sta_raster_ref_node node = {
        .origin = { 10.0f, 0.0f, 0.0f }, .step = { 1.0f, 1.0f, 1.0f }, .points = point, .count = 1
    };
    static float depth[W * H];
    static uint32_t ids[2 * W * H];
    sta_raster_ref_draw(&view, &node, 1, depth, ids);
    float centre_depth = 0;
    long centre = sta_raster_ref_project(&view, node.origin, &centre_depth);
    assert_true(centre >= 0);
    int covered = 0, x0 = W, x1 = -1, y0 = H, y1 = -1;
    float nearest = 0, farthest = 1;
    for (int y = 0; y < H; y++) {
        for (int x = 0; x < W; x++) {
            float d = depth[x + y * W];
            if (d > 0) {
                covered++;
                x0 = x < x0 ? x : x0;
                x1 = x > x1 ? x : x1;
                y0 = y < y0 ? y : y0;
                y1 = y > y1 ? y : y1;
                nearest = fmaxf(nearest, d);
                farthest = fminf(farthest, d);
            }
        }
    }
    printf("9 px disk: %d pixels, x %d..%d, y %d..%d, depth %g..%g (centre %g)\n", covered, x0, x1,
           y0, y1, (double)farthest, (double)nearest, (double)centre_depth);
    // pi * 4.5^2 = 63.6; the point sits on a pixel corner, so pixel centres lie at
    // half-pixel offsets and the disk spans 8 of them (9 or 10 elsewhere).
    assert_in_range(covered, 57, 73);
    assert_in_range(x1 - x0 + 1, 8, 10);
    assert_in_range(y1 - y0 + 1, 8, 10);
    assert_int_equal(x1 - x0, y1 - y0);
    // The rim is the point's depth (within the sub-pixel distance of the outermost
    // pixel centre to the rim); the middle is nearer by the radius in metres: at 10 m
    // a 4.5 px radius is 10 * 4.5 * 2 tan(30 deg) / 64 = 0.81 m, depth = near / 9.19.
    assert_true(farthest >= centre_depth && farthest < centre_depth * 1.02f);
    float expected_middle = (float)(camera.near_m / (10.0 - 10.0 * 4.5 * 2.0 * tan(M_PI / 6) / H));
    assert_float_equal(depth[centre], expected_middle, expected_middle * 0.01f);
    assert_true(nearest == depth[centre]);
}

// The compute path's node rows against the GL_POINTS rule, in the twin alone, on random
// points of random nodes at 1920x1080 (a few metres to 200 m ahead, some off screen):
// the rows round once where GL_POINTS rounds after every product, so a point may move
// one pixel over, never more, in at most 0.1 % of the drawn points (the stated tolerance,
// docs/PIPELINE.md, is 0.5 % of the pixels), and its depth changes only in the last bits.
static void node_rows_stay_within_a_pixel_of_gl_points(void **state)
{
    (void)state;
    sta_camera camera = test_camera();
    camera.width_px = 1920;
    camera.height_px = 1080;
    camera.yaw = 0.3;
    camera.pitch = -0.1;
    sta_raster_ref_view points = { .width_px = 1920, .height_px = 1080, .subpixel_bits = 8 };
    sta_camera_view_rotation(&camera, points.view);
    sta_camera_projection(&camera, points.projection);
    sta_raster_ref_view rows_view = points;
    rows_view.node_rows = 1;
    rng_state = 7;
    size_t drawn = 0, moved = 0, border = 0, far_moves = 0;
    float worst_depth = 0.0f;
    for (int n = 0; n < 200; n++) {
        const float ahead = 3.0f + (float)(rng() % 197000) * 0.001f;
        float origin[3] = { ahead, -0.6f * ahead + (float)(rng() % 1000) * 0.0012f * ahead,
                            -0.4f * ahead + (float)(rng() % 1000) * 0.0008f * ahead };
        float step[3];
        for (int a = 0; a < 3; a++) {
            step[a] = (float)(1 + rng() % 50) * 1e-5f * ahead;
        }
        sta_raster_ref_rows rows;
        sta_raster_ref_node_rows(&rows_view, origin, step, &rows);
        for (int i = 0; i < 1000; i++) {
            float q[3], relative[3], d_points = 0.0f, d_rows = 0.0f;
            for (int a = 0; a < 3; a++) {
                q[a] = (float)(rng() % 65536);
                relative[a] = origin[a] + q[a] * step[a];
            }
            long a = sta_raster_ref_project(&points, relative, &d_points);
            long b = sta_raster_ref_project_rows(&rows_view, &rows, q, &d_rows);
            if (a < 0 && b < 0) {
                continue;
            }
            drawn++;
            if (a < 0 || b < 0) {
                border++; // one rule puts it just inside the view, the other just outside
                continue;
            }
            if (a != b) {
                moved++;
                long dx = a % 1920 - b % 1920, dy = a / 1920 - b / 1920;
                far_moves += dx < -1 || dx > 1 || dy < -1 || dy > 1;
            }
            worst_depth = fmaxf(worst_depth, fabsf(d_rows - d_points) / d_points);
        }
    }
    printf("%zu drawn, %zu in another pixel, %zu only by one rule (border), %zu moved by more "
           "than a pixel; worst relative depth difference %g\n",
           drawn, moved, border, far_moves, (double)worst_depth);
    assert_true(drawn > 50000);
    assert_true((moved + border) * 1000 <= drawn);
    assert_int_equal(far_moves, 0);
    assert_true(worst_depth < 1e-5f);
}

static const struct CMUnitTest tests[] = {
    cmocka_unit_test(node_rows_stay_within_a_pixel_of_gl_points),
    cmocka_unit_test_setup_teardown(twin_matches_on_random_nodes, sta_fixture_gl_setup,
                                    sta_fixture_gl_teardown),
    cmocka_unit_test_setup_teardown(flagged_points_are_hidden, sta_fixture_gl_setup,
                                    sta_fixture_gl_teardown),
    cmocka_unit_test_setup_teardown(clip_plane_cuts_like_the_twin, sta_fixture_gl_setup,
                                    sta_fixture_gl_teardown),
    cmocka_unit_test_setup_teardown(nearest_point_wins_in_any_draw_order, sta_fixture_gl_setup,
                                    sta_fixture_gl_teardown),
    cmocka_unit_test_setup_teardown(equal_depths_keep_the_first_drawn, sta_fixture_gl_setup,
                                    sta_fixture_gl_teardown),
    cmocka_unit_test_setup_teardown(many_points_contend_for_few_pixels, sta_fixture_gl_setup,
                                    sta_fixture_gl_teardown),
    cmocka_unit_test_setup_teardown(points_outside_the_frustum_are_not_drawn, sta_fixture_gl_setup,
                                    sta_fixture_gl_teardown),
    cmocka_unit_test_setup_teardown(empty_nodes_are_skipped, sta_fixture_gl_setup,
                                    sta_fixture_gl_teardown),
    cmocka_unit_test_setup_teardown(node_larger_than_a_batch, sta_fixture_gl_setup,
                                    sta_fixture_gl_teardown),
    cmocka_unit_test_setup_teardown(arena_view_follows_a_repack_under_a_reused_name,
                                    sta_fixture_gl_setup, sta_fixture_gl_teardown),
    cmocka_unit_test_setup_teardown(arena_repack_keeps_every_node, sta_fixture_gl_setup,
                                    sta_fixture_gl_teardown),
    cmocka_unit_test_setup_teardown(fallback_without_64bit_atomics, sta_fixture_gl_setup,
                                    sta_fixture_gl_teardown),
    cmocka_unit_test_setup_teardown(both_rasterisers_render_a_scene_alike, sta_fixture_gl_setup,
                                    sta_fixture_gl_teardown),
    cmocka_unit_test_setup_teardown(wide_points_match_the_twin, sta_fixture_gl_setup,
                                    sta_fixture_gl_teardown),
    cmocka_unit_test_setup_teardown(adaptive_points_match_the_twin, sta_fixture_gl_setup,
                                    sta_fixture_gl_teardown),
    cmocka_unit_test(wide_point_is_a_disk_with_a_paraboloid),
};

STA_TEST_MAIN(tests)
