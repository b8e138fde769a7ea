/* SPDX-License-Identifier: MIT
 * Tests for the converter's in-memory nested octree (preprocess/index.c): every point
 * lands in exactly one node, inside it, at most one per cell in gridded nodes; the
 * merge above chunks keeps those rules. */
#include "test_support.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/alloc.h"
#include "core/octahedral.h"
#include "index.h"
#include "octree.h"
#include "record.h"

typedef struct collected_node {
    sta_node_key key;
    size_t count;
    unsigned flags;
    int32_t *xyz; /* 3 per point */
} collected_node;

typedef struct collector {
    collected_node *nodes;
    size_t count;
    size_t capacity;
    const sta_record_layout *layout;
} collector;

static sta_status collect(void *context, int worker, const sta_node_key *key,
                          const uint8_t *records, size_t count, unsigned flags, sta_error *err)
{
    (void)worker;
    (void)err;
    collector *c = context;
    if (c->count == c->capacity) {
        c->capacity = c->capacity ? 2 * c->capacity : 64;
        c->nodes = realloc(c->nodes, c->capacity * sizeof(*c->nodes));
        assert_non_null(c->nodes);
    }
    collected_node *n = &c->nodes[c->count++];
    n->key = *key;
    n->count = count;
    n->flags = flags;
    n->xyz = malloc(3 * sizeof(int32_t) * (count ? count : 1));
    assert_non_null(n->xyz);
    for (size_t i = 0; i < count; i++) {
        sta_record_position(records + i * c->layout->size, n->xyz + 3 * i);
    }
    return STA_OK;
}

static void collector_release(collector *c)
{
    for (size_t i = 0; i < c->count; i++) {
        free(c->nodes[i].xyz);
    }
    free(c->nodes);
}

static void add_pending(collector *c, const sta_pending_node *p)
{
    sta_error err = { 0 };
    assert_int_equal(collect(c, 0, &p->key, p->records, p->count, p->flags, &err), STA_OK);
}

static uint64_t splitmix(uint64_t *state)
{
    uint64_t z = (*state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

// Checks the invariants over all collected nodes; returns total points.
static size_t check_invariants(const sta_octree_space *space, const collector *c)
{
    size_t total = 0;
    size_t cells = (size_t)1 << (3 * space->grid_log2);
    uint8_t *seen = calloc(cells, 1);
    assert_non_null(seen);
    for (size_t n = 0; n < c->count; n++) {
        const collected_node *node = &c->nodes[n];
        memset(seen, 0, cells);
        for (size_t i = 0; i < node->count; i++) {
            const int32_t *p = node->xyz + 3 * i;
            assert_true(sta_node_contains(space, &node->key, p));
            if (!(node->flags & STA_NODE_UNGRIDDED)) {
                uint32_t cell = sta_node_cell(space, &node->key, p);
                assert_int_equal(seen[cell], 0);
                seen[cell] = 1;
            }
        }
        // No two nodes share a key.
        for (size_t m = n + 1; m < c->count; m++) {
            assert_false(sta_node_key_compare(&node->key, &c->nodes[m].key) == 0);
        }
        total += node->count;
    }
    free(seen);
    return total;
}

static void make_points(sta_record_layout *layout, uint8_t *records, size_t count, int32_t extent,
                        int duplicates, uint64_t seed)
{
    for (size_t i = 0; i < count; i++) {
        sta_point p = { 0 };
        if (duplicates && i % 2 == 1) {
            p.X = p.Y = p.Z = 77; // many exact duplicates
        } else {
            p.X = (int32_t)(splitmix(&seed) % (uint64_t)extent);
            p.Y = (int32_t)(splitmix(&seed) % (uint64_t)extent);
            p.Z = (int32_t)(splitmix(&seed) % (uint64_t)(extent / 16 + 1)); // flat-ish
        }
        p.intensity = (uint16_t)i;
        sta_record_pack(layout, &p, NULL, records + i * layout->size);
    }
}

static void index_and_check(size_t count, int32_t extent, int duplicates, size_t leaf_capacity)
{
    sta_record_layout layout;
    sta_record_layout_init(&layout, STA_ATTR_INTENSITY, 0);
    uint8_t *records = malloc(count * layout.size);
    assert_non_null(records);
    make_points(&layout, records, count, extent, duplicates, 42);

    const sta_grid grid = { { 0.01, 0.01, 0.01 }, { 0, 0, 0 } };
    const int64_t lo[3] = { 0, 0, 0 };
    const int64_t hi[3] = { extent - 1, extent - 1, extent / 16 };
    sta_octree_space space;
    assert_int_equal(sta_octree_space_init(&space, &grid, lo, hi, 4, NULL), STA_OK);

    collector c = { .layout = &layout };
    sta_node_sink sink = { collect, &c };
    sta_index_scratch scratch = { 0 };
    sta_pending_node root;
    sta_error err = { 0 };
    const sta_node_key root_key = { 0, 0, 0, 0 };
    assert_int_equal(sta_index_chunk(&space, &layout, &root_key, records, count, leaf_capacity, 0,
                                     &sink, &scratch, &root, &err),
                     STA_OK);
    add_pending(&c, &root);
    assert_int_equal(check_invariants(&space, &c), count);
    // The root is gridded unless everything fit in one leaf.
    if (count > leaf_capacity) {
        assert_int_equal(root.flags & STA_NODE_UNGRIDDED, 0);
        assert_true(root.count > 0);
    }
    sta_free(root.records);
    sta_index_scratch_release(&scratch);
    collector_release(&c);
    free(records);
}

static void every_point_once_inside_one_per_cell(void **state)
{
    (void)state;
    index_and_check(20000, 1 << 12, 0, 64);
}

static void small_input_is_one_leaf(void **state)
{
    (void)state;
    index_and_check(50, 1 << 10, 0, 64);
}

static void duplicates_stop_splitting(void **state)
{
    (void)state;
    // Half the points are one position: they must not recurse to the depth cap
    // one point per level but end in a leaf bucket.
    sta_record_layout layout;
    sta_record_layout_init(&layout, 0, 0);
    size_t count = 5000;
    uint8_t *records = malloc(count * layout.size);
    assert_non_null(records);
    make_points(&layout, records, count, 1 << 12, 1, 7);
    const sta_grid grid = { { 1, 1, 1 }, { 0, 0, 0 } };
    const int64_t lo[3] = { 0, 0, 0 }, hi[3] = { 4095, 4095, 256 };
    sta_octree_space space;
    assert_int_equal(sta_octree_space_init(&space, &grid, lo, hi, 4, NULL), STA_OK);
    collector c = { .layout = &layout };
    sta_node_sink sink = { collect, &c };
    sta_index_scratch scratch = { 0 };
    sta_pending_node root;
    const sta_node_key root_key = { 0, 0, 0, 0 };
    assert_int_equal(sta_index_chunk(&space, &layout, &root_key, records, count, 32, 0, &sink,
                                     &scratch, &root, NULL),
                     STA_OK);
    add_pending(&c, &root);
    assert_int_equal(check_invariants(&space, &c), count);
    size_t deepest = 0;
    for (size_t i = 0; i < c.count; i++) {
        deepest = c.nodes[i].key.level > deepest ? c.nodes[i].key.level : deepest;
    }
    assert_true(deepest < (size_t)space.max_level); // stopped before the cap
    sta_free(root.records);
    sta_index_scratch_release(&scratch);
    collector_release(&c);
    free(records);
}

static void merge_moves_one_point_per_parent_cell(void **state)
{
    (void)state;
    // Index the 8 children of the root separately as chunks, then merge upward.
    sta_record_layout layout;
    sta_record_layout_init(&layout, STA_ATTR_INTENSITY, 0);
    size_t count = 40000;
    uint8_t *records = malloc(count * layout.size);
    assert_non_null(records);
    make_points(&layout, records, count, 1 << 12, 0, 3);
    const sta_grid grid = { { 0.01, 0.01, 0.01 }, { 0, 0, 0 } };
    const int64_t lo[3] = { 0, 0, 0 }, hi[3] = { 4095, 4095, 256 };
    sta_octree_space space;
    assert_int_equal(sta_octree_space_init(&space, &grid, lo, hi, 4, NULL), STA_OK);
    const sta_node_key root_key = { 0, 0, 0, 0 };
    // Sort records by octant of the root into 8 buffers.
    uint8_t *parts[8];
    size_t part_count[8] = { 0 };
    for (int o = 0; o < 8; o++) {
        parts[o] = malloc(count * layout.size);
        assert_non_null(parts[o]);
    }
    for (size_t i = 0; i < count; i++) {
        int32_t p[3];
        sta_record_position(records + i * layout.size, p);
        int o = sta_node_octant(&space, &root_key, p);
        memcpy(parts[o] + part_count[o]++ * layout.size, records + i * layout.size, layout.size);
    }
    collector c = { .layout = &layout };
    sta_node_sink sink = { collect, &c };
    sta_index_scratch scratch = { 0 };
    sta_pending_node pending[8];
    size_t pending_count = 0;
    for (int o = 0; o < 8; o++) {
        if (part_count[o] == 0) {
            continue;
        }
        sta_node_key key = sta_node_child(&root_key, o);
        assert_int_equal(sta_index_chunk(&space, &layout, &key, parts[o], part_count[o], 64, 0,
                                         &sink, &scratch, &pending[pending_count], NULL),
                         STA_OK);
        pending_count++;
    }
    sta_pending_node parent;
    assert_int_equal(
        sta_index_merge_parent(&space, &layout, pending, pending_count, &scratch, &parent, NULL),
        STA_OK);
    assert_true(parent.count > 0);
    assert_int_equal(parent.key.level, 0);
    for (size_t i = 0; i < pending_count; i++) {
        add_pending(&c, &pending[i]);
        sta_free(pending[i].records);
    }
    add_pending(&c, &parent);
    assert_int_equal(check_invariants(&space, &c), count);
    sta_free(parent.records);
    for (int o = 0; o < 8; o++) {
        free(parts[o]);
    }
    sta_index_scratch_release(&scratch);
    collector_release(&c);
    free(records);
}

static void record_pack_round_trip(void **state)
{
    (void)state;
    sta_record_layout layout;
    uint32_t all = STA_ATTR_INTENSITY | STA_ATTR_RETURNS | STA_ATTR_CLASSIFICATION |
                   STA_ATTR_SCAN_ANGLE | STA_ATTR_USER_DATA | STA_ATTR_POINT_SOURCE_ID |
                   STA_ATTR_SCAN_FLAGS | STA_ATTR_GPS_TIME | STA_ATTR_RGB | STA_ATTR_NIR |
                   STA_ATTR_WAVE_PACKET | STA_ATTR_NORMAL | STA_ATTR_SCANNER_CHANNEL;
    sta_record_layout_init(&layout, all, 3);
    assert_int_equal(layout.size, 12 + 2 + 2 + 2 + 2 + 1 + 2 + 1 + 8 + 6 + 2 + 29 + 12 + 1 + 3);
    sta_point p = { .X = -5,
                    .Y = 7,
                    .Z = INT32_MAX,
                    .intensity = 65535,
                    .return_number = 3,
                    .number_of_returns = 5,
                    .classification = 200,
                    .classification_flags = 9,
                    .scan_angle = -30000,
                    .user_data = 4,
                    .point_source_id = 999,
                    .scan_direction_flag = 1,
                    .edge_of_flight_line = 1,
                    .gps_time = 1.5e9 + 0.25,
                    .red = 1,
                    .green = 2,
                    .blue = 65535,
                    .nir = 77,
                    .wave_descriptor_index = 2,
                    .wave_byte_offset = 1ull << 40,
                    .wave_packet_size = 123,
                    .wave_return_location = 1.5f,
                    .wave_xt = -1,
                    .wave_yt = 2,
                    .wave_zt = 3,
                    .normal = { 0, 0, 1 },
                    .scanner_channel = 3 };
    const uint8_t extra[3] = { 1, 2, 3 };
    uint8_t buf[128];
    sta_record_pack(&layout, &p, extra, buf);
    sta_point q;
    uint8_t extra_back[3];
    sta_record_unpack(&layout, buf, &q, extra_back);
    uint8_t again[128];
    sta_record_pack(&layout, &q, extra_back, again);
    assert_memory_equal(buf, again, layout.size);
    assert_int_equal(q.Z, INT32_MAX);
    assert_int_equal(q.scan_angle, -30000);
    assert_true(q.gps_time == 1.5e9 + 0.25);
    assert_int_equal(q.wave_byte_offset, 1ull << 40);
    assert_int_equal(q.edge_of_flight_line, 1);
    assert_memory_equal(extra, extra_back, 3);
    // A narrower layout zeroes what it does not store.
    sta_record_layout_init(&layout, STA_ATTR_RGB, 0);
    sta_record_pack(&layout, &p, NULL, buf);
    sta_record_unpack(&layout, buf, &q, NULL);
    assert_int_equal(q.blue, 65535);
    assert_int_equal(q.intensity, 0);
    assert_int_equal(q.Z, INT32_MAX);
}

// The SPLAT bytes of a packed record are sta_splat_pack's, also where sta_record_pack
// shortcuts a point without a normal or radius (zeros, negative zeros) to zeros.
static void record_pack_splat_is_the_splat_packing(void **state)
{
    (void)state;
    sta_record_layout layout;
    sta_record_layout_init(&layout, STA_ATTR_GPS_TIME | STA_ATTR_SPLAT, 0);
    const float cases[][4] = { { 0.0f, 0.0f, 0.0f, 0.0f },   { -0.0f, 0.0f, -0.0f, -0.0f },
                               { 0.0f, 0.0f, 0.0f, 0.25f },  { 0.0f, 0.0f, -1.0f, 0.0f },
                               { 0.6f, -0.8f, 0.0f, 1e-9f }, { 0.0f, 0.0f, 0.0f, -3.0f },
                               { NAN, 0.0f, 0.0f, 0.0f },    { 0.0f, 0.0f, 0.0f, NAN },
                               { 1e-30f, 0.0f, 0.0f, 0.0f } };
    for (size_t c = 0; c < sizeof(cases) / sizeof(cases[0]); c++) {
        sta_point p = { .X = 1, .Y = 2, .Z = 3, .gps_time = 4.0 };
        memcpy(p.normal, cases[c], sizeof(p.normal));
        p.radius = cases[c][3];
        uint8_t buf[64];
        memset(buf, 0xAB, sizeof(buf));
        sta_record_pack(&layout, &p, NULL, buf);
        uint16_t want[3];
        sta_splat_pack(p.normal, p.radius, want);
        assert_memory_equal(buf + layout.splat_offset, want, sizeof(want));
    }
}

static const struct CMUnitTest tests[] = {
    cmocka_unit_test(every_point_once_inside_one_per_cell),
    cmocka_unit_test(small_input_is_one_leaf),
    cmocka_unit_test(duplicates_stop_splitting),
    cmocka_unit_test(merge_moves_one_point_per_parent_cell),
    cmocka_unit_test(record_pack_round_trip),
    cmocka_unit_test(record_pack_splat_is_the_splat_packing),
};

STA_TEST_MAIN(tests)
