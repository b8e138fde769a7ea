/* SPDX-License-Identifier: MIT
 * End-to-end tests of strata-convert's pipeline (preprocess/convert.c): every input
 * point comes back exactly once with identical integer coordinates and attributes,
 * the nested-octree invariants hold, bad input leaves nothing behind. */
#include "test_support.h"

#include <dirent.h>
#include <glob.h>
#include <math.h>
#include <pthread.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "convert.h"
#include "core/alloc.h"
#include "core/log.h"
#include "format/strata_reader.h"
#include "io/cloud.h"
#include "io/las_write.h"
#include "output_grid.h"

/* Order-independent digest of a multiset of points: count, sum and sum of squares of
 * a 64-bit hash of every field that the converter must keep. */
typedef struct digest {
    uint64_t count, sum, sum_sq;
} digest;

static uint64_t mix(uint64_t h, uint64_t v)
{
    h ^= v + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
    h *= 0xff51afd7ed558ccdull;
    return h ^ (h >> 33);
}

static void digest_add(digest *d, const sta_point *p, uint32_t attributes, int64_t dx, int64_t dy,
                       int64_t dz)
{
    uint64_t h = 1469598103934665603ull;
    h = mix(h, (uint64_t)((int64_t)p->X + dx));
    h = mix(h, (uint64_t)((int64_t)p->Y + dy));
    h = mix(h, (uint64_t)((int64_t)p->Z + dz));
    if (attributes & STA_ATTR_INTENSITY) {
        h = mix(h, p->intensity);
    }
    if (attributes & STA_ATTR_RETURNS) {
        h = mix(h, (uint64_t)p->return_number << 8 | p->number_of_returns);
    }
    if (attributes & STA_ATTR_CLASSIFICATION) {
        h = mix(h, (uint64_t)p->classification << 8 | p->classification_flags);
    }
    if (attributes & STA_ATTR_GPS_TIME) {
        uint64_t bits;
        memcpy(&bits, &p->gps_time, sizeof(bits));
        h = mix(h, bits);
    }
    if (attributes & STA_ATTR_RGB) {
        h = mix(h, (uint64_t)p->red << 32 | (uint64_t)p->green << 16 | p->blue);
    }
    if (attributes & STA_ATTR_POINT_SOURCE_ID) {
        h = mix(h, p->point_source_id);
    }
    if (attributes & STA_ATTR_SCAN_ANGLE) {
        h = mix(h, (uint16_t)p->scan_angle);
    }
    if (attributes & STA_ATTR_USER_DATA) {
        h = mix(h, p->user_data);
    }
    if (attributes & STA_ATTR_NIR) {
        h = mix(h, p->nir);
    }
    d->count++;
    d->sum += h;
    d->sum_sq += h * h;
}

// Digest of the inputs (on the first input's grid: all test inputs share it).
static uint32_t digest_inputs(const char *const *paths, size_t count, digest *d)
{
    memset(d, 0, sizeof(*d));
    uint32_t attributes = 0;
    for (size_t f = 0; f < count; f++) {
        sta_cloud_reader *r = NULL;
        sta_error err = { 0 };
        assert_int_equal(sta_cloud_open(paths[f], NULL, &r, &err), STA_OK);
        const sta_cloud_info *info = sta_cloud_reader_info(r);
        attributes |= info->attributes;
        sta_point_batch batch;
        assert_int_equal(sta_point_batch_init(&batch, 4096, info->extra_size, &err), STA_OK);
        for (;;) {
            assert_int_equal(sta_cloud_read(r, &batch, &err), STA_OK);
            if (batch.count == 0) {
                break;
            }
            for (size_t i = 0; i < batch.count; i++) {
                digest_add(d, &batch.points[i], info->attributes, 0, 0, 0);
            }
        }
        sta_point_batch_release(&batch);
        sta_cloud_close(r);
    }
    return attributes;
}

static void digest_output(const char *path, uint32_t attributes, digest *d)
{
    memset(d, 0, sizeof(*d));
    sta_strata_reader *r = NULL;
    sta_strata_decoder *dec = NULL;
    sta_error err = { 0 };
    assert_int_equal(sta_strata_open(path, NULL, &r, &err), STA_OK);
    assert_int_equal(sta_strata_decoder_create(&dec, &err), STA_OK);
    const sta_strata_info *info = sta_strata_reader_info(r);
    for (uint32_t n = 0; n < info->node_count; n++) {
        sta_strata_points pts;
        if (sta_strata_decode_node(r, n, dec, &pts, &err) != STA_OK) {
            fail_msg("%s", err.message);
        }
        for (size_t i = 0; i < pts.count; i++) {
            digest_add(d, &pts.points[i], attributes, 0, 0, 0);
        }
    }
    if (sta_strata_verify(r, NULL, NULL, &err) != STA_OK) {
        fail_msg("verify: %s", err.message);
    }
    sta_strata_decoder_destroy(dec);
    sta_strata_close(r);
}

// Files in the temporary folder (to prove nothing is left behind).
static int count_files(const char *dir)
{
    DIR *d = opendir(dir);
    assert_non_null(d);
    int n = 0;
    struct dirent *e;
    while ((e = readdir(d)) != NULL) {
        if (strcmp(e->d_name, ".") != 0 && strcmp(e->d_name, "..") != 0) {
            n++;
        }
    }
    closedir(d);
    return n;
}

static void round_trip(const char *const *paths, size_t count, size_t chunk_points, int threads,
                       int compress)
{
    char out[4096];
    snprintf(out, sizeof(out), "%s/rt.strata", sta_test_tmpdir());
    unlink(out);
    int files_before = count_files(sta_test_tmpdir());
    sta_convert_options o = { .inputs = paths,
                              .input_count = count,
                              .output = out,
                              .threads = threads,
                              .compress_level = compress,
                              .leaf_capacity = 256,
                              .chunk_points = chunk_points };
    sta_convert_report report;
    sta_error err = { 0 };
    if (sta_convert(&o, &report, &err) != STA_OK) {
        fail_msg("convert: %s", err.message);
    }
    digest in, got;
    uint32_t attributes = digest_inputs(paths, count, &in);
    digest_output(out, attributes, &got);
    assert_int_equal(got.count, in.count);
    assert_int_equal(report.point_count, in.count);
    assert_true(got.sum == in.sum);
    assert_true(got.sum_sq == in.sum_sq);
    assert_int_equal(count_files(sta_test_tmpdir()), files_before + 1); // only the output
    unlink(out);
}

static void shared_las_files_round_trip(void **state)
{
    (void)state;
    STA_TEST_REQUIRE_SHARED_DATA();
    // Every readable LAS file of the corpus, one by one, small chunks to force merges.
    const char *files[] = {
        "las/simple.las",         "las/1815.las",
        "las/test1_4.las",        "las/simple1_4.las",
        "las/simple1_3.las",      "las/gib_las_col.las",
        "las/autzen_trim.las",    "las/epsg_4326.las",
        "las/Megaplot.las",       "las/MixedConifer.las",
        "las/extra-bytes.las",    "las/sample_c.las",
        "las/mvk-thin.las",       "las/liblas_1.0_0.las",
        "las/no-points.las",      "las/gps-time-nan.las",
        "las/vegetation_1_3.las", "las/test_data_0000_0000_LA93_IGN69_ground.las"
    };
    for (size_t i = 0; i < sizeof(files) / sizeof(files[0]); i++) {
        char path[4096];
        snprintf(path, sizeof(path), "%s", sta_test_shared_path(files[i]));
        const char *one[] = { path };
        round_trip(one, 1, 5000, 2, 3);
    }
}

/* LAZ through the converter with two threads: each thread seeks into the middle of a
 * chunk (autzen_trim: 110 000 points in chunks of 50 000; the point14 file: one chunk of
 * 1000) and decodes its own chunks; every point arrives exactly once. */
static void laz_files_convert_on_parallel_threads(void **state)
{
    (void)state;
    STA_TEST_REQUIRE_SHARED_DATA();
    const char *files[] = { "laz/autzen_trim.laz", "laz/1_4_w_evlr.laz", "laz/point10.laz" };
    for (size_t i = 0; i < sizeof(files) / sizeof(files[0]); i++) {
        char path[4096];
        snprintf(path, sizeof(path), "%s", sta_test_shared_path(files[i]));
        const char *one[] = { path };
        round_trip(one, 1, 20000, 2, 3);
    }
}

static void lion_tiles_merge_into_one_scene(void **state)
{
    (void)state;
    STA_TEST_REQUIRE_SHARED_DATA();
    glob_t g;
    char pattern[4096];
    snprintf(pattern, sizeof(pattern), "%s",
             sta_test_shared_path("las/potree_lion_takanawa/*.las"));
    assert_int_equal(glob(pattern, 0, NULL, &g), 0);
    assert_int_equal(g.gl_pathc, 200);
    round_trip((const char *const *)g.gl_pathv, g.gl_pathc, 20000, 2, 1);
    globfree(&g);
}

static void uncompressed_single_thread_one_chunk(void **state)
{
    (void)state;
    STA_TEST_REQUIRE_SHARED_DATA();
    char path[4096];
    snprintf(path, sizeof(path), "%s", sta_test_shared_path("las/autzen_trim.las"));
    const char *one[] = { path };
    round_trip(one, 1, 0, 1, STA_CONVERT_STORE);
}

static void dense_chunks_are_split_out_of_core(void **state)
{
    (void)state;
    STA_TEST_REQUIRE_SHARED_DATA();
    // Chunks of at most 300 points: most counting cells are denser and must be split
    // again from the temporary file before indexing.
    char path[4096];
    snprintf(path, sizeof(path), "%s", sta_test_shared_path("las/autzen_trim.las"));
    const char *one[] = { path };
    round_trip(one, 1, 300, 2, 1);
}

// Hard numerical cases: a 1e-9 scale and integer coordinates at the ends of the int32
// range survive the conversion bit for bit, and the octree holds them.
static void extreme_grids_round_trip(void **state)
{
    (void)state;
    const sta_grid grids[2] = { { { 1e-9, 1e-9, 1e-9 }, { 0.5, -0.25, 100 } },
                                { { 0.001, 0.001, 0.01 }, { 650000, 5400000, -2000 } } };
    for (int g = 0; g < 2; g++) {
        char path[4096];
        snprintf(path, sizeof(path), "%s/extreme%d.las", sta_test_tmpdir(), g);
        sta_las_write_options wo = { .version_minor = 4, .point_format = 6, .grid = grids[g] };
        sta_las_writer *w = NULL;
        sta_error err = { 0 };
        assert_int_equal(sta_las_writer_open(path, &wo, &w, &err), STA_OK);
        enum {
            N = 5000
        };
        sta_point *points = calloc(N, sizeof(*points));
        assert_non_null(points);
        uint64_t seed = 99;
        for (int i = 0; i < N; i++) {
            seed = seed * 6364136223846793005ull + 1442695040888963407ull;
            // Corners of the int32 cube plus points spread between them.
            int32_t extreme = (i & 1) ? INT32_MAX - (int32_t)(i % 7) : INT32_MIN + (int32_t)(i % 5);
            points[i].X = i < 16 ? extreme : (int32_t)(seed >> 32);
            points[i].Y = i < 16 ? ((i & 2) ? INT32_MAX : INT32_MIN) : (int32_t)(seed >> 16);
            points[i].Z = i < 16 ? ((i & 4) ? INT32_MAX : INT32_MIN) : (int32_t)seed;
            points[i].intensity = (uint16_t)i;
            points[i].return_number = 1;
            points[i].number_of_returns = 1;
        }
        assert_int_equal(sta_las_writer_write(w, points, N, &err), STA_OK);
        assert_int_equal(sta_las_writer_close(w, &err), STA_OK);
        free(points);
        const char *one[] = { path };
        round_trip(one, 1, 1000, 2, 3);
        unlink(path);
    }
}

static void broken_inputs_leave_nothing(void **state)
{
    (void)state;
    STA_TEST_REQUIRE_SHARED_DATA();
    const char *broken[] = { "las/1.2-with-color-clipped.las", "las/garbage_nVariableLength.las" };
    char out[4096];
    snprintf(out, sizeof(out), "%s/bad.strata", sta_test_tmpdir());
    for (size_t i = 0; i < sizeof(broken) / sizeof(broken[0]); i++) {
        char path[4096];
        snprintf(path, sizeof(path), "%s", sta_test_shared_path(broken[i]));
        const char *one[] = { path };
        sta_convert_options o = { .inputs = one, .input_count = 1, .output = out };
        sta_error err = { 0 };
        assert_int_not_equal(sta_convert(&o, NULL, &err), STA_OK);
        assert_non_null(strstr(err.message, broken[i] + 4)); // names the file
        assert_int_equal(count_files(sta_test_tmpdir()), 0);
    }
    // A missing file among good ones: nothing written either.
    char good[4096];
    snprintf(good, sizeof(good), "%s", sta_test_shared_path("las/simple.las"));
    const char *mixed[] = { good, "/nonexistent/x.las" };
    sta_convert_options o = { .inputs = mixed, .input_count = 2, .output = out };
    sta_error err = { 0 };
    assert_int_equal(sta_convert(&o, NULL, &err), STA_ERR_IO);
    assert_non_null(strstr(err.message, "/nonexistent/x.las"));
    assert_int_equal(count_files(sta_test_tmpdir()), 0);
}

static void existing_output_needs_force_and_cancel_cleans_up(void **state)
{
    (void)state;
    STA_TEST_REQUIRE_SHARED_DATA();
    char out[4096], path[4096];
    snprintf(out, sizeof(out), "%s/exists.strata", sta_test_tmpdir());
    snprintf(path, sizeof(path), "%s", sta_test_shared_path("las/simple.las"));
    sta_test_write_file(out, "keep", 4);
    const char *one[] = { path };
    sta_convert_options o = { .inputs = one, .input_count = 1, .output = out };
    sta_error err = { 0 };
    assert_int_equal(sta_convert(&o, NULL, &err), STA_ERR_ARG);
    assert_non_null(strstr(err.message, "--force"));
    // A cancelled run leaves the old file and no temporaries.
    atomic_bool cancel = true;
    o.force = true;
    o.cancel = &cancel;
    assert_int_equal(sta_convert(&o, NULL, &err), STA_ERR_CANCELLED);
    assert_int_equal(count_files(sta_test_tmpdir()), 1);
    size_t size;
    uint8_t *kept = sta_test_read_file(out, &size);
    assert_int_equal(size, 4);
    free(kept);
    unlink(out);
}

// A PLY of 125 points on a grid spanning ex x ey x ez metres.
static void write_grid_ply(const char *path, double ex, double ey, double ez)
{
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fprintf(f, "ply\nformat ascii 1.0\nelement vertex 125\nproperty float x\n"
               "property float y\nproperty float z\nend_header\n");
    for (int i = 0; i < 125; i++) {
        fprintf(f, "%g %g %g\n", ex * (i % 5) / 4.0, ey * (i / 5 % 5) / 4.0, ez * (i / 25) / 4.0);
    }
    fclose(f);
}

// The header's up axis: +Y for a PLY model, +Z for flat or z-tall PLY data and LAS.
static void up_axis_from_the_source(void **state)
{
    (void)state;
    const struct {
        double ex, ey, ez;
        int up;
    } cases[] = { { 1.0, 1.2, 0.8, STA_STRATA_UP_Y },
                  { 10.0, 10.0, 0.5, STA_STRATA_UP_Z },
                  { 1.0, 1.0, 3.0, STA_STRATA_UP_Z } };
    char ply[4096], out[4096];
    snprintf(ply, sizeof(ply), "%s/up.ply", sta_test_tmpdir());
    snprintf(out, sizeof(out), "%s/up.strata", sta_test_tmpdir());
    for (size_t i = 0; i < sizeof(cases) / sizeof(cases[0]); i++) {
        write_grid_ply(ply, cases[i].ex, cases[i].ey, cases[i].ez);
        const char *one[] = { ply };
        sta_convert_options o = { .inputs = one, .input_count = 1, .output = out, .force = true };
        sta_convert_report report;
        sta_error err = { 0 };
        assert_int_equal(sta_convert(&o, &report, &err), STA_OK);
        assert_int_equal(report.up_axis, cases[i].up);
        assert_non_null(strstr(report.up_why, "PLY"));
        sta_strata_reader *r = NULL;
        assert_int_equal(sta_strata_open(out, NULL, &r, &err), STA_OK);
        assert_int_equal(sta_strata_reader_info(r)->up_axis, cases[i].up);
        sta_strata_close(r);
    }
    unlink(ply);
    unlink(out);
}

static void corrupted_output_is_refused(void **state)
{
    (void)state;
    STA_TEST_REQUIRE_SHARED_DATA();
    char out[4096], path[4096];
    snprintf(out, sizeof(out), "%s/corrupt.strata", sta_test_tmpdir());
    snprintf(path, sizeof(path), "%s", sta_test_shared_path("las/autzen_trim.las"));
    const char *one[] = { path };
    sta_convert_options o = {
        .inputs = one, .input_count = 1, .output = out, .leaf_capacity = 1000
    };
    sta_error err = { 0 };
    sta_convert_report report;
    assert_int_equal(sta_convert(&o, &report, &err), STA_OK);
    assert_int_equal(report.up_axis, STA_STRATA_UP_Z); // LAS is z-up
    size_t size;
    uint8_t *bytes = sta_test_read_file(out, &size);
    // Flip a byte in the middle (a payload): open succeeds, verify names a node.
    bytes[size / 2] ^= 0x40;
    sta_strata_reader *r = NULL;
    assert_int_equal(sta_strata_open_memory(bytes, size, "corrupt.strata", NULL, &r, &err), STA_OK);
    assert_int_equal(sta_strata_verify(r, NULL, NULL, &err), STA_ERR_FORMAT);
    assert_non_null(strstr(err.message, "node"));
    sta_strata_close(r);
    bytes[size / 2] ^= 0x40;
    // A cut file is refused at open.
    assert_int_not_equal(sta_strata_open_memory(bytes, size - 100, "cut.strata", NULL, &r, &err),
                         STA_OK);
    assert_non_null(strstr(err.message, "cut.strata"));
    free(bytes);
    unlink(out);
}

// Writes `n` pseudo-random format-0 points within `extent` units of `origin` on `grid`.
static void write_random_las(const char *path, size_t n, const sta_grid *grid,
                             const double origin[3], double extent, uint64_t seed)
{
    sta_las_write_options wo = { .version_minor = 2, .point_format = 0, .grid = *grid };
    sta_las_writer *w = NULL;
    sta_error err = { 0 };
    assert_int_equal(sta_las_writer_open(path, &wo, &w, &err), STA_OK);
    enum {
        BATCH = 65536
    };
    sta_point *points = calloc(BATCH, sizeof(*points));
    assert_non_null(points);
    for (size_t done = 0; done < n;) {
        size_t m = n - done < BATCH ? n - done : BATCH;
        for (size_t i = 0; i < m; i++) {
            int32_t *xyz[3] = { &points[i].X, &points[i].Y, &points[i].Z };
            for (int a = 0; a < 3; a++) {
                seed = seed * 6364136223846793005ull + 1442695040888963407ull;
                double real = origin[a] + extent * (double)(seed >> 11) / 9007199254740992.0;
                *xyz[a] = (int32_t)llround((real - grid->offset[a]) / grid->scale[a]);
            }
            points[i].intensity = (uint16_t)(done + i);
            points[i].return_number = 1;
            points[i].number_of_returns = 1;
        }
        assert_int_equal(sta_las_writer_write(w, points, m, &err), STA_OK);
        done += m;
    }
    assert_int_equal(sta_las_writer_close(w, &err), STA_OK);
    free(points);
}

static bool exists(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0;
}

/* The output is checked against the inputs before any work: a folder, an input (by
 * any name, even with --force), an existing file without --force, a file given twice
 * are all refused with a message naming them, and nothing is written. */
static void output_and_input_paths_are_checked(void **state)
{
    (void)state;
    const sta_grid grid = { { 0.01, 0.01, 0.01 }, { 0, 0, 0 } };
    const double origin[3] = { 0, 0, 0 };
    char in[4096], link_path[4096], folder[4096], twice[4096];
    snprintf(in, sizeof(in), "%s/in.las", sta_test_tmpdir());
    snprintf(link_path, sizeof(link_path), "%s/other-name.las", sta_test_tmpdir());
    snprintf(folder, sizeof(folder), "%s/folder", sta_test_tmpdir());
    snprintf(twice, sizeof(twice), "%s/./in.las", sta_test_tmpdir());
    write_random_las(in, 1000, &grid, origin, 10, 1);
    assert_int_equal(link(in, link_path), 0);
    assert_int_equal(mkdir(folder, 0777), 0);
    size_t size_before = 0;
    free(sta_test_read_file(in, &size_before));
    static const struct {
        int input_count; /* in, then twice */
        int output;      /* 0 folder, 1 the input, 2 a hard link to it */
        const char *needle;
    } cases[] = {
        { 1, 0, "the output is a folder" },
        { 1, 1, "the output is the input" },
        { 1, 2, "the output is the input" },
        { 2, 0, "the output is a folder" },
    };
    for (size_t i = 0; i < sizeof(cases) / sizeof(cases[0]); i++) {
        const char *inputs[] = { in, twice };
        const char *outputs[] = { folder, in, link_path };
        sta_convert_options o = { .inputs = inputs,
                                  .input_count = (size_t)cases[i].input_count,
                                  .output = outputs[cases[i].output],
                                  .force = true };
        sta_error err = { 0 };
        assert_int_equal(sta_convert(&o, NULL, &err), STA_ERR_ARG);
        if (!strstr(err.message, cases[i].needle) ||
            !strstr(err.message, outputs[cases[i].output])) {
            fail_msg("case %zu: \"%s\" lacks \"%s\"", i, err.message, cases[i].needle);
        }
        assert_int_equal(count_files(sta_test_tmpdir()), 3); // in.las, its link, the folder
    }
    // The same file twice (another spelling): refused, naming both.
    char out[4096];
    snprintf(out, sizeof(out), "%s/twice.strata", sta_test_tmpdir());
    const char *inputs[] = { in, link_path };
    sta_convert_options o = { .inputs = inputs, .input_count = 2, .output = out };
    sta_error err = { 0 };
    assert_int_equal(sta_convert(&o, NULL, &err), STA_ERR_ARG);
    assert_non_null(strstr(err.message, "same file"));
    assert_non_null(strstr(err.message, in));
    assert_non_null(strstr(err.message, link_path));
    assert_false(exists(out));
    size_t size_after = 0;
    free(sta_test_read_file(in, &size_after));
    assert_int_equal(size_after, size_before);
    unlink(link_path);
    unlink(in);
    rmdir(folder);
}

/* SIGKILL at any moment (here: after 0, 50, 150 and 400 ms of a conversion in a
 * child process) leaves no temporary file in the output's folder, and a rerun
 * leaves exactly its output. */
// What a conversion killed at any moment may leave in `folder` beside its input: nothing;
// the whole output, verified (killed after its rename, before it exited); or its temporary
// file, named only between the link and the rename at the very end (strata_writer.c),
// which the next conversion to that output sweeps. Never a partial output. (A load that
// slows the conversion to its last milliseconds at the kill hits the last two.)
static void check_left_after_kill(const char *folder, const char *out)
{
    int files = count_files(folder);
    if (files == 1) {
        return; // only the input
    }
    assert_int_equal(files, 2);
    struct stat st;
    if (stat(out, &st) == 0) {
        sta_strata_reader *r = NULL;
        sta_error err = { 0 };
        if (sta_strata_open(out, NULL, &r, &err) != STA_OK ||
            sta_strata_verify(r, NULL, NULL, &err) != STA_OK) {
            fail_msg("a killed conversion left a broken %s: %s", out, err.message);
        }
        sta_strata_close(r);
        assert_int_equal(unlink(out), 0);
        return;
    }
    char pattern[4200];
    snprintf(pattern, sizeof(pattern), "%s.tmp.*", out);
    glob_t found;
    assert_int_equal(glob(pattern, 0, NULL, &found), 0); // its temporary, nothing else
    assert_int_equal(found.gl_pathc, 1);
    globfree(&found);
}

static void kill_9_leaves_nothing_behind(void **state)
{
    (void)state;
    char sub[2048], in[4096], out[4096];
    snprintf(sub, sizeof(sub), "%s/kill", sta_test_tmpdir());
    assert_int_equal(mkdir(sub, 0777), 0);
    snprintf(in, sizeof(in), "%s/in.las", sub);
    snprintf(out, sizeof(out), "%s/out.strata", sub);
    const sta_grid grid = { { 0.001, 0.001, 0.001 }, { 0, 0, 0 } };
    const double origin[3] = { 0, 0, 0 };
    write_random_las(in, 1500000, &grid, origin, 500, 7);
    static const int delays_ms[] = { 0, 50, 150, 400 };
    const char *one[] = { in };
    sta_convert_options o = {
        .inputs = one, .input_count = 1, .output = out, .threads = 2, .chunk_points = 40000
    };
    int killed = 0;
    for (size_t i = 0; i < sizeof(delays_ms) / sizeof(delays_ms[0]); i++) {
        pid_t child = fork();
        assert_true(child >= 0);
        if (child == 0) {
            sta_error err = { 0 };
            _exit(sta_convert(&o, NULL, &err) == STA_OK ? 0 : 1);
        }
        struct timespec delay = { 0, delays_ms[i] * 1000000L };
        nanosleep(&delay, NULL);
        kill(child, SIGKILL);
        int wstatus = 0;
        assert_int_equal(waitpid(child, &wstatus, 0), child);
        if (WIFSIGNALED(wstatus)) {
            killed++;
            check_left_after_kill(sub, out);
        } else {
            unlink(out); // finished before the kill: start again
        }
    }
    assert_true(killed >= 2); // the conversion takes well over 50 ms
    sta_error err = { 0 };
    if (sta_convert(&o, NULL, &err) != STA_OK) {
        fail_msg("rerun: %s", err.message);
    }
    assert_int_equal(count_files(sub), 2); // the input and the output (a temporary swept)
    unlink(out);
    unlink(in);
    rmdir(sub);
}

/* Inputs on different grids: a common step on which both lie exactly is found
 * (0.01 / offset 0 and 0.001 / offset 3e6 + 0.0005 meet on 0.0005), and an offset that
 * would put points outside int32 is moved by whole steps; integers map exactly. A
 * scale that is no whole multiple (0.003 on 0.002) is rounded and named. */
static void different_grids_merge_losslessly(void **state)
{
    (void)state;
    sta_cloud_info a = { .path = "a.las",
                         .point_count = 10,
                         .grid = { { 0.01, 0.01, 0.01 }, { 0, 0, 0 } },
                         .header_min = { 3e6, 3e6, 0 },
                         .header_max = { 3e6 + 100, 3e6 + 100, 50 } };
    sta_cloud_info b = { .path = "b.las",
                         .point_count = 10,
                         .grid = { { 0.001, 0.001, 0.001 }, { 3e6 + 0.0005, 3e6, 0.0005 } },
                         .header_min = { 3e6, 3e6, 0 },
                         .header_max = { 3e6 + 100, 3e6 + 100, 50 } };
    const sta_cloud_info *infos[2] = { &a, &b };
    sta_grid out;
    sta_regrid maps[2];
    sta_output_grid_choose(infos, 2, &out, maps);
    assert_true(fabs(out.scale[0] - 0.0005) < 1e-15);
    assert_true(fabs(out.scale[1] - 0.001) < 1e-15);
    for (int i = 0; i < 2; i++) {
        for (int axis = 0; axis < 3; axis++) {
            assert_true(maps[i].is_exact[axis]);
        }
    }
    // Every point of both inputs lands on an output integer whose real value is its own.
    for (int i = 0; i < 2; i++) {
        const sta_grid *g = &infos[i]->grid;
        for (int k = 0; k < 1000; k++) {
            double real[3] = { 3e6 + k * 0.1, 3e6 + k * 0.1, k * 0.05 };
            sta_point p = { 0 };
            int32_t *xyz[3] = { &p.X, &p.Y, &p.Z };
            for (int axis = 0; axis < 3; axis++) {
                *xyz[axis] = (int32_t)llround((real[axis] - g->offset[axis]) / g->scale[axis]);
            }
            sta_point q = p;
            assert_true(sta_output_grid_apply(&maps[i], g, &out, &q));
            const int32_t in_xyz[3] = { p.X, p.Y, p.Z }, out_xyz[3] = { q.X, q.Y, q.Z };
            for (int axis = 0; axis < 3; axis++) {
                double before = g->offset[axis] + in_xyz[axis] * g->scale[axis];
                double after = out.offset[axis] + out_xyz[axis] * out.scale[axis];
                assert_true(fabs(before - after) < 1e-7);
            }
        }
    }
    // 0.003 and 0.0017 share no step 0.0017 / k (k <= 16): the finest scale is kept,
    // the other input is rounded (with a warning).
    sta_cloud_info c = a, d = b;
    c.grid.scale[0] = 0.003;
    d.grid.scale[0] = 0.0017;
    d.grid.offset[0] = 0;
    const sta_cloud_info *odd[2] = { &c, &d };
    sta_log_set_level(STA_LOG_QUIET);
    sta_output_grid_choose(odd, 2, &out, maps);
    sta_log_set_level(STA_LOG_WARN);
    assert_true(fabs(out.scale[0] - 0.0017) < 1e-15);
    assert_false(maps[0].is_exact[0]);
    assert_true(maps[1].is_exact[0]);
}

/* sta_convert with warnings silenced (small budgets and odd grids warn on purpose);
 * fails the test, naming `what`, when the conversion fails. */
static void convert_quietly(const sta_convert_options *o, sta_convert_report *report,
                            const char *what)
{
    sta_error err = { 0 };
    sta_log_set_level(STA_LOG_QUIET);
    sta_status status = sta_convert(o, report, &err);
    sta_log_set_level(STA_LOG_WARN);
    if (status != STA_OK) {
        fail_msg("%s: %s", what, err.message);
    }
}

/* Two files on different grids, far from the first file's offset at the finer
 * scale, convert into one scene with every point. */
static void different_grids_convert_into_one_scene(void **state)
{
    (void)state;
    char a[4096], b[4096];
    snprintf(a, sizeof(a), "%s/a.las", sta_test_tmpdir());
    snprintf(b, sizeof(b), "%s/b.las", sta_test_tmpdir());
    const sta_grid ga = { { 0.01, 0.01, 0.01 }, { 0, 0, 0 } };
    const sta_grid gb = { { 0.001, 0.001, 0.001 }, { 3e6, 3e6, 0.0005 } };
    const double origin[3] = { 3e6, 3e6, 0 };
    write_random_las(a, 20000, &ga, origin, 100, 3);
    write_random_las(b, 30000, &gb, origin, 100, 4);
    const char *inputs[] = { a, b };
    char out[4096];
    snprintf(out, sizeof(out), "%s/ab.strata", sta_test_tmpdir());
    sta_convert_options o = { .inputs = inputs, .input_count = 2, .output = out };
    sta_convert_report report;
    convert_quietly(&o, &report, "convert");
    assert_int_equal(report.point_count, 50000);
    unlink(out);
    unlink(a);
    unlink(b);
}

/* Deterministic output: the same inputs and options give the same bytes whatever
 * --threads and --memory, and run after run (many small chunks, so workers finish in
 * varying order and chunk roots merge above them). */
static void output_is_byte_identical_across_threads_and_memory(void **state)
{
    (void)state;
    STA_TEST_REQUIRE_SHARED_DATA();
    char path[4096], first[4096], out[4096];
    snprintf(path, sizeof(path), "%s", sta_test_shared_path("las/autzen_trim.las"));
    snprintf(first, sizeof(first), "%s/det0.strata", sta_test_tmpdir());
    snprintf(out, sizeof(out), "%s/det.strata", sta_test_tmpdir());
    const char *one[] = { path };
    static const struct {
        int threads;
        size_t memory_mib;
    } runs[] = { { 1, 2048 }, { 2, 2048 }, { 4, 64 }, { 3, 300 }, { 2, 2048 }, { 8, 4096 } };
    size_t size0 = 0;
    uint8_t *bytes0 = NULL;
    for (size_t i = 0; i < sizeof(runs) / sizeof(runs[0]); i++) {
        sta_convert_options o = { .inputs = one,
                                  .input_count = 1,
                                  .output = i == 0 ? first : out,
                                  .threads = runs[i].threads,
                                  .memory_mib = runs[i].memory_mib,
                                  .leaf_capacity = 500,
                                  .chunk_points = 3000,
                                  .force = true };
        char what[32];
        snprintf(what, sizeof(what), "run %zu", i);
        convert_quietly(&o, NULL, what); // 64 MiB warns that a chunk needs more
        if (i == 0) {
            bytes0 = sta_test_read_file(first, &size0);
            continue;
        }
        size_t size = 0;
        uint8_t *bytes = sta_test_read_file(out, &size);
        if (size != size0 || memcmp(bytes, bytes0, size) != 0) {
            fail_msg("run %zu (%d threads, %zu MiB) differs from run 0", i, runs[i].threads,
                     runs[i].memory_mib);
        }
        free(bytes);
    }
    free(bytes0);
    unlink(first);
    unlink(out);
}

/* Temporary disk: at most 0.6x the input's LAS size at any --memory, and a stray
 * point 1000 km away (one more input) does not multiply it. autzen_trim.las: 110 000
 * real points. */
static void temporary_disk_is_bounded_and_outlier_proof(void **state)
{
    (void)state;
    STA_TEST_REQUIRE_SHARED_DATA();
    char path[4096], stray[4096], out[4096];
    snprintf(path, sizeof(path), "%s", sta_test_shared_path("las/autzen_trim.las"));
    snprintf(stray, sizeof(stray), "%s/stray.las", sta_test_tmpdir());
    snprintf(out, sizeof(out), "%s/temp.strata", sta_test_tmpdir());
    struct stat st;
    assert_int_equal(stat(path, &st), 0);
    double las_bytes = (double)st.st_size;
    // The stray point: on autzen's grid, 1000 km east of its first point.
    sta_cloud_reader *r = NULL;
    sta_error err = { 0 };
    assert_int_equal(sta_cloud_open(path, NULL, &r, &err), STA_OK);
    const sta_cloud_info *info = sta_cloud_reader_info(r);
    sta_point_batch batch;
    assert_int_equal(sta_point_batch_init(&batch, 1, 0, &err), STA_OK);
    assert_int_equal(sta_cloud_read(r, &batch, &err), STA_OK);
    sta_point far = batch.points[0];
    far.X += (int32_t)(1e6 / info->grid.scale[0]);
    sta_las_write_options wo = { .version_minor = 2,
                                 .point_format = info->point_format,
                                 .grid = info->grid };
    sta_las_writer *w = NULL;
    assert_int_equal(sta_las_writer_open(stray, &wo, &w, &err), STA_OK);
    assert_int_equal(sta_las_writer_write(w, &far, 1, &err), STA_OK);
    assert_int_equal(sta_las_writer_close(w, &err), STA_OK);
    sta_point_batch_release(&batch);
    sta_cloud_close(r);

    uint64_t plain_bytes[2] = { 0, 0 };
    static const size_t memories[2] = { 64, 2048 };
    for (int with_stray = 0; with_stray <= 1; with_stray++) {
        for (int m = 0; m < 2; m++) {
            const char *inputs[] = { path, stray };
            sta_convert_options o = { .inputs = inputs,
                                      .input_count = (size_t)(1 + with_stray),
                                      .output = out,
                                      .memory_mib = memories[m],
                                      .chunk_points = 20000,
                                      .runs_on_disk = true, // the runs are measured here
                                      .force = true };
            sta_convert_report report;
            convert_quietly(&o, &report, "convert");
            double ratio = (double)report.temp_bytes / las_bytes;
            print_message("stray %d, memory %zu MiB: temporary %.3fx the LAS size\n", with_stray,
                          memories[m], ratio);
            assert_true(report.temp_bytes > 0);
            assert_true(ratio <= 0.6);
            if (!with_stray) {
                plain_bytes[m] = report.temp_bytes;
            } else {
                assert_true(report.temp_bytes <= plain_bytes[m] * 3 / 2);
            }
        }
    }
    unlink(out);
    unlink(stray);
}

/* Records kept in memory (they fit --memory) give the same file as the temporary
 * runs, on any number of threads; a budget too small for them takes the runs. */
static void records_in_memory_match_the_runs(void **state)
{
    (void)state;
    STA_TEST_REQUIRE_SHARED_DATA();
    char path[4096], first[4096], out[4096];
    snprintf(path, sizeof(path), "%s", sta_test_shared_path("las/autzen_trim.las"));
    snprintf(first, sizeof(first), "%s/mem0.strata", sta_test_tmpdir());
    snprintf(out, sizeof(out), "%s/mem.strata", sta_test_tmpdir());
    const char *one[] = { path };
    static const struct {
        int threads;
        size_t memory_mib;
        size_t chunk_points;
        bool on_disk;
        bool in_memory; /* expected */
    } runs[] = {
        { 2, 2048, 0, true, false },     /* the reference: temporary runs */
        { 1, 2048, 0, false, true },     /* one chunk in memory */
        { 2, 2048, 0, false, true },     /* two threads fill their shares of it */
        { 2, 64, 0, false, false },      /* a 1 M-point chunk's workers need more than 64 MiB */
        { 3, 2048, 30000, false, true }, /* several chunks, three threads */
        { 3, 2048, 30000, true, false }, /* the same through the runs */
    };
    size_t size0 = 0;
    uint8_t *bytes0 = NULL, *bytes_chunked = NULL;
    size_t size_chunked = 0;
    for (size_t i = 0; i < sizeof(runs) / sizeof(runs[0]); i++) {
        sta_convert_options o = { .inputs = one,
                                  .input_count = 1,
                                  .output = i == 0 ? first : out,
                                  .threads = runs[i].threads,
                                  .memory_mib = runs[i].memory_mib,
                                  .chunk_points = runs[i].chunk_points,
                                  .runs_on_disk = runs[i].on_disk,
                                  .force = true };
        sta_convert_report report;
        char what[32];
        snprintf(what, sizeof(what), "run %zu", i);
        convert_quietly(&o, &report, what); // 64 MiB warns that a chunk needs more
        if (report.records_in_memory != runs[i].in_memory) {
            fail_msg("run %zu: records %s memory", i, report.records_in_memory ? "in" : "not in");
        }
        size_t size = 0;
        uint8_t *bytes = sta_test_read_file(i == 0 ? first : out, &size);
        // Chunk size shapes the tree: each chunk size has its own reference.
        uint8_t **reference = runs[i].chunk_points ? &bytes_chunked : &bytes0;
        size_t *reference_size = runs[i].chunk_points ? &size_chunked : &size0;
        if (!*reference) {
            *reference = bytes;
            *reference_size = size;
            continue;
        }
        if (size != *reference_size || memcmp(bytes, *reference, size) != 0) {
            fail_msg("run %zu (%d threads, %zu MiB, %s) differs", i, runs[i].threads,
                     runs[i].memory_mib, report.records_in_memory ? "in memory" : "runs");
        }
        free(bytes);
    }
    free(bytes0);
    free(bytes_chunked);
    unlink(first);
    unlink(out);
}

// One --normals conversion of a series: its threads and budget, whether it may keep the
// records in memory, and where they are expected to be.
typedef struct {
    int threads;
    size_t memory_mib;
    bool on_disk;
    bool in_memory; /* expected */
} records_run;

// Converts `path` with --normals once per run: each run keeps its records where expected,
// and every run's file equals the first's (byte for byte).
static void check_records_runs(const char *path, const char *out, size_t chunk_points,
                               const records_run *runs, size_t run_count)
{
    const char *one[] = { path };
    uint8_t *reference = NULL;
    size_t reference_size = 0;
    for (size_t i = 0; i < run_count; i++) {
        sta_convert_options o = { .inputs = one,
                                  .input_count = 1,
                                  .output = out,
                                  .threads = runs[i].threads,
                                  .memory_mib = runs[i].memory_mib,
                                  .chunk_points = chunk_points,
                                  .runs_on_disk = runs[i].on_disk,
                                  .normals = true,
                                  .knn = 10,
                                  .force = true };
        sta_convert_report report;
        char what[64];
        snprintf(what, sizeof(what), "normals run %zu (--memory %zu)", i, runs[i].memory_mib);
        convert_quietly(&o, &report, what);
        if (report.records_in_memory != runs[i].in_memory) {
            fail_msg("%s: records %s memory", what, report.records_in_memory ? "in" : "not in");
        }
        size_t size = 0;
        uint8_t *bytes = sta_test_read_file(out, &size);
        if (!reference) {
            reference = bytes;
            reference_size = size;
            continue;
        }
        if (size != reference_size || memcmp(bytes, reference, size) != 0) {
            fail_msg("%s (%d threads, %s) differs from the first run's", what, runs[i].threads,
                     report.records_in_memory ? "in memory" : "runs");
        }
        free(bytes);
    }
    free(reference);
    unlink(out);
}

/* --normals with the records kept in memory (the halo pass reads the chunks' arrays) gives
 * the same file as with the temporary runs (several chunks: halos cross them), on 1 and 3
 * threads; a budget too small for the records and the normals' workers takes the runs. */
static void normals_from_memory_match_the_runs(void **state)
{
    (void)state;
    STA_TEST_REQUIRE_SHARED_DATA();
    char out[4096];
    snprintf(out, sizeof(out), "%s/normals-mem.strata", sta_test_tmpdir());
    static const records_run runs[] = {
        { 2, 2048, true, false }, /* the reference: temporary runs */
        { 1, 2048, false, true },
        { 3, 2048, false, true },
        { 2, 100, false, false }, /* the records and two normals workers need more */
    };
    check_records_runs(sta_test_shared_path("las/autzen_trim.las"), out, 30000, runs,
                       sizeof(runs) / sizeof(runs[0]));
}

// The --memory plan for keeping the records in memory counts the largest chunk there is
// (at least the smallest capacity's points), not the capacity: autzen_trim's 110 000
// points with chunks of up to 4 M (one index worker: the index phase's own plan counts the
// capacity). 1 GiB holds the records beside a worker planned for 1 M points (about 0.25
// GB), not beside one planned for 4 M (about 1 GB: the plan before); 200 MiB holds
// neither. In memory or not, the same bytes.
static void normals_plan_the_largest_chunk(void **state)
{
    (void)state;
    STA_TEST_REQUIRE_SHARED_DATA();
    char out[4096];
    snprintf(out, sizeof(out), "%s/normals-plan.strata", sta_test_tmpdir());
    static const records_run runs[] = {
        { 2, 2048, true, false }, /* the reference: temporary runs */
        { 2, 1024, false, true },
        { 2, 200, false, false },
    };
    check_records_runs(sta_test_shared_path("las/autzen_trim.las"), out, 4u << 20, runs,
                       sizeof(runs) / sizeof(runs[0]));
}

// One chunk's arrays on a worker thread: 24 MiB allocated, written and freed.
static void *chunk_arrays(void *arg)
{
    (void)arg;
    size_t bytes = (size_t)24 << 20;
    unsigned char *block = sta_alloc_array(bytes, 1);
    if (block) {
        memset(block, 1, bytes);
    }
    sta_free(block);
    return block ? arg : (void *)1;
}

static long minor_faults(void)
{
    struct rusage usage;
    getrusage(RUSAGE_SELF, &usage);
    return usage.ru_minflt;
}

// Whether the kernel backs all anonymous memory with huge pages (a 24 MiB block then faults
// in a dozen times, not 6 144).
static bool huge_pages_always(void)
{
    char mode[128] = "";
    FILE *f = fopen("/sys/kernel/mm/transparent_hugepage/enabled", "r");
    if (f) {
        if (!fgets(mode, sizeof(mode), f)) {
            mode[0] = 0;
        }
        fclose(f);
    }
    return strstr(mode, "[always]") != NULL;
}

// sta_convert_keep_heap: the next chunk's arrays, on another worker thread, reuse the
// pages the last chunk freed instead of faulting in new ones (6 144 pages of 4 KiB a
// chunk). Without it glibc maps the block apart (or in the thread's own 64 MiB heap) and
// gives it back at the free, and every chunk faults its pages in again.
static void kept_heap_serves_the_next_chunk_without_faults(void **state)
{
    (void)state;
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
    // (a sanitizer's allocator takes no mallopt settings: the release build checks the heap)
    STA_TEST_SKIP("under a sanitizer: its allocator takes no mallopt settings");
#endif
    assert_true(sta_convert_keep_heap());
    long faults[4];
    for (int chunk = 0; chunk < 4; chunk++) {
        long before = minor_faults();
        pthread_t worker;
        void *result = (void *)1;
        assert_int_equal(pthread_create(&worker, NULL, chunk_arrays, NULL), 0);
        pthread_join(worker, &result);
        assert_null(result);
        faults[chunk] = minor_faults() - before;
    }
    assert_true(faults[0] >= 6000 || huge_pages_always()); // the first chunk's pages are new
    for (int chunk = 1; chunk < 4; chunk++) {
        assert_true(faults[chunk] < 600); // (the thread's own stack and bookkeeping)
    }
}

// The default --memory: a quarter of the machine's memory (or of a container's limit
// below it), never below 2048 MiB nor above 16 GiB; unknown memory gives the least.
static void default_memory_is_a_quarter_of_the_ram_within_bounds(void **state)
{
    (void)state;
    assert_int_equal(sta_convert_default_memory_mib(0), STA_CONVERT_DEFAULT_MEMORY_MIB);
    assert_int_equal(sta_convert_default_memory_mib(4096), 2048);
    assert_int_equal(sta_convert_default_memory_mib(8192), 2048);
    assert_int_equal(sta_convert_default_memory_mib(24576), 6144);
    assert_int_equal(sta_convert_default_memory_mib(65536), 16384);
    assert_int_equal(sta_convert_default_memory_mib(131072), 16384);
    // A container's limit (cgroup files): bytes in MiB, "max" or nonsense none.
    assert_int_equal(sta_convert_memory_limit_mib("4294967296\n"), 4096);
    assert_int_equal(sta_convert_memory_limit_mib("536870912"), 512);
    assert_int_equal(sta_convert_memory_limit_mib("max\n"), 0);
    assert_int_equal(sta_convert_memory_limit_mib(""), 0);
    assert_int_equal(sta_convert_memory_limit_mib("12ab"), 0);
    assert_int_equal(sta_convert_memory_limit_mib(NULL), 0);
    sta_convert_options o = { 0 };
    sta_convert_options_defaults(&o);
    assert_true(o.memory_mib >= STA_CONVERT_DEFAULT_MEMORY_MIB &&
                o.memory_mib <= STA_CONVERT_DEFAULT_MEMORY_MAX_MIB);
    assert_true(o.threads >= 1);
}

static const struct CMUnitTest tests[] = {
    cmocka_unit_test(default_memory_is_a_quarter_of_the_ram_within_bounds),
    cmocka_unit_test(shared_las_files_round_trip),
    cmocka_unit_test(up_axis_from_the_source),
    cmocka_unit_test(laz_files_convert_on_parallel_threads),
    cmocka_unit_test(lion_tiles_merge_into_one_scene),
    cmocka_unit_test(uncompressed_single_thread_one_chunk),
    cmocka_unit_test(dense_chunks_are_split_out_of_core),
    cmocka_unit_test(extreme_grids_round_trip),
    cmocka_unit_test(broken_inputs_leave_nothing),
    cmocka_unit_test(existing_output_needs_force_and_cancel_cleans_up),
    cmocka_unit_test(corrupted_output_is_refused),
    cmocka_unit_test(output_and_input_paths_are_checked),
    cmocka_unit_test(kill_9_leaves_nothing_behind),
    cmocka_unit_test(temporary_disk_is_bounded_and_outlier_proof),
    cmocka_unit_test(output_is_byte_identical_across_threads_and_memory),
    cmocka_unit_test(records_in_memory_match_the_runs),
    cmocka_unit_test(normals_from_memory_match_the_runs),
    cmocka_unit_test(normals_plan_the_largest_chunk),
    cmocka_unit_test(different_grids_merge_losslessly),
    cmocka_unit_test(different_grids_convert_into_one_scene),
    cmocka_unit_test(kept_heap_serves_the_next_chunk_without_faults),
};

STA_TEST_MAIN(tests)
