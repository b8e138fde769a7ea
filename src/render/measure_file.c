/* SPDX-License-Identifier: MIT
 * Measurement files: JSON save/load (cJSON), CSV export. */
#include "render/measure_file.h"

#include <cjson/cJSON.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "core/alloc.h"
#include "core/json_out.h"
#include "render/json_file.h"

// Opens "<path>.tmp-<pid>" for writing; the caller renames it.
static FILE *open_temporary(const char *path, char *tmp, size_t size, sta_error *err)
{
    snprintf(tmp, size, "%s.tmp-%ld", path, (long)getpid());
    FILE *f = fopen(tmp, "w");
    if (!f) {
        sta_fail(err, STA_ERR_IO, "%s: cannot write: %s", path, strerror(errno));
    }
    return f;
}

static sta_status finish_temporary(FILE *f, const char *tmp, const char *path, sta_error *err)
{
    bool ok = !ferror(f);
    ok = fclose(f) == 0 && ok;
    if (!ok || rename(tmp, path) != 0) {
        unlink(tmp);
        return sta_fail(err, STA_ERR_IO, "%s: cannot write: %s", path, strerror(errno));
    }
    return STA_OK;
}

sta_status sta_measure_save_json(const char *path, const sta_measure_list *list, sta_error *err)
{
    char tmp[4200];
    FILE *f = open_temporary(path, tmp, sizeof(tmp), err);
    if (!f) {
        return STA_ERR_IO;
    }
    sta_json_out json;
    sta_json_init(&json, f, true);
    sta_json_begin_object(&json);
    sta_json_key(&json, "strata_measurements");
    sta_json_int(&json, 1);
    sta_json_key(&json, "measurements");
    sta_json_begin_array(&json);
    for (size_t i = 0; i < list->count; i++) {
        const sta_measure *m = &list->items[i];
        sta_measure_values v;
        sta_measure_compute(m->kind, (const double(*)[3])m->points, m->count, &v, NULL);
        sta_json_begin_object(&json);
        sta_json_key(&json, "kind");
        sta_json_string(&json, sta_measure_kind_name(m->kind));
        sta_json_key(&json, "name");
        sta_json_string(&json, m->name);
        sta_json_key(&json, "points");
        sta_json_begin_array(&json);
        for (size_t k = 0; k < m->count; k++) {
            sta_json_begin_array(&json);
            for (int a = 0; a < 3; a++) {
                sta_json_double(&json, m->points[k][a]);
            }
            sta_json_end_array(&json);
        }
        sta_json_end_array(&json);
        sta_json_key(&json, "values");
        sta_json_begin_object(&json);
        const char *keys[5] = { "distance_3d", "distance_xy", "distance_z", "area_xy", "area_3d" };
        const double values[5] = { v.distance_3d, v.distance_xy, v.distance_z, v.area_xy,
                                   v.area_3d };
        for (int k = 0; k < 5; k++) {
            sta_json_key(&json, keys[k]);
            sta_json_double(&json, values[k]);
        }
        sta_json_end_object(&json);
        sta_json_end_object(&json);
    }
    sta_json_end_array(&json);
    sta_json_end_object(&json);
    sta_json_finish(&json);
    return finish_temporary(f, tmp, path, err);
}

// Reads one measurement's points into `out` (STA_MEASURE_MAX_POINTS rows).
static sta_status load_points(const cJSON *points, const char *path, size_t index, double (*out)[3],
                              size_t *out_count, sta_error *err)
{
    size_t count = 0;
    const cJSON *p;
    cJSON_ArrayForEach(p, points)
    {
        if (count == STA_MEASURE_MAX_POINTS) {
            return sta_fail(err, STA_ERR_FORMAT, "%s: measurement %zu: more than %d points", path,
                            index, STA_MEASURE_MAX_POINTS);
        }
        if (!cJSON_IsArray(p) || cJSON_GetArraySize(p) != 3) {
            return sta_fail(err, STA_ERR_FORMAT, "%s: measurement %zu: point %zu is not [x, y, z]",
                            path, index, count);
        }
        for (int a = 0; a < 3; a++) {
            const cJSON *c = cJSON_GetArrayItem(p, a);
            if (!cJSON_IsNumber(c) || !isfinite(c->valuedouble)) {
                return sta_fail(err, STA_ERR_FORMAT,
                                "%s: measurement %zu: point %zu: coordinate %d is not a number",
                                path, index, count, a);
            }
            out[count][a] = c->valuedouble;
        }
        count++;
    }
    *out_count = count;
    return STA_OK;
}

static sta_status load_items(const cJSON *items, const char *path, sta_measure_list *out,
                             double (*points)[3], sta_error *err)
{
    size_t index = 0;
    const cJSON *item;
    cJSON_ArrayForEach(item, items)
    {
        const cJSON *kind = cJSON_GetObjectItemCaseSensitive(item, "kind");
        const cJSON *name = cJSON_GetObjectItemCaseSensitive(item, "name");
        const cJSON *list = cJSON_GetObjectItemCaseSensitive(item, "points");
        int k = cJSON_IsString(kind) ? sta_measure_kind_from_name(kind->valuestring) : -1;
        if (k < 0) {
            return sta_fail(err, STA_ERR_FORMAT,
                            "%s: measurement %zu: \"kind\" is not point, distance, height, "
                            "polyline or area",
                            path, index);
        }
        if (!cJSON_IsArray(list)) {
            return sta_fail(err, STA_ERR_FORMAT, "%s: measurement %zu: no \"points\" array", path,
                            index);
        }
        size_t count = 0;
        sta_status s = load_points(list, path, index, points, &count, err);
        if (s == STA_OK) {
            s = sta_measure_list_add(out, (sta_measure_kind)k,
                                     cJSON_IsString(name) ? name->valuestring : "",
                                     (const double(*)[3])points, count, err);
        }
        if (s == STA_ERR_ARG) { // the kind's point count: a file error here
            sta_error_prefix(err, "%s: measurement %zu", path, index);
            if (err) {
                err->code = STA_ERR_FORMAT;
            }
            return STA_ERR_FORMAT;
        }
        if (s != STA_OK) {
            return s;
        }
        index++;
    }
    return STA_OK;
}

sta_status sta_measure_load_json(const char *path, sta_measure_list *list, sta_error *err)
{
    cJSON *root = NULL;
    sta_status status = sta_json_file_load(path, &root, err);
    if (status != STA_OK) {
        return status;
    }
    const cJSON *items = cJSON_GetObjectItemCaseSensitive(root, "measurements");
    if (!cJSON_IsArray(items)) {
        cJSON_Delete(root);
        return sta_fail(err, STA_ERR_FORMAT, "%s: no \"measurements\" array", path);
    }
    double(*points)[3] = sta_alloc_array(STA_MEASURE_MAX_POINTS, sizeof(*points));
    size_t before = list->count;
    status = points ? load_items(items, path, list, points, err)
                    : sta_fail(err, STA_ERR_NOMEM, "%s: out of memory", path);
    sta_free(points);
    cJSON_Delete(root);
    if (status != STA_OK) {
        while (list->count > before) {
            sta_measure_list_pop(list);
        }
    }
    return status;
}

static void csv_double(FILE *f, double v)
{
    char text[40];
    fputs(sta_format_double(v, text, sizeof(text)), f);
}

sta_status sta_measure_save_csv(const char *path, const sta_measure_list *list, sta_error *err)
{
    char tmp[4200];
    FILE *f = open_temporary(path, tmp, sizeof(tmp), err);
    if (!f) {
        return STA_ERR_IO;
    }
    fputs("name,kind,points,distance_3d,distance_xy,distance_z,area_xy,area_3d,vertices\n", f);
    for (size_t i = 0; i < list->count; i++) {
        const sta_measure *m = &list->items[i];
        sta_measure_values v;
        sta_measure_compute(m->kind, (const double(*)[3])m->points, m->count, &v, NULL);
        // Names are quoted with doubled quotes (RFC 4180).
        fputc('"', f);
        for (const char *c = m->name; *c; c++) {
            if (*c == '"') {
                fputc('"', f);
            }
            fputc(*c, f);
        }
        fprintf(f, "\",%s,%zu,", sta_measure_kind_name(m->kind), m->count);
        const double values[5] = { v.distance_3d, v.distance_xy, v.distance_z, v.area_xy,
                                   v.area_3d };
        for (int k = 0; k < 5; k++) {
            csv_double(f, values[k]);
            fputc(',', f);
        }
        for (size_t k = 0; k < m->count; k++) {
            for (int a = 0; a < 3; a++) {
                csv_double(f, m->points[k][a]);
                fputc(a < 2 ? ' ' : (k + 1 < m->count ? ';' : '\n'), f);
            }
        }
    }
    return finish_temporary(f, tmp, path, err);
}
