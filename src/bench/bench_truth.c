/* SPDX-License-Identifier: MIT
 * Ground truth from a strata-synth sidecar. */
#include "bench/bench_truth.h"

#include <cjson/cJSON.h>
#include <errno.h>
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/alloc.h"
#include "core/file_map.h"

sta_status sta_bench_truth_init(const sta_synth_params *params, const double origin[3],
                                sta_bench_truth *out, sta_error *err)
{
    memset(out, 0, sizeof(*out));
    sta_status s = sta_synth_scene_create(params, &out->scene, err);
    if (s != STA_OK) {
        return s;
    }
    memcpy(out->origin, origin, sizeof(out->origin));
    out->noise_m = params->has_noise ? params->noise_m : 0.0;
    return STA_OK;
}

void sta_bench_truth_release(sta_bench_truth *t)
{
    sta_synth_scene_destroy(t->scene);
    memset(t, 0, sizeof(*t));
}

static const cJSON *field(const cJSON *object, const char *name)
{
    return object ? cJSON_GetObjectItemCaseSensitive(object, name) : NULL;
}

static bool get_number(const cJSON *object, const char *name, double *out)
{
    const cJSON *item = field(object, name);
    if (!cJSON_IsNumber(item)) {
        return false;
    }
    *out = item->valuedouble;
    return true;
}

// Seeds span 0 .. 2^64 - 1, beyond what a double holds exactly: read the digits from
// the text itself (the sidecar writes "seed": <digits> once, at the top level).
static bool parse_seed(const char *text, size_t size, uint64_t *out)
{
    static const char key[] = "\"seed\":";
    const size_t key_len = sizeof(key) - 1;
    for (size_t i = 0; i + key_len < size; i++) {
        if (memcmp(text + i, key, key_len) != 0) {
            continue;
        }
        char digits[32];
        size_t j = i + key_len, n = 0;
        while (j < size && text[j] == ' ') {
            j++;
        }
        while (j < size && n + 1 < sizeof(digits) && text[j] >= '0' && text[j] <= '9') {
            digits[n++] = text[j++];
        }
        if (n == 0) {
            return false;
        }
        digits[n] = '\0';
        errno = 0;
        unsigned long long v = strtoull(digits, NULL, 10);
        *out = (uint64_t)v;
        return errno == 0;
    }
    return false;
}

sta_status sta_bench_truth_load(const char *path, sta_bench_truth *out, sta_error *err)
{
    memset(out, 0, sizeof(*out));
    sta_file_map map = { 0 };
    sta_status s = sta_file_map_open(path, &map, err);
    if (s != STA_OK) {
        return s;
    }
    cJSON *root = cJSON_ParseWithLength((const char *)map.data, map.size);
    sta_synth_params p = { 0 };
    double origin[3] = { 0 }, number = 0.0;
    char mesh_buf[4096];
    const char *bad = NULL;
    if (!root) {
        bad = "not valid JSON";
        goto out_close;
    }
    const cJSON *format = field(root, "format");
    if (!cJSON_IsString(format) || strcmp(format->valuestring, "strata-synth-truth") != 0) {
        bad = "field \"format\" is not \"strata-synth-truth\"";
        goto out_close;
    }
    const cJSON *scene = field(root, "scene");
    if (!cJSON_IsString(scene) || !sta_synth_kind_from_name(scene->valuestring, &p.kind)) {
        bad = "field \"scene\" names no known scene";
        goto out_close;
    }
    if (!parse_seed((const char *)map.data, map.size, &p.seed)) {
        bad = "field \"seed\" is missing or not an unsigned integer";
        goto out_close;
    }
    if (!get_number(root, "point_count", &number) || number < 1.0) {
        bad = "field \"point_count\" is missing or below 1";
        goto out_close;
    }
    p.point_count = (uint64_t)number;
    if (get_number(root, "noise_sigma_m", &p.noise_m)) {
        p.has_noise = true;
    }
    const cJSON *georef = field(root, "georef");
    const cJSON *o = field(georef, "origin");
    if (!cJSON_IsArray(o) || cJSON_GetArraySize(o) != 3) {
        bad = "field \"georef.origin\" is not an array of 3 numbers";
        goto out_close;
    }
    for (int a = 0; a < 3; a++) {
        const cJSON *v = cJSON_GetArrayItem(o, a);
        if (!cJSON_IsNumber(v)) {
            bad = "field \"georef.origin\" is not an array of 3 numbers";
            goto out_close;
        }
        origin[a] = v->valuedouble;
    }
    const cJSON *kind = field(georef, "origin_kind");
    if (cJSON_IsString(kind)) {
        p.origin = strcmp(kind->valuestring, "zero") == 0   ? STA_SYNTH_ORIGIN_ZERO
                   : strcmp(kind->valuestring, "ecef") == 0 ? STA_SYNTH_ORIGIN_ECEF
                                                            : STA_SYNTH_ORIGIN_UTM;
    }
    const cJSON *las = field(root, "las");
    double format_number = 7.0;
    if (get_number(las, "point_format", &format_number)) {
        p.point_format = (int)format_number;
    }
    if (p.kind == STA_SYNTH_MESH) {
        const cJSON *mesh_path = field(field(root, "mesh"), "path");
        if (!cJSON_IsString(mesh_path)) {
            bad = "field \"mesh.path\" is missing";
            goto out_close;
        }
        // A relative mesh path is relative to the sidecar's folder, not to the
        // working directory (the sidecar travels with its LAS).
        const char *mesh = mesh_path->valuestring;
        const char *slash = strrchr(path, '/');
        if (mesh[0] != '/' && slash) {
            int n =
                snprintf(mesh_buf, sizeof(mesh_buf), "%.*s/%s", (int)(slash - path), path, mesh);
            if (n < 0 || (size_t)n >= sizeof(mesh_buf)) {
                bad = "field \"mesh.path\" is too long";
                goto out_close;
            }
            mesh = mesh_buf;
        }
        p.mesh_path = mesh;
        // The model's up as the synth applied it; sidecars from before "up" kept the
        // model's axes.
        const cJSON *up = field(field(root, "mesh"), "up");
        bool y = cJSON_IsString(up) && strcmp(up->valuestring, "y") == 0;
        bool z = !up || (cJSON_IsString(up) && strcmp(up->valuestring, "z") == 0);
        if (!y && !z) {
            bad = "field \"mesh.up\" is neither \"y\" nor \"z\"";
            goto out_close;
        }
        p.mesh_up = y ? STA_SYNTH_MESH_UP_Y : STA_SYNTH_MESH_UP_Z;
    }
    const cJSON *scanner = field(root, "scanner");
    if (p.kind == STA_SYNTH_STREET) {
        double length = 0.0;
        if (get_number(scanner, "raycast_length_m", &length) && length > 0.0) {
            p.street_length_m = length;
        }
    }
    s = sta_bench_truth_init(&p, origin, out, err);
    if (s == STA_OK && p.kind == STA_SYNTH_STREET) {
        get_number(scanner, "gps_time_start", &out->gps_time[0]);
        get_number(scanner, "gps_time_end", &out->gps_time[1]);
    }
out_close:
    cJSON_Delete(root);
    sta_file_map_close(&map);
    if (bad) {
        return sta_fail(err, STA_ERR_FORMAT, "%s: %s", path, bad);
    }
    return s;
}

bool sta_bench_truth_ray(sta_bench_truth *t, const double eye[3], const double dir[3], double max_t,
                         sta_synth_hit *out_hit)
{
    const double local[3] = { eye[0] - t->origin[0], eye[1] - t->origin[1], eye[2] - t->origin[2] };
    return sta_synth_scene_raycast(t->scene, local, dir, max_t, out_hit);
}

bool sta_bench_truth_ray_glass(sta_bench_truth *t, const double eye[3], const double dir[3],
                               double max_t, sta_synth_hit *out_hit)
{
    const double local[3] = { eye[0] - t->origin[0], eye[1] - t->origin[1], eye[2] - t->origin[2] };
    return sta_synth_scene_raycast_ex(t->scene, local, dir, 0.0, max_t, STA_SYNTH_RAY_GLASS,
                                      out_hit);
}

bool sta_bench_truth_point_visible(sta_bench_truth *t, const double eye[3], const double point[3],
                                   double tolerance_m)
{
    double d[3] = { point[0] - eye[0], point[1] - eye[1], point[2] - eye[2] };
    double distance = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    if (distance <= tolerance_m || distance == 0.0) {
        return true;
    }
    for (int a = 0; a < 3; a++) {
        d[a] /= distance;
    }
    sta_synth_hit hit;
    return !sta_bench_truth_ray(t, eye, d, distance - tolerance_m, &hit);
}

void sta_bench_camera_to_world(const sta_camera *camera, const double v[3], double out[3])
{
    double f[3], r[3], u[3];
    sta_camera_basis(camera, f, r, u);
    for (int a = 0; a < 3; a++) {
        out[a] = v[0] * r[a] + v[1] * u[a] - v[2] * f[a];
    }
}

void sta_bench_pixel_ray(const sta_camera *camera, int x, int y, double out_dir[3],
                         double *out_axis_cosine)
{
    double tan_y = tan(0.5 * camera->fov_y);
    double tan_x = tan_y * (double)camera->width_px / (double)camera->height_px;
    double v[3] = { (((double)x + 0.5) / camera->width_px * 2.0 - 1.0) * tan_x,
                    (((double)y + 0.5) / camera->height_px * 2.0 - 1.0) * tan_y, -1.0 };
    double length = sqrt(v[0] * v[0] + v[1] * v[1] + 1.0);
    for (int a = 0; a < 3; a++) {
        v[a] /= length;
    }
    sta_bench_camera_to_world(camera, v, out_dir);
    *out_axis_cosine = 1.0 / length;
}
