/* SPDX-License-Identifier: MIT
 * PLY mesh loader: vertex positions and triangulated faces, for mesh sampling.
 *
 * Design: one pass over the body in element order. Vertex positions are kept as
 * double (x, y, z as stored); faces are the list "vertex_indices" (or "vertex_index")
 * of element "face", each polygon fanned from its first vertex. Other elements are
 * skipped; elements after both vertices and faces are not read. Counts are checked
 * against the bytes of the body before anything is allocated for them.
 */
#include <math.h>
#include <string.h>

#include "core/alloc.h"
#include "core/array.h"
#include "core/file_map.h"
#include "io/ply.h"
#include "io/ply_internal.h"

void sta_mesh_release(sta_mesh *mesh)
{
    sta_free(mesh->positions);
    sta_free(mesh->triangles);
    memset(mesh, 0, sizeof(*mesh));
}

// Most records of `e` that the body's `bytes` can hold.
static uint64_t max_records(const sta_ply_header *h, const sta_ply_element *e, size_t bytes)
{
    // ASCII: each field takes a character and a blank or newline.
    size_t min_size = h->format == STA_PLY_ASCII ? 2 * e->property_count : e->min_record_size;
    if (min_size == 0) {
        return UINT64_MAX;
    }
    return (uint64_t)(bytes / min_size) + 1;
}

static sta_status fail_read(const sta_ply_cursor *c, sta_ply_read result, const sta_ply_element *e,
                            uint64_t record, size_t failed, const char *name, sta_error *err)
{
    char detail[400];
    const sta_ply_property *p = failed < e->property_count ? &e->properties[failed] : NULL;
    sta_ply_describe_read(c, result, e, record, p, detail, sizeof(detail));
    return sta_fail(err, STA_ERR_FORMAT, "%s: %s%s", name,
                    sta_ply_read_is_truncation(result) ? "body truncated: " : "", detail);
}

typedef struct mesh_loader {
    const char *name;
    const sta_ply_header *header;
    sta_ply_cursor cursor;
    sta_mesh mesh;
    size_t triangle_capacity;
} mesh_loader;

static sta_status read_vertices(mesh_loader *ml, const sta_ply_element *e, const long axis[3],
                                sta_error *err)
{
    sta_status status = STA_OK;
    double *values = sta_alloc_array(e->property_count, sizeof(*values));
    if (!values) {
        return sta_fail(err, STA_ERR_NOMEM, "%s: out of memory", ml->name);
    }
    for (uint64_t i = 0; i < e->count; i++) {
        size_t failed = 0;
        sta_ply_read result = sta_ply_read_record(&ml->cursor, e, values, &failed);
        if (result != STA_PLY_READ_OK) {
            status = fail_read(&ml->cursor, result, e, i, failed, ml->name, err);
            goto out_free;
        }
        for (int a = 0; a < 3; a++) {
            double value = values[axis[a]];
            if (!isfinite(value)) {
                status = sta_fail(err, STA_ERR_FORMAT,
                                  "%s: vertex %llu: property \"%s\" is %s (coordinates must be "
                                  "finite)",
                                  ml->name, (unsigned long long)i, e->properties[axis[a]].name,
                                  isnan(value) ? "NaN" : "infinite");
                goto out_free;
            }
            ml->mesh.positions[i * 3 + (size_t)a] = value;
        }
    }
out_free:
    sta_free(values);
    return status;
}

static sta_status push_triangle(mesh_loader *ml, uint32_t a, uint32_t b, uint32_t c, sta_error *err)
{
    sta_mesh *m = &ml->mesh;
    if (sta_array_reserve((void **)&m->triangles, &ml->triangle_capacity, m->triangle_count + 1,
                          3 * sizeof(*m->triangles), 64, NULL) != STA_OK) {
        return sta_fail(err, STA_ERR_NOMEM, "%s: out of memory for %zu triangles", ml->name,
                        m->triangle_count + 1);
    }
    uint32_t *t = &m->triangles[m->triangle_count * 3];
    t[0] = a;
    t[1] = b;
    t[2] = c;
    m->triangle_count++;
    return STA_OK;
}

// Reads one face's index list and fans it into triangles.
static sta_status read_polygon(mesh_loader *ml, const sta_ply_element *e, size_t list,
                               uint64_t face, sta_error *err)
{
    sta_ply_cursor *c = &ml->cursor;
    const sta_ply_property *p = &e->properties[list];
    uint64_t count = 0;
    sta_ply_read result = sta_ply_read_count(c, p, &count);
    if (result != STA_PLY_READ_OK) {
        return fail_read(c, result, e, face, list, ml->name, err);
    }
    uint32_t first = 0;
    uint32_t previous = 0;
    for (uint64_t k = 0; k < count; k++) {
        double value = 0.0;
        result = sta_ply_read_scalar(c, p->type, &value);
        if (result != STA_PLY_READ_OK) {
            return fail_read(c, result, e, face, list, ml->name, err);
        }
        if (!(value >= 0.0 && value < (double)ml->mesh.vertex_count) || value != floor(value)) {
            return sta_fail(err, STA_ERR_FORMAT,
                            "%s: face %llu: vertex index %.15g is not one of the %zu vertices",
                            ml->name, (unsigned long long)face, value, ml->mesh.vertex_count);
        }
        uint32_t index = (uint32_t)value;
        if (k == 0) {
            first = index;
        } else if (k >= 2) {
            sta_status status = push_triangle(ml, first, previous, index, err);
            if (status != STA_OK) {
                return status;
            }
        }
        previous = index;
    }
    return STA_OK;
}

static sta_status read_faces(mesh_loader *ml, const sta_ply_element *e, size_t list, sta_error *err)
{
    sta_ply_cursor *c = &ml->cursor;
    for (uint64_t f = 0; f < e->count; f++) {
        sta_ply_read result = sta_ply_record_begin(c);
        if (result != STA_PLY_READ_OK) {
            return fail_read(c, result, e, f, e->property_count, ml->name, err);
        }
        for (size_t i = 0; i < e->property_count; i++) {
            const sta_ply_property *p = &e->properties[i];
            if (i == list) {
                sta_status status = read_polygon(ml, e, list, f, err);
                if (status != STA_OK) {
                    return status;
                }
                continue;
            }
            if (p->count_type) {
                uint64_t count = 0;
                result = sta_ply_read_count(c, p, &count);
                if (result == STA_PLY_READ_OK) {
                    result = sta_ply_skip_items(c, p, count);
                }
            } else {
                double value;
                result = sta_ply_read_scalar(c, p->type, &value);
            }
            if (result != STA_PLY_READ_OK) {
                return fail_read(c, result, e, f, i, ml->name, err);
            }
        }
        result = sta_ply_record_end(c);
        if (result != STA_PLY_READ_OK) {
            return fail_read(c, result, e, f, e->property_count, ml->name, err);
        }
    }
    return STA_OK;
}

static sta_status skip_element(mesh_loader *ml, const sta_ply_element *e, sta_error *err)
{
    sta_ply_cursor *c = &ml->cursor;
    if (c->format != STA_PLY_ASCII && e->record_size > 0) {
        uint64_t fit = (c->size - c->pos) / e->record_size;
        if (e->count > fit) {
            return sta_fail(err, STA_ERR_FORMAT,
                            "%s: element \"%s\" declares %llu records of %zu bytes, but only %zu "
                            "bytes are left (room for %llu)",
                            ml->name, e->name, (unsigned long long)e->count, e->record_size,
                            c->size - c->pos, (unsigned long long)fit);
        }
        c->pos += (size_t)e->count * e->record_size;
        return STA_OK;
    }
    for (uint64_t k = 0; k < e->count; k++) {
        size_t failed = 0;
        sta_ply_read result = sta_ply_read_record(c, e, NULL, &failed);
        if (result != STA_PLY_READ_OK) {
            return fail_read(c, result, e, k, failed, ml->name, err);
        }
    }
    return STA_OK;
}

// Finds the vertex element and its x/y/z, and the face list; allocates positions.
static sta_status prepare(mesh_loader *ml, long *out_vertex, long axis[3], long *out_face,
                          long *out_list, sta_error *err)
{
    const sta_ply_header *h = ml->header;
    size_t body_bytes = ml->cursor.size - ml->cursor.pos;
    long vertex = sta_ply_header_find(h, "vertex");
    if (vertex < 0) {
        return sta_fail(err, STA_ERR_FORMAT, "%s: PLY file has no \"vertex\" element", ml->name);
    }
    const sta_ply_element *ve = &h->elements[vertex];
    static const char *const names[3] = { "x", "y", "z" };
    for (int a = 0; a < 3; a++) {
        axis[a] = sta_ply_element_find(ve, names[a]);
        if (axis[a] < 0 || ve->properties[axis[a]].count_type) {
            return sta_fail(err, STA_ERR_FORMAT, "%s: vertex element has no scalar property \"%s\"",
                            ml->name, names[a]);
        }
    }
    if (ve->count > UINT32_MAX || ve->count > max_records(h, ve, body_bytes)) {
        return sta_fail(err, STA_ERR_FORMAT,
                        "%s: vertex element declares %llu vertices, more than the %zu bytes of "
                        "the body can hold (or than 32-bit indices reach)",
                        ml->name, (unsigned long long)ve->count, body_bytes);
    }
    *out_face = sta_ply_header_find(h, "face");
    *out_list = -1;
    if (*out_face >= 0) {
        const sta_ply_element *fe = &h->elements[*out_face];
        *out_list = sta_ply_element_find(fe, "vertex_indices");
        if (*out_list < 0) {
            *out_list = sta_ply_element_find(fe, "vertex_index");
        }
        if (fe->count > 0 && (*out_list < 0 || !fe->properties[*out_list].count_type)) {
            return sta_fail(err, STA_ERR_FORMAT,
                            "%s: face element has no list property \"vertex_indices\" or "
                            "\"vertex_index\"",
                            ml->name);
        }
    }
    *out_vertex = vertex;
    ml->mesh.vertex_count = (size_t)ve->count;
    if (ve->count > 0) {
        ml->mesh.positions = sta_alloc_array((size_t)ve->count, 3 * sizeof(double));
        if (!ml->mesh.positions) {
            return sta_fail(err, STA_ERR_NOMEM, "%s: out of memory for %llu vertices", ml->name,
                            (unsigned long long)ve->count);
        }
    }
    return STA_OK;
}

sta_status sta_ply_load_mesh_memory(const uint8_t *data, size_t size, const char *name,
                                    sta_mesh *out_mesh, sta_error *err)
{
    sta_ply_header header = { 0 };
    mesh_loader ml = { .name = name, .header = &header };
    long vertex = -1, face = -1, list = -1;
    long axis[3];
    memset(out_mesh, 0, sizeof(*out_mesh));
    sta_status status = sta_ply_header_parse(data, size, name, &header, err);
    if (status != STA_OK) {
        return status;
    }
    sta_ply_cursor_init(&ml.cursor, data, size, &header);
    status = prepare(&ml, &vertex, axis, &face, &list, err);
    if (status != STA_OK) {
        goto out_release;
    }
    size_t last = (size_t)(vertex > face ? vertex : face);
    for (size_t i = 0; i <= last && status == STA_OK; i++) {
        const sta_ply_element *e = &header.elements[i];
        if ((long)i == vertex) {
            status = read_vertices(&ml, e, axis, err);
        } else if ((long)i == face) {
            status = read_faces(&ml, e, (size_t)list, err);
        } else {
            status = skip_element(&ml, e, err);
        }
    }
    if (status != STA_OK) {
        goto out_release;
    }
    *out_mesh = ml.mesh;
    sta_ply_header_release(&header);
    return STA_OK;
out_release:
    sta_mesh_release(&ml.mesh);
    sta_ply_header_release(&header);
    return status;
}

sta_status sta_ply_load_mesh(const char *path, sta_mesh *out_mesh, sta_error *err)
{
    sta_file_map map = { 0 };
    memset(out_mesh, 0, sizeof(*out_mesh));
    sta_status status = sta_file_map_open(path, &map, err);
    if (status != STA_OK) {
        return status;
    }
    status = sta_ply_load_mesh_memory(map.data, map.size, map.path, out_mesh, err);
    sta_file_map_close(&map);
    return status;
}
