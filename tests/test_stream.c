/* SPDX-License-Identifier: MIT
 * The streaming policy without GL: the streamer over a fake node source (a complete
 * octree in memory whose loads can be held back or fail), with a simulated GPU that
 * carries out each frame's evictions and uploads. Every frame is checked: budget, GPU
 * cap, nothing drawn is evicted, every drawn node resident, draw order by priority. */
#include "test_support.h"

#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdbool.h>
#include <string.h>
#include <time.h>

#include "core/alloc.h"
#include "stream/gpu_points.h"
#include "stream/gpu_splats.h"
#include "stream/ground.h"
#include "stream/residency.h"
#include "stream/select.h"
#include "stream/streamer.h"

enum {
    LEVELS = 4,       /* 1 + 8 + 64 + 512 nodes */
    NODE_COUNT = 585, /* complete octree of LEVELS levels */
    POINTS_PER_NODE = 2000,
    MAX_FRAMES = 4000
};
#define EDGE_M 100.0

typedef struct fake_source {
    sta_node_source source;
    sta_lod_tree tree;
    uint32_t corrupt;           /* node whose load fails, or UINT32_MAX */
    int held_level;             /* loads of nodes at this level or deeper wait while held */
    atomic_bool held;           /* hold back deep loads */
    pthread_mutex_t lock;       /* guards the counters below */
    uint32_t calls[NODE_COUNT]; /* loads per node */
    uint32_t order[NODE_COUNT * 4];
    size_t order_count;
    bool splats; /* loads carry a splat section (set before the streamer starts) */
} fake_source;

// The fake splat of point i of `node`: a normal turning with i, a radius from the node.
static void fake_splat(uint32_t node, size_t i, float normal[3], float *radius)
{
    double angle = 0.001 * (double)i;
    normal[0] = (float)(0.6 * cos(angle));
    normal[1] = (float)(0.6 * sin(angle));
    normal[2] = 0.8f;
    *radius = 0.01f * (float)(node % 97 + 1);
}

static sta_status fake_load(void *context, void *worker, uint32_t node, uint8_t **out_gpu,
                            size_t *out_count, sta_error *err)
{
    (void)worker;
    fake_source *f = context;
    pthread_mutex_lock(&f->lock);
    f->calls[node]++;
    if (f->order_count < sizeof(f->order) / sizeof(f->order[0])) {
        f->order[f->order_count++] = node;
    }
    pthread_mutex_unlock(&f->lock);
    while (atomic_load(&f->held) && f->tree.nodes[node].level >= f->held_level) {
        struct timespec nap = { 0, 1000000 };
        nanosleep(&nap, NULL);
    }
    if (node == f->corrupt) {
        return sta_fail(err, STA_ERR_FORMAT, "fake: node %u checksum mismatch", node);
    }
    size_t count = f->tree.nodes[node].point_count;
    size_t point_bytes = STA_GPU_POINT_SIZE + (f->splats ? STA_GPU_SPLAT_SIZE : 0);
    uint8_t *gpu = sta_alloc_array(count, point_bytes);
    if (!gpu) {
        return sta_fail(err, STA_ERR_NOMEM, "fake: out of memory");
    }
    memset(gpu, 0, count * point_bytes);
    for (size_t i = 0; i < count; i++) {
        memcpy(gpu + i * STA_GPU_POINT_SIZE, &node, sizeof(node)); // whose bytes these are
        if (f->splats) {
            float normal[3], radius;
            fake_splat(node, i, normal, &radius);
            sta_gpu_splats_encode((const float(*)[3])normal, &radius, 1,
                                  gpu + count * STA_GPU_POINT_SIZE + i * STA_GPU_SPLAT_SIZE);
        }
    }
    *out_gpu = gpu;
    *out_count = count;
    return STA_OK;
}

// A complete octree in breadth-first order (children of a node are consecutive).
static void fake_init(fake_source *f)
{
    memset(f, 0, sizeof(*f));
    f->corrupt = UINT32_MAX;
    f->held_level = LEVELS;
    pthread_mutex_init(&f->lock, NULL);
    f->tree.nodes = sta_calloc(NODE_COUNT, sizeof(sta_lod_node));
    assert_non_null(f->tree.nodes);
    f->tree.count = NODE_COUNT;
    f->tree.nodes[0] = (sta_lod_node){ .min = { 0, 0, 0 },
                                       .max = { EDGE_M, EDGE_M, EDGE_M },
                                       .spacing = EDGE_M / 64,
                                       .point_count = POINTS_PER_NODE };
    uint32_t next = 1;
    for (uint32_t i = 0; i < NODE_COUNT; i++) {
        sta_lod_node *n = &f->tree.nodes[i];
        if (n->level + 1 >= LEVELS) {
            continue;
        }
        n->first_child = next;
        n->child_mask = 0xff;
        for (int c = 0; c < 8; c++) {
            sta_lod_node *child = &f->tree.nodes[next++];
            for (int a = 0; a < 3; a++) {
                double half = 0.5 * (n->max[a] - n->min[a]);
                child->min[a] = n->min[a] + ((c >> a) & 1) * half;
                child->max[a] = child->min[a] + half;
            }
            child->spacing = 0.5 * n->spacing;
            child->point_count = POINTS_PER_NODE;
            child->level = (uint8_t)(n->level + 1);
        }
    }
    assert_int_equal(next, NODE_COUNT);
    f->source = (sta_node_source){ .context = f, .node_count = NODE_COUNT, .load = fake_load };
}

static void fake_release(fake_source *f)
{
    sta_lod_tree_release(&f->tree);
    pthread_mutex_destroy(&f->lock);
}

static uint32_t parent_of(const sta_lod_tree *tree, uint32_t node)
{
    for (uint32_t i = 0; i < tree->count; i++) {
        const sta_lod_node *n = &tree->nodes[i];
        if (n->child_mask && node >= n->first_child && node < n->first_child + 8) {
            return i;
        }
    }
    return UINT32_MAX;
}

static sta_camera camera_at(double x, double y, double z, double yaw_deg)
{
    sta_camera c = { .position = { x, y, z },
                     .yaw = yaw_deg * M_PI / 180,
                     .pitch = 0,
                     .fov_y = 60 * M_PI / 180,
                     .near_m = 0.1,
                     .width_px = 640,
                     .height_px = 480 };
    return c;
}

/* The simulated GPU: points per resident node, carried out from each frame's lists. */
typedef struct sim_gpu {
    bool resident[NODE_COUNT];
    uint32_t count[NODE_COUNT];
    uint64_t bytes;
    uint64_t bytes_cap;
    uint64_t budget;
    uint64_t point_bytes; /* 16, or 24 with the splat section */
    size_t evictions, uploads;
} sim_gpu;

// The upload's splat section: every record decodes to the fake's splat of that point.
static void check_splats(const sta_stream_upload *u)
{
    const uint8_t *section = u->gpu + (size_t)u->count * STA_GPU_POINT_SIZE;
    for (uint32_t i = 0; i < u->count; i++) {
        float want[3], want_radius, got[3], got_radius;
        fake_splat(u->node, i, want, &want_radius);
        sta_gpu_splat_decode(section + (size_t)i * STA_GPU_SPLAT_SIZE, got, &got_radius);
        assert_float_equal(got_radius, sta_half_to_float(sta_half_from_float(want_radius)), 0);
        for (int a = 0; a < 3; a++) {
            assert_float_equal(got[a], want[a], 1e-4);
        }
    }
}

// Carries out one frame and checks every rule the streamer promises.
static void apply_and_check(sim_gpu *gpu, const sta_stream_frame *f, const sta_camera *camera,
                            const sta_lod_tree *tree)
{
    assert_true(f->points_selected <= gpu->budget);
    assert_true(f->points_selected <= gpu->bytes_cap / gpu->point_bytes);
    assert_true(f->points_drawn <= f->points_selected);
    bool drawn[NODE_COUNT] = { false };
    for (size_t i = 0; i < f->draw_count; i++) {
        drawn[f->draw[i]] = true;
    }
    for (size_t i = 0; i < f->evict_count; i++) {
        uint32_t node = f->evict[i];
        assert_true(gpu->resident[node]);
        assert_false(drawn[node]); // nothing drawn this frame is evicted
        gpu->resident[node] = false;
        gpu->bytes -= (uint64_t)gpu->count[node] * gpu->point_bytes;
        gpu->evictions++;
    }
    for (size_t i = 0; i < f->upload_count; i++) {
        const sta_stream_upload *u = &f->upload[i];
        assert_false(gpu->resident[u->node]);
        uint32_t owner;
        memcpy(&owner, u->gpu, sizeof(owner));
        assert_int_equal(owner, u->node); // the bytes are that node's
        if (gpu->point_bytes > STA_GPU_POINT_SIZE) {
            check_splats(u);
        }
        gpu->resident[u->node] = true;
        gpu->count[u->node] = u->count;
        gpu->bytes += (uint64_t)u->count * gpu->point_bytes;
        assert_true(gpu->bytes <= gpu->bytes_cap);
        gpu->uploads++;
    }
    assert_true(gpu->bytes <= gpu->bytes_cap);
    assert_int_equal(gpu->bytes, f->resident_bytes);
    uint64_t points = 0;
    sta_frustum frustum;
    sta_camera_frustum(camera, 1e300, &frustum);
    double previous = INFINITY;
    for (size_t i = 0; i < f->draw_count; i++) {
        uint32_t node = f->draw[i];
        assert_true(gpu->resident[node]); // every drawn node is on the GPU
        points += gpu->count[node];
        double priority = sta_select_node_priority(&tree->nodes[node], camera, &frustum);
        assert_true(priority > 0);
        assert_true(priority <= previous); // highest priority first
        previous = priority;
    }
    assert_int_equal(points, f->points_drawn);
}

static void nap(void)
{
    struct timespec t = { 0, 500000 };
    nanosleep(&t, NULL);
}

// Runs frames until complete; returns the number of frames it took.
static int run_until_complete(sta_streamer *s, sim_gpu *gpu, const sta_camera *camera,
                              const sta_lod_tree *tree, sta_stream_frame *out_last)
{
    sta_error err = { 0 };
    for (int frame = 1; frame <= MAX_FRAMES; frame++) {
        assert_int_equal(sta_streamer_update(s, camera, out_last, &err), STA_OK);
        apply_and_check(gpu, out_last, camera, tree);
        if (out_last->complete) {
            return frame;
        }
        nap();
    }
    fail_msg("the streamer never completed the view");
    return MAX_FRAMES;
}

static sta_streamer *open_streamer(fake_source *f, const sta_streamer_options *options,
                                   sim_gpu *gpu)
{
    sta_streamer *s = NULL;
    sta_error err = { 0 };
    assert_int_equal(sta_streamer_create(&f->tree, &f->source, options, &s, &err), STA_OK);
    memset(gpu, 0, sizeof(*gpu));
    gpu->bytes_cap = sta_streamer_options_used(s)->gpu_bytes_cap;
    gpu->budget = sta_streamer_options_used(s)->budget_points;
    gpu->point_bytes = STA_GPU_POINT_SIZE + (sta_streamer_has_splats(s) ? STA_GPU_SPLAT_SIZE : 0);
    return s;
}

static void budget_is_never_exceeded(void **state)
{
    (void)state;
    fake_source f;
    fake_init(&f);
    const uint64_t budgets[] = { 1, POINTS_PER_NODE, 5 * POINTS_PER_NODE + 1, 123457, 10000000 };
    for (size_t b = 0; b < sizeof(budgets) / sizeof(budgets[0]); b++) {
        sta_streamer_options o = { .budget_points = budgets[b], .loader_threads = 2 };
        sim_gpu gpu;
        sta_streamer *s = open_streamer(&f, &o, &gpu);
        sta_stream_frame last;
        sta_camera near = camera_at(50, -20, 50, 90), far = camera_at(50, -400, 50, 90);
        run_until_complete(s, &gpu, &near, &f.tree, &last);
        uint64_t selected_near = last.points_selected;
        run_until_complete(s, &gpu, &far, &f.tree, &last);
        assert_true(selected_near <= budgets[b]);
        if (budgets[b] >= POINTS_PER_NODE) {
            assert_true(last.points_selected >= POINTS_PER_NODE); // at least the root
        } else {
            assert_int_equal(last.points_selected, 0);
        }
        sta_streamer_close(s);
    }
    fake_release(&f);
}

static void gpu_cap_holds_with_evictions(void **state)
{
    (void)state;
    fake_source f;
    fake_init(&f);
    // Room for 12 nodes; the budget is capped to what fits.
    sta_streamer_options o = { .gpu_bytes_cap = 12 * POINTS_PER_NODE * STA_GPU_POINT_SIZE,
                               .loader_threads = 2 };
    sim_gpu gpu;
    sta_streamer *s = open_streamer(&f, &o, &gpu);
    sta_stream_frame last;
    // Walk round the cube close up: every view wants different nodes.
    for (int step = 0; step < 8; step++) {
        double angle = step * M_PI / 4;
        sta_camera c = camera_at(50 - 60 * sin(angle), 50 - 60 * cos(angle), 50, 90 - step * 45.0);
        c.position[0] = 50 + 60 * cos(angle + M_PI);
        c.position[1] = 50 + 60 * sin(angle + M_PI);
        c.yaw = angle;
        run_until_complete(s, &gpu, &c, &f.tree, &last);
        assert_true(last.points_selected <= 12 * POINTS_PER_NODE);
        assert_int_equal(last.draw_count, last.nodes_selected);
    }
    assert_true(gpu.evictions > 0);
    assert_int_equal(gpu.evictions, last.evictions);
    sta_streamer_close(s);
    fake_release(&f);
}

// Issue 12: a source with splats hands the whole buffer (points, then splat records)
// through the loader and the upload list, and the splat bytes count against the GPU cap.
static void splat_sections_travel_and_count_against_the_cap(void **state)
{
    (void)state;
    fake_source f;
    fake_init(&f);
    f.splats = true;
    f.source.has_splats = 1;
    // The cap that holds 12 nodes of points alone holds 8 with their splats.
    sta_streamer_options o = { .gpu_bytes_cap = 12 * POINTS_PER_NODE * STA_GPU_POINT_SIZE,
                               .loader_threads = 2 };
    sim_gpu gpu;
    sta_streamer *s = open_streamer(&f, &o, &gpu);
    assert_true(sta_streamer_has_splats(s));
    assert_int_equal(gpu.point_bytes, STA_GPU_POINT_SIZE + STA_GPU_SPLAT_SIZE);
    sta_stream_frame last;
    for (int step = 0; step < 4; step++) {
        sta_camera c = camera_at(50 + 60 * cos(step * M_PI / 2 + M_PI),
                                 50 + 60 * sin(step * M_PI / 2 + M_PI), 50, 0);
        c.yaw = step * M_PI / 2;
        run_until_complete(s, &gpu, &c, &f.tree, &last);
        assert_true(last.points_selected <= 8 * POINTS_PER_NODE);
        assert_true(last.points_selected >= POINTS_PER_NODE);
        assert_true(last.resident_bytes <= o.gpu_bytes_cap);
    }
    assert_true(gpu.uploads > 0);
    sta_streamer_close(s);
    fake_release(&f);
}

static void parent_stands_in_for_missing_children(void **state)
{
    (void)state;
    fake_source f;
    fake_init(&f);
    f.held_level = 2; // levels 2 and deeper wait
    atomic_store(&f.held, true);
    sta_streamer_options o = { .loader_threads = 1 };
    sim_gpu gpu;
    sta_streamer *s = open_streamer(&f, &o, &gpu);
    sta_camera c = camera_at(50, -30, 50, 90);
    sta_error err = { 0 };
    sta_stream_frame frame;
    size_t drawn_levels_01 = 0;
    for (int i = 0; i < 400; i++) {
        assert_int_equal(sta_streamer_update(s, &c, &frame, &err), STA_OK);
        apply_and_check(&gpu, &frame, &c, &f.tree);
        assert_false(frame.complete);
        for (size_t d = 0; d < frame.draw_count; d++) {
            uint32_t node = frame.draw[d];
            assert_true(f.tree.nodes[node].level < 2); // held-back children are absent
            uint32_t parent = parent_of(&f.tree, node);
            bool parent_drawn = parent == UINT32_MAX;
            for (size_t k = 0; k < frame.draw_count && !parent_drawn; k++) {
                parent_drawn = frame.draw[k] == parent;
            }
            assert_true(parent_drawn); // what is drawn is closed under "parent first"
        }
        drawn_levels_01 = frame.draw_count;
        nap();
    }
    // The one worker waits in the first held-back load: every load of a shallower node
    // that started has finished, and each of those nodes is drawn.
    size_t loaded_01 = 0;
    pthread_mutex_lock(&f.lock);
    for (uint32_t node = 0; node < 9; node++) {
        loaded_01 += f.calls[node];
    }
    pthread_mutex_unlock(&f.lock);
    assert_true(loaded_01 >= 2);
    assert_int_equal(drawn_levels_01, loaded_01); // the root and its children stand in
    assert_true(frame.nodes_selected > 9);
    atomic_store(&f.held, false);
    run_until_complete(s, &gpu, &c, &f.tree, &frame);
    assert_int_equal(frame.draw_count, frame.nodes_selected);
    sta_streamer_close(s);
    fake_release(&f);
}

static void loads_follow_priority_order(void **state)
{
    (void)state;
    fake_source f;
    fake_init(&f);
    sta_streamer_options o = { .loader_threads = 1 };
    sim_gpu gpu;
    sta_streamer *s = open_streamer(&f, &o, &gpu);
    sta_camera c = camera_at(10, -5, 20, 60); // off-centre: priorities differ
    sta_stream_frame last;
    run_until_complete(s, &gpu, &c, &f.tree, &last);
    sta_frustum frustum;
    sta_camera_frustum(&c, 1e300, &frustum);
    assert_true(f.order_count > 20);
    double previous = INFINITY;
    for (size_t i = 0; i < f.order_count; i++) {
        double p = sta_select_node_priority(&f.tree.nodes[f.order[i]], &c, &frustum);
        assert_true(p <= previous); // one worker, one camera: loads in priority order
        previous = p;
        assert_int_equal(f.calls[f.order[i]], 1); // nothing loaded twice
    }
    assert_int_equal(f.order_count, last.nodes_selected);
    sta_streamer_close(s);
    fake_release(&f);
}

static void corrupt_node_is_skipped_and_reported_once(void **state)
{
    (void)state;
    fake_source f;
    fake_init(&f);
    f.corrupt = 3; // a child of the root
    sta_streamer_options o = { .loader_threads = 2 };
    sim_gpu gpu;
    sta_streamer *s = open_streamer(&f, &o, &gpu);
    sta_camera c = camera_at(50, -150, 50, 90);
    sta_error err = { 0 };
    size_t reported = 0;
    sta_stream_frame frame;
    bool complete = false;
    for (int i = 0; i < MAX_FRAMES && !(complete && i > 50); i++) {
        assert_int_equal(sta_streamer_update(s, &c, &frame, &err), STA_OK);
        apply_and_check(&gpu, &frame, &c, &f.tree);
        for (size_t k = 0; k < frame.new_bad_count; k++) {
            assert_int_equal(frame.new_bad[k], 3);
            reported++;
        }
        for (size_t d = 0; d < frame.draw_count; d++) {
            assert_int_not_equal(frame.draw[d], 3);
        }
        for (size_t u = 0; u < frame.upload_count; u++) {
            assert_int_not_equal(frame.upload[u].node, 3);
        }
        complete = complete || frame.complete;
        nap();
    }
    assert_true(complete); // a bad node does not keep the view loading
    assert_int_equal(reported, 1);
    assert_int_equal(frame.bad_nodes, 1);
    assert_int_equal(f.calls[3], 1); // never asked for again
    assert_int_equal(frame.draw_count + 1, frame.nodes_selected);
    sta_streamer_close(s);
    fake_release(&f);
}

static void camera_jump_converges(void **state)
{
    (void)state;
    fake_source f;
    fake_init(&f);
    sta_streamer_options o = { .loader_threads = 2,
                               .gpu_bytes_cap = 200 * POINTS_PER_NODE * STA_GPU_POINT_SIZE,
                               .upload_bytes_per_frame = 4 * POINTS_PER_NODE * STA_GPU_POINT_SIZE };
    sim_gpu gpu;
    sta_streamer *s = open_streamer(&f, &o, &gpu);
    sta_stream_frame last;
    sta_camera a = camera_at(5, -10, 5, 45), b = camera_at(150, 95, 95, 180);
    run_until_complete(s, &gpu, &a, &f.tree, &last);
    uint64_t selected_a = last.points_selected;
    int frames = run_until_complete(s, &gpu, &b, &f.tree, &last);
    assert_true(frames > 1); // the jump needed new nodes, uploaded a few per frame
    assert_int_equal(last.draw_count, last.nodes_selected);
    assert_int_equal(last.points_drawn, last.points_selected);
    assert_true(last.points_selected > 0 && selected_a > 0);
    // And back: the first view converges again, drawing exactly what it selects.
    run_until_complete(s, &gpu, &a, &f.tree, &last);
    assert_int_equal(last.points_selected, selected_a);
    assert_int_equal(last.points_drawn, selected_a);
    sta_streamer_close(s);
    fake_release(&f);
}

static void residency_evicts_least_recently_used_of_earlier_frames(void **state)
{
    (void)state;
    sta_residency r;
    sta_error err = { 0 };
    const uint64_t node_bytes = 10 * STA_GPU_POINT_SIZE;
    assert_int_equal(sta_residency_init(&r, 8, 3 * node_bytes, &err), STA_OK);
    uint32_t evicted[8];
    size_t n = 0;
    assert_true(sta_residency_admit(&r, 0, 10, evicted, &n)); // frame 1
    sta_residency_begin_frame(&r);
    assert_true(sta_residency_admit(&r, 1, 10, evicted, &n)); // frame 2
    assert_true(sta_residency_admit(&r, 2, 10, evicted, &n));
    assert_false(sta_residency_admit(&r, 2, 10, evicted, &n)); // already resident
    assert_int_equal(n, 0);
    sta_residency_begin_frame(&r); // frame 3: node 1 used, 0 and 2 not
    sta_residency_touch(&r, 1);
    assert_true(sta_residency_admit(&r, 3, 10, evicted, &n));
    assert_int_equal(n, 1);
    assert_int_equal(evicted[0], 0); // the oldest
    assert_true(sta_residency_admit(&r, 4, 10, evicted, &n));
    assert_int_equal(evicted[1], 2); // then the next oldest; 1 and 3 belong to this frame
    assert_false(sta_residency_admit(&r, 5, 10, evicted, &n)); // only this frame's are left
    assert_int_equal(n, 2);
    assert_false(sta_residency_admit(&r, 6, 40, evicted, &n)); // larger than the cap
    assert_true(r.bytes_used <= r.bytes_cap);
    assert_int_equal(r.evictions, 2);
    sta_residency_release(&r);
    sta_residency_release(&r); // a zeroed struct is a no-op
}

static void source_and_tree_must_agree(void **state)
{
    (void)state;
    fake_source f;
    fake_init(&f);
    f.source.node_count = NODE_COUNT - 1;
    sta_streamer *s = NULL;
    sta_error err = { 0 };
    assert_int_equal(sta_streamer_create(&f.tree, &f.source, NULL, &s, &err), STA_ERR_ARG);
    assert_null(s);
    assert_non_null(strstr(err.message, "584"));
    fake_release(&f);
}

// A sloped terrain far from the origin (UTM-like), 200 x 200 m, rising 10 % along x, with
// a 20 x 20 m building 8 m high and trees 12 m high; classes optional.
enum {
    TERRAIN_STEP_DM = 5 /* terrain sample spacing, decimetres */
};
#define UTM_X 650000.0
#define UTM_Y 5400000.0

static double terrain_z(double x)
{
    return 100.0 + 0.1 * (x - UTM_X);
}

static size_t sloped_scene(sta_ground_sample *out, size_t capacity, bool classified, bool hole)
{
    size_t n = 0;
    for (int iy = 0; iy < 400; iy++) {
        for (int ix = 0; ix < 400; ix++) {
            double x = UTM_X + ix * 0.5, y = UTM_Y + iy * 0.5;
            bool in_building =
                x >= UTM_X + 90 && x < UTM_X + 110 && y >= UTM_Y + 90 && y < UTM_Y + 110;
            bool in_hole =
                hole && x >= UTM_X + 20 && x < UTM_X + 40 && y >= UTM_Y + 20 && y < UTM_Y + 40;
            if (n < capacity && !in_building && !in_hole) { // the building hides its ground
                out[n++] = (sta_ground_sample){ { x, y, terrain_z(x) }, classified ? 2 : 1 };
            }
            if (n < capacity && in_building) {
                out[n++] = (sta_ground_sample){ { x, y, terrain_z(UTM_X + 90) + 8.0 },
                                                classified ? 6 : 1 };
            }
            if (n < capacity && ix % 40 == 20 && iy % 40 == 20 && !in_building) { // trees
                for (int k = 0; k < 20 && n < capacity; k++) {
                    out[n++] = (sta_ground_sample){ { x + 0.1 * k, y, terrain_z(x) + 12.0 },
                                                    classified ? 5 : 1 };
                }
            }
        }
    }
    return n;
}

static void check_ground(const sta_ground *g, double tolerance_m, bool hole)
{
    for (int iy = 0; iy < 40; iy++) {
        for (int ix = 0; ix < 40; ix++) {
            double x = UTM_X + 2.5 + ix * 5.0, y = UTM_Y + 2.5 + iy * 5.0;
            double error = sta_ground_at(g, x, y) - terrain_z(x);
            bool near_edge = x < UTM_X + 3 || x > UTM_X + 197; // clamped at the grid's edge
            // Filled cells lean towards their nearest ground (neighbour means, ring by
            // ring): allow 0.5 m inside the 20 m hole on this 10 % slope.
            bool in_hole =
                hole && x > UTM_X + 18 && x < UTM_X + 42 && y > UTM_Y + 18 && y < UTM_Y + 42;
            double allowed = in_hole ? fmax(tolerance_m, 0.5) : tolerance_m;
            if (!near_edge && fabs(error) > allowed) {
                fail_msg("ground off by %.2f m at (%.1f, %.1f)%s", error, x - UTM_X, y - UTM_Y,
                         hole ? " (scene with a hole)" : "");
            }
        }
    }
}

static void ground_from_classes_follows_the_slope(void **state)
{
    (void)state;
    size_t capacity = 400 * 400 + 400;
    sta_ground_sample *samples = sta_alloc_array(capacity, sizeof(*samples));
    assert_non_null(samples);
    size_t n = sloped_scene(samples, capacity, true, true);
    sta_ground g;
    sta_error err = { 0 };
    assert_int_equal(sta_ground_from_samples(samples, n, &g, &err), STA_OK);
    assert_true(g.from_class);
    assert_int_equal(g.sampled, n);
    // Under the building and in the 20 m hole, without ground points: filled from the
    // neighbours, still on the plane within centimetres (the harmonic fill).
    check_ground(&g, 0.15, true);
    // Tree tops stand 12 m above the ground.
    double h = UTM_X + 20.0;
    assert_true(fabs(terrain_z(h) + 12.0 - sta_ground_at(&g, h, UTM_Y + 10.0) - 12.0) < 0.15);
    sta_ground_release(&g);
    sta_ground_release(&g); // a zeroed model is a no-op
    sta_free(samples);
}

static void ground_without_classes_removes_roofs_and_trees(void **state)
{
    (void)state;
    size_t capacity = 400 * 400 + 400;
    sta_ground_sample *samples = sta_alloc_array(capacity, sizeof(*samples));
    assert_non_null(samples);
    size_t n = sloped_scene(samples, capacity, false, false);
    sta_ground g;
    sta_error err = { 0 };
    assert_int_equal(sta_ground_from_samples(samples, n, &g, &err), STA_OK);
    assert_false(g.from_class);
    // The opening keeps the slope and drops the 20 m building and the trees.
    check_ground(&g, 0.6, false);
    double roof = terrain_z(UTM_X + 90) + 8.0;
    double above = roof - sta_ground_at(&g, UTM_X + 100, UTM_Y + 100);
    assert_true(above > 7.0 && above < 9.0);
    sta_ground_release(&g);
    sta_free(samples);
    assert_int_equal(sta_ground_from_samples(NULL, 0, &g, &err), STA_ERR_ARG);
}

static const struct CMUnitTest tests[] = {
    cmocka_unit_test(budget_is_never_exceeded),
    cmocka_unit_test(gpu_cap_holds_with_evictions),
    cmocka_unit_test(splat_sections_travel_and_count_against_the_cap),
    cmocka_unit_test(parent_stands_in_for_missing_children),
    cmocka_unit_test(loads_follow_priority_order),
    cmocka_unit_test(corrupt_node_is_skipped_and_reported_once),
    cmocka_unit_test(camera_jump_converges),
    cmocka_unit_test(residency_evicts_least_recently_used_of_earlier_frames),
    cmocka_unit_test(source_and_tree_must_agree),
    cmocka_unit_test(ground_from_classes_follows_the_slope),
    cmocka_unit_test(ground_without_classes_removes_roofs_and_trees),
};

STA_TEST_MAIN(tests)
