/* SPDX-License-Identifier: MIT
 * The splat pass (render/pass_splats.h), both ways of drawing (instanced quads and the
 * geometry shader), against the C twin render/ref/splat_ref.h on small hand-made sets
 * with analytic normals: ids, depth and shaded colour per pixel; disks crossing each
 * other cut along their intersection (per-fragment depth); a sphere of splats closes
 * without holes where the same points at a third of the radius do not; the runtime
 * scale; the smallest on-screen size; splats kept beside their points when the arena
 * is repacked. */
#include "scene_fixture.h"
#include "test_support.h"

#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "convert.h"
#include "core/camera.h"
#include "render/bindings.h"
#include "render/gl.h"
#include "render/gpu_cache.h"
#include "render/pass_splats.h"
#include "render/ref/shade_ref.h"
#include "render/ref/splat_ref.h"
#include "render/scene.h"
#include "render/splat_normals.h"
#include "stream/gpu_points.h"
#include "stream/gpu_splats.h"

enum {
    W = 96,
    H = 64,
    MAX_POINTS = 80000
};
#define STEP_M (1.0 / 1024.0)

/* One node of splats: points (GPU layout) followed by their splat records, as a node
 * source hands them over; the camera sits at the origin looking along +X. */
typedef struct splat_node {
    double corner[3];
    uint32_t count;
    uint8_t *bytes; /* count * 16 bytes of points, then count * 8 of splats */
    float (*normals)[3];
    float *radii;
    float (*colours)[3];
} splat_node;

static void node_init(splat_node *n, double x, double y, double z)
{
    memset(n, 0, sizeof(*n));
    n->corner[0] = x, n->corner[1] = y, n->corner[2] = z;
    n->bytes = calloc(MAX_POINTS, STA_GPU_POINT_SIZE + STA_GPU_SPLAT_SIZE);
    n->normals = calloc(MAX_POINTS, sizeof(*n->normals));
    n->radii = calloc(MAX_POINTS, sizeof(*n->radii));
    n->colours = calloc(MAX_POINTS, sizeof(*n->colours));
    assert_true(n->bytes && n->normals && n->radii && n->colours);
}

static void node_free(splat_node *n)
{
    free(n->bytes);
    free(n->normals);
    free(n->radii);
    free(n->colours);
}

// Adds a splat at world position p (metres, camera at the origin), on the node's lattice.
static void add_splat(splat_node *n, const double p[3], const double normal[3], double radius,
                      uint32_t rgb)
{
    assert_true(n->count < MAX_POINTS);
    uint8_t *r = n->bytes + (size_t)n->count * STA_GPU_POINT_SIZE;
    for (int a = 0; a < 3; a++) {
        long q = lround((p[a] - n->corner[a]) / STEP_M);
        assert_true(q >= 0 && q <= 65535);
        r[2 * a] = (uint8_t)(q & 0xFF);
        r[2 * a + 1] = (uint8_t)(q >> 8);
        n->normals[n->count][a] = (float)normal[a];
    }
    r[8] = (uint8_t)(rgb >> 16);
    r[9] = (uint8_t)(rgb >> 8);
    r[10] = (uint8_t)rgb;
    r[12] = r[13] = 1;
    n->radii[n->count] = (float)radius;
    for (int c = 0; c < 3; c++) {
        n->colours[n->count][c] = (float)r[8 + c] / 255.0f;
    }
    n->count++;
}

// Moves the splat records right after the points, as the node source lays them out.
static void node_finish(splat_node *n)
{
    sta_gpu_splats_encode((const float(*)[3])n->normals, n->radii, n->count,
                          n->bytes + (size_t)n->count * STA_GPU_POINT_SIZE);
}

static sta_camera test_camera(void)
{
    sta_camera c = { .fov_y = 60.0 * M_PI / 180.0, .near_m = 0.5, .width_px = W, .height_px = H };
    return c;
}

typedef struct splat_out {
    float depth[W * H];      /* GL order: rows from the bottom */
    uint32_t ids[2 * W * H]; /* GL order */
    float rgb[3 * W * H];    /* 0..1 */
    size_t drawn;
} splat_out;

static size_t count_drawn(const splat_out *out)
{
    size_t drawn = 0;
    for (int i = 0; i < W * H; i++) {
        drawn += out->ids[2 * i] != STA_TARGET_NO_POINT;
    }
    return drawn;
}

static unsigned hide_flags; /* GPU point flags not drawn (mirror ghosts), both sides */

static void twin(const splat_node *n, uint32_t slot, const sta_splat_options *options,
                 splat_out *out)
{
    sta_camera camera = test_camera();
    sta_splat_options o = *options;
    sta_splat_options_defaults(&o);
    sta_splat_ref_params p = { .width_px = W,
                               .height_px = H,
                               .scale = o.scale,
                               .default_radius_m = 0.05f,
                               .min_radius_px = o.min_radius_px,
                               .light = { STA_SHADE_DEFAULT_AMBIENT, STA_SHADE_DEFAULT_DIFFUSE,
                                          STA_SHADE_DEFAULT_SPECULAR, STA_SHADE_DEFAULT_SHININESS },
                               .lit = !o.unlit };
    sta_camera_view_rotation(&camera, p.view);
    sta_camera_projection(&camera, p.projection);
    sta_splat_ref_point *points = calloc(n->count ? n->count : 1, sizeof(*points));
    assert_non_null(points);
    size_t kept = 0;
    for (uint32_t i = 0; i < n->count; i++) {
        const uint8_t *r = n->bytes + (size_t)i * STA_GPU_POINT_SIZE;
        if (r[STA_GPU_POINT_FLAGS_BYTE] & hide_flags) {
            continue; // the twin is given only the points the pass may draw
        }
        sta_splat_ref_point *pt = &points[kept++];
        float radius;
        for (int a = 0; a < 3; a++) {
            unsigned q = (unsigned)r[2 * a] | (unsigned)r[2 * a + 1] << 8;
            pt->relative[a] = (float)(n->corner[a] + q * STEP_M);
            pt->colour[a] = n->colours[i][a];
        }
        // The normal and radius as the GPU sees them: through the record.
        sta_gpu_splat_decode(n->bytes + (size_t)n->count * STA_GPU_POINT_SIZE +
                                 (size_t)i * STA_GPU_SPLAT_SIZE,
                             pt->normal, &radius);
        pt->radius = radius;
        pt->id[0] = slot;
        pt->id[1] = i;
    }
    sta_splat_ref_draw(&p, points, kept, out->depth, out->ids, out->rgb);
    free(points);
    out->drawn = count_drawn(out);
}

static void upload(sta_gpu_cache *cache, const splat_node *n)
{
    sta_error err = { 0 };
    assert_int_equal(sta_gpu_cache_init(cache, 1, &err), STA_OK);
    sta_gpu_cache_enable_splats(cache);
    sta_stream_upload u = { 0, n->count, n->bytes };
    sta_stream_frame frame = { .upload = &u, .upload_count = 1 };
    assert_int_equal(sta_gpu_cache_apply(cache, &frame, &err), STA_OK);
    assert_true(cache->splat_buffer != 0);
}

static void flip_rows(void *data, size_t row_bytes)
{
    uint8_t *bytes = data, row[3 * W * sizeof(float)];
    assert_true(row_bytes <= sizeof(row));
    for (int y = 0; y < H / 2; y++) {
        memcpy(row, bytes + y * row_bytes, row_bytes);
        memcpy(bytes + y * row_bytes, bytes + (H - 1 - y) * row_bytes, row_bytes);
        memcpy(bytes + (H - 1 - y) * row_bytes, row, row_bytes);
    }
}

// Draws nodes `draw` of `cache` (frames from `nodes`, indexed by slot) with `options`.
// Draws with `pass` (built for options->method) into `out`.
static void gpu_with(sta_pass_splats *pass, const sta_gpu_cache *cache, const splat_node *nodes,
                     const uint32_t *draw, size_t draw_count, const sta_splat_options *options,
                     splat_out *out)
{
    sta_error err = { 0 };
    sta_gpu_node_frame frames[4];
    memset(frames, 0, sizeof(frames));
    for (uint32_t i = 0; i < cache->node_count && i < 4; i++) {
        for (int a = 0; a < 3; a++) {
            frames[i].corner[a] = nodes[i].corner[a];
            frames[i].step[a] = STEP_M;
        }
    }
    sta_camera camera = test_camera();
    sta_geometry_colours colours = { .mode = STA_COLOUR_RGB,
                                     .elevation_span = 1,
                                     .intensity_scale = 1.0f,
                                     .hide_flags = hide_flags };
    sta_render_target target = { 0 };
    assert_int_equal(sta_render_target_resize(&target, W, H, &err), STA_OK);
    if (sta_pass_splats_draw(pass, options, &camera, &colours, cache, frames, draw, draw_count,
                             0.05f, &target, &err) != STA_OK) {
        fail_msg("%s", err.message);
    }
    static uint8_t rgba[4 * W * H];
    sta_render_target_read_depth(&target, out->depth);
    sta_render_target_read_ids(&target, out->ids);
    sta_render_target_read_rgba(&target, rgba);
    flip_rows(out->depth, W * sizeof(float));
    flip_rows(out->ids, 2 * W * sizeof(uint32_t));
    for (int y = 0; y < H; y++) { // rgba is top row first
        for (int x = 0; x < W; x++) {
            for (int c = 0; c < 3; c++) {
                out->rgb[3 * ((H - 1 - y) * W + x) + c] = rgba[4 * (y * W + x) + c] / 255.0f;
            }
        }
    }
    sta_render_target_release(&target);
    out->drawn = count_drawn(out);
}

static void gpu(const sta_gpu_cache *cache, const splat_node *nodes, const uint32_t *draw,
                size_t draw_count, const sta_splat_options *options, splat_out *out)
{
    sta_error err = { 0 };
    sta_pass_splats pass;
    if (sta_pass_splats_init(&pass, options->method, &err) != STA_OK) {
        fail_msg("%s", err.message);
    }
    gpu_with(&pass, cache, nodes, draw, draw_count, options, out);
    sta_pass_splats_release(&pass);
}

// The GPU equals the twin up to rounding at disk rims: ids differ on at most
// `max_rim_fraction` of the drawn pixels; where the ids agree depth agrees to 1e-5
// (relative) and colour to 2/255. Returns the pixels drawn.
static size_t check_against_twin(const splat_node *n, const sta_splat_options *options,
                                 double max_rim_fraction)
{
    static splat_out expected, got;
    twin(n, 0, options, &expected);
    sta_gpu_cache cache;
    upload(&cache, n);
    const uint32_t draw[1] = { 0 };
    gpu(&cache, n, draw, 1, options, &got);
    size_t id_differ = 0, depth_differ = 0, colour_differ = 0;
    for (int i = 0; i < W * H; i++) {
        if (memcmp(&expected.ids[2 * i], &got.ids[2 * i], 8) != 0) {
            id_differ++;
            continue;
        }
        if (fabsf(expected.depth[i] - got.depth[i]) > 1e-5f * expected.depth[i]) {
            depth_differ++;
        }
        for (int c = 0; c < 3; c++) {
            if (fabsf(expected.rgb[3 * i + c] - got.rgb[3 * i + c]) > 2.0f / 255.0f) {
                colour_differ++;
                break;
            }
        }
    }
    printf("%s: %zu pixels drawn (twin %zu), %zu ids, %zu depths, %zu colours differ\n",
           sta_splat_method_name(options->method), got.drawn, expected.drawn, id_differ,
           depth_differ, colour_differ);
    assert_true(expected.drawn > 0);
    assert_true((double)id_differ <= max_rim_fraction * (double)expected.drawn);
    assert_int_equal(depth_differ, 0);
    assert_int_equal(colour_differ, 0);
    sta_gpu_cache_release(&cache);
    return got.drawn;
}

static const int methods[3] = { STA_SPLAT_INSTANCED, STA_SPLAT_GEOMETRY, STA_SPLAT_PULLED };

// Seven large disks at different depths and tilts, overlapping on screen.
static void twin_matches_overlapping_disks(void **state)
{
    (void)state;
    splat_node n;
    node_init(&n, 2.0, -10.0, -10.0);
    for (int k = 0; k < 7; k++) {
        double tilt = 0.3 * (k - 3);
        double p[3] = { 6.0 + 1.5 * k, -2.4 + 0.8 * k, -1.0 + 0.3 * (k % 3) };
        double normal[3] = { -cos(tilt), sin(tilt) * 0.6, sin(tilt) * 0.8 };
        add_splat(&n, p, normal, 1.5 + 0.1 * k, 0x204080u + 0x181008u * (uint32_t)k);
    }
    node_finish(&n);
    for (int m = 0; m < 3; m++) {
        sta_splat_options o = { .method = methods[m] };
        size_t drawn = check_against_twin(&n, &o, 0.02);
        assert_true(drawn > W * H / 8);
    }
    node_free(&n);
}

// Two disks with the same centre, turned +-40 degrees about the vertical: each is the
// nearer on one side of the centre, so each must win there. Fat points (one depth per
// splat) would show one disk everywhere.
static void crossing_disks_cut_each_other(void **state)
{
    (void)state;
    splat_node n;
    node_init(&n, 2.0, -10.0, -10.0);
    const double centre[3] = { 8.0, 0.0, 0.0 }, a = 40.0 * M_PI / 180.0;
    const double left[3] = { -cos(a), sin(a), 0.0 }, right[3] = { -cos(a), -sin(a), 0.0 };
    add_splat(&n, centre, left, 2.0, 0xFF0000u);
    add_splat(&n, centre, right, 2.0, 0x0000FFu);
    node_finish(&n);
    for (int m = 0; m < 3; m++) {
        sta_splat_options o = { .method = methods[m] };
        check_against_twin(&n, &o, 0.02);
        static splat_out got;
        sta_gpu_cache cache;
        upload(&cache, &n);
        const uint32_t draw[1] = { 0 };
        gpu(&cache, &n, draw, 1, &o, &got);
        // Middle row: to the left of the centre column one disk, to the right the other
        // (+Y is left in this view).
        int y = H / 2;
        uint32_t left_id = got.ids[2 * (y * W + W / 2 - 8) + 1];
        uint32_t right_id = got.ids[2 * (y * W + W / 2 + 8) + 1];
        assert_true(left_id <= 1 && right_id <= 1);
        assert_int_not_equal(left_id, right_id);
        sta_gpu_cache_release(&cache);
    }
    node_free(&n);
}

// A sphere of radius 3 m, 12 m ahead, splats on a Fibonacci lattice with analytic
// normals and the lattice spacing as radius.
static void sphere(splat_node *n, int count)
{
    node_init(n, 2.0, -10.0, -10.0);
    const double centre[3] = { 12.0, 0.0, 0.0 }, radius = 3.0;
    double spacing = radius * sqrt(4.0 * M_PI / count);
    for (int i = 0; i < count; i++) {
        double z = 1.0 - (2.0 * i + 1.0) / count, r = sqrt(1.0 - z * z);
        double phi = i * M_PI * (3.0 - sqrt(5.0));
        double normal[3] = { r * cos(phi), r * sin(phi), z };
        double p[3];
        for (int a = 0; a < 3; a++) {
            p[a] = centre[a] + radius * normal[a];
        }
        add_splat(n, p, normal, spacing, 0xC0C0C0u);
    }
    node_finish(n);
}

// Pixels inside the sphere's silhouette (shrunk by two pixels) left empty.
static size_t holes(const splat_out *out)
{
    sta_camera camera = test_camera();
    double f = 1.0 / tan(camera.fov_y / 2), angle = asin(3.0 / 12.0);
    double silhouette_px = tan(angle) * f * H / 2 - 2.0;
    size_t empty = 0;
    for (int y = 0; y < H; y++) {
        for (int x = 0; x < W; x++) {
            double dx = x + 0.5 - W / 2.0, dy = y + 0.5 - H / 2.0;
            if (dx * dx + dy * dy < silhouette_px * silhouette_px &&
                out->ids[2 * (y * W + x)] == STA_TARGET_NO_POINT) {
                empty++;
            }
        }
    }
    return empty;
}

static void sphere_closes_and_is_shaded(void **state)
{
    (void)state;
    splat_node n;
    sphere(&n, 300);
    sta_gpu_cache cache;
    upload(&cache, &n);
    const uint32_t draw[1] = { 0 };
    static splat_out full, thin;
    for (int m = 0; m < 3; m++) {
        sta_splat_options o = { .method = methods[m] };
        check_against_twin(&n, &o, 0.03);
        gpu(&cache, &n, draw, 1, &o, &full);
        sta_splat_options small = { .method = methods[m], .scale = 0.3f };
        gpu(&cache, &n, draw, 1, &small, &thin);
        printf("%s: holes at scale 1: %zu, at 0.3: %zu\n", sta_splat_method_name(methods[m]),
               holes(&full), holes(&thin));
        assert_int_equal(holes(&full), 0);
        assert_true(holes(&thin) > 50);
        // Headlight: the middle (facing us) is brighter than near the rim.
        double f = 1.0 / tan(test_camera().fov_y / 2), rim = tan(asin(3.0 / 12.0)) * f * H / 2;
        int centre = (H / 2) * W + W / 2, near_rim = (H / 2) * W + W / 2 + (int)(rim - 2.0);
        assert_true(full.rgb[3 * centre] > full.rgb[3 * near_rim] + 0.1f);
    }
    sta_gpu_cache_release(&cache);
    node_free(&n);
}

// Mirror ghosts (GPU point flags byte 14) get no splat in any of the three paths, as in
// the geometry pass; shown again, they are drawn.
static void flagged_points_have_no_splat(void **state)
{
    (void)state;
    splat_node n;
    sphere(&n, 300);
    for (uint32_t i = 0; i < n.count; i += 3) {
        n.bytes[(size_t)i * STA_GPU_POINT_SIZE + STA_GPU_POINT_FLAGS_BYTE] =
            STA_GPU_FLAG_MIRROR_GHOST;
    }
    sta_gpu_cache cache;
    upload(&cache, &n);
    const uint32_t draw[1] = { 0 };
    static splat_out hidden, shown;
    for (int m = 0; m < 3; m++) {
        sta_splat_options o = { .method = methods[m] };
        hide_flags = STA_GPU_FLAG_MIRROR_GHOST;
        check_against_twin(&n, &o, 0.03);
        gpu(&cache, &n, draw, 1, &o, &hidden);
        hide_flags = 0;
        gpu(&cache, &n, draw, 1, &o, &shown);
        size_t flagged = 0;
        for (int i = 0; i < W * H; i++) {
            flagged += hidden.ids[2 * i] != STA_TARGET_NO_POINT && hidden.ids[2 * i + 1] % 3 == 0;
        }
        printf("%s: %zu pixels with ghosts hidden, %zu shown\n", sta_splat_method_name(methods[m]),
               hidden.drawn, shown.drawn);
        assert_int_equal(flagged, 0);
        assert_true(hidden.drawn > 0 && shown.drawn >= hidden.drawn);
    }
    sta_gpu_cache_release(&cache);
    node_free(&n);
}

// The three paths make the same squares: the same pixels and ids, depths equal up to
// float rounding (the programs compile the same arithmetic differently).
static void the_three_paths_agree(void **state)
{
    (void)state;
    splat_node n;
    sphere(&n, 300);
    sta_gpu_cache cache;
    upload(&cache, &n);
    const uint32_t draw[1] = { 0 };
    static splat_out a, b;
    gpu(&cache, &n, draw, 1, &(sta_splat_options){ .method = STA_SPLAT_INSTANCED }, &a);
    assert_true(a.drawn > 0);
    for (int m = STA_SPLAT_GEOMETRY; m <= STA_SPLAT_PULLED; m++) {
        gpu(&cache, &n, draw, 1, &(sta_splat_options){ .method = m }, &b);
        size_t differ = 0;
        for (int i = 0; i < W * H; i++) {
            differ += memcmp(&a.ids[2 * i], &b.ids[2 * i], 8) != 0 ||
                      fabsf(a.depth[i] - b.depth[i]) > 1e-5f * a.depth[i];
        }
        printf("instanced %zu pixels, %s %zu, %zu differ\n", a.drawn, sta_splat_method_name(m),
               b.drawn, differ);
        assert_int_equal(differ, 0);
    }
    sta_gpu_cache_release(&cache);
    node_free(&n);
}

// The runtime scale grows the disk's area with its square; a tiny splat far away still
// covers a pixel (the smallest on-screen radius).
static void scale_and_smallest_size(void **state)
{
    (void)state;
    splat_node n;
    node_init(&n, 2.0, -10.0, -10.0);
    const double p[3] = { 10.0, 0.0, 0.0 }, facing[3] = { -1.0, 0.0, 0.0 };
    add_splat(&n, p, facing, 1.0, 0xFFFFFFu);
    node_finish(&n);
    sta_gpu_cache cache;
    upload(&cache, &n);
    const uint32_t draw[1] = { 0 };
    static splat_out one, two;
    gpu(&cache, &n, draw, 1, &(sta_splat_options){ .scale = 1.0f }, &one);
    gpu(&cache, &n, draw, 1, &(sta_splat_options){ .scale = 2.0f }, &two);
    double ratio = (double)two.drawn / (double)one.drawn;
    printf("scale 1: %zu pixels, scale 2: %zu (x%.2f)\n", one.drawn, two.drawn, ratio);
    assert_true(ratio > 3.6 && ratio < 4.4);
    sta_gpu_cache_release(&cache);
    node_free(&n);

    node_init(&n, 40.0, -10.0, -10.0);
    const double far[3] = { 50.0, 0.0, 0.0 };
    add_splat(&n, far, facing, 0.0005, 0xFFFFFFu);
    node_finish(&n);
    upload(&cache, &n);
    gpu(&cache, &n, draw, 1, &(sta_splat_options){ 0 }, &one);
    assert_true(one.drawn >= 1);
    sta_gpu_cache_release(&cache);
    node_free(&n);
}

// More splats than the first arena holds, all edge-on (they draw nothing visible): its
// upload forces a repack.
static void big_edge_on_node(splat_node *n)
{
    node_init(n, 2.0, -10.0, -10.0);
    for (uint32_t i = 0; i < STA_GPU_CACHE_MIN_POINTS + 100; i++) {
        double p[3] = { 30.0, -8.0 + (i % 256) * 0.05, -8.0 + (i / 256) * 0.05 };
        const double normal[3] = { 0.0, 0.0, 1.0 };
        add_splat(n, p, normal, 0.01, 0x00FF00u);
    }
    node_finish(n);
}

// A node uploaded, then one large enough to force a repack: the first node's splats
// move with its points (drawn alone it still equals the twin).
static void arena_repack_keeps_splats_with_points(void **state)
{
    (void)state;
    static splat_node nodes[2];
    sphere(&nodes[0], 1000);
    big_edge_on_node(&nodes[1]);
    sta_error err = { 0 };
    sta_gpu_cache cache;
    assert_int_equal(sta_gpu_cache_init(&cache, 2, &err), STA_OK);
    sta_gpu_cache_enable_splats(&cache);
    for (uint32_t k = 0; k < 2; k++) {
        sta_stream_upload u = { k, nodes[k].count, nodes[k].bytes };
        sta_stream_frame frame = { .upload = &u, .upload_count = 1 };
        assert_int_equal(sta_gpu_cache_apply(&cache, &frame, &err), STA_OK);
    }
    assert_true(cache.compactions >= 1);
    static splat_out expected, got;
    for (int m = 0; m < 3; m++) {
        sta_splat_options o = { .method = methods[m] };
        twin(&nodes[0], 0, &o, &expected);
        const uint32_t draw[1] = { 0 };
        gpu(&cache, nodes, draw, 1, &o, &got);
        size_t differ = 0;
        for (int i = 0; i < W * H; i++) {
            differ += memcmp(&expected.ids[2 * i], &got.ids[2 * i], 8) != 0;
        }
        assert_true(expected.drawn > 500);
        assert_true(differ <= expected.drawn / 30);
    }
    sta_gpu_cache_release(&cache);
    node_free(&nodes[0]);
    node_free(&nodes[1]);
}

// The pulled splats read the arenas through texture views, which must follow a repack
// even when the new arena has the deleted one's name (NVIDIA's driver reuses names; Mesa
// never does, so the reuse is simulated). A stale view read the sphere's new offset in
// the old arena, where a red wall was.
static void pulled_view_follows_a_repack_under_a_reused_name(void **state)
{
    (void)state;
    static splat_node nodes[3];
    sphere(&nodes[0], 1000);
    node_init(&nodes[1], 2.0, -10.0, -10.0);
    for (uint32_t i = 0; i < 1000; i++) { // a wall facing the camera, behind the sphere
        double p[3] = { 20.0, -6.0 + (i % 40) * 0.3, -6.0 + (i / 40) * 0.5 };
        const double normal[3] = { -1.0, 0.0, 0.0 };
        add_splat(&nodes[1], p, normal, 0.3, 0xFF0000u);
    }
    node_finish(&nodes[1]);
    big_edge_on_node(&nodes[2]);
    sta_error err = { 0 };
    sta_gpu_cache cache;
    assert_int_equal(sta_gpu_cache_init(&cache, 3, &err), STA_OK);
    sta_gpu_cache_enable_splats(&cache);
    // The wall first, then the sphere behind it in the arena.
    sta_stream_upload first[2] = { { 1, nodes[1].count, nodes[1].bytes },
                                   { 0, nodes[0].count, nodes[0].bytes } };
    sta_stream_frame frame = { .upload = first, .upload_count = 2 };
    assert_int_equal(sta_gpu_cache_apply(&cache, &frame, &err), STA_OK);
    sta_splat_options o = { .method = STA_SPLAT_PULLED };
    sta_pass_splats pass;
    assert_int_equal(sta_pass_splats_init(&pass, o.method, &err), STA_OK);
    static splat_out expected, got;
    twin(&nodes[0], 0, &o, &expected);
    const uint32_t draw[1] = { 0 };
    gpu_with(&pass, &cache, nodes, draw, 1, &o, &got); // the views are made here
    // The wall goes and the big node comes: a repack moves the sphere to offset 0.
    uint32_t generation = cache.generation;
    const uint32_t wall[1] = { 1 };
    sta_stream_upload big = { 2, nodes[2].count, nodes[2].bytes };
    frame =
        (sta_stream_frame){ .evict = wall, .evict_count = 1, .upload = &big, .upload_count = 1 };
    assert_int_equal(sta_gpu_cache_apply(&cache, &frame, &err), STA_OK);
    assert_true(cache.generation > generation);
    assert_int_equal(cache.entries[0].offset, 0);
    pass.points_viewed = cache.buffer; // as if the new arena had the old one's name
    gpu_with(&pass, &cache, nodes, draw, 1, &o, &got);
    size_t differ = 0;
    for (int i = 0; i < W * H; i++) {
        differ += memcmp(&expected.ids[2 * i], &got.ids[2 * i], 8) != 0;
    }
    printf("pulled after the repack: %zu of %zu pixels differ from the twin\n", differ,
           expected.drawn);
    assert_true(expected.drawn > 500);
    assert_true(differ <= expected.drawn / 30);
    sta_pass_splats_release(&pass);
    sta_gpu_cache_release(&cache);
    for (int k = 0; k < 3; k++) {
        node_free(&nodes[k]);
    }
}

// The benchmark's readback: each drawn pixel's normal is its splat's (by id), in camera
// space, facing the camera.
static void normal_image_follows_the_ids(void **state)
{
    (void)state;
    splat_node n;
    sphere(&n, 300);
    sta_gpu_cache cache;
    upload(&cache, &n);
    sta_error err = { 0 };
    sta_pass_splats pass;
    assert_int_equal(sta_pass_splats_init(&pass, 0, &err), STA_OK);
    sta_gpu_node_frame frame = { .corner = { n.corner[0], n.corner[1], n.corner[2] },
                                 .step = { STEP_M, STEP_M, STEP_M } };
    sta_camera camera = test_camera();
    sta_geometry_colours colours = { .mode = STA_COLOUR_RGB,
                                     .elevation_span = 1,
                                     .intensity_scale = 1.0f };
    sta_render_target target = { 0 };
    assert_int_equal(sta_render_target_resize(&target, W, H, &err), STA_OK);
    const uint32_t draw[1] = { 0 };
    assert_int_equal(sta_pass_splats_draw(&pass, &(sta_splat_options){ 0 }, &camera, &colours,
                                          &cache, &frame, draw, 1, 0.05f, &target, &err),
                     STA_OK);
    static uint32_t ids[2 * W * H];
    sta_render_target_read_ids(&target, ids);
    sta_image normals = { 0 };
    assert_int_equal(sta_splat_normal_image(&cache, &target, &camera, &normals, &err), STA_OK);
    float view[16];
    sta_camera_view_rotation(&camera, view);
    size_t drawn = 0, flipped = 0;
    for (int y = 0; y < H; y++) {
        for (int x = 0; x < W; x++) {
            const uint32_t *id = ids + 2 * ((H - 1 - y) * W + x);
            const float *got = normals.data + 4 * (y * W + x);
            if (id[0] == STA_TARGET_NO_POINT) {
                assert_float_equal(got[3], 0.0f, 0);
                continue;
            }
            drawn++;
            assert_float_equal(got[3], 1.0f, 0);
            const float *world = n.normals[id[1]];
            float want[3];
            for (int i = 0; i < 3; i++) {
                want[i] = view[i] * world[0] + view[4 + i] * world[1] + view[8 + i] * world[2];
            }
            // The record's normal, or its opposite (at the limb a disk can be seen from
            // behind), and then against the eye ray through the pixel.
            const float t = (float)tan(0.5 * camera.fov_y);
            float ray[3] = { ((x + 0.5f) * 2.0f / W - 1.0f) * t * ((float)W / H),
                             ((y + 0.5f) * 2.0f / H - 1.0f) * t, -1.0f };
            float sign = got[0] * want[0] + got[1] * want[1] + got[2] * want[2] < 0 ? -1.0f : 1.0f;
            for (int i = 0; i < 3; i++) {
                assert_float_equal(got[i], sign * want[i], 1e-3);
            }
            assert_true(got[0] * ray[0] + got[1] * ray[1] + got[2] * ray[2] <= 0.0f);
            flipped += sign < 0;
        }
    }
    printf("%zu pixels, %zu seen from behind (at the limb)\n", drawn, flipped);
    assert_true(drawn > 500);
    assert_true(flipped < drawn / 10);
    sta_image_release(&normals);
    sta_render_target_release(&target);
    sta_pass_splats_release(&pass);
    sta_gpu_cache_release(&cache);
    node_free(&n);
}

// Renders the fixture scene (no normals) fully loaded in `mode`; RGBA, caller frees.
static uint8_t *render_fixture(const char *path, int mode, bool *out_has_splats)
{
    sta_scene *scene = NULL;
    sta_error err = { 0 };
    assert_int_equal(sta_scene_open(path, NULL, &scene, &err), STA_OK);
    *out_has_splats = sta_scene_has_splats(scene);
    sta_scene_set_pipeline(scene, &(sta_pipeline_options){ .mode = mode });
    sta_scene_set_splats(scene, &(sta_splat_options){ .scale = 2.0f });
    const double origin[3] = { 0, 0, 0 };
    sta_camera camera = sta_fixture_camera(origin, W, H);
    sta_render_target target = { 0 };
    sta_fixture_render_complete(scene, &camera, &target);
    uint8_t *rgba = malloc((size_t)W * H * 4);
    assert_non_null(rgba);
    sta_render_target_read_rgba(&target, rgba);
    sta_render_target_release(&target);
    sta_scene_close(scene);
    return rgba;
}

// The documented fallback: a scene without normals in the splats mode draws exactly
// the shaded pipeline (and the log says why).
static void scene_without_normals_falls_back_to_shaded(void **state)
{
    (void)state;
    char path[4096];
    const double origin[3] = { 0, 0, 0 };
    sta_fixture_build_scene("splats_fallback", 5000, origin, path, sizeof(path));
    bool has_splats = true;
    uint8_t *splats = render_fixture(path, STA_PIPELINE_SPLATS, &has_splats);
    assert_false(has_splats);
    uint8_t *shaded = render_fixture(path, STA_PIPELINE_SHADED, &has_splats);
    size_t lit = 0;
    for (size_t i = 0; i < (size_t)W * H; i++) {
        lit += shaded[4 * i] + shaded[4 * i + 1] + shaded[4 * i + 2] > 0;
    }
    assert_true(lit > 100);
    assert_memory_equal(splats, shaded, (size_t)W * H * 4);
    free(splats);
    free(shaded);
}

// End to end on a converted scene (strata-convert --normals of the fixture's sphere and
// wall): the scene has splats, the splat frame closes the sphere's silhouette where the
// points leave gaps, every drawn pixel names a resident point, and the normals drawn on
// the sphere are its analytic normals (converter, loader, arena, pass and readback).
static void converted_scene_draws_splats_with_its_normals(void **state)
{
    (void)state;
    char plain[4096], path[4096];
    const double origin[3] = { 0, 0, 0 };
    sta_fixture_build_scene("splats_e2e", 20000, origin, plain, sizeof(plain));
    char ply[4096];
    snprintf(ply, sizeof(ply), "%s/splats_e2e.ply", sta_test_tmpdir());
    snprintf(path, sizeof(path), "%s/splats_e2e_normals.strata", sta_test_tmpdir());
    const char *inputs[] = { ply };
    sta_convert_options co = { .inputs = inputs,
                               .input_count = 1,
                               .output = path,
                               .force = true,
                               .normals = true,
                               .leaf_capacity = 2000,
                               .compress_level = 1 };
    sta_error err = { 0 };
    if (sta_convert(&co, NULL, &err) != STA_OK) {
        fail_msg("%s", err.message);
    }
    enum {
        SW = 240,
        SH = 180
    };
    sta_camera camera = sta_fixture_camera(origin, SW, SH);
    size_t covered[2] = { 0, 0 };
    static uint32_t ids[2 * SW * SH];
    static float depth[SW * SH];
    for (int k = 0; k < 2; k++) {
        sta_scene *scene = NULL;
        assert_int_equal(sta_scene_open(path, NULL, &scene, &err), STA_OK);
        assert_true(sta_scene_has_splats(scene));
        int mode = k == 0 ? STA_PIPELINE_RAW : STA_PIPELINE_SPLATS;
        sta_scene_set_pipeline(scene, &(sta_pipeline_options){ .mode = mode });
        sta_render_target target = { 0 };
        sta_fixture_render_complete(scene, &camera, &target);
        sta_render_target_read_ids(&target, ids);
        for (int i = 0; i < SW * SH; i++) {
            covered[k] += ids[2 * i] != STA_TARGET_NO_POINT;
        }
        if (k == 1) {
            const sta_gpu_cache *cache = sta_scene_gpu_cache(scene);
            sta_image normals = { 0 };
            assert_int_equal(sta_splat_normal_image(cache, &target, &camera, &normals, &err),
                             STA_OK);
            sta_render_target_read_depth(&target, depth);
            double forward[3], right[3], up[3];
            sta_camera_basis(&camera, forward, right, up);
            double t = tan(0.5 * camera.fov_y), aspect = (double)SW / SH;
            size_t on_sphere = 0, within_5deg = 0;
            for (int y = 0; y < SH; y++) { // depth and ids: top row first
                for (int x = 0; x < SW; x++) {
                    int i = y * SW + x;
                    if (ids[2 * i] == STA_TARGET_NO_POINT) {
                        continue;
                    }
                    const sta_gpu_cache_entry *e = &cache->entries[ids[2 * i]];
                    assert_true(e->is_resident && ids[2 * i + 1] < e->count);
                    double nx = (x + 0.5) * 2.0 / SW - 1.0, ny = 1.0 - (y + 0.5) * 2.0 / SH;
                    double along = camera.near_m / (double)depth[i], p[3], d[3];
                    for (int a = 0; a < 3; a++) {
                        p[a] = camera.position[a] +
                               along * (forward[a] + nx * t * aspect * right[a] + ny * t * up[a]);
                    }
                    d[0] = p[0], d[1] = p[1] - 10.0, d[2] = p[2];
                    double r = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
                    if (fabs(r - 5.0) > 0.05) {
                        continue; // the wall, or a rim splat reaching past the sphere
                    }
                    // The analytic normal in camera space (facing us: the visible side).
                    const float *got = normals.data + 4 * ((SH - 1 - y) * SW + x);
                    double cam[3] = { 0, 0, 0 };
                    for (int a = 0; a < 3; a++) {
                        cam[0] += right[a] * d[a] / r;
                        cam[1] += up[a] * d[a] / r;
                        cam[2] -= forward[a] * d[a] / r;
                    }
                    double dot =
                        cam[0] * (double)got[0] + cam[1] * (double)got[1] + cam[2] * (double)got[2];
                    on_sphere++;
                    within_5deg += dot > cos(5.0 * M_PI / 180.0);
                }
            }
            printf("%zu sphere pixels, %zu with the normal within 5 degrees\n", on_sphere,
                   within_5deg);
            assert_true(on_sphere > 2000);
            assert_true(within_5deg > on_sphere * 9 / 10);
            sta_image_release(&normals);
        }
        sta_render_target_release(&target);
        sta_scene_close(scene);
    }
    printf("covered: points %zu, splats %zu pixels\n", covered[0], covered[1]);
    assert_true(covered[1] > covered[0] * 3 / 2);
}

static void options_and_names(void **state)
{
    (void)state;
    sta_splat_options o = { 0 };
    sta_splat_options_defaults(&o);
    assert_int_equal(o.method, STA_SPLAT_DEFAULT_METHOD);
    assert_float_equal(o.scale, STA_SPLAT_DEFAULT_SCALE, 0);
    assert_float_equal(o.min_radius_px, STA_SPLAT_DEFAULT_MIN_RADIUS_PX, 0);
    assert_int_equal(sta_splat_method_from_name("instanced"), STA_SPLAT_INSTANCED);
    assert_int_equal(sta_splat_method_from_name("geometry"), STA_SPLAT_GEOMETRY);
    assert_int_equal(sta_splat_method_from_name("pulled"), STA_SPLAT_PULLED);
    assert_int_equal(sta_splat_method_from_name("default"), -1);
    assert_int_equal(sta_splat_method_from_name("quads"), -1);
    assert_string_equal(sta_splat_method_name(STA_SPLAT_GEOMETRY), "geometry");
    // The default by renderer: software rasterisers the geometry shader, GPUs instancing.
    assert_int_equal(sta_splat_default_method("llvmpipe (LLVM 15.0.6, 256 bits)"),
                     STA_SPLAT_GEOMETRY);
    assert_int_equal(sta_splat_default_method("softpipe"), STA_SPLAT_GEOMETRY);
    assert_int_equal(sta_splat_default_method(NULL), STA_SPLAT_GEOMETRY);
    assert_int_equal(sta_splat_default_method("NVIDIA H100 80GB HBM3/PCIe/SSE2"),
                     STA_SPLAT_INSTANCED);
    assert_int_equal(sta_splat_default_method("AMD Radeon RX 7900 XTX (radeonsi, navi31)"),
                     STA_SPLAT_INSTANCED);
}

// A pass built for the default method takes the renderer's (llvmpipe in CI: geometry).
static void default_method_follows_the_renderer(void **state)
{
    (void)state;
    sta_error err = { 0 };
    sta_pass_splats pass;
    assert_int_equal(sta_pass_splats_init(&pass, STA_SPLAT_DEFAULT, &err), STA_OK);
    const char *renderer = (const char *)glGetString(GL_RENDERER);
    assert_int_equal(pass.method, sta_splat_default_method(renderer));
    if (strstr(renderer, "llvmpipe")) {
        assert_int_equal(pass.method, STA_SPLAT_GEOMETRY);
    }
    sta_pass_splats_release(&pass);
}

static const struct CMUnitTest tests[] = {
    cmocka_unit_test_setup_teardown(twin_matches_overlapping_disks, sta_fixture_gl_setup,
                                    sta_fixture_gl_teardown),
    cmocka_unit_test_setup_teardown(crossing_disks_cut_each_other, sta_fixture_gl_setup,
                                    sta_fixture_gl_teardown),
    cmocka_unit_test_setup_teardown(sphere_closes_and_is_shaded, sta_fixture_gl_setup,
                                    sta_fixture_gl_teardown),
    cmocka_unit_test_setup_teardown(flagged_points_have_no_splat, sta_fixture_gl_setup,
                                    sta_fixture_gl_teardown),
    cmocka_unit_test_setup_teardown(the_three_paths_agree, sta_fixture_gl_setup,
                                    sta_fixture_gl_teardown),
    cmocka_unit_test_setup_teardown(scale_and_smallest_size, sta_fixture_gl_setup,
                                    sta_fixture_gl_teardown),
    cmocka_unit_test_setup_teardown(pulled_view_follows_a_repack_under_a_reused_name,
                                    sta_fixture_gl_setup, sta_fixture_gl_teardown),
    cmocka_unit_test_setup_teardown(arena_repack_keeps_splats_with_points, sta_fixture_gl_setup,
                                    sta_fixture_gl_teardown),
    cmocka_unit_test_setup_teardown(normal_image_follows_the_ids, sta_fixture_gl_setup,
                                    sta_fixture_gl_teardown),
    cmocka_unit_test_setup_teardown(converted_scene_draws_splats_with_its_normals,
                                    sta_fixture_gl_setup, sta_fixture_gl_teardown),
    cmocka_unit_test_setup_teardown(scene_without_normals_falls_back_to_shaded,
                                    sta_fixture_gl_setup, sta_fixture_gl_teardown),
    cmocka_unit_test(options_and_names),
    cmocka_unit_test_setup_teardown(default_method_follows_the_renderer, sta_fixture_gl_setup,
                                    sta_fixture_gl_teardown),
};

STA_TEST_MAIN(tests)
