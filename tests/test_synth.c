/* SPDX-License-Identifier: MIT
 * Tests for strata-synth (src/synth): determinism, exact counts, analytic truth, the
 * street's classes/returns/times/intensities, origin independence, the ray caster
 * (and its agreement with the generated points), and the command line. Files are
 * read back through sta_cloud_open. */
#include "test_support.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "core/alloc.h"
#include "io/cloud.h"
#include "synth/synth.h"

/* A whole small LAS file in memory. */
typedef struct loaded {
    sta_point *points;
    size_t count;
    sta_grid grid;
    int version_minor;
    int point_format;
    uint16_t global_encoding;
    char wkt_start[64]; /* first characters of the WKT, or "" */
} loaded;

static void load(const char *path, loaded *out)
{
    memset(out, 0, sizeof(*out));
    sta_error err = { 0 };
    sta_cloud_reader *r = NULL;
    if (sta_cloud_open(path, NULL, &r, &err) != STA_OK) {
        fail_msg("%s", err.message);
    }
    const sta_cloud_info *info = sta_cloud_reader_info(r);
    out->count = (size_t)info->point_count;
    out->grid = info->grid;
    out->version_minor = info->version_minor;
    out->point_format = info->point_format;
    out->global_encoding = info->global_encoding;
    if (info->crs_wkt) {
        snprintf(out->wkt_start, sizeof(out->wkt_start), "%s", info->crs_wkt);
    }
    out->points = sta_calloc(out->count + 1, sizeof(sta_point));
    assert_non_null(out->points);
    sta_point_batch batch = { 0 };
    assert_int_equal(sta_point_batch_init(&batch, 8192, info->extra_size, &err), STA_OK);
    size_t seen = 0;
    for (;;) {
        assert_int_equal(sta_cloud_read(r, &batch, &err), STA_OK);
        if (batch.count == 0) {
            break;
        }
        assert_true(seen + batch.count <= out->count);
        memcpy(out->points + seen, batch.points, batch.count * sizeof(sta_point));
        seen += batch.count;
    }
    assert_int_equal(seen, out->count);
    sta_point_batch_release(&batch);
    sta_cloud_close(r);
}

static void unload(loaded *l)
{
    sta_free(l->points);
    l->points = NULL;
}

/* Local coordinates of point i (real coordinate minus the georeference origin). */
static void local_of(const loaded *l, const sta_synth_georef *g, size_t i, double out[3])
{
    const sta_point *p = &l->points[i];
    const int32_t xyz[3] = { p->X, p->Y, p->Z };
    for (int a = 0; a < 3; a++) {
        out[a] = sta_grid_apply(&l->grid, a, xyz[a]) - g->origin[a];
    }
}

static void generate(const sta_synth_params *p, const char *path)
{
    sta_error err = { 0 };
    if (sta_synth_generate(p, path, NULL, NULL, &err) != STA_OK) {
        fail_msg("%s", err.message);
    }
}

static char *path_copy(const char *name)
{
    char *p = sta_strdup(sta_test_tmp_path(name));
    assert_non_null(p);
    return p;
}

static char *truth_of(const char *las)
{
    char *t = NULL;
    assert_int_equal(sta_synth_truth_path(las, &t, NULL), STA_OK);
    return t;
}

static void same_seed_gives_same_bytes(void **state)
{
    (void)state;
    const sta_synth_kind kinds[2] = { STA_SYNTH_STREET, STA_SYNTH_SPHERE };
    for (int k = 0; k < 2; k++) {
        sta_synth_params p = { .kind = kinds[k], .seed = 7, .point_count = 30000 };
        char *a = path_copy("det_a.las"), *b = path_copy("det_b.las"), *c = path_copy("det_c.las");
        generate(&p, a);
        generate(&p, b);
        p.seed = 8;
        generate(&p, c);
        assert_true(sta_test_files_equal(a, b));
        assert_false(sta_test_files_equal(a, c));
        char *ta = truth_of(a), *tb = truth_of(b);
        assert_true(sta_test_files_equal(ta, tb));
        sta_free(ta);
        sta_free(tb);
        sta_free(a);
        sta_free(b);
        sta_free(c);
    }
}

static void point_count_is_exact(void **state)
{
    (void)state;
    // Below one batch, and across batch boundaries (batches hold 65536 points).
    const uint64_t counts[3] = { 1, 12345, 140001 };
    for (int i = 0; i < 3; i++) {
        sta_synth_params p = { .kind = STA_SYNTH_STREET, .seed = 3, .point_count = counts[i] };
        char *path = path_copy("count.las");
        generate(&p, path);
        loaded l;
        load(path, &l);
        assert_int_equal(l.count, counts[i]);
        unload(&l);
        p.kind = STA_SYNTH_NESTED;
        generate(&p, path);
        load(path, &l);
        assert_int_equal(l.count, counts[i]);
        unload(&l);
        sta_free(path);
    }
}

static void sphere_points_and_normals_are_true(void **state)
{
    (void)state;
    sta_synth_params p = { .kind = STA_SYNTH_SPHERE, .seed = 11, .point_count = 20000 };
    char *path = path_copy("sphere.las");
    generate(&p, path);
    loaded l;
    load(path, &l);
    assert_int_equal(l.version_minor, 4);
    assert_int_equal(l.point_format, 7);
    sta_synth_georef g;
    sta_synth_georef_init(STA_SYNTH_ORIGIN_UTM, &g);
    sta_synth_scene *scene = NULL;
    assert_int_equal(sta_synth_scene_create(&p, &scene, NULL), STA_OK);
    const double grid_error = 0.5e-3 * sqrt(3.0);
    double n_sum[3] = { 0, 0, 0 };
    for (size_t i = 0; i < l.count; i++) {
        double q[3];
        local_of(&l, &g, i, q);
        double r = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
        assert_true(fabs(r - 10.0) <= grid_error + 1e-9);
        double n[3] = { q[0] / r, q[1] / r, q[2] / r };
        for (int a = 0; a < 3; a++) {
            n_sum[a] += n[a];
        }
        // The colour encodes the true normal as (n + 1) / 2 in 8 bits.
        const uint16_t rgb[3] = { l.points[i].red, l.points[i].green, l.points[i].blue };
        for (int a = 0; a < 3; a++) {
            assert_true(fabs((double)rgb[a] / 65535.0 * 2.0 - 1.0 - n[a]) < 2.5 / 255.0);
        }
        // A ray from outside along -n meets the surface at this point with normal n.
        double o[3] = { 30.0 * n[0], 30.0 * n[1], 30.0 * n[2] };
        double d[3] = { -n[0], -n[1], -n[2] };
        sta_synth_hit hit;
        assert_true(sta_synth_scene_raycast(scene, o, d, 100.0, &hit));
        assert_true(fabs(hit.t - 20.0) < 1e-9);
        assert_true(hit.normal[0] * n[0] + hit.normal[1] * n[1] + hit.normal[2] * n[2] >
                    1.0 - 1e-12);
        assert_int_equal(hit.primitive_id, 0);
    }
    // Uniform on the sphere: the mean normal is near zero (|mean| ~ 1/sqrt(3N)).
    for (int a = 0; a < 3; a++) {
        assert_true(fabs(n_sum[a] / (double)l.count) < 0.03);
    }
    sta_synth_scene_destroy(scene);
    unload(&l);
    sta_free(path);
}

static void sphere_noise_has_the_given_sigma(void **state)
{
    (void)state;
    sta_synth_params p = { .kind = STA_SYNTH_SPHERE,
                           .seed = 2,
                           .point_count = 20000,
                           .origin = STA_SYNTH_ORIGIN_ZERO,
                           .has_noise = true,
                           .noise_m = 0.01 };
    char *path = path_copy("noisy.las");
    generate(&p, path);
    loaded l;
    load(path, &l);
    sta_synth_georef g;
    sta_synth_georef_init(STA_SYNTH_ORIGIN_ZERO, &g);
    double sum2 = 0.0;
    for (size_t i = 0; i < l.count; i++) {
        double q[3];
        local_of(&l, &g, i, q);
        double e = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]) - 10.0;
        sum2 += e * e;
    }
    double rms = sqrt(sum2 / (double)l.count);
    assert_true(rms > 0.0095 && rms < 0.0105);
    unload(&l);
    sta_free(path);
}

static void nested_sphere_is_inside_the_box_and_hidden(void **state)
{
    (void)state;
    sta_synth_params p = { .kind = STA_SYNTH_NESTED, .seed = 5, .point_count = 30000 };
    char *path = path_copy("nested.las");
    generate(&p, path);
    loaded l;
    load(path, &l);
    sta_synth_georef g;
    sta_synth_georef_init(STA_SYNTH_ORIGIN_UTM, &g);
    sta_synth_scene *scene = NULL;
    assert_int_equal(sta_synth_scene_create(&p, &scene, NULL), STA_OK);
    size_t on_sphere = 0;
    for (size_t i = 0; i < l.count; i++) {
        double q[3];
        local_of(&l, &g, i, q);
        double r = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
        bool box = fabs(fabs(q[0]) - 5.0) < 1e-3 || fabs(fabs(q[1]) - 5.0) < 1e-3 ||
                   fabs(fabs(q[2]) - 5.0) < 1e-3;
        for (int a = 0; a < 3; a++) {
            assert_true(fabs(q[a]) <= 5.0 + 1e-3);
        }
        if (!box) {
            assert_true(fabs(r - 3.0) < 1e-3);
            assert_int_equal(l.points[i].user_data, 6);
            on_sphere++;
            // From any point outside the box, the box is met first.
            double o[3] = { 20.0, -13.0, 9.0 };
            double d[3] = { q[0] - o[0], q[1] - o[1], q[2] - o[2] };
            double len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
            for (int a = 0; a < 3; a++) {
                d[a] /= len;
            }
            sta_synth_hit hit;
            assert_true(sta_synth_scene_raycast(scene, o, d, 1e3, &hit));
            assert_true(hit.primitive_id < 6);
            assert_true(hit.t < len - 2.0);
        } else {
            assert_true(l.points[i].user_data < 6);
        }
    }
    // Points follow area: 4 pi 3^2 of 600 + 4 pi 3^2 square metres.
    double share = 36.0 * M_PI / (600.0 + 36.0 * M_PI);
    assert_true(fabs((double)on_sphere - share * (double)l.count) <= 1.0);
    sta_synth_scene_destroy(scene);
    unload(&l);
    sta_free(path);
}

static void planes_lie_at_their_depths(void **state)
{
    (void)state;
    sta_synth_params p = {
        .kind = STA_SYNTH_PLANES, .seed = 9, .point_count = 10000, .origin = STA_SYNTH_ORIGIN_ECEF
    };
    char *path = path_copy("planes.las");
    generate(&p, path);
    loaded l;
    load(path, &l);
    sta_synth_georef g;
    sta_synth_georef_init(STA_SYNTH_ORIGIN_ECEF, &g);
    const double depth[5] = { 0.0, -0.01, -0.11, -1.11, -11.11 };
    size_t per_plane[5] = { 0 };
    for (size_t i = 0; i < l.count; i++) {
        double q[3];
        local_of(&l, &g, i, q);
        int k = l.points[i].user_data;
        assert_true(k >= 0 && k < 5);
        per_plane[k]++;
        assert_true(fabs(q[2] - depth[k]) <= 0.5e-3 + 1e-9);
        assert_true(q[0] >= -5.0 + 2.0 * k - 1e-3 && q[0] <= 5.0 + 2.0 * k + 1e-3);
        assert_true(q[1] >= -5.0 - 1e-3 && q[1] <= 5.0 + 1e-3);
    }
    for (int k = 0; k < 5; k++) {
        assert_int_equal(per_plane[k], 2000);
    }
    unload(&l);
    sta_free(path);
}

static void mesh_points_lie_on_the_triangles(void **state)
{
    (void)state;
    // A tetrahedron: its bounding box centre goes to 0 and its size to 10 m, so the
    // faces become x = -5, y = -5, z = -5 and x + y + z = -5.
    static const char ply[] = "ply\nformat ascii 1.0\nelement vertex 4\n"
                              "property float x\nproperty float y\nproperty float z\n"
                              "element face 4\nproperty list uchar int vertex_indices\n"
                              "end_header\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n"
                              "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
    char *mesh = path_copy("tetra.ply");
    sta_test_write_file(mesh, ply, sizeof(ply) - 1);
    sta_synth_params p = { .kind = STA_SYNTH_MESH,
                           .seed = 4,
                           .point_count = 8000,
                           .origin = STA_SYNTH_ORIGIN_ZERO,
                           .mesh_path = mesh };
    char *path = path_copy("mesh.las");
    generate(&p, path);
    loaded l;
    load(path, &l);
    sta_synth_georef g;
    sta_synth_georef_init(STA_SYNTH_ORIGIN_ZERO, &g);
    size_t slanted = 0;
    for (size_t i = 0; i < l.count; i++) {
        double q[3];
        local_of(&l, &g, i, q);
        double e = 1e-3;
        bool on = fabs(q[0] + 5.0) < e || fabs(q[1] + 5.0) < e || fabs(q[2] + 5.0) < e;
        if (fabs(q[0] + q[1] + q[2] + 5.0) < 2e-3) {
            on = true;
            slanted++;
        }
        assert_true(on);
        for (int a = 0; a < 3; a++) {
            assert_true(q[a] >= -5.0 - e && q[a] <= 5.0 + e);
        }
    }
    // Area share of the slanted face: sqrt(3) / (3 + sqrt(3)) = 0.366.
    assert_true(fabs((double)slanted / (double)l.count - 0.366) < 0.03);
    // The ray caster sees the same mesh: down the z axis from above, the slanted face.
    sta_synth_scene *scene = NULL;
    assert_int_equal(sta_synth_scene_create(&p, &scene, NULL), STA_OK);
    const double o[3] = { -4.0, -4.0, 20.0 }, d[3] = { 0.0, 0.0, -1.0 };
    sta_synth_hit hit;
    assert_true(sta_synth_scene_raycast(scene, o, d, 100.0, &hit));
    assert_true(fabs(hit.t - 17.0) < 1e-9); // x + y + z = -5 at z = 3
    assert_true(fabs(hit.normal[2] - 1.0 / sqrt(3.0)) < 1e-9);
    sta_synth_scene_destroy(scene);
    unload(&l);
    sta_free(path);
    sta_free(mesh);
}

static void bunny_mesh_samples_fill_its_box(void **state)
{
    (void)state;
    STA_TEST_REQUIRE_SHARED_DATA();
    char *mesh = sta_strdup(sta_test_shared_path("models/bun_zipper.ply"));
    sta_synth_params p = {
        .kind = STA_SYNTH_MESH, .seed = 1, .point_count = 20000, .mesh_path = mesh
    };
    char *path = path_copy("bunny.las");
    generate(&p, path);
    loaded l;
    load(path, &l);
    assert_int_equal(l.count, 20000);
    sta_synth_georef g;
    sta_synth_georef_init(STA_SYNTH_ORIGIN_UTM, &g);
    double lo[3] = { 1e9, 1e9, 1e9 }, hi[3] = { -1e9, -1e9, -1e9 };
    for (size_t i = 0; i < l.count; i++) {
        double q[3];
        local_of(&l, &g, i, q);
        for (int a = 0; a < 3; a++) {
            lo[a] = fmin(lo[a], q[a]);
            hi[a] = fmax(hi[a], q[a]);
        }
    }
    // README: extent x -0.0947 .. 0.0610 is the largest (0.1557), scaled to 10 m.
    assert_true(hi[0] - lo[0] > 9.9 && hi[0] - lo[0] <= 10.001);
    for (int a = 0; a < 3; a++) {
        assert_true(lo[a] >= -5.001 && hi[a] <= 5.001);
    }
    unload(&l);
    sta_free(path);
    sta_free(mesh);
}

/* Street file shared by the street cases (each case runs in its own process). */
static void street_file(const char *name, sta_synth_params *p, loaded *l)
{
    char *path = path_copy(name);
    generate(p, path);
    load(path, l);
    sta_free(path);
}

static void street_has_classes_returns_and_times(void **state)
{
    (void)state;
    sta_synth_params p = { .kind = STA_SYNTH_STREET, .seed = 1, .point_count = 150000 };
    loaded l;
    street_file("street.las", &p, &l);
    assert_int_equal(l.version_minor, 4);
    assert_int_equal(l.point_format, 7);
    assert_true(l.global_encoding & 1u);        // adjusted standard GPS time
    assert_true(l.global_encoding & (1u << 4)); // WKT
    assert_non_null(strstr(l.wkt_start, "UTM zone 32N"));
    sta_synth_georef g;
    sta_synth_georef_init(STA_SYNTH_ORIGIN_UTM, &g);
    size_t classes[256] = { 0 };
    size_t multi_in_trees = 0;
    for (size_t i = 0; i < l.count; i++) {
        const sta_point *pt = &l.points[i];
        classes[pt->classification]++;
        assert_true(pt->return_number >= 1);
        assert_true(pt->return_number <= pt->number_of_returns);
        if (pt->classification == 5 && pt->number_of_returns > 1) {
            multi_in_trees++;
        }
        if (i > 0) {
            assert_true(pt->gps_time >= l.points[i - 1].gps_time);
        }
        assert_int_equal(pt->point_source_id, 1);
        assert_true(pt->scan_angle >= -30000 && pt->scan_angle <= 30000);
        double q[3];
        local_of(&l, &g, i, q);
        // Within the run (a few hundred metres) of the UTM origin.
        assert_true(fabs(q[0]) < 400.0 && fabs(q[1]) < 400.0 && q[2] > -1.0 && q[2] < 40.0);
    }
    assert_true(l.points[0].gps_time >= 388102418.0);
    const int expected[] = { 2, 5, 6, 11, 14, 15, 64 };
    for (size_t k = 0; k < sizeof(expected) / sizeof(expected[0]); k++) {
        if (classes[expected[k]] == 0) {
            fail_msg("class %d missing", expected[k]);
        }
    }
    assert_true(multi_in_trees > 100);
    unload(&l);
}

static void street_intensity_follows_incidence(void **state)
{
    (void)state;
    sta_synth_params p = { .kind = STA_SYNTH_STREET, .seed = 21, .point_count = 100000 };
    loaded l;
    street_file("intensity.las", &p, &l);
    sta_synth_scene *scene = NULL;
    assert_int_equal(sta_synth_scene_create(&p, &scene, NULL), STA_OK);
    sta_synth_georef g;
    sta_synth_georef_init(STA_SYNTH_ORIGIN_UTM, &g);
    // Road points (one material) 4 .. 8 m from the scanner: steep against grazing.
    double sum[2] = { 0, 0 };
    size_t n[2] = { 0, 0 };
    for (size_t i = 0; i < l.count; i++) {
        const sta_point *pt = &l.points[i];
        if (pt->user_data != STA_SYNTH_MAT_ROAD || pt->number_of_returns != 1) {
            continue;
        }
        double q[3], s[3];
        local_of(&l, &g, i, q);
        assert_int_equal(sta_synth_scene_scanner_position(scene, pt->gps_time, s, NULL), STA_OK);
        double d[3] = { q[0] - s[0], q[1] - s[1], q[2] - s[2] };
        double range = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        if (range < 4.0 || range > 8.0) {
            continue;
        }
        double cos_i = fabs(d[2]) / range; // the road is within 1.2 degrees of level
        int bin = cos_i > 0.6 ? 0 : (cos_i < 0.35 ? 1 : -1);
        if (bin >= 0) {
            sum[bin] += pt->intensity;
            n[bin]++;
        }
    }
    assert_true(n[0] > 100 && n[1] > 100);
    double steep = sum[0] / (double)n[0], grazing = sum[1] / (double)n[1];
    assert_true(steep > 1.4 * grazing);
    sta_synth_scene_destroy(scene);
    unload(&l);
}

static void street_points_agree_with_the_ray_caster(void **state)
{
    (void)state;
    sta_synth_params p = {
        .kind = STA_SYNTH_STREET, .seed = 5, .point_count = 60000, .has_noise = true, .noise_m = 0.0
    };
    loaded l;
    street_file("agree.las", &p, &l);
    sta_synth_scene *scene = NULL;
    assert_int_equal(sta_synth_scene_create(&p, &scene, NULL), STA_OK);
    sta_synth_georef g;
    sta_synth_georef_init(STA_SYNTH_ORIGIN_UTM, &g);
    size_t checked = 0, agreed = 0;
    for (size_t i = 0; i < l.count; i += 7) {
        const sta_point *pt = &l.points[i];
        if (pt->number_of_returns != 1) {
            continue;
        }
        double q[3], s[3];
        local_of(&l, &g, i, q);
        sta_synth_scene_scanner_position(scene, pt->gps_time, s, NULL);
        double d[3] = { q[0] - s[0], q[1] - s[1], q[2] - s[2] };
        double range = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        for (int a = 0; a < 3; a++) {
            d[a] /= range;
        }
        sta_synth_hit hit;
        checked++;
        bool got = sta_synth_scene_raycast_ex(scene, s, d, 0.5, 200.0, 0, &hit);
        // The stored point is within half a grid step per axis of the true surface point:
        // compare its distance to the hit surface's plane (robust at grazing angles).
        double off = 1.0;
        if (got) {
            off = 0.0;
            for (int a = 0; a < 3; a++) {
                off += (q[a] - (s[a] + hit.t * d[a])) * hit.normal[a];
            }
        }
        if (got && fabs(off) < 1e-3 && fabs(hit.t - range) < 0.05 &&
            hit.classification == pt->classification && hit.material == pt->user_data) {
            agreed++;
        } else if (getenv("STA_SYNTH_DEBUG")) {
            fprintf(stderr, "point %zu mat %d range %.4f: got %d t %.4f mat %d\n", i, pt->user_data,
                    range, got, got ? hit.t : 0.0, got ? hit.material : 0);
        }
    }
    // Grid rounding (0.5 mm) can move a ray off an edge now and then.
    assert_true(checked > 5000);
    assert_true((double)agreed > 0.995 * (double)checked);
    sta_synth_scene_destroy(scene);
    unload(&l);
}

static void street_geometry_does_not_depend_on_the_origin(void **state)
{
    (void)state;
    const sta_synth_origin origins[3] = { STA_SYNTH_ORIGIN_ZERO, STA_SYNTH_ORIGIN_UTM,
                                          STA_SYNTH_ORIGIN_ECEF };
    loaded l[3];
    sta_synth_georef g[3];
    for (int k = 0; k < 3; k++) {
        sta_synth_params p = {
            .kind = STA_SYNTH_STREET, .seed = 12, .point_count = 20000, .origin = origins[k]
        };
        street_file("origin.las", &p, &l[k]);
        sta_synth_georef_init(origins[k], &g[k]);
    }
    // The ECEF origin is about 6.4e6 m from the Earth's centre.
    double r = sqrt(g[2].origin[0] * g[2].origin[0] + g[2].origin[1] * g[2].origin[1] +
                    g[2].origin[2] * g[2].origin[2]);
    assert_true(r > 6.3e6 && r < 6.45e6);
    assert_true(fabs(g[1].origin[0] - 650000.0) < 1000.0 &&
                fabs(g[1].origin[1] - 5400000.0) < 3000.0);
    for (size_t i = 0; i < l[0].count; i++) {
        double zero[3];
        local_of(&l[0], &g[0], i, zero);
        for (int k = 1; k < 3; k++) {
            double q[3];
            local_of(&l[k], &g[k], i, q);
            for (int a = 0; a < 3; a++) {
                // Exactly the same integers; the real coordinates within one grid step.
                assert_true(fabs(q[a] - zero[a]) <= 0.001);
            }
            assert_int_equal(l[k].points[i].X - l[0].points[i].X, g[k].origin_steps[0]);
            assert_int_equal(l[k].points[i].Y - l[0].points[i].Y, g[k].origin_steps[1]);
            assert_int_equal(l[k].points[i].Z - l[0].points[i].Z, g[k].origin_steps[2]);
            assert_int_equal(l[k].points[i].intensity, l[0].points[i].intensity);
            assert_true(l[k].points[i].gps_time == l[0].points[i].gps_time);
        }
    }
    for (int k = 0; k < 3; k++) {
        unload(&l[k]);
    }
}

static void las12_format3_uses_legacy_classes(void **state)
{
    (void)state;
    sta_synth_params p = {
        .kind = STA_SYNTH_STREET, .seed = 1, .point_count = 40000, .point_format = 3
    };
    loaded l;
    street_file("legacy.las", &p, &l);
    assert_int_equal(l.version_minor, 2);
    assert_int_equal(l.point_format, 3);
    for (size_t i = 0; i < l.count; i++) {
        uint8_t c = l.points[i].classification;
        assert_true(c == 1 || c == 2 || c == 5 || c == 6);
        assert_true(l.points[i].number_of_returns <= 5);
    }
    unload(&l);
}

static void raycast_hits_and_misses(void **state)
{
    (void)state;
    sta_synth_params p = { .kind = STA_SYNTH_SPHERE, .point_count = 1 };
    sta_synth_scene *scene = NULL;
    assert_int_equal(sta_synth_scene_create(&p, &scene, NULL), STA_OK);
    sta_synth_hit hit = { .t = -1.0 };
    const double o[3] = { 0.0, 0.0, -30.0 }, up[3] = { 0.0, 0.0, 1.0 };
    assert_true(sta_synth_scene_raycast(scene, o, up, 100.0, &hit));
    assert_true(fabs(hit.t - 20.0) < 1e-12); // distance 30 minus radius 10
    assert_true(fabs(hit.normal[2] + 1.0) < 1e-12);
    assert_false(sta_synth_scene_raycast(scene, o, up, 19.9, &hit));
    const double beside[3] = { 0.0, 10.5, -30.0 };
    assert_false(sta_synth_scene_raycast(scene, beside, up, 1e6, &hit));
    sta_synth_scene_destroy(scene);

    // The street: straight down from 50 m above the run start meets the road; a ray
    // into the sky from there meets nothing.
    p = (sta_synth_params){ .kind = STA_SYNTH_STREET, .seed = 1, .point_count = 1000 };
    assert_int_equal(sta_synth_scene_create(&p, &scene, NULL), STA_OK);
    double s[3];
    assert_int_equal(sta_synth_scene_scanner_position(scene, 388102418.0, s, NULL), STA_OK);
    const double above[3] = { s[0], s[1], 50.0 }, down[3] = { 0.0, 0.0, -1.0 };
    assert_true(sta_synth_scene_raycast(scene, above, down, 1e3, &hit));
    assert_true(hit.material == STA_SYNTH_MAT_ROAD || hit.material == STA_SYNTH_MAT_MARKING);
    assert_int_equal(hit.classification, 11);
    assert_true(hit.t > 50.0 && hit.t < 50.2); // the crowned road is a little below 0
    assert_true(hit.normal[2] > 0.999);
    assert_false(sta_synth_scene_raycast(scene, above, up, 1e3, &hit));
    sta_error err = { 0 };
    sta_synth_scene_destroy(scene);
    p = (sta_synth_params){ .kind = STA_SYNTH_SPHERE, .point_count = 1 };
    assert_int_equal(sta_synth_scene_create(&p, &scene, NULL), STA_OK);
    assert_int_equal(sta_synth_scene_scanner_position(scene, 0.0, s, &err), STA_ERR_ARG);
    sta_synth_scene_destroy(scene);
}

static void bad_parameters_are_refused(void **state)
{
    (void)state;
    sta_error err = { 0 };
    sta_synth_scene *scene = NULL;
    sta_synth_params p = { .kind = STA_SYNTH_STREET, .point_count = 0 };
    assert_int_equal(sta_synth_scene_create(&p, &scene, &err), STA_ERR_ARG);
    p = (sta_synth_params){ .kind = STA_SYNTH_SPHERE, .point_count = 10, .point_format = 6 };
    assert_int_equal(sta_synth_scene_create(&p, &scene, &err), STA_ERR_ARG);
    p = (sta_synth_params){ .kind = STA_SYNTH_MESH, .point_count = 10 };
    assert_int_equal(sta_synth_scene_create(&p, &scene, &err), STA_ERR_ARG);
    assert_non_null(strstr(err.message, "--mesh"));
    p = (sta_synth_params){ .kind = STA_SYNTH_SPHERE,
                            .point_count = 5000000000ull,
                            .point_format = 3 };
    assert_int_equal(sta_synth_scene_create(&p, &scene, &err), STA_ERR_ARG);
    p = (sta_synth_params){ .kind = STA_SYNTH_MESH,
                            .point_count = 10,
                            .mesh_path = "/nonexistent/model.ply" };
    assert_int_not_equal(sta_synth_scene_create(&p, &scene, &err), STA_OK);
    assert_non_null(strstr(err.message, "/nonexistent/model.ply"));
    assert_null(scene);
    sta_synth_kind kind;
    assert_true(sta_synth_kind_from_name("nested", &kind) && kind == STA_SYNTH_NESTED);
    assert_false(sta_synth_kind_from_name("tower", &kind));
}

static void truth_path_replaces_the_las_suffix(void **state)
{
    (void)state;
    const char *cases[4][2] = { { "a/x.las", "a/x.truth.json" },
                                { "X.LAS", "X.truth.json" },
                                { "scan", "scan.truth.json" },
                                { "las", "las.truth.json" } };
    for (int i = 0; i < 4; i++) {
        char *t = truth_of(cases[i][0]);
        assert_string_equal(t, cases[i][1]);
        sta_free(t);
    }
}

static void sidecar_holds_the_truth(void **state)
{
    (void)state;
    sta_synth_params p = { .kind = STA_SYNTH_NESTED, .seed = 99, .point_count = 1000 };
    char *path = path_copy("side.las");
    generate(&p, path);
    char *truth = truth_of(path);
    size_t size = 0;
    char *text = (char *)sta_test_read_file(truth, &size);
    char *json = sta_calloc(size + 1, 1);
    memcpy(json, text, size);
    assert_non_null(strstr(json, "\"scene\": \"nested\""));
    assert_non_null(strstr(json, "\"seed\": 99"));
    assert_non_null(strstr(json, "\"point_count\": 1000"));
    assert_non_null(strstr(json, "\"type\": \"sphere\", \"centre\": [0, 0, 0], \"radius_m\": 3"));
    assert_non_null(strstr(json, "\"box\": {\"min\": [-5, -5, -5], \"max\": [5, 5, 5]}"));
    assert_non_null(strstr(json, "\"origin\": [650241.375, 5401873.625, 103.25]"));
    free(text);
    sta_free(json);
    sta_free(truth);

    p = (sta_synth_params){ .kind = STA_SYNTH_STREET, .seed = 99, .point_count = 1000 };
    generate(&p, path);
    truth = truth_of(path);
    text = (char *)sta_test_read_file(truth, &size);
    json = sta_calloc(size + 1, 1);
    memcpy(json, text, size);
    assert_non_null(strstr(json, "\"generator_version\": 1"));
    assert_non_null(strstr(json, "\"rays_per_profile\": "));
    assert_non_null(strstr(json, "\"run_length_m\": "));
    free(text);
    sta_free(json);
    sta_free(truth);
    sta_free(path);
}

/* Runs strata-synth with `args`; returns its exit status, stderr in `message`. */
static int run_cli(const char *args, char *message, size_t size)
{
    const char *exe = STA_BINARY_DIR "/src/strata-synth";
    char err_path[4096];
    snprintf(err_path, sizeof(err_path), "%s", sta_test_tmp_path("cli.err"));
    char command[8192];
    snprintf(command, sizeof(command), "'%s' %s 2>'%s' >/dev/null", exe, args, err_path);
    int status = system(command);
    size_t n = 0;
    uint8_t *text = sta_test_read_file(err_path, &n);
    n = n < size - 1 ? n : size - 1;
    memcpy(message, text, n);
    message[n] = '\0';
    free(text);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

static void cli_reports_bad_arguments(void **state)
{
    (void)state;
    if (access(STA_BINARY_DIR "/src/strata-synth", X_OK) != 0) {
        STA_TEST_SKIP("strata-synth is not built");
    }
    char msg[2048];
    char out[4096];
    snprintf(out, sizeof(out), "%s", sta_test_tmp_path("cli.las"));
    char args[8192];
    assert_int_equal(run_cli("tower -o x.las", msg, sizeof(msg)), 2);
    assert_non_null(strstr(msg, "unknown scene 'tower'"));
    assert_int_equal(run_cli("sphere -o x.las --points 0", msg, sizeof(msg)), 2);
    assert_non_null(strstr(msg, "--points"));
    assert_int_equal(run_cli("sphere -o x.las --points 12x", msg, sizeof(msg)), 2);
    assert_non_null(strstr(msg, "'12x'"));
    assert_int_equal(run_cli("sphere --points 10", msg, sizeof(msg)), 2);
    assert_non_null(strstr(msg, "-o"));
    assert_int_equal(run_cli("sphere -o x.las --format 6", msg, sizeof(msg)), 2);
    assert_int_equal(run_cli("mesh -o x.las", msg, sizeof(msg)), 2);
    assert_int_equal(run_cli("--help", msg, sizeof(msg)), 0);
    snprintf(args, sizeof(args), "sphere --points 10 -o '%s/no/such/dir/x.las'", sta_test_tmpdir());
    assert_int_equal(run_cli(args, msg, sizeof(msg)), 1);
    assert_non_null(strstr(msg, "/no/such/dir/x.las"));
    snprintf(args, sizeof(args), "street --points 2k --seed 3 --quiet -o '%s'", out);
    assert_int_equal(run_cli(args, msg, sizeof(msg)), 0);
    assert_string_equal(msg, "");
    loaded l;
    load(out, &l);
    assert_int_equal(l.count, 2000);
    unload(&l);
}

static const struct CMUnitTest tests[] = {
    cmocka_unit_test(same_seed_gives_same_bytes),
    cmocka_unit_test(point_count_is_exact),
    cmocka_unit_test(sphere_points_and_normals_are_true),
    cmocka_unit_test(sphere_noise_has_the_given_sigma),
    cmocka_unit_test(nested_sphere_is_inside_the_box_and_hidden),
    cmocka_unit_test(planes_lie_at_their_depths),
    cmocka_unit_test(mesh_points_lie_on_the_triangles),
    cmocka_unit_test(bunny_mesh_samples_fill_its_box),
    cmocka_unit_test(street_has_classes_returns_and_times),
    cmocka_unit_test(street_intensity_follows_incidence),
    cmocka_unit_test(street_points_agree_with_the_ray_caster),
    cmocka_unit_test(street_geometry_does_not_depend_on_the_origin),
    cmocka_unit_test(las12_format3_uses_legacy_classes),
    cmocka_unit_test(raycast_hits_and_misses),
    cmocka_unit_test(bad_parameters_are_refused),
    cmocka_unit_test(truth_path_replaces_the_las_suffix),
    cmocka_unit_test(sidecar_holds_the_truth),
    cmocka_unit_test(cli_reports_bad_arguments),
};

STA_TEST_MAIN(tests)
