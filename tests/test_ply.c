/* SPDX-License-Identifier: MIT
 * Tests for the PLY reader (src/io/ply.c, ply_header.c) and mesh loader (ply_mesh.c):
 * the Stanford bunny files against the facts in ../shared/data/README.md, small files
 * written here in all three encodings, broken files, and allocation failures. */
#include "test_support.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/alloc.h"
#include "core/bytes.h"
#include "io/cloud.h"
#include "io/ply.h"

/* ---- helpers ---------------------------------------------------------------------- */

// A growable byte buffer for writing test files.
typedef struct buf {
    uint8_t *data;
    size_t size;
    size_t capacity;
} buf;

static void put(buf *b, const void *bytes, size_t n)
{
    if (b->size + n > b->capacity) {
        size_t capacity = b->capacity ? b->capacity : 256;
        while (capacity < b->size + n) {
            capacity *= 2;
        }
        b->data = realloc(b->data, capacity);
        assert_non_null(b->data);
        b->capacity = capacity;
    }
    memcpy(b->data + b->size, bytes, n);
    b->size += n;
}

static void putf(buf *b, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void putf(buf *b, const char *fmt, ...)
{
    char text[512];
    va_list args;
    va_start(args, fmt);
    int n = vsnprintf(text, sizeof(text), fmt, args);
    va_end(args);
    assert_true(n >= 0 && (size_t)n < sizeof(text));
    put(b, text, (size_t)n);
}

static void put_uint(buf *b, uint64_t v, size_t bytes, bool big_endian)
{
    uint8_t out[8];
    for (size_t i = 0; i < bytes; i++) {
        size_t shift = big_endian ? bytes - 1 - i : i;
        out[i] = (uint8_t)(v >> (8 * shift));
    }
    put(b, out, bytes);
}

static void put_f32(buf *b, float v, bool big_endian)
{
    uint32_t bits;
    memcpy(&bits, &v, sizeof(bits));
    put_uint(b, bits, 4, big_endian);
}

static void put_f64(buf *b, double v, bool big_endian)
{
    uint64_t bits;
    memcpy(&bits, &v, sizeof(bits));
    put_uint(b, bits, 8, big_endian);
}

// The first occurrence of `text` in the buffer (it is not NUL-terminated), or NULL.
static uint8_t *buf_find(const buf *b, const char *text)
{
    size_t n = strlen(text);
    for (size_t i = 0; i + n <= b->size; i++) {
        if (memcmp(b->data + i, text, n) == 0) {
            return b->data + i;
        }
    }
    return NULL;
}

static void buf_free(buf *b)
{
    free(b->data);
    memset(b, 0, sizeof(*b));
}

// Writes `data` to a temporary file called `name`; its path goes to `path`.
static void write_tmp(const char *name, const void *data, size_t size, char *path, size_t path_size)
{
    snprintf(path, path_size, "%s", sta_test_tmp_path(name));
    sta_test_write_file(path, data, size);
}

typedef struct points {
    sta_point *items;
    size_t count;
    sta_cloud_info info; // copied at open (pointers inside are not used)
} points;

// Opens `path` and reads all points in batches of `batch_capacity`.
static sta_status read_points(const char *path, const sta_read_options *options,
                              size_t batch_capacity, points *out, sta_error *err)
{
    memset(out, 0, sizeof(*out));
    sta_cloud_reader *reader = NULL;
    sta_status status = sta_cloud_open(path, options, &reader, err);
    if (status != STA_OK) {
        return status;
    }
    const sta_cloud_info *info = sta_cloud_reader_info(reader);
    out->info = *info;
    out->items = calloc(info->point_count ? (size_t)info->point_count : 1, sizeof(sta_point));
    assert_non_null(out->items);
    sta_point_batch batch = { 0 };
    assert_int_equal(sta_point_batch_init(&batch, batch_capacity, info->extra_size, err), STA_OK);
    for (;;) {
        status = sta_cloud_read(reader, &batch, err);
        if (status != STA_OK || batch.count == 0) {
            break;
        }
        assert_int_equal(batch.first_index, out->count);
        assert_true(out->count + batch.count <= info->point_count);
        memcpy(out->items + out->count, batch.points, batch.count * sizeof(sta_point));
        out->count += batch.count;
    }
    sta_point_batch_release(&batch);
    sta_cloud_close(reader);
    return status;
}

static void points_free(points *p)
{
    free(p->items);
    memset(p, 0, sizeof(*p));
}

// Asserts that opening `data` (written as temporary file `name`) fails with `code` and
// a message that names the file and contains each of the NULL-terminated needles.
static void expect_open_error(const char *name, const void *data, size_t size, sta_status code, ...)
{
    char path[4096];
    write_tmp(name, data, size, path, sizeof(path));
    sta_error err = { 0 };
    sta_cloud_reader *reader = NULL;
    sta_status status = sta_cloud_open(path, NULL, &reader, &err);
    if (status == STA_OK) {
        sta_cloud_close(reader);
        fail_msg("%s opened although it is broken", name);
    }
    print_message("%s -> %s\n", name, err.message);
    assert_int_equal(status, code);
    assert_non_null(strstr(err.message, path));
    va_list args;
    va_start(args, code);
    for (const char *needle = va_arg(args, const char *); needle;
         needle = va_arg(args, const char *)) {
        if (!strstr(err.message, needle)) {
            va_end(args);
            fail_msg("message \"%s\" lacks \"%s\"", err.message, needle);
        }
    }
    va_end(args);
    assert_null(reader);
}

static bool same_point(const sta_point *a, const sta_point *b)
{
    return a->X == b->X && a->Y == b->Y && a->Z == b->Z && a->red == b->red &&
           a->green == b->green && a->blue == b->blue && a->intensity == b->intensity &&
           memcmp(a->normal, b->normal, sizeof(a->normal)) == 0;
}

/* ---- Stanford models -------------------------------------------------------------- */

// Checks point count and the real-world extent (README facts) after the grid round trip.
static void check_model(const char *file, uint64_t count, const double min[3], const double max[3],
                        uint32_t attributes)
{
    sta_error err = { 0 };
    points p;
    sta_status status = read_points(sta_test_shared_path(file), NULL, 5000, &p, &err);
    if (status != STA_OK) {
        fail_msg("%s: %s", file, err.message);
    }
    assert_int_equal(p.info.kind, STA_CLOUD_PLY);
    assert_int_equal(p.info.point_count, count);
    assert_int_equal(p.info.header_point_count, count);
    assert_int_equal(p.info.skipped_point_count, 0);
    assert_int_equal(p.info.attributes, attributes);
    assert_int_equal(p.count, count);
    double lo[3] = { HUGE_VAL, HUGE_VAL, HUGE_VAL };
    double hi[3] = { -HUGE_VAL, -HUGE_VAL, -HUGE_VAL };
    for (size_t i = 0; i < p.count; i++) {
        const int32_t xyz[3] = { p.items[i].X, p.items[i].Y, p.items[i].Z };
        for (int a = 0; a < 3; a++) {
            assert_true(xyz[a] > -(1 << 30) - 1 && xyz[a] < (1 << 30) + 1);
            double v = sta_grid_apply(&p.info.grid, a, xyz[a]);
            lo[a] = fmin(lo[a], v);
            hi[a] = fmax(hi[a], v);
        }
    }
    for (int a = 0; a < 3; a++) {
        assert_true(fabs(lo[a] - min[a]) <= 1e-7 * fabs(min[a]));
        assert_true(fabs(hi[a] - max[a]) <= 1e-7 * fabs(max[a]));
        assert_true(fabs(p.info.header_min[a] - min[a]) <= 1e-7 * fabs(min[a]));
        assert_true(fabs(p.info.header_max[a] - max[a]) <= 1e-7 * fabs(max[a]));
        // One power-of-two step for all axes, fine enough for float input.
        assert_true(p.info.grid.scale[a] == p.info.grid.scale[0]);
        assert_true(p.info.grid.scale[a] < 1e-9);
    }
    points_free(&p);
}

static void bun_zipper_points(void **state)
{
    (void)state;
    STA_TEST_REQUIRE_SHARED_DATA();
    const double min[3] = { -0.0946899, 0.0329874, -0.0618736 };
    const double max[3] = { 0.0610091, 0.187321, 0.0587997 };
    check_model("models/bun_zipper.ply", 35947, min, max, STA_ATTR_INTENSITY);
}

static void bun_zipper_intensity_and_seek(void **state)
{
    (void)state;
    STA_TEST_REQUIRE_SHARED_DATA();
    const char *path = sta_test_shared_path("models/bun_zipper.ply");
    char copy[4096];
    snprintf(copy, sizeof(copy), "%s", path);
    sta_error err = { 0 };
    points all;
    assert_int_equal(read_points(copy, NULL, 4096, &all, &err), STA_OK);
    // The first vertex line reads "-0.0378297 0.12794 0.00447467 0.850855 0.5": the float
    // intensities are all within 0..1, so 0.5 is scaled to 0.5 * 65535, rounded.
    assert_int_equal(all.items[0].intensity, 32768);
    assert_true(fabs(sta_grid_apply(&all.info.grid, 0, all.items[0].X) - -0.0378297) < 1e-9);
    // ASCII seeks go through the index of every 1024th vertex.
    sta_cloud_reader *reader = NULL;
    assert_int_equal(sta_cloud_open(copy, NULL, &reader, &err), STA_OK);
    sta_point_batch batch = { 0 };
    assert_int_equal(sta_point_batch_init(&batch, 7, 0, &err), STA_OK);
    const uint64_t targets[] = { 20000, 0, 1023, 1024, 35940, 8193, 35947 };
    for (size_t t = 0; t < sizeof(targets) / sizeof(targets[0]); t++) {
        assert_int_equal(sta_cloud_seek(reader, targets[t], &err), STA_OK);
        assert_int_equal(sta_cloud_read(reader, &batch, &err), STA_OK);
        assert_int_equal(batch.first_index, targets[t]);
        size_t expected = (size_t)(all.count - targets[t] < 7 ? all.count - targets[t] : 7);
        assert_int_equal(batch.count, expected);
        for (size_t i = 0; i < batch.count; i++) {
            assert_true(same_point(&batch.points[i], &all.items[targets[t] + i]));
        }
    }
    sta_point_batch_release(&batch);
    sta_cloud_close(reader);
    points_free(&all);
}

static void bun000_skips_range_grid(void **state)
{
    (void)state;
    STA_TEST_REQUIRE_SHARED_DATA();
    const double min[3] = { -0.09475, 0.0357363, -0.0586982 };
    const double max[3] = { 0.061, 0.18794, 0.0587228 };
    check_model("models/bun000.ply", 40256, min, max, 0);
}

static void bun045_points(void **state)
{
    (void)state;
    STA_TEST_REQUIRE_SHARED_DATA();
    const double min[3] = { -0.06325, 0.0342091, -0.0451653 };
    const double max[3] = { 0.084, 0.187639, 0.0935233 };
    check_model("models/bun045.ply", 40097, min, max, 0);
}

static void bun_zipper_mesh(void **state)
{
    (void)state;
    STA_TEST_REQUIRE_SHARED_DATA();
    sta_mesh mesh = { 0 };
    sta_error err = { 0 };
    sta_status status =
        sta_ply_load_mesh(sta_test_shared_path("models/bun_zipper.ply"), &mesh, &err);
    if (status != STA_OK) {
        fail_msg("%s", err.message);
    }
    assert_int_equal(mesh.vertex_count, 35947);
    assert_int_equal(mesh.triangle_count, 69451);
    for (size_t i = 0; i < mesh.triangle_count * 3; i++) {
        assert_true(mesh.triangles[i] < mesh.vertex_count);
    }
    const double min[3] = { -0.0946899, 0.0329874, -0.0618736 };
    const double max[3] = { 0.0610091, 0.187321, 0.0587997 };
    for (int a = 0; a < 3; a++) {
        double lo = HUGE_VAL, hi = -HUGE_VAL;
        for (size_t i = 0; i < mesh.vertex_count; i++) {
            lo = fmin(lo, mesh.positions[i * 3 + (size_t)a]);
            hi = fmax(hi, mesh.positions[i * 3 + (size_t)a]);
        }
        assert_true(fabs(lo - min[a]) <= 1e-7 * fabs(min[a]));
        assert_true(fabs(hi - max[a]) <= 1e-7 * fabs(max[a]));
    }
    sta_mesh_release(&mesh);
    sta_mesh_release(&mesh); // released twice: a zeroed mesh is a no-op
}

static void bun000_mesh_has_no_faces(void **state)
{
    (void)state;
    STA_TEST_REQUIRE_SHARED_DATA();
    sta_mesh mesh = { 0 };
    sta_error err = { 0 };
    assert_int_equal(sta_ply_load_mesh(sta_test_shared_path("models/bun000.ply"), &mesh, &err),
                     STA_OK);
    assert_int_equal(mesh.vertex_count, 40256);
    assert_int_equal(mesh.triangle_count, 0);
    sta_mesh_release(&mesh);
}

/* ---- small files in all encodings ------------------------------------------------- */

typedef enum encoding {
    ENC_ASCII,
    ENC_LE,
    ENC_BE
} encoding;

static const char *const encoding_names[] = { "ascii", "binary_little_endian",
                                              "binary_big_endian" };

typedef struct sample {
    double xyz[3];
    uint8_t rgb[3];
    float normal[3];
    uint16_t intensity;
} sample;

static uint64_t lcg_state;

static double next_unit(void)
{
    lcg_state = lcg_state * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(lcg_state >> 11) / 9007199254740992.0;
}

static void make_samples(sample *s, size_t n)
{
    lcg_state = 42;
    for (size_t i = 0; i < n; i++) {
        s[i].xyz[0] = 512000.0 + 100.0 * next_unit();
        s[i].xyz[1] = 5400000.0 - 37.5 * next_unit();
        s[i].xyz[2] = -3.0 + next_unit();
        for (int c = 0; c < 3; c++) {
            s[i].rgb[c] = (uint8_t)(next_unit() * 256.0);
            s[i].normal[c] = (float)(next_unit() * 2.0 - 1.0);
        }
        s[i].intensity = (uint16_t)(next_unit() * 65536.0);
    }
}

// A PLY with a face element (lists) and a scalar element before the vertices, the
// vertices (double x/y/z, an unknown float, uchar colour, float normals, ushort
// intensity), and an element after them.
static void write_samples(buf *b, encoding enc, const sample *s, size_t n)
{
    bool be = enc == ENC_BE;
    putf(b, "ply\nformat %s 1.0\ncomment written by test_ply\n", encoding_names[enc]);
    putf(b, "element face 3\nproperty list uchar int vertex_indices\nproperty uchar flags\n");
    putf(b, "element material 2\nproperty float shininess\n");
    putf(b, "element vertex %zu\nproperty double x\nproperty double y\nproperty double z\n", n);
    putf(b, "property float confidence\nproperty uchar red\nproperty uchar green\n");
    putf(b, "property uchar blue\nproperty float nx\nproperty float ny\nproperty float nz\n");
    putf(b, "property ushort intensity\n");
    putf(b, "element edge 1\nproperty int vertex1\nproperty int vertex2\nend_header\n");
    static const int faces[3][5] = { { 3, 0, 1, 2 }, { 4, 0, 1, 2, 3 }, { 0 } };
    for (int f = 0; f < 3; f++) {
        if (enc == ENC_ASCII) {
            putf(b, "%d", faces[f][0]);
            for (int k = 1; k <= faces[f][0]; k++) {
                putf(b, " %d", faces[f][k]);
            }
            putf(b, " 7\n");
        } else {
            put_uint(b, (uint64_t)faces[f][0], 1, be);
            for (int k = 1; k <= faces[f][0]; k++) {
                put_uint(b, (uint64_t)faces[f][k], 4, be);
            }
            put_uint(b, 7, 1, be);
        }
    }
    for (int m = 0; m < 2; m++) {
        if (enc == ENC_ASCII) {
            putf(b, "%d.5\n", m);
        } else {
            put_f32(b, (float)m + 0.5f, be);
        }
    }
    for (size_t i = 0; i < n; i++) {
        if (enc == ENC_ASCII) {
            putf(b, "%.17g %.17g %.17g 0.25 %u %u %u %.9g %.9g %.9g %u\n", s[i].xyz[0], s[i].xyz[1],
                 s[i].xyz[2], s[i].rgb[0], s[i].rgb[1], s[i].rgb[2], (double)s[i].normal[0],
                 (double)s[i].normal[1], (double)s[i].normal[2], s[i].intensity);
        } else {
            for (int a = 0; a < 3; a++) {
                put_f64(b, s[i].xyz[a], be);
            }
            put_f32(b, 0.25f, be);
            put(b, s[i].rgb, 3);
            for (int a = 0; a < 3; a++) {
                put_f32(b, s[i].normal[a], be);
            }
            put_uint(b, s[i].intensity, 2, be);
        }
    }
    if (enc == ENC_ASCII) {
        putf(b, "0 1\n");
    } else {
        put_uint(b, 0, 4, be);
        put_uint(b, 1, 4, be);
    }
}

static void encodings_give_identical_points(void **state)
{
    (void)state;
    enum {
        N = 10000
    }; // more than two seek-index strides
    sample *s = calloc(N, sizeof(*s));
    assert_non_null(s);
    make_samples(s, N);
    points p[3];
    for (int enc = 0; enc < 3; enc++) {
        buf b = { 0 };
        write_samples(&b, (encoding)enc, s, N);
        char name[64], path[4096];
        snprintf(name, sizeof(name), "samples_%s.ply", encoding_names[enc]);
        write_tmp(name, b.data, b.size, path, sizeof(path));
        buf_free(&b);
        sta_error err = { 0 };
        sta_status status = read_points(path, NULL, 999, &p[enc], &err);
        if (status != STA_OK) {
            fail_msg("%s", err.message);
        }
        assert_int_equal(p[enc].count, N);
        assert_int_equal(p[enc].info.attributes,
                         STA_ATTR_RGB | STA_ATTR_NORMAL | STA_ATTR_INTENSITY);
        // Binary vertices have a fixed size: 3 doubles + float + 3 uchar + 3 floats + ushort.
        assert_int_equal(p[enc].info.record_length, enc == ENC_ASCII ? 0 : 24 + 4 + 3 + 12 + 2);
    }
    const sta_grid *grid = &p[0].info.grid;
    for (int enc = 1; enc < 3; enc++) {
        assert_memory_equal(&p[enc].info.grid, grid, sizeof(*grid));
    }
    for (size_t i = 0; i < N; i++) {
        assert_true(same_point(&p[0].items[i], &p[1].items[i]));
        assert_true(same_point(&p[0].items[i], &p[2].items[i]));
        const sta_point *q = &p[0].items[i];
        const int32_t xyz[3] = { q->X, q->Y, q->Z };
        for (int a = 0; a < 3; a++) {
            double back = sta_grid_apply(grid, a, xyz[a]);
            assert_true(fabs(back - s[i].xyz[a]) <= 0.5 * grid->scale[a] * (1.0 + 1e-9));
            assert_true(xyz[a] >= -(1 << 30) && xyz[a] <= (1 << 30));
        }
        assert_int_equal(q->red, s[i].rgb[0]);
        assert_int_equal(q->green, s[i].rgb[1]);
        assert_int_equal(q->blue, s[i].rgb[2]);
        assert_memory_equal(q->normal, s[i].normal, sizeof(q->normal));
        assert_int_equal(q->intensity, s[i].intensity);
    }
    // Grid: offset at the bounds centre, a power-of-two scale from the largest extent.
    int exponent = 0;
    assert_true(frexp(grid->scale[0], &exponent) == 0.5);
    double extent = p[0].info.header_max[0] - p[0].info.header_min[0];
    assert_true(grid->scale[0] <= extent / 1073741824.0);
    assert_true(grid->scale[0] * 2.0 > extent / 1073741824.0);
    for (int enc = 0; enc < 3; enc++) {
        points_free(&p[enc]);
    }
    free(s);
}

static void binary_seek_is_exact(void **state)
{
    (void)state;
    enum {
        N = 5000
    };
    sample *s = calloc(N, sizeof(*s));
    assert_non_null(s);
    make_samples(s, N);
    for (int enc = 0; enc < 3; enc++) {
        buf b = { 0 };
        write_samples(&b, (encoding)enc, s, N);
        char path[4096];
        write_tmp("seek.ply", b.data, b.size, path, sizeof(path));
        buf_free(&b);
        sta_error err = { 0 };
        points all;
        assert_int_equal(read_points(path, NULL, 4096, &all, &err), STA_OK);
        sta_cloud_reader *reader = NULL;
        assert_int_equal(sta_cloud_open(path, NULL, &reader, &err), STA_OK);
        sta_point_batch batch = { 0 };
        assert_int_equal(sta_point_batch_init(&batch, 3, 0, &err), STA_OK);
        const uint64_t targets[] = { 4999, 17, 4096, 0, 4095, 5000, 2500 };
        for (size_t t = 0; t < sizeof(targets) / sizeof(targets[0]); t++) {
            assert_int_equal(sta_cloud_seek(reader, targets[t], &err), STA_OK);
            assert_int_equal(sta_cloud_read(reader, &batch, &err), STA_OK);
            size_t expected = (size_t)(N - targets[t] < 3 ? N - targets[t] : 3);
            assert_int_equal(batch.count, expected);
            for (size_t i = 0; i < batch.count; i++) {
                assert_true(same_point(&batch.points[i], &all.items[targets[t] + i]));
            }
        }
        assert_int_equal(sta_cloud_seek(reader, N + 1, &err), STA_ERR_ARG);
        sta_point_batch_release(&batch);
        sta_cloud_close(reader);
        points_free(&all);
    }
    free(s);
}

// Vertices with a list property have no fixed size: binary seeks use the index too.
static void vertex_list_property_is_skipped(void **state)
{
    (void)state;
    enum {
        N = 9000
    };
    for (int enc = 0; enc < 3; enc++) {
        bool be = enc == ENC_BE;
        buf b = { 0 };
        putf(&b, "ply\nformat %s 1.0\nelement vertex %d\nproperty float x\n", encoding_names[enc],
             N);
        putf(&b, "property list uchar short tags\nproperty float y\nproperty float z\n");
        putf(&b, "end_header\n");
        for (int i = 0; i < N; i++) {
            int tags = i % 4;
            if (enc == ENC_ASCII) {
                putf(&b, "%d %d", i, tags);
                for (int k = 0; k < tags; k++) {
                    putf(&b, " %d", -k);
                }
                putf(&b, " %d.5 %d\n", i % 100, -i);
            } else {
                put_f32(&b, (float)i, be);
                put_uint(&b, (uint64_t)tags, 1, be);
                for (int k = 0; k < tags; k++) {
                    put_uint(&b, (uint16_t)-k, 2, be);
                }
                put_f32(&b, (float)(i % 100) + 0.5f, be);
                put_f32(&b, (float)-i, be);
            }
        }
        char path[4096];
        write_tmp("vlist.ply", b.data, b.size, path, sizeof(path));
        buf_free(&b);
        sta_error err = { 0 };
        sta_cloud_reader *reader = NULL;
        assert_int_equal(sta_cloud_open(path, NULL, &reader, &err), STA_OK);
        const sta_cloud_info *info = sta_cloud_reader_info(reader);
        assert_int_equal(info->point_count, N);
        assert_int_equal(info->record_length, 0);
        sta_point_batch batch = { 0 };
        assert_int_equal(sta_point_batch_init(&batch, 2, 0, &err), STA_OK);
        const uint64_t targets[] = { 8999, 0, 4097, 8192, 123, 4096 };
        for (size_t t = 0; t < sizeof(targets) / sizeof(targets[0]); t++) {
            assert_int_equal(sta_cloud_seek(reader, targets[t], &err), STA_OK);
            assert_int_equal(sta_cloud_read(reader, &batch, &err), STA_OK);
            assert_true(batch.count >= 1);
            for (size_t i = 0; i < batch.count; i++) {
                int v = (int)(targets[t] + i);
                const sta_point *q = &batch.points[i];
                assert_true(sta_grid_apply(&info->grid, 0, q->X) == (double)v);
                assert_true(sta_grid_apply(&info->grid, 1, q->Y) == (double)(v % 100) + 0.5);
                assert_true(sta_grid_apply(&info->grid, 2, q->Z) == (double)-v);
            }
        }
        sta_point_batch_release(&batch);
        sta_cloud_close(reader);
    }
}

static void float_colours_and_intensity(void **state)
{
    (void)state;
    const char unit[] = "ply\nformat ascii 1.0\nelement vertex 3\n"
                        "property float x\nproperty float y\nproperty float z\n"
                        "property float r\nproperty float g\nproperty float b\n"
                        "property double scalar_intensity\nend_header\n"
                        "0 0 0 0 0.5 1 0\n"
                        "1 0 0 1.5 -0.5 0.2 0.25\n"
                        "2 0 0 0.1 0.9 1 1\n";
    char path[4096];
    write_tmp("unit.ply", unit, sizeof(unit) - 1, path, sizeof(path));
    sta_error err = { 0 };
    points p;
    assert_int_equal(read_points(path, NULL, 2, &p, &err), STA_OK);
    assert_int_equal(p.info.attributes, STA_ATTR_RGB | STA_ATTR_INTENSITY);
    // Float colour is 0..1 scaled to 0..255 (clamped, rounded).
    assert_int_equal(p.items[0].red, 0);
    assert_int_equal(p.items[0].green, 128);
    assert_int_equal(p.items[0].blue, 255);
    assert_int_equal(p.items[1].red, 255);
    assert_int_equal(p.items[1].green, 0);
    assert_int_equal(p.items[1].blue, 51);
    // All intensities within 0..1: scaled by 65535.
    assert_int_equal(p.items[0].intensity, 0);
    assert_int_equal(p.items[1].intensity, 16384);
    assert_int_equal(p.items[2].intensity, 65535);
    points_free(&p);

    const char wide[] = "ply\nformat ascii 1.0\nelement vertex 3\n"
                        "property float x\nproperty float y\nproperty float z\n"
                        "property float intensity\nproperty ushort red\nproperty ushort green\n"
                        "property ushort blue\nproperty float scalar\nend_header\n"
                        "0 0 0 0.4 65535 256 0 9\n"
                        "1 0 0 1200.6 1 2 3 9\n"
                        "2 0 0 70000 0 0 0 9\n";
    write_tmp("wide.ply", wide, sizeof(wide) - 1, path, sizeof(path));
    assert_int_equal(read_points(path, NULL, 10, &p, &err), STA_OK);
    // Not all within 0..1: rounded and clamped to 0..65535; ushort colour kept as is.
    assert_int_equal(p.items[0].intensity, 0);
    assert_int_equal(p.items[1].intensity, 1201);
    assert_int_equal(p.items[2].intensity, 65535);
    assert_int_equal(p.items[0].red, 65535);
    assert_int_equal(p.items[0].green, 256);
    assert_int_equal(p.items[1].blue, 3);
    points_free(&p);
}

static void crlf_header_and_body(void **state)
{
    (void)state;
    const char text[] = "ply\r\nformat ascii 1.0\r\ncomment made on Windows\r\n"
                        "element vertex 2\r\nproperty float x\r\nproperty float y\r\n"
                        "property float z\r\nproperty uchar red\r\nproperty uchar green\r\n"
                        "property uchar blue\r\nend_header\r\n"
                        "1.5 2.5 -3.5 10 20 30\r\n"
                        "\r\n"
                        "-1.5 0.25 3.5 40 50 60\r\n";
    char path[4096];
    write_tmp("crlf.ply", text, sizeof(text) - 1, path, sizeof(path));
    sta_error err = { 0 };
    points p;
    sta_status status = read_points(path, NULL, 16, &p, &err);
    if (status != STA_OK) {
        fail_msg("%s", err.message);
    }
    assert_int_equal(p.count, 2);
    assert_true(sta_grid_apply(&p.info.grid, 0, p.items[0].X) == 1.5);
    assert_true(sta_grid_apply(&p.info.grid, 1, p.items[1].Y) == 0.25);
    assert_true(sta_grid_apply(&p.info.grid, 2, p.items[1].Z) == 3.5);
    assert_int_equal(p.items[1].blue, 60);
    points_free(&p);

    // A binary body after a CRLF header starts right after "end_header\r\n".
    buf b = { 0 };
    putf(&b, "ply\r\nformat binary_little_endian 1.0\r\nelement vertex 1\r\n"
             "property float x\r\nproperty float y\r\nproperty float z\r\nend_header\r\n");
    put_f32(&b, 10.0f, false);
    put_f32(&b, 13.0f, false);
    put_f32(&b, -2.0f, false);
    write_tmp("crlf_bin.ply", b.data, b.size, path, sizeof(path));
    buf_free(&b);
    assert_int_equal(read_points(path, NULL, 16, &p, &err), STA_OK);
    assert_int_equal(p.count, 1);
    assert_true(sta_grid_apply(&p.info.grid, 1, p.items[0].Y) == 13.0);
    assert_true(sta_grid_apply(&p.info.grid, 2, p.items[0].Z) == -2.0);
    points_free(&p);
}

static void big_endian_floats(void **state)
{
    (void)state;
    buf b = { 0 };
    putf(&b, "ply\nformat binary_big_endian 1.0\nelement vertex 2\nproperty float32 x\n"
             "property float64 y\nproperty int16 z\nproperty uint8 intensity\nend_header\n");
    // 1.5f = 3f c0 00 00; -2.0 (double) = c0 00 00 ...; z = -2 as int16 = ff fe.
    const uint8_t v0[] = { 0x3f, 0xc0, 0x00, 0x00, 0xc0, 0x00, 0x00, 0x00,
                           0x00, 0x00, 0x00, 0x00, 0xff, 0xfe, 0xc8 };
    put(&b, v0, sizeof(v0));
    put_f32(&b, 256.25f, true);
    put_f64(&b, 1e6, true);
    put_uint(&b, 7, 2, true);
    put_uint(&b, 3, 1, true);
    char path[4096];
    write_tmp("be.ply", b.data, b.size, path, sizeof(path));
    buf_free(&b);
    sta_error err = { 0 };
    points p;
    assert_int_equal(read_points(path, NULL, 16, &p, &err), STA_OK);
    assert_int_equal(p.count, 2);
    const sta_grid *g = &p.info.grid;
    assert_true(sta_grid_apply(g, 0, p.items[0].X) == 1.5);
    assert_true(sta_grid_apply(g, 1, p.items[0].Y) == -2.0);
    assert_true(sta_grid_apply(g, 2, p.items[0].Z) == -2.0);
    assert_true(sta_grid_apply(g, 0, p.items[1].X) == 256.25);
    assert_true(sta_grid_apply(g, 1, p.items[1].Y) == 1e6);
    assert_true(sta_grid_apply(g, 2, p.items[1].Z) == 7.0);
    assert_int_equal(p.items[0].intensity, 200);
    assert_int_equal(p.items[1].intensity, 3);
    assert_true(p.info.header_min[1] == -2.0 && p.info.header_max[1] == 1e6);
    points_free(&p);
}

static void zero_and_one_vertex(void **state)
{
    (void)state;
    const char empty[] = "ply\nformat binary_little_endian 1.0\nelement vertex 0\n"
                         "property float x\nproperty float y\nproperty float z\nend_header\n";
    char path[4096];
    write_tmp("empty.ply", empty, sizeof(empty) - 1, path, sizeof(path));
    sta_error err = { 0 };
    points p;
    assert_int_equal(read_points(path, NULL, 16, &p, &err), STA_OK);
    assert_int_equal(p.info.point_count, 0);
    assert_int_equal(p.count, 0);
    assert_true(p.info.grid.scale[0] > 0.0);
    points_free(&p);

    // One point: zero extent still gives a positive grid step, and the point is exact.
    const char one[] = "ply\nformat ascii 1.0\nelement vertex 1\n"
                       "property double x\nproperty double y\nproperty double z\nend_header\n"
                       "6378137.125 -33.0000001 1e-3";
    write_tmp("one.ply", one, sizeof(one) - 1, path, sizeof(path));
    assert_int_equal(read_points(path, NULL, 16, &p, &err), STA_OK);
    assert_int_equal(p.count, 1);
    assert_true(p.info.grid.scale[0] == ldexp(1.0, -30));
    assert_true(sta_grid_apply(&p.info.grid, 0, p.items[0].X) == 6378137.125);
    assert_true(sta_grid_apply(&p.info.grid, 1, p.items[0].Y) == -33.0000001);
    assert_true(sta_grid_apply(&p.info.grid, 2, p.items[0].Z) == 1e-3);
    points_free(&p);
}

/* ---- broken files ----------------------------------------------------------------- */

static void build_small_binary(buf *b, int declared, int written)
{
    putf(b,
         "ply\nformat binary_little_endian 1.0\nelement vertex %d\nproperty float x\n"
         "property float y\nproperty float z\nend_header\n",
         declared);
    for (int i = 0; i < written; i++) {
        put_f32(b, (float)i, false);
        put_f32(b, (float)(2 * i), false);
        put_f32(b, (float)(3 * i), false);
    }
}

static void truncated_binary_body(void **state)
{
    (void)state;
    buf b = { 0 };
    build_small_binary(&b, 10, 10);
    b.size -= 20; // cuts vertex 8 and all of vertex 9
    expect_open_error("trunc.ply", b.data, b.size, STA_ERR_FORMAT, "8 vertices are complete", NULL);
    // Salvage reads the complete vertices and says how many were missing.
    char path[4096];
    write_tmp("trunc.ply", b.data, b.size, path, sizeof(path));
    buf_free(&b);
    const sta_read_options salvage = { .salvage_truncated = true };
    sta_error err = { 0 };
    points p;
    assert_int_equal(read_points(path, &salvage, 3, &p, &err), STA_OK);
    assert_int_equal(p.info.point_count, 8);
    assert_int_equal(p.info.header_point_count, 10);
    assert_int_equal(p.info.skipped_point_count, 2);
    assert_int_equal(p.count, 8);
    assert_true(sta_grid_apply(&p.info.grid, 2, p.items[7].Z) == 21.0);
    points_free(&p);

    // ASCII: the last line cut in its middle, and lines missing at the end.
    const char text[] = "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\n"
                        "property float y\nproperty float z\nend_header\n"
                        "1 2 3\n4 5 6\n7 8 9\n10 11";
    expect_open_error("trunc_ascii.ply", text, sizeof(text) - 1, STA_ERR_FORMAT,
                      "only 3 of 5 vertices are complete", NULL);
    write_tmp("trunc_ascii.ply", text, sizeof(text) - 1, path, sizeof(path));
    assert_int_equal(read_points(path, &salvage, 2, &p, &err), STA_OK);
    assert_int_equal(p.count, 3);
    assert_int_equal(p.info.skipped_point_count, 2);
    assert_true(sta_grid_apply(&p.info.grid, 0, p.items[2].X) == 7.0);
    points_free(&p);
}

static void count_too_large(void **state)
{
    (void)state;
    buf b = { 0 };
    build_small_binary(&b, 0, 4);
    buf big = { 0 };
    putf(&big, "ply\nformat binary_little_endian 1.0\nelement vertex 1000000000000000000\n"
               "property float x\nproperty float y\nproperty float z\nend_header\n");
    put(&big, b.data + b.size - 48, 48);
    expect_open_error("huge_count.ply", big.data, big.size, STA_ERR_FORMAT,
                      "declares 1000000000000000000 vertices", "4 vertices are complete", NULL);
    buf_free(&big);
    // A face element before the vertices that claims more records than the file holds.
    putf(&big, "ply\nformat binary_little_endian 1.0\nelement face 18446744073709551615\n"
               "property int flags\nelement vertex 1\nproperty float x\nproperty float y\n"
               "property float z\nend_header\n");
    put(&big, b.data + b.size - 12, 12);
    expect_open_error("huge_face.ply", big.data, big.size, STA_ERR_FORMAT,
                      "element \"face\" declares 18446744073709551615 records", NULL);
    buf_free(&big);
    // A count that does not fit 64 bits is not a count.
    const char text[] = "ply\nformat ascii 1.0\nelement vertex 99999999999999999999\n"
                        "property float x\nproperty float y\nproperty float z\nend_header\n";
    expect_open_error("overflow.ply", text, sizeof(text) - 1, STA_ERR_FORMAT, "header line 3",
                      "99999999999999999999", NULL);
    buf_free(&b);
}

static void missing_x(void **state)
{
    (void)state;
    const char text[] = "ply\nformat ascii 1.0\nelement vertex 1\n"
                        "property float y\nproperty float z\nend_header\n1 2\n";
    expect_open_error("no_x.ply", text, sizeof(text) - 1, STA_ERR_FORMAT, "no property \"x\"",
                      NULL);
    const char none[] = "ply\nformat ascii 1.0\nelement point 1\nproperty float x\n"
                        "end_header\n1\n";
    expect_open_error("no_vertex.ply", none, sizeof(none) - 1, STA_ERR_FORMAT,
                      "no \"vertex\" element", NULL);
    const char list[] = "ply\nformat ascii 1.0\nelement vertex 1\nproperty list uchar float x\n"
                        "property float y\nproperty float z\nend_header\n1 5 2 3\n";
    expect_open_error("list_x.ply", list, sizeof(list) - 1, STA_ERR_FORMAT, "\"x\"", "list", NULL);
}

static void nan_coordinate(void **state)
{
    (void)state;
    const char text[] = "ply\nformat ascii 1.0\nelement vertex 4\n"
                        "property float x\nproperty float y\nproperty float z\nend_header\n"
                        "1 2 3\n4 5 6\n7 nan 9\n1 1 1\n";
    expect_open_error("nan.ply", text, sizeof(text) - 1, STA_ERR_FORMAT, "vertex 2",
                      "property \"y\" is NaN", NULL);
    buf b = { 0 };
    build_small_binary(&b, 3, 2);
    put_f32(&b, 1.0f, false);
    put_f32(&b, 1.0f, false);
    put_f32(&b, INFINITY, false);
    expect_open_error("inf.ply", b.data, b.size, STA_ERR_FORMAT, "vertex 2",
                      "property \"z\" is infinite", NULL);
    buf_free(&b);
}

static void bad_list_count(void **state)
{
    (void)state;
    const char text[] = "ply\nformat ascii 1.0\nelement face 2\n"
                        "property list uchar int vertex_indices\nelement vertex 1\n"
                        "property float x\nproperty float y\nproperty float z\nend_header\n"
                        "3 0 1 2\n-1 0\n1 2 3\n";
    expect_open_error("neg_list.ply", text, sizeof(text) - 1, STA_ERR_FORMAT, "line 11", "face 1",
                      "vertex_indices", "negative", NULL);
    const char huge[] = "ply\nformat ascii 1.0\nelement face 1\n"
                        "property list int int vertex_indices\nelement vertex 1\n"
                        "property float x\nproperty float y\nproperty float z\nend_header\n"
                        "2000000000 0 1 2\n1 2 3\n";
    expect_open_error("big_list.ply", huge, sizeof(huge) - 1, STA_ERR_FORMAT, "2000000000",
                      "larger than the fields left on the line", NULL);
    // Binary: a signed count of -1, and an unsigned one whose items pass the end.
    for (int variant = 0; variant < 2; variant++) {
        buf b = { 0 };
        putf(&b,
             "ply\nformat binary_little_endian 1.0\nelement face 1\n"
             "property list %s int vertex_indices\nelement vertex 1\nproperty float x\n"
             "property float y\nproperty float z\nend_header\n",
             variant == 0 ? "char" : "uint");
        put_uint(&b, variant == 0 ? 0xff : 0xfffffff0u, variant == 0 ? 1 : 4, false);
        for (int i = 0; i < 6; i++) {
            put_f32(&b, 1.0f, false);
        }
        if (variant == 0) {
            expect_open_error("neg_list_bin.ply", b.data, b.size, STA_ERR_FORMAT, "face 0",
                              "count -1 is negative", NULL);
        } else {
            expect_open_error("big_list_bin.ply", b.data, b.size, STA_ERR_FORMAT, "face 0",
                              "count 4294967280", "bytes left", NULL);
        }
        buf_free(&b);
    }
}

static void garbage_header_line(void **state)
{
    (void)state;
    const char text[] = "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
                        "hello world\nproperty float y\nend_header\n";
    expect_open_error("garbage.ply", text, sizeof(text) - 1, STA_ERR_FORMAT, "header line 5",
                      "unknown keyword \"hello\"", NULL);
    const char type[] = "ply\nformat ascii 1.0\nelement vertex 1\nproperty float128 x\n"
                        "end_header\n";
    expect_open_error("bad_type.ply", type, sizeof(type) - 1, STA_ERR_FORMAT,
                      "unknown property type \"float128\"", NULL);
    const char no_end[] = "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n";
    expect_open_error("no_end.ply", no_end, sizeof(no_end) - 1, STA_ERR_FORMAT, "no end_header",
                      NULL);
    const char format[] = "ply\nformat binary_middle_endian 1.0\nend_header\n";
    expect_open_error("bad_format.ply", format, sizeof(format) - 1, STA_ERR_FORMAT,
                      "unknown format \"binary_middle_endian\"", NULL);
    const char version[] = "ply\nformat ascii 2.0\nend_header\n";
    expect_open_error("bad_version.ply", version, sizeof(version) - 1, STA_ERR_FORMAT,
                      "version \"2.0\"", NULL);
    const char no_format[] = "ply\nelement vertex 0\nproperty float x\nend_header\n";
    expect_open_error("no_format.ply", no_format, sizeof(no_format) - 1, STA_ERR_FORMAT,
                      "no format line", NULL);
    const char orphan[] = "ply\nformat ascii 1.0\nproperty float x\nend_header\n";
    expect_open_error("orphan.ply", orphan, sizeof(orphan) - 1, STA_ERR_FORMAT,
                      "property before any element", NULL);
    const char float_count[] = "ply\nformat ascii 1.0\nelement face 0\n"
                               "property list float int vertex_indices\nend_header\n";
    expect_open_error("float_count.ply", float_count, sizeof(float_count) - 1, STA_ERR_FORMAT,
                      "count type \"float\" is not an integer type", NULL);
}

static void not_ply(void **state)
{
    (void)state;
    const char text[] = "hello, this is not a point cloud\n";
    expect_open_error("hello.ply", text, sizeof(text) - 1, STA_ERR_UNSUPPORTED, "not a LAS or PLY",
                      NULL);
    // The PLY opener itself names a file whose first line is not "ply".
    const char almost[] = "ply\rformat ascii 1.0\n";
    expect_open_error("almost.ply", almost, sizeof(almost) - 1, STA_ERR_FORMAT, "not a PLY file",
                      NULL);
    sta_file_map map = { 0 };
    sta_error err = { 0 };
    assert_int_equal(sta_file_map_wrap((const uint8_t *)"plyx", 4, "mem.ply", &map, &err), STA_OK);
    void *impl = NULL;
    const sta_cloud_ops *ops = NULL;
    assert_int_equal(sta_ply_open_map(&map, NULL, &impl, &ops, &err), STA_ERR_FORMAT);
    assert_non_null(strstr(err.message, "mem.ply"));
    assert_null(impl);
    sta_file_map_close(&map);
}

static void ascii_bad_fields(void **state)
{
    (void)state;
    const char few[] = "ply\nformat ascii 1.0\nelement vertex 2\n"
                       "property float x\nproperty float y\nproperty float z\nend_header\n"
                       "1 2 3\n4 5\n";
    expect_open_error("few.ply", few, sizeof(few) - 1, STA_ERR_FORMAT, "line 9", "vertex 1",
                      "too few fields", "\"z\"", NULL);
    const char many[] = "ply\nformat ascii 1.0\nelement vertex 1\n"
                        "property float x\nproperty float y\nproperty float z\nend_header\n"
                        "1 2 3 4\n";
    expect_open_error("many.ply", many, sizeof(many) - 1, STA_ERR_FORMAT, "line 8",
                      "extra field \"4\"", NULL);
    const char word[] = "ply\nformat ascii 1.0\nelement vertex 2\n"
                        "property float x\nproperty float y\nproperty float z\nend_header\n"
                        "1 2 3\n4 five 6\n";
    expect_open_error("word.ply", word, sizeof(word) - 1, STA_ERR_FORMAT, "line 9",
                      "field \"five\" is not a number", NULL);
    const char range[] = "ply\nformat ascii 1.0\nelement vertex 1\n"
                         "property float x\nproperty float y\nproperty float z\n"
                         "property uchar red\nproperty uchar green\nproperty uchar blue\n"
                         "end_header\n1 2 3 300 0 0\n";
    expect_open_error("range.ply", range, sizeof(range) - 1, STA_ERR_FORMAT,
                      "value 300 is not a uchar", NULL);
    // The map is not NUL-terminated: a field at the very end of the file still parses.
    const char tail[] = "ply\nformat ascii 1.0\nelement vertex 1\n"
                        "property float x\nproperty float y\nproperty float z\nend_header\n"
                        "1 2 3.25";
    sta_cloud_reader *reader = NULL;
    sta_error err = { 0 };
    assert_int_equal(sta_cloud_open_memory((const uint8_t *)tail, sizeof(tail) - 1, "tail.ply",
                                           NULL, &reader, &err),
                     STA_OK);
    assert_true(sta_cloud_reader_info(reader)->header_max[2] == 3.25);
    sta_cloud_close(reader);
}

// ASCII numbers parse to the same double as strtod, whichever path the parser takes.
static void ascii_numbers_parse_exactly(void **state)
{
    (void)state;
    static const char *const fixed[] = {
        "0",
        "-0",
        "+.5",
        "5.",
        "1E-5",
        "1e22",
        "1e23",
        "-1e-22",
        "123456789012345678",
        "9007199254740993",
        "9007199254740992",
        "0.1",
        "4.9e-324",
        "1.7976931348623157e308",
        "0.30000000000000004",
        "1234567890123456789012",
        "-0.000000000000000000000000123",
        "0x1p-3",
        "2.2250738585072014e-308",
        "1e+0",
        "7e-0",
    };
    enum {
        RANDOM = 3000,
        FIXED = sizeof(fixed) / sizeof(fixed[0])
    };
    char(*text)[64] = calloc(RANDOM + FIXED, sizeof(*text));
    assert_non_null(text);
    lcg_state = 7;
    for (size_t i = 0; i < RANDOM; i++) {
        double v = (next_unit() - 0.5) * pow(10.0, floor(next_unit() * 30.0) - 15.0);
        static const int digits[] = { 17, 6, 9, 15, 3, 12 };
        if (i % 3 == 0) {
            snprintf(text[i], sizeof(text[i]), "%.*g", digits[i % 6], v);
        } else if (i % 3 == 1) {
            snprintf(text[i], sizeof(text[i]), "%.*e", digits[i % 6], v);
        } else {
            snprintf(text[i], sizeof(text[i]), "%.*f", digits[i % 6], v);
        }
    }
    for (size_t i = 0; i < FIXED; i++) {
        snprintf(text[RANDOM + i], sizeof(text[0]), "%s", fixed[i]);
    }
    buf b = { 0 };
    putf(&b,
         "ply\nformat ascii 1.0\nelement vertex %d\nproperty double x\nproperty float y\n"
         "property float z\nend_header\n",
         RANDOM + FIXED);
    for (size_t i = 0; i < RANDOM + FIXED; i++) {
        putf(&b, "%s 0 0\n", text[i]);
    }
    sta_mesh mesh = { 0 };
    sta_error err = { 0 };
    sta_status status = sta_ply_load_mesh_memory(b.data, b.size, "numbers.ply", &mesh, &err);
    if (status != STA_OK) {
        fail_msg("%s", err.message);
    }
    for (size_t i = 0; i < RANDOM + FIXED; i++) {
        double want = strtod(text[i], NULL);
        if (memcmp(&mesh.positions[i * 3], &want, sizeof(want)) != 0) {
            fail_msg("\"%s\" parsed as %.17g, strtod gives %.17g", text[i], mesh.positions[i * 3],
                     want);
        }
    }
    sta_mesh_release(&mesh);
    buf_free(&b);
    free(text);
}

/* ---- mesh ------------------------------------------------------------------------- */

static void mesh_fans_polygons_and_checks_indices(void **state)
{
    (void)state;
    for (int enc = 0; enc < 3; enc++) {
        bool be = enc == ENC_BE;
        buf b = { 0 };
        putf(&b,
             "ply\nformat %s 1.0\nelement face 3\nproperty uchar flags\n"
             "property list uchar uint vertex_index\nelement vertex 5\nproperty float x\n"
             "property float y\nproperty float z\nend_header\n",
             encoding_names[enc]);
        static const int faces[3][6] = { { 4, 0, 1, 2, 3 }, { 3, 2, 3, 4 }, { 2, 0, 1 } };
        for (int f = 0; f < 3; f++) {
            if (enc == ENC_ASCII) {
                putf(&b, "1 %d", faces[f][0]);
                for (int k = 1; k <= faces[f][0]; k++) {
                    putf(&b, " %d", faces[f][k]);
                }
                putf(&b, "\n");
            } else {
                put_uint(&b, 1, 1, be);
                put_uint(&b, (uint64_t)faces[f][0], 1, be);
                for (int k = 1; k <= faces[f][0]; k++) {
                    put_uint(&b, (uint64_t)faces[f][k], 4, be);
                }
            }
        }
        for (int v = 0; v < 5; v++) {
            if (enc == ENC_ASCII) {
                putf(&b, "%d 0.5 -1\n", v);
            } else {
                put_f32(&b, (float)v, be);
                put_f32(&b, 0.5f, be);
                put_f32(&b, -1.0f, be);
            }
        }
        sta_mesh mesh = { 0 };
        sta_error err = { 0 };
        sta_status status = sta_ply_load_mesh_memory(b.data, b.size, "fan.ply", &mesh, &err);
        if (status != STA_OK) {
            fail_msg("%s", err.message);
        }
        assert_int_equal(mesh.vertex_count, 5);
        // A quad gives 2 triangles, a triangle 1, a two-vertex face none.
        assert_int_equal(mesh.triangle_count, 3);
        const uint32_t want[9] = { 0, 1, 2, 0, 2, 3, 2, 3, 4 };
        assert_memory_equal(mesh.triangles, want, sizeof(want));
        assert_true(mesh.positions[3 * 4] == 4.0 && mesh.positions[3 * 4 + 1] == 0.5);
        sta_mesh_release(&mesh);

        // Vertex index 5 of 5 vertices is out of range.
        if (enc == ENC_ASCII) {
            uint8_t *line = buf_find(&b, "1 3 2 3 4");
            assert_non_null(line);
            line[8] = '5';
        } else {
            // The last index of face 1: after the header, face 0 (1+1+16) and 1+1+8 bytes.
            const uint8_t *end = buf_find(&b, "end_header\n");
            assert_non_null(end);
            size_t at = (size_t)(end - b.data) + 11 + 18 + 10;
            memset(b.data + at, 0, 4);
            b.data[at + (be ? 3 : 0)] = 5;
        }
        assert_int_equal(sta_ply_load_mesh_memory(b.data, b.size, "fan.ply", &mesh, &err),
                         STA_ERR_FORMAT);
        assert_non_null(strstr(err.message, "fan.ply"));
        assert_non_null(strstr(err.message, "face 1: vertex index 5"));
        assert_null(mesh.triangles);
        buf_free(&b);
    }
    sta_mesh mesh = { 0 };
    sta_error err = { 0 };
    assert_int_equal(sta_ply_load_mesh(sta_test_tmp_path("missing.ply"), &mesh, &err), STA_ERR_IO);
}

/* ---- allocation failures ---------------------------------------------------------- */

static void allocation_failures_clean_up(void **state)
{
    (void)state;
    enum {
        N = 5000
    };
    sample *s = calloc(N, sizeof(*s));
    assert_non_null(s);
    make_samples(s, N);
    buf b = { 0 };
    write_samples(&b, ENC_ASCII, s, N);
    free(s);
    char path[4096];
    write_tmp("alloc.ply", b.data, b.size, path, sizeof(path));
    bool done = false;
    long n = 0;
    for (; !done && n < 1000; n++) {
        sta_error err = { 0 };
        sta_cloud_reader *reader = NULL;
        sta_point_batch batch = { 0 };
        sta_mesh mesh = { 0 };
        size_t total = 0;
        sta_alloc_fail_after(n);
        sta_status status = sta_cloud_open(path, NULL, &reader, &err);
        if (status == STA_OK) {
            status = sta_point_batch_init(&batch, 1000, 0, &err);
        }
        while (status == STA_OK) {
            status = sta_cloud_read(reader, &batch, &err);
            if (status != STA_OK || batch.count == 0) {
                break;
            }
            total += batch.count;
        }
        if (status == STA_OK) {
            status = sta_cloud_seek(reader, 4500, &err);
        }
        if (status == STA_OK) {
            status = sta_ply_load_mesh_memory(b.data, b.size, "alloc.ply", &mesh, &err);
        }
        sta_alloc_fail_after(-1);
        if (status != STA_OK && status != STA_ERR_NOMEM) {
            fail_msg("allocation %ld: %s", n, err.message);
        }
        if (status == STA_OK) {
            assert_int_equal(total, N);
            assert_int_equal(mesh.triangle_count, 3); // faces {3}, {4} and {0} vertices
            done = true;
        }
        sta_mesh_release(&mesh);
        sta_point_batch_release(&batch);
        sta_cloud_close(reader);
    }
    assert_true(done);
    assert_true(n > 5); // the loop really failed allocations along the way
    buf_free(&b);
}

static const struct CMUnitTest tests[] = {
    cmocka_unit_test(bun_zipper_points),
    cmocka_unit_test(bun_zipper_intensity_and_seek),
    cmocka_unit_test(bun000_skips_range_grid),
    cmocka_unit_test(bun045_points),
    cmocka_unit_test(bun_zipper_mesh),
    cmocka_unit_test(bun000_mesh_has_no_faces),
    cmocka_unit_test(encodings_give_identical_points),
    cmocka_unit_test(binary_seek_is_exact),
    cmocka_unit_test(vertex_list_property_is_skipped),
    cmocka_unit_test(float_colours_and_intensity),
    cmocka_unit_test(crlf_header_and_body),
    cmocka_unit_test(big_endian_floats),
    cmocka_unit_test(zero_and_one_vertex),
    cmocka_unit_test(truncated_binary_body),
    cmocka_unit_test(count_too_large),
    cmocka_unit_test(missing_x),
    cmocka_unit_test(nan_coordinate),
    cmocka_unit_test(bad_list_count),
    cmocka_unit_test(garbage_header_line),
    cmocka_unit_test(not_ply),
    cmocka_unit_test(ascii_bad_fields),
    cmocka_unit_test(ascii_numbers_parse_exactly),
    cmocka_unit_test(mesh_fans_polygons_and_checks_indices),
    cmocka_unit_test(allocation_failures_clean_up),
};

STA_TEST_MAIN(tests)
