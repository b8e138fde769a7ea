/* SPDX-License-Identifier: MIT
 * CSV and JSON output of the benchmark. */
#include "bench/report.h"

#include <errno.h>
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

#include "core/json_out.h"

typedef enum column_type {
    COL_STR,
    COL_INT,
    COL_U32,
    COL_U64,
    COL_F64,
} column_type;

typedef struct column {
    const char *name;
    column_type type;
    size_t offset;
} column;

#define COL(name, type)                                                                            \
 {                                                                                                 \
#  name, type, offsetof(sta_bench_row, name)                                                       \
 }
#define PASS(label, pass)                                                                          \
 {                                                                                                 \
  label, COL_F64, offsetof(sta_bench_row, pass_ms) + (pass) * sizeof(double)                       \
 }
#define EYE(label, axis)                                                                           \
 {                                                                                                 \
  label, COL_F64, offsetof(sta_bench_row, eye) + (axis) * sizeof(double)                           \
 }

static const column columns[] = {
    COL(scene, COL_STR),
    COL(scene_points, COL_U64),
    COL(camera, COL_INT),
    COL(camera_kind, COL_STR),
    EYE("eye_x", 0),
    EYE("eye_y", 1),
    EYE("eye_z", 2),
    COL(yaw_deg, COL_F64),
    COL(pitch_deg, COL_F64),
    COL(width_px, COL_INT),
    COL(height_px, COL_INT),
    COL(budget, COL_U64),
    COL(setting, COL_STR),
    COL(pipeline, COL_STR),
    COL(normals, COL_STR),
    COL(samples, COL_INT),
    COL(hpr, COL_STR),
    COL(s0_m, COL_F64),
    COL(repeat, COL_INT),
    COL(points_drawn, COL_U64),
    COL(points_selected, COL_U64),
    COL(nodes_drawn, COL_U32),
    COL(nodes_resident, COL_U32),
    COL(loader_backlog, COL_U64),
    COL(load_s, COL_F64),
    COL(geometry_ms, COL_F64),
    PASS("unproject_ms", STA_PASS_UNPROJECT),
    PASS("hpr_ms", STA_PASS_HPR),
    PASS("pullpush_ms", STA_PASS_PULLPUSH),
    PASS("normals_ms", STA_PASS_NORMALS),
    PASS("smooth_ms", STA_PASS_SMOOTH),
    PASS("shade_ms", STA_PASS_SHADE),
    COL(screen_ms, COL_F64),
    COL(gpu_ms, COL_F64),
    COL(frame_ms, COL_F64),
    COL(cpu_ms, COL_F64),
    COL(truth_points, COL_U64),
    COL(truly_hidden, COL_U64),
    COL(hpr_tp, COL_U64),
    COL(hpr_fp, COL_U64),
    COL(hpr_fn, COL_U64),
    COL(hpr_tn, COL_U64),
    COL(hpr_precision, COL_F64),
    COL(hpr_recall, COL_F64),
    COL(hpr_f1, COL_F64),
    COL(hpr_face_points, COL_U64),
    COL(hpr_face_f1, COL_F64),
    COL(hpr_face_glass_points, COL_U64),
    COL(hpr_face_glass_f1, COL_F64),
    COL(hpr_volumetric_points, COL_U64),
    COL(hpr_volumetric_f1, COL_F64),
    COL(normal_count, COL_U64),
    COL(normal_mean_deg, COL_F64),
    COL(normal_median_deg, COL_F64),
    COL(normal_p95_deg, COL_F64),
    COL(normal_sampled_count, COL_U64),
    COL(normal_sampled_mean_deg, COL_F64),
    COL(normal_sampled_median_deg, COL_F64),
    COL(normal_sampled_p95_deg, COL_F64),
    COL(normal_face_count, COL_U64),
    COL(normal_face_mean_deg, COL_F64),
    COL(normal_face_median_deg, COL_F64),
    COL(normal_face_p95_deg, COL_F64),
    COL(normal_off_share, COL_F64),
    COL(normal_off_facing_share, COL_F64),
    COL(normal_off_other_share, COL_F64),
    COL(normal_face_off_share, COL_F64),
    COL(normal_off_fill_share, COL_F64),
    COL(normal_unknown_share, COL_F64),
    COL(normal_shaded_median_deg, COL_F64),
    COL(normal_shaded_p95_deg, COL_F64),
    COL(normal_shaded_off_share, COL_F64),
    COL(depth_count, COL_U64),
    COL(depth_rel_mean, COL_F64),
    COL(depth_rel_median, COL_F64),
    COL(depth_rel_p95, COL_F64),
    COL(point_size, COL_STR),
    COL(surface_pixels, COL_U64),
    COL(surface_hole, COL_F64),
    COL(surface_see_through, COL_F64),
    COL(surface_bleed, COL_F64),
    COL(surface_error, COL_F64),
    COL(depth_sampled_count, COL_U64),
    COL(depth_sampled_rel_mean, COL_F64),
    COL(depth_sampled_rel_median, COL_F64),
    COL(depth_sampled_rel_p95, COL_F64),
    COL(depth_glass_count, COL_U64),
    COL(depth_glass_rel_mean, COL_F64),
    COL(depth_glass_rel_median, COL_F64),
    COL(depth_glass_rel_p95, COL_F64),
    COL(fill_left_out, COL_U64),
    COL(border_count, COL_U64),
    COL(border_empty, COL_F64),
    COL(gap_blocks_8, COL_F64),
    COL(gap_blocks_16, COL_F64),
    COL(gap_blocks_32, COL_F64),
    COL(psnr_db, COL_F64),
    COL(ssim, COL_F64),
    COL(katz_ms, COL_F64),
    COL(katz_radius_m, COL_F64),
    COL(katz_hull_ms, COL_F64),
    COL(katz_plain_hull_ms, COL_F64),
    COL(katz_plain_f1, COL_F64),
    COL(katz_points, COL_U64),
    COL(katz_visible, COL_U64),
    COL(katz_precision, COL_F64),
    COL(katz_recall, COL_F64),
    COL(katz_f1, COL_F64),
    COL(katz_live_latency_ms, COL_F64),
    COL(katz_live_frames, COL_INT),
    COL(katz_live_hull_cpu_ms, COL_F64),
    COL(katz_live_plain_hull_ms, COL_F64),
};

#define COLUMN_COUNT (sizeof(columns) / sizeof(columns[0]))

static const void *at(const sta_bench_row *row, const column *c)
{
    return (const char *)row + c->offset;
}

static double get_f64(const sta_bench_row *row, const column *c)
{
    double v;
    memcpy(&v, at(row, c), sizeof(v));
    return v;
}

static uint64_t get_u64(const sta_bench_row *row, const column *c)
{
    switch (c->type) {
    case COL_INT: {
        int v;
        memcpy(&v, at(row, c), sizeof(v));
        return (uint64_t)(int64_t)v;
    }
    case COL_U32: {
        uint32_t v;
        memcpy(&v, at(row, c), sizeof(v));
        return v;
    }
    default: {
        uint64_t v;
        memcpy(&v, at(row, c), sizeof(v));
        return v;
    }
    }
}

// CSV fields: strings quoted when they hold a comma, quote or newline.
static void put_csv_string(FILE *f, const char *s)
{
    if (!strpbrk(s, ",\"\n")) {
        fputs(s, f);
        return;
    }
    fputc('"', f);
    for (; *s; s++) {
        if (*s == '"') {
            fputc('"', f);
        }
        fputc(*s, f);
    }
    fputc('"', f);
}

static void put_csv_row(FILE *f, const sta_bench_row *row)
{
    char text[48];
    for (size_t i = 0; i < COLUMN_COUNT; i++) {
        const column *c = &columns[i];
        if (i) {
            fputc(',', f);
        }
        switch (c->type) {
        case COL_STR:
            put_csv_string(f, (const char *)at(row, c));
            break;
        case COL_INT:
            fprintf(f, "%d", (int)(int64_t)get_u64(row, c));
            break;
        case COL_U32:
        case COL_U64:
            fprintf(f, "%llu", (unsigned long long)get_u64(row, c));
            break;
        case COL_F64: {
            double v = get_f64(row, c);
            if (isinf(v)) {
                fputs(v > 0 ? "inf" : "-inf", f);
            } else if (!isnan(v)) {
                fputs(sta_format_double(v, text, sizeof(text)), f);
            }
            break;
        }
        }
    }
    fputc('\n', f);
}

static sta_status close_checked(FILE *f, const char *path, sta_error *err)
{
    bool failed = ferror(f) != 0;
    if (fclose(f) != 0 || failed) {
        return sta_fail(err, STA_ERR_IO, "%s: write failed: %s", path, strerror(errno));
    }
    return STA_OK;
}

sta_status sta_bench_write_csv(const char *path, const sta_bench_results *results, sta_error *err)
{
    FILE *f = fopen(path, "w");
    if (!f) {
        return sta_fail(err, STA_ERR_IO, "%s: cannot create: %s", path, strerror(errno));
    }
    for (size_t i = 0; i < COLUMN_COUNT; i++) {
        fprintf(f, "%s%s", i ? "," : "", columns[i].name);
    }
    fputc('\n', f);
    for (size_t r = 0; r < results->count; r++) {
        put_csv_row(f, &results->rows[r]);
    }
    return close_checked(f, path, err);
}

sta_status sta_bench_write_json(const char *path, const char *renderer,
                                const sta_bench_results *results, sta_error *err)
{
    FILE *f = fopen(path, "w");
    if (!f) {
        return sta_fail(err, STA_ERR_IO, "%s: cannot create: %s", path, strerror(errno));
    }
    sta_json_out json;
    sta_json_init(&json, f, true);
    sta_json_begin_object(&json);
    sta_json_key(&json, "tool");
    sta_json_string(&json, "strata-bench");
    sta_json_key(&json, "renderer");
    sta_json_string(&json, renderer ? renderer : "");
    sta_json_key(&json, "rows");
    sta_json_begin_array(&json);
    for (size_t r = 0; r < results->count; r++) {
        const sta_bench_row *row = &results->rows[r];
        sta_json_begin_object(&json);
        for (size_t i = 0; i < COLUMN_COUNT; i++) {
            const column *c = &columns[i];
            sta_json_key(&json, c->name);
            switch (c->type) {
            case COL_STR:
                sta_json_string(&json, (const char *)at(row, c));
                break;
            case COL_INT:
                sta_json_int(&json, (int64_t)get_u64(row, c));
                break;
            case COL_U32:
            case COL_U64:
                sta_json_uint(&json, get_u64(row, c));
                break;
            case COL_F64:
                sta_json_double(&json, get_f64(row, c));
                break;
            }
        }
        sta_json_key(&json, "identical");
        sta_json_bool(&json, isinf(row->psnr_db) && row->psnr_db > 0);
        sta_json_end_object(&json);
    }
    sta_json_end_array(&json);
    sta_json_end_object(&json);
    sta_json_finish(&json);
    return close_checked(f, path, err);
}

sta_status sta_bench_write_reports(const char *dir, const char *renderer,
                                   const sta_bench_results *results, sta_error *err)
{
    char path[4096];
    if (!dir[0]) {
        return sta_fail(err, STA_ERR_ARG, "empty output folder name");
    }
    // Make each missing parent in turn (mkdir -p).
    snprintf(path, sizeof(path), "%s", dir);
    for (char *p = path + 1;; p++) {
        char saved = *p;
        if (saved == '/' || saved == '\0') {
            *p = '\0';
            if (mkdir(path, 0777) != 0 && errno != EEXIST) {
                return sta_fail(err, STA_ERR_IO, "%s: cannot create: %s", path, strerror(errno));
            }
            *p = saved;
        }
        if (saved == '\0') {
            break;
        }
    }
    if (snprintf(path, sizeof(path), "%s/results.csv", dir) >= (int)sizeof(path)) {
        return sta_fail(err, STA_ERR_ARG, "%s: output folder name too long", dir);
    }
    sta_status s = sta_bench_write_csv(path, results, err);
    if (s == STA_OK) {
        snprintf(path, sizeof(path), "%s/results.json", dir);
        s = sta_bench_write_json(path, renderer, results, err);
    }
    return s;
}
