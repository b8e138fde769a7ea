/* SPDX-License-Identifier: MIT
 * The mirror file (docs/MIRRORS.md): parsed with cJSON, strictly (unknown keys, wrong
 * types and non-finite numbers are errors naming the file and the mirror), written
 * with the shortest round-trip numbers of core/json_out.h. */
#include <cjson/cJSON.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "core/file_map.h"
#include "mirror/mirror_set.h"

static bool is_key(const cJSON *item, const char *const *keys)
{
    for (; *keys; keys++) {
        if (strcmp(item->string, *keys) == 0) {
            return true;
        }
    }
    return false;
}

/* A finite number or, when absent and optional, leaves *out alone. */
static sta_status number_field(const cJSON *object, const char *key, double min, double max,
                               double *out, const char *where, sta_error *err)
{
    const cJSON *item = cJSON_GetObjectItemCaseSensitive(object, key);
    if (!item) {
        return STA_OK;
    }
    if (!cJSON_IsNumber(item) || !isfinite(item->valuedouble) || item->valuedouble < min ||
        item->valuedouble > max) {
        return sta_fail(err, STA_ERR_FORMAT, "%s: \"%s\" must be a number in [%g, %g]", where, key,
                        min, max);
    }
    *out = item->valuedouble;
    return STA_OK;
}

static sta_status parse_mirror(const cJSON *item, size_t index, const char *path,
                               sta_mirror_set *set, sta_error *err)
{
    static const char *const keys[] = { "name", "polygon", NULL };
    if (!cJSON_IsObject(item)) {
        return sta_fail(err, STA_ERR_FORMAT, "%s: mirror %zu: not an object", path, index);
    }
    const cJSON *name_item = cJSON_GetObjectItemCaseSensitive(item, "name");
    const char *name = cJSON_IsString(name_item) ? name_item->valuestring : "";
    char where[STA_MIRROR_NAME_MAX + 4200];
    snprintf(where, sizeof(where), "%s: mirror %zu '%s'", path, index, name);
    if (name_item && !cJSON_IsString(name_item)) {
        return sta_fail(err, STA_ERR_FORMAT, "%s: \"name\" must be a string", where);
    }
    if (strlen(name) >= STA_MIRROR_NAME_MAX) {
        return sta_fail(err, STA_ERR_FORMAT, "%s: name longer than %d bytes", where,
                        STA_MIRROR_NAME_MAX - 1);
    }
    const cJSON *child;
    cJSON_ArrayForEach(child, item)
    {
        if (!is_key(child, keys)) {
            return sta_fail(err, STA_ERR_FORMAT, "%s: unknown key \"%s\"", where, child->string);
        }
    }
    const cJSON *polygon = cJSON_GetObjectItemCaseSensitive(item, "polygon");
    if (!cJSON_IsArray(polygon)) {
        return sta_fail(err, STA_ERR_FORMAT, "%s: \"polygon\" (an array of [x, y, z]) is missing",
                        where);
    }
    int count = cJSON_GetArraySize(polygon);
    if (count > STA_MIRROR_MAX_VERTICES) {
        return sta_fail(err, STA_ERR_FORMAT, "%s: %d vertices, at most %d are supported", where,
                        count, STA_MIRROR_MAX_VERTICES);
    }
    double vertices[STA_MIRROR_MAX_VERTICES][3];
    int v = 0;
    cJSON_ArrayForEach(child, polygon)
    {
        if (!cJSON_IsArray(child) || cJSON_GetArraySize(child) != 3) {
            return sta_fail(err, STA_ERR_FORMAT, "%s: vertex %d is not [x, y, z]", where, v + 1);
        }
        for (int a = 0; a < 3; a++) {
            const cJSON *c = cJSON_GetArrayItem(child, a);
            if (!cJSON_IsNumber(c) || !isfinite(c->valuedouble)) {
                return sta_fail(err, STA_ERR_FORMAT,
                                "%s: vertex %d: coordinate %d is not a finite "
                                "number",
                                where, v + 1, a + 1);
            }
            vertices[v][a] = c->valuedouble;
        }
        v++;
    }
    sta_error inner = { 0 };
    if (sta_mirror_set_add(set, name, (const double(*)[3])vertices, (size_t)count, &inner) !=
        STA_OK) {
        return sta_fail(err, inner.code, "%s: %s", path, inner.message);
    }
    return STA_OK;
}

// One entry of "stations": {"point_source_id": 0..65535, "position": [x, y, z]}.
static sta_status parse_station(const cJSON *item, size_t index, const char *path,
                                sta_mirror_set *set, sta_error *err)
{
    static const char *const keys[] = { "point_source_id", "position", NULL };
    if (!cJSON_IsObject(item)) {
        return sta_fail(err, STA_ERR_FORMAT, "%s: station %zu: not an object", path, index);
    }
    const cJSON *child;
    cJSON_ArrayForEach(child, item)
    {
        if (!is_key(child, keys)) {
            return sta_fail(err, STA_ERR_FORMAT, "%s: station %zu: unknown key \"%s\"", path, index,
                            child->string);
        }
    }
    const cJSON *id = cJSON_GetObjectItemCaseSensitive(item, "point_source_id");
    if (!cJSON_IsNumber(id) || !(id->valuedouble >= 0.0 && id->valuedouble <= 65535.0) ||
        id->valuedouble != floor(id->valuedouble)) {
        return sta_fail(err, STA_ERR_FORMAT,
                        "%s: station %zu: \"point_source_id\" must be an integer 0..65535", path,
                        index);
    }
    const cJSON *position = cJSON_GetObjectItemCaseSensitive(item, "position");
    double p[3];
    for (int a = 0; a < 3; a++) {
        const cJSON *c = cJSON_IsArray(position) && cJSON_GetArraySize(position) == 3
                             ? cJSON_GetArrayItem(position, a)
                             : NULL;
        if (!cJSON_IsNumber(c) || !isfinite(c->valuedouble)) {
            return sta_fail(err, STA_ERR_FORMAT,
                            "%s: station %zu: \"position\" must be [x, y, z], finite", path, index);
        }
        p[a] = c->valuedouble;
    }
    sta_error inner = { 0 };
    if (sta_mirror_set_add_station(set, (uint16_t)id->valuedouble, p, &inner) != STA_OK) {
        return sta_fail(err, inner.code, "%s: %s", path, inner.message);
    }
    return STA_OK;
}

static sta_status parse_root(const cJSON *root, const char *path, sta_mirror_set *out,
                             sta_error *err)
{
    static const char *const keys[] = {
        "format",  "version",  "tolerance_m", "behind_m", "max_incidence_deg",
        "mirrors", "stations", NULL
    };
    if (!cJSON_IsObject(root)) {
        return sta_fail(err, STA_ERR_FORMAT, "%s: not a JSON object", path);
    }
    const cJSON *child;
    cJSON_ArrayForEach(child, root)
    {
        if (!is_key(child, keys)) {
            return sta_fail(err, STA_ERR_FORMAT, "%s: unknown key \"%s\"", path, child->string);
        }
    }
    const cJSON *format = cJSON_GetObjectItemCaseSensitive(root, "format");
    if (!cJSON_IsString(format) || strcmp(format->valuestring, STA_MIRROR_FILE_FORMAT) != 0) {
        return sta_fail(err, STA_ERR_FORMAT, "%s: \"format\" must be \"%s\"", path,
                        STA_MIRROR_FILE_FORMAT);
    }
    const cJSON *version = cJSON_GetObjectItemCaseSensitive(root, "version");
    if (!cJSON_IsNumber(version) || version->valuedouble != STA_MIRROR_FILE_VERSION) {
        return sta_fail(err, STA_ERR_UNSUPPORTED, "%s: \"version\" must be %d", path,
                        STA_MIRROR_FILE_VERSION);
    }
    sta_status s = number_field(root, "tolerance_m", 1e-6, 10.0, &out->tolerance_m, path, err);
    s = s == STA_OK ? number_field(root, "behind_m", 1e-6, 10.0, &out->behind_m, path, err) : s;
    s = s == STA_OK
            ? number_field(root, "max_incidence_deg", 0.0, 89.9, &out->max_incidence_deg, path, err)
            : s;
    if (s != STA_OK) {
        return s;
    }
    sta_mirror_set_defaults(out);
    const cJSON *mirrors = cJSON_GetObjectItemCaseSensitive(root, "mirrors");
    if (!cJSON_IsArray(mirrors)) {
        return sta_fail(err, STA_ERR_FORMAT, "%s: \"mirrors\" (an array) is missing", path);
    }
    size_t index = 1;
    cJSON_ArrayForEach(child, mirrors)
    {
        s = parse_mirror(child, index++, path, out, err);
        if (s != STA_OK) {
            return s;
        }
    }
    const cJSON *stations = cJSON_GetObjectItemCaseSensitive(root, "stations");
    if (stations && !cJSON_IsArray(stations)) {
        return sta_fail(err, STA_ERR_FORMAT, "%s: \"stations\" must be an array", path);
    }
    index = 1;
    cJSON_ArrayForEach(child, stations)
    {
        s = parse_station(child, index++, path, out, err);
        if (s != STA_OK) {
            return s;
        }
    }
    return STA_OK;
}

sta_status sta_mirror_set_parse(const char *text, size_t size, const char *path,
                                sta_mirror_set *out, sta_error *err)
{
    memset(out, 0, sizeof(*out));
    cJSON *root = cJSON_ParseWithLength(text, size);
    if (!root) {
        return sta_fail(err, STA_ERR_FORMAT, "%s: not valid JSON", path);
    }
    sta_status s = parse_root(root, path, out, err);
    cJSON_Delete(root);
    if (s != STA_OK) {
        sta_mirror_set_release(out);
    }
    return s;
}

sta_status sta_mirror_set_load(const char *path, sta_mirror_set *out, sta_error *err)
{
    memset(out, 0, sizeof(*out));
    sta_file_map map = { 0 };
    sta_status s = sta_file_map_open(path, &map, err);
    if (s != STA_OK) {
        return s;
    }
    s = sta_mirror_set_parse((const char *)map.data, map.size, path, out, err);
    sta_file_map_close(&map);
    return s;
}

void sta_mirror_set_write_json(sta_json_out *json, const sta_mirror_set *set)
{
    sta_json_begin_object(json);
    sta_json_key(json, "format");
    sta_json_string(json, STA_MIRROR_FILE_FORMAT);
    sta_json_key(json, "version");
    sta_json_int(json, STA_MIRROR_FILE_VERSION);
    sta_json_key(json, "tolerance_m");
    sta_json_double(json, set->tolerance_m);
    sta_json_key(json, "behind_m");
    sta_json_double(json, set->behind_m);
    sta_json_key(json, "max_incidence_deg");
    sta_json_double(json, set->max_incidence_deg);
    sta_json_key(json, "mirrors");
    sta_json_begin_array(json);
    for (size_t k = 0; k < set->count; k++) {
        const sta_mirror *m = &set->mirrors[k];
        sta_json_begin_object(json);
        sta_json_key(json, "name");
        sta_json_string(json, m->name);
        sta_json_key(json, "polygon");
        sta_json_begin_array(json);
        for (size_t i = 0; i < m->vertex_count; i++) {
            sta_json_begin_array(json);
            for (int a = 0; a < 3; a++) {
                sta_json_double(json, m->vertices[i][a]);
            }
            sta_json_end_array(json);
        }
        sta_json_end_array(json);
        sta_json_end_object(json);
    }
    sta_json_end_array(json);
    if (set->station_count > 0) {
        sta_json_key(json, "stations");
        sta_json_begin_array(json);
        for (size_t i = 0; i < set->station_count; i++) {
            sta_json_begin_object(json);
            sta_json_key(json, "point_source_id");
            sta_json_int(json, set->stations[i].point_source_id);
            sta_json_key(json, "position");
            sta_json_begin_array(json);
            for (int a = 0; a < 3; a++) {
                sta_json_double(json, set->stations[i].position[a]);
            }
            sta_json_end_array(json);
            sta_json_end_object(json);
        }
        sta_json_end_array(json);
    }
    sta_json_end_object(json);
}

sta_status sta_mirror_set_save(const char *path, const sta_mirror_set *set, sta_error *err)
{
    char tmp[4200];
    snprintf(tmp, sizeof(tmp), "%s.tmp-%ld", path, (long)getpid());
    FILE *f = fopen(tmp, "w");
    if (!f) {
        return sta_fail(err, STA_ERR_IO, "%s: cannot write: %s", path, strerror(errno));
    }
    sta_mirror_set resolved = *set;
    sta_mirror_set_defaults(&resolved);
    sta_json_out json;
    sta_json_init(&json, f, true);
    sta_mirror_set_write_json(&json, &resolved);
    sta_json_finish(&json);
    bool ok = !ferror(f);
    ok = fclose(f) == 0 && ok;
    if (!ok || rename(tmp, path) != 0) {
        int e = errno;
        unlink(tmp);
        return sta_fail(err, STA_ERR_IO, "%s: cannot write: %s", path, strerror(e));
    }
    return STA_OK;
}
