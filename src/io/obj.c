/* SPDX-License-Identifier: MIT
 * Wavefront OBJ mesh loader (vertices and faces) and the mesh loader by content.
 *
 * Design: one pass over the lines. Each line is copied into a NUL-terminated buffer
 * (the mapped bytes are not terminated) and split into blank-separated tokens; numbers
 * go through strtod / strtoll, which must consume the whole token (up to the first '/'
 * for a face reference). Positive face references are checked once every vertex is
 * read; negative ones count back from the vertices read so far.
 */
#include "io/obj.h"

#include <errno.h>
#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "core/alloc.h"
#include "core/array.h"
#include "core/file_map.h"

typedef struct obj_loader {
    const char *name;
    size_t line_number;
    char *line; /* the current line, NUL-terminated */
    size_t line_capacity;
    sta_mesh mesh;
    size_t vertex_capacity, triangle_capacity;
} obj_loader;

static bool is_blank(char c)
{
    return c == ' ' || c == '\t' || c == '\f' || c == '\v';
}

// The next token of *cursor (blank-separated), NUL-terminated in place; NULL at the end.
static char *next_token(char **cursor)
{
    char *p = *cursor;
    while (is_blank(*p)) {
        p++;
    }
    if (*p == '\0') {
        *cursor = p;
        return NULL;
    }
    char *start = p;
    while (*p != '\0' && !is_blank(*p)) {
        p++;
    }
    if (*p != '\0') {
        *p++ = '\0';
    }
    *cursor = p;
    return start;
}

static sta_status fail_line(const obj_loader *ol, sta_error *err, const char *what,
                            const char *token)
{
    return sta_fail(err, STA_ERR_FORMAT, "%s: line %zu: %s%s%.40s%s", ol->name, ol->line_number,
                    what, token ? " \"" : "", token ? token : "", token ? "\"" : "");
}

static sta_status out_of_memory(const obj_loader *ol, sta_error *err)
{
    return sta_fail(err, STA_ERR_NOMEM, "%s: line %zu: out of memory for the mesh", ol->name,
                    ol->line_number);
}

// `v x y z [...]`: three finite coordinates; what follows (w, or a colour) is ignored.
static sta_status read_vertex(obj_loader *ol, char *cursor, sta_error *err)
{
    sta_mesh *m = &ol->mesh;
    if (sta_array_reserve((void **)&m->positions, &ol->vertex_capacity, 3 * (m->vertex_count + 1),
                          sizeof(double), 3 * 1024, NULL) != STA_OK) {
        return out_of_memory(ol, err);
    }
    for (int a = 0; a < 3; a++) {
        char *token = next_token(&cursor);
        if (!token) {
            return fail_line(ol, err, "a vertex needs three coordinates", NULL);
        }
        char *end = NULL;
        double v = strtod(token, &end);
        if (end == token || *end != '\0') {
            return fail_line(ol, err, "coordinate is not a number:", token);
        }
        if (!isfinite(v)) {
            return fail_line(ol, err, "coordinate is not finite:", token);
        }
        m->positions[3 * m->vertex_count + (size_t)a] = v;
    }
    m->vertex_count++;
    return STA_OK;
}

// One face reference ("i", "i/t", "i//n", "i/t/n"): its vertex as a 0-based index.
// Positive references may point past the vertices read so far (checked at the end).
static sta_status read_reference(obj_loader *ol, const char *token, uint32_t *out, sta_error *err)
{
    char *end = NULL;
    errno = 0;
    long long r = strtoll(token, &end, 10);
    if (end == token || (*end != '\0' && *end != '/') || errno == ERANGE) {
        return fail_line(ol, err, "vertex reference is not a number:", token);
    }
    if (r == 0) {
        return fail_line(ol, err, "vertex reference 0 (references start at 1):", token);
    }
    long long index = r > 0 ? r - 1 : (long long)ol->mesh.vertex_count + r;
    if (index < 0) {
        return fail_line(ol, err, "vertex reference before the first vertex:", token);
    }
    if ((unsigned long long)index > UINT32_MAX - 1u) {
        return fail_line(ol, err, "vertex reference beyond 2^32 vertices:", token);
    }
    *out = (uint32_t)index;
    return STA_OK;
}

// `f a b c ...`: a fan of triangles from its first vertex.
static sta_status read_face(obj_loader *ol, char *cursor, sta_error *err)
{
    sta_mesh *m = &ol->mesh;
    uint32_t first = 0, previous = 0;
    size_t count = 0;
    for (char *token = next_token(&cursor); token; token = next_token(&cursor), count++) {
        uint32_t index = 0;
        sta_status status = read_reference(ol, token, &index, err);
        if (status != STA_OK) {
            return status;
        }
        if (count >= 2) {
            if (sta_array_reserve((void **)&m->triangles, &ol->triangle_capacity,
                                  3 * (m->triangle_count + 1), sizeof(uint32_t), 3 * 1024,
                                  NULL) != STA_OK) {
                return out_of_memory(ol, err);
            }
            uint32_t *t = &m->triangles[3 * m->triangle_count++];
            t[0] = first;
            t[1] = previous;
            t[2] = index;
        }
        first = count == 0 ? index : first;
        previous = index;
    }
    return STA_OK;
}

static sta_status read_line(obj_loader *ol, sta_error *err)
{
    char *cursor = ol->line;
    char *keyword = next_token(&cursor);
    if (!keyword || keyword[0] == '#') {
        return STA_OK;
    }
    if (strcmp(keyword, "v") == 0) {
        return read_vertex(ol, cursor, err);
    }
    if (strcmp(keyword, "f") == 0 || strcmp(keyword, "fo") == 0) {
        return read_face(ol, cursor, err);
    }
    return STA_OK; // vn, vt, vp, o, g, s, usemtl, mtllib, l, p, ...: not needed
}

sta_status sta_obj_load_mesh_memory(const uint8_t *data, size_t size, const char *name,
                                    sta_mesh *out_mesh, sta_error *err)
{
    memset(out_mesh, 0, sizeof(*out_mesh));
    obj_loader ol = { .name = name };
    sta_status status = STA_OK;
    size_t at = 0;
    while (status == STA_OK && at < size) {
        const uint8_t *newline = memchr(data + at, '\n', size - at);
        size_t end = newline ? (size_t)(newline - data) : size;
        size_t length = end - at;
        while (length > 0 && data[at + length - 1] == '\r') {
            length--;
        }
        ol.line_number++;
        if (sta_array_reserve((void **)&ol.line, &ol.line_capacity, length + 1, 1, 256, NULL) !=
            STA_OK) {
            status = out_of_memory(&ol, err);
            break;
        }
        memcpy(ol.line, data + at, length);
        ol.line[length] = '\0';
        if (memchr(ol.line, '\0', length)) {
            status = fail_line(&ol, err, "a NUL byte (not a text file?)", NULL);
        } else if (length > 0 && ol.line[length - 1] == '\\') {
            status =
                fail_line(&ol, err, "lines continued with a backslash are not supported", NULL);
        } else {
            status = read_line(&ol, err);
        }
        at = end + 1;
    }
    for (size_t i = 0; status == STA_OK && i < 3 * ol.mesh.triangle_count; i++) {
        if (ol.mesh.triangles[i] >= ol.mesh.vertex_count) {
            status = sta_fail(
                err, STA_ERR_FORMAT, "%s: face %zu refers to vertex %lu, but the file has %zu",
                name, i / 3 + 1, (unsigned long)ol.mesh.triangles[i] + 1ul, ol.mesh.vertex_count);
        }
    }
    sta_free(ol.line);
    if (status != STA_OK) {
        sta_mesh_release(&ol.mesh);
        return status;
    }
    *out_mesh = ol.mesh;
    return STA_OK;
}

// Whether `data` looks like OBJ: its first statement (after blank lines) is a comment or
// one of the usual keywords.
static bool looks_like_obj(const uint8_t *data, size_t size)
{
    static const char *const keywords[] = {
        "v", "vn", "vt", "f", "o", "g", "s", "usemtl", "mtllib"
    };
    size_t i = 0;
    while (i < size && (is_blank((char)data[i]) || data[i] == '\r' || data[i] == '\n')) {
        i++;
    }
    if (i < size && data[i] == '#') {
        return true;
    }
    size_t start = i;
    while (i < size && !is_blank((char)data[i]) && data[i] != '\r' && data[i] != '\n') {
        i++;
    }
    for (size_t k = 0; k < sizeof(keywords) / sizeof(keywords[0]); k++) {
        size_t n = strlen(keywords[k]);
        if (i - start == n && memcmp(data + start, keywords[k], n) == 0) {
            return true;
        }
    }
    return false;
}

sta_status sta_mesh_load(const char *path, sta_mesh *out_mesh, sta_error *err)
{
    sta_file_map map = { 0 };
    memset(out_mesh, 0, sizeof(*out_mesh));
    sta_status status = sta_file_map_open(path, &map, err);
    if (status != STA_OK) {
        return status;
    }
    if (map.size >= 3 && memcmp(map.data, "ply", 3) == 0) {
        status = sta_ply_load_mesh_memory(map.data, map.size, map.path, out_mesh, err);
    } else if (looks_like_obj(map.data, map.size)) {
        status = sta_obj_load_mesh_memory(map.data, map.size, map.path, out_mesh, err);
    } else {
        status = sta_fail(err, STA_ERR_FORMAT,
                          "%s: neither a PLY mesh (no \"ply\" signature) nor an OBJ mesh (no "
                          "v, f, o, g or # statement first)",
                          map.path);
    }
    sta_file_map_close(&map);
    return status;
}
