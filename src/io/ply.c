/* SPDX-License-Identifier: MIT
 * PLY point reader: the vertices of an ASCII or binary PLY file become points.
 *
 * Design: open parses the header, skips the elements stored before "vertex", then
 * scans every vertex once (bounded memory, streaming over the map) to validate it,
 * find the bounds and choose the grid (see ply.h). For ASCII this means parsing the
 * vertex text twice in all (once here, once when reading); for a file of a few hundred
 * MB that costs a few seconds, accepted for exact bounds. Reads decode records again.
 *
 * Attributes: x, y, z (any scalar type, finite) are required. Colour is taken from
 * red/green/blue, r/g/b or diffuse_red/... (all three needed): integer types are
 * stored as they are, clamped to 0..65535 (uchar stays 0..255); float types are taken
 * as 0..1, clamped and scaled to 0..255. Normals come from nx/ny/nz (or normal_x/...).
 * Intensity comes from "intensity", else "scalar_intensity", else "scalar": integer
 * types are clamped to 0..65535; float types are scaled by 65535 when every vertex's
 * value lies in 0..1 (as in the Stanford scans), else rounded and clamped to 0..65535.
 * Other properties ("confidence", ...) and other elements (faces) are ignored.
 *
 * Seeking: binary vertices without list properties are a fixed size, so a seek is
 * one multiplication (and decoding loads only the properties used, at fixed offsets).
 * Otherwise (ASCII, or lists in the vertex) the scan records the position of every
 * 1024th vertex, and a seek moves forward from the nearest mark: ASCII by lines (each
 * vertex was validated to be one line), binary by decoding the list counts.
 */
#include "io/ply.h"

#include <float.h>
#include <math.h>
#include <string.h>

#include "core/alloc.h"
#include "core/array.h"
#include "io/ply_internal.h"

#define MARK_STRIDE 1024 // vertices between two recorded positions (variable records)

enum {
    ROLE_X,
    ROLE_Y,
    ROLE_Z,
    ROLE_RED,
    ROLE_GREEN,
    ROLE_BLUE,
    ROLE_NX,
    ROLE_NY,
    ROLE_NZ,
    ROLE_INTENSITY,
    ROLE_COUNT
};

// Property names for each role, preferred first; NULL-terminated.
static const char *const role_names[ROLE_COUNT][4] = {
    [ROLE_X] = { "x", NULL },
    [ROLE_Y] = { "y", NULL },
    [ROLE_Z] = { "z", NULL },
    [ROLE_RED] = { "red", "r", "diffuse_red", NULL },
    [ROLE_GREEN] = { "green", "g", "diffuse_green", NULL },
    [ROLE_BLUE] = { "blue", "b", "diffuse_blue", NULL },
    [ROLE_NX] = { "nx", "normal_x", NULL },
    [ROLE_NY] = { "ny", "normal_y", NULL },
    [ROLE_NZ] = { "nz", "normal_z", NULL },
    [ROLE_INTENSITY] = { "intensity", "scalar_intensity", "scalar", NULL },
};

typedef struct ply_mark {
    size_t pos;    // byte offset of the vertex
    uint64_t line; // its ASCII line
} ply_mark;

typedef struct ply_reader {
    sta_cloud_info info;
    sta_ply_header header;
    const sta_ply_element *vertex;  // in header
    long role[ROLE_COUNT];          // property index per role, -1 when absent
    bool intensity_is_unit;         // float intensity within 0..1: scale by 65535
    bool is_fixed;                  // binary records of one size: seek by arithmetic
    size_t role_offset[ROLE_COUNT]; // is_fixed: byte offset of each role in a record
    sta_ply_cursor start;           // at vertex 0
    sta_ply_cursor cursor;          // at vertex next_index
    uint64_t next_index;
    double *values;  // one per vertex property, for decoding
    ply_mark *marks; // position of vertex k * MARK_STRIDE (variable records only)
    size_t mark_count;
    size_t mark_capacity;
} ply_reader;

static const sta_cloud_info *ply_info(const void *impl)
{
    return &((const ply_reader *)impl)->info;
}

static void ply_close(void *impl)
{
    ply_reader *r = impl;
    if (!r) {
        return;
    }
    sta_ply_header_release(&r->header);
    sta_free(r->values);
    sta_free(r->marks);
    sta_free(r);
}

static uint16_t clamp_u16(double value)
{
    if (!(value > 0.0)) { // also NaN
        return 0;
    }
    if (value >= 65535.0) {
        return 65535;
    }
    return (uint16_t)floor(value + 0.5);
}

static float clamp_float(double value)
{
    if (value > (double)FLT_MAX) {
        return FLT_MAX;
    }
    if (value < -(double)FLT_MAX) {
        return -FLT_MAX;
    }
    return (float)value;
}

static bool is_float_type(sta_ply_type type)
{
    return type == STA_PLY_FLOAT32 || type == STA_PLY_FLOAT64;
}

static uint16_t colour_value(double value, sta_ply_type type)
{
    if (is_float_type(type)) {
        double unit = value > 1.0 ? 1.0 : value;
        return clamp_u16(unit * 255.0);
    }
    return clamp_u16(value);
}

static int32_t to_grid(double value, const sta_grid *grid, int axis)
{
    double q = floor((value - grid->offset[axis]) / grid->scale[axis] + 0.5);
    if (q > 2147483647.0) {
        return INT32_MAX; // not reached: the grid is chosen so that |q| <= 2^30
    }
    if (q < -2147483647.0) {
        return -INT32_MAX;
    }
    return (int32_t)q;
}

// Offset = bounds centre; scale = the largest power of two <= largest extent / 2^30,
// so |X| <= 2^30; 2^-30 when all points coincide.
static void choose_grid(ply_reader *r)
{
    sta_grid *grid = &r->info.grid;
    double half_max = 0.0;
    for (int a = 0; a < 3; a++) {
        double lo = r->info.header_min[a];
        double hi = r->info.header_max[a];
        // Halves first, so that neither sum nor difference can overflow.
        grid->offset[a] = lo * 0.5 + hi * 0.5;
        double half = hi * 0.5 - lo * 0.5;
        if (half > half_max) {
            half_max = half;
        }
    }
    double scale = ldexp(1.0, -30);
    if (half_max > 0.0) {
        int exponent = 0;
        frexp(half_max, &exponent); // half_max = m * 2^exponent, 0.5 <= m < 1
        scale = ldexp(1.0, exponent - 30);
        if (scale < DBL_MIN) {
            scale = DBL_MIN; // tiny extents: |X| still < 2^30
        }
    }
    for (int a = 0; a < 3; a++) {
        grid->scale[a] = scale;
    }
}

static void decode_point(const ply_reader *r, const double *v, sta_point *p)
{
    static const sta_point zero_point = { 0 };
    *p = zero_point; // a copy: cheaper than memset's string instruction at this size
    p->X = to_grid(v[r->role[ROLE_X]], &r->info.grid, 0);
    p->Y = to_grid(v[r->role[ROLE_Y]], &r->info.grid, 1);
    p->Z = to_grid(v[r->role[ROLE_Z]], &r->info.grid, 2);
    const sta_ply_property *props = r->vertex->properties;
    if (r->info.attributes & STA_ATTR_RGB) {
        p->red = colour_value(v[r->role[ROLE_RED]], props[r->role[ROLE_RED]].type);
        p->green = colour_value(v[r->role[ROLE_GREEN]], props[r->role[ROLE_GREEN]].type);
        p->blue = colour_value(v[r->role[ROLE_BLUE]], props[r->role[ROLE_BLUE]].type);
    }
    if (r->info.attributes & STA_ATTR_NORMAL) {
        p->normal[0] = clamp_float(v[r->role[ROLE_NX]]);
        p->normal[1] = clamp_float(v[r->role[ROLE_NY]]);
        p->normal[2] = clamp_float(v[r->role[ROLE_NZ]]);
    }
    if (r->info.attributes & STA_ATTR_INTENSITY) {
        double value = v[r->role[ROLE_INTENSITY]];
        p->intensity = clamp_u16(r->intensity_is_unit ? value * 65535.0 : value);
    }
}

// Fixed-size binary record at `record`: loads the properties that have a role.
static void load_fixed(ply_reader *r, const uint8_t *record)
{
    bool big_endian = r->header.format == STA_PLY_BINARY_BE;
    for (int role = 0; role < ROLE_COUNT; role++) {
        long index = r->role[role];
        if (index >= 0) {
            r->values[index] = sta_ply_load_binary(record + r->role_offset[role],
                                                   r->vertex->properties[index].type, big_endian);
        }
    }
}

// Reads the vertex at the cursor into r->values (only the properties with a role when
// the records have a fixed size).
static sta_ply_read next_vertex(ply_reader *r, sta_ply_cursor *c, size_t *out_failed)
{
    const sta_ply_element *e = r->vertex;
    if (!r->is_fixed) {
        return sta_ply_read_record(c, e, r->values, out_failed);
    }
    *out_failed = e->property_count;
    c->record_pos = c->pos;
    if (c->size - c->pos < e->record_size) {
        return STA_PLY_READ_END_OF_FILE;
    }
    load_fixed(r, c->data + c->pos);
    c->pos += e->record_size;
    return STA_PLY_READ_OK;
}

static void find_offsets(ply_reader *r)
{
    const sta_ply_element *e = r->vertex;
    for (int role = 0; role < ROLE_COUNT; role++) {
        size_t offset = 0;
        for (long i = 0; i < r->role[role]; i++) {
            offset += sta_ply_type_size(e->properties[i].type); // no lists: is_fixed
        }
        r->role_offset[role] = offset;
    }
}

static sta_status find_roles(ply_reader *r, const char *path, sta_error *err)
{
    const sta_ply_element *e = r->vertex;
    for (int role = 0; role < ROLE_COUNT; role++) {
        r->role[role] = -1;
        for (size_t k = 0; role_names[role][k] && r->role[role] < 0; k++) {
            long index = sta_ply_element_find(e, role_names[role][k]);
            if (index >= 0 && !e->properties[index].count_type) {
                r->role[role] = index;
            }
        }
    }
    static const char *const axes[3] = { "x", "y", "z" };
    for (int a = 0; a < 3; a++) {
        if (r->role[ROLE_X + a] < 0) {
            if (sta_ply_element_find(e, axes[a]) >= 0) {
                return sta_fail(err, STA_ERR_FORMAT,
                                "%s: vertex property \"%s\" is a list, not a scalar", path,
                                axes[a]);
            }
            return sta_fail(err, STA_ERR_FORMAT, "%s: vertex element has no property \"%s\"", path,
                            axes[a]);
        }
    }
    if (r->role[ROLE_RED] >= 0 && r->role[ROLE_GREEN] >= 0 && r->role[ROLE_BLUE] >= 0) {
        r->info.attributes |= STA_ATTR_RGB;
    }
    if (r->role[ROLE_NX] >= 0 && r->role[ROLE_NY] >= 0 && r->role[ROLE_NZ] >= 0) {
        r->info.attributes |= STA_ATTR_NORMAL;
    }
    if (r->role[ROLE_INTENSITY] >= 0) {
        r->info.attributes |= STA_ATTR_INTENSITY;
    }
    return STA_OK;
}

// Moves the cursor past the elements stored before the vertex element.
static sta_status skip_leading_elements(ply_reader *r, const char *path, size_t vertex_index,
                                        sta_error *err)
{
    sta_ply_cursor *c = &r->start;
    for (size_t i = 0; i < vertex_index; i++) {
        const sta_ply_element *e = &r->header.elements[i];
        if (c->format != STA_PLY_ASCII && e->record_size > 0) {
            uint64_t fit = (c->size - c->pos) / e->record_size;
            if (e->count > fit) {
                return sta_fail(err, STA_ERR_FORMAT,
                                "%s: element \"%s\" declares %llu records of %zu bytes, but only "
                                "%zu bytes follow it (room for %llu): the count is wrong or the "
                                "file is truncated",
                                path, e->name, (unsigned long long)e->count, e->record_size,
                                c->size - c->pos, (unsigned long long)fit);
            }
            c->pos += (size_t)e->count * e->record_size;
            continue;
        }
        for (uint64_t k = 0; k < e->count; k++) {
            size_t failed = 0;
            sta_ply_read result = sta_ply_read_record(c, e, NULL, &failed);
            if (result != STA_PLY_READ_OK) {
                char detail[400];
                const sta_ply_property *p =
                    failed < e->property_count ? &e->properties[failed] : NULL;
                sta_ply_describe_read(c, result, e, k, p, detail, sizeof(detail));
                return sta_fail(err, STA_ERR_FORMAT, "%s: %s%s (before the vertex element)", path,
                                sta_ply_read_is_truncation(result) ? "truncated: " : "", detail);
            }
        }
    }
    return STA_OK;
}

static sta_status push_mark(ply_reader *r, const sta_ply_cursor *c, const char *path,
                            sta_error *err)
{
    if (sta_array_reserve((void **)&r->marks, &r->mark_capacity, r->mark_count + 1,
                          sizeof(*r->marks), 16, NULL) != STA_OK) {
        return sta_fail(err, STA_ERR_NOMEM, "%s: out of memory for the seek index", path);
    }
    r->marks[r->mark_count].pos = c->pos;
    r->marks[r->mark_count].line = c->line;
    r->mark_count++;
    return STA_OK;
}

static sta_status check_coordinates(const ply_reader *r, const double *v, uint64_t index,
                                    const char *path, sta_error *err)
{
    for (int a = 0; a < 3; a++) {
        double value = v[r->role[ROLE_X + a]];
        if (!isfinite(value)) {
            return sta_fail(err, STA_ERR_FORMAT,
                            "%s: vertex %llu: property \"%s\" is %s (coordinates must be "
                            "finite)",
                            path, (unsigned long long)index,
                            r->vertex->properties[r->role[ROLE_X + a]].name,
                            isnan(value) ? "NaN" : "infinite");
        }
    }
    return STA_OK;
}

// Reads every vertex once: validates, records seek marks, finds bounds and counts the
// complete vertices of a truncated file.
static sta_status scan_vertices(ply_reader *r, const sta_read_options *options, const char *path,
                                sta_error *err)
{
    const sta_ply_element *e = r->vertex;
    sta_ply_cursor c = r->start;
    uint64_t declared = e->count;
    uint64_t limit = declared;
    uint64_t complete = 0;
    bool has_float_intensity =
        r->role[ROLE_INTENSITY] >= 0 && is_float_type(e->properties[r->role[ROLE_INTENSITY]].type);
    double *lo = r->info.header_min;
    double *hi = r->info.header_max;
    r->intensity_is_unit = has_float_intensity;
    if (r->is_fixed) {
        uint64_t fit = (c.size - c.pos) / e->record_size;
        if (declared > fit) {
            if (!options->salvage_truncated) {
                return sta_fail(err, STA_ERR_FORMAT,
                                "%s: vertex element declares %llu vertices of %zu bytes, but "
                                "only %zu bytes follow the header: the count is wrong or the "
                                "body is truncated (%llu vertices are complete)",
                                path, (unsigned long long)declared, e->record_size, c.size - c.pos,
                                (unsigned long long)fit);
            }
            limit = fit;
        }
    }
    for (; complete < limit; complete++) {
        if (!r->is_fixed && complete % MARK_STRIDE == 0) {
            sta_status status = push_mark(r, &c, path, err);
            if (status != STA_OK) {
                return status;
            }
        }
        size_t failed = 0;
        sta_ply_read result = next_vertex(r, &c, &failed);
        if (result != STA_PLY_READ_OK) {
            if (sta_ply_read_is_truncation(result) && options->salvage_truncated) {
                break;
            }
            char detail[400];
            const sta_ply_property *p = failed < e->property_count ? &e->properties[failed] : NULL;
            sta_ply_describe_read(&c, result, e, complete, p, detail, sizeof(detail));
            if (sta_ply_read_is_truncation(result)) {
                return sta_fail(err, STA_ERR_FORMAT,
                                "%s: body truncated: only %llu of %llu vertices are complete "
                                "(%s)",
                                path, (unsigned long long)complete, (unsigned long long)declared,
                                detail);
            }
            return sta_fail(err, STA_ERR_FORMAT, "%s: %s", path, detail);
        }
        sta_status status = check_coordinates(r, r->values, complete, path, err);
        if (status != STA_OK) {
            return status;
        }
        for (int a = 0; a < 3; a++) {
            double value = r->values[r->role[ROLE_X + a]];
            if (complete == 0 || value < lo[a]) {
                lo[a] = value;
            }
            if (complete == 0 || value > hi[a]) {
                hi[a] = value;
            }
        }
        if (has_float_intensity) {
            double value = r->values[r->role[ROLE_INTENSITY]];
            if (!(value >= 0.0 && value <= 1.0)) {
                r->intensity_is_unit = false;
            }
        }
    }
    r->info.point_count = complete;
    r->info.skipped_point_count = declared - complete;
    return STA_OK;
}

static sta_status ply_seek(void *impl, uint64_t index, sta_error *err)
{
    ply_reader *r = impl;
    if (r->is_fixed) {
        r->cursor = r->start;
        r->cursor.pos += (size_t)index * r->vertex->record_size; // index <= point_count
        r->next_index = index;
        return STA_OK;
    }
    size_t mark = (size_t)(index / MARK_STRIDE);
    if (mark >= r->mark_count) {
        mark = r->mark_count ? r->mark_count - 1 : 0;
    }
    r->cursor = r->start;
    r->next_index = 0;
    if (r->mark_count) {
        r->cursor.pos = r->marks[mark].pos;
        r->cursor.line = r->marks[mark].line;
        r->next_index = (uint64_t)mark * MARK_STRIDE;
    }
    while (r->next_index < index) {
        size_t failed = 0;
        sta_ply_read result = STA_PLY_READ_OK;
        if (r->cursor.format == STA_PLY_ASCII) {
            // Validated at open: the vertex is the next non-blank line.
            result = sta_ply_record_begin(&r->cursor);
            r->cursor.pos = r->cursor.line_end + (r->cursor.line_terminated ? 1 : 0);
            r->cursor.line++;
        } else {
            result = sta_ply_read_record(&r->cursor, r->vertex, NULL, &failed);
        }
        if (result != STA_PLY_READ_OK) { // the scan at open read these records
            return sta_fail(err, STA_ERR_FORMAT, "%s: vertex %llu changed since open", r->info.path,
                            (unsigned long long)r->next_index);
        }
        r->next_index++;
    }
    return STA_OK;
}

static sta_status ply_read(void *impl, sta_point_batch *batch, sta_error *err)
{
    ply_reader *r = impl;
    batch->count = 0;
    batch->first_index = r->next_index;
    while (batch->count < batch->capacity && r->next_index < r->info.point_count) {
        size_t failed = 0;
        sta_ply_read result = next_vertex(r, &r->cursor, &failed);
        if (result != STA_PLY_READ_OK) {
            char detail[400];
            const sta_ply_property *p =
                failed < r->vertex->property_count ? &r->vertex->properties[failed] : NULL;
            sta_ply_describe_read(&r->cursor, result, r->vertex, r->next_index, p, detail,
                                  sizeof(detail));
            return sta_fail(err, STA_ERR_FORMAT, "%s: %s", r->info.path, detail);
        }
        decode_point(r, r->values, &batch->points[batch->count]);
        batch->count++;
        r->next_index++;
    }
    return STA_OK;
}

static const sta_cloud_ops ply_ops = {
    .read = ply_read,
    .seek = ply_seek,
    .info = ply_info,
    .close = ply_close,
};

sta_status sta_ply_open_map(const sta_file_map *map, const sta_read_options *options,
                            void **out_impl, const sta_cloud_ops **out_ops, sta_error *err)
{
    static const sta_read_options no_options = { 0 };
    const char *path = map->path;
    sta_status status = STA_OK;
    *out_impl = NULL;
    *out_ops = NULL;
    if (!options) {
        options = &no_options;
    }
    ply_reader *r = sta_calloc(1, sizeof(*r));
    if (!r) {
        return sta_fail(err, STA_ERR_NOMEM, "%s: out of memory", path);
    }
    status = sta_ply_header_parse(map->data, map->size, path, &r->header, err);
    if (status != STA_OK) {
        goto out_close;
    }
    long vertex_index = sta_ply_header_find(&r->header, "vertex");
    if (vertex_index < 0) {
        status = sta_fail(err, STA_ERR_FORMAT, "%s: PLY file has no \"vertex\" element", path);
        goto out_close;
    }
    r->vertex = &r->header.elements[vertex_index];
    status = find_roles(r, path, err);
    if (status != STA_OK) {
        goto out_close;
    }
    r->values = sta_alloc_array(r->vertex->property_count, sizeof(*r->values));
    if (!r->values) {
        status = sta_fail(err, STA_ERR_NOMEM, "%s: out of memory", path);
        goto out_close;
    }
    r->is_fixed = r->header.format != STA_PLY_ASCII && r->vertex->record_size > 0;
    if (r->is_fixed) {
        find_offsets(r);
    }
    sta_ply_cursor_init(&r->start, map->data, map->size, &r->header);
    status = skip_leading_elements(r, path, (size_t)vertex_index, err);
    if (status != STA_OK) {
        goto out_close;
    }
    status = scan_vertices(r, options, path, err);
    if (status != STA_OK) {
        goto out_close;
    }
    choose_grid(r);
    r->cursor = r->start;

    sta_cloud_info *info = &r->info;
    info->kind = STA_CLOUD_PLY;
    info->path = path;
    info->version_major = 1;
    info->version_minor = 0;
    info->point_format = -1;
    info->offset_to_point_data =
        r->header.body_offset > UINT32_MAX ? UINT32_MAX : (uint32_t)r->header.body_offset;
    info->record_length =
        r->is_fixed && r->vertex->record_size <= UINT16_MAX ? (uint16_t)r->vertex->record_size : 0;
    info->header_point_count = r->vertex->count;
    *out_impl = r;
    *out_ops = &ply_ops;
    return STA_OK;
out_close:
    ply_close(r);
    return status;
}
