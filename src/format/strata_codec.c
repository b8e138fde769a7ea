/* SPDX-License-Identifier: MIT
 * Attribute layout and the column codec of .strata payloads (docs/FORMAT.md §5).
 *
 * A payload of n points is a sequence of columns, each n values of one component:
 * X, Y, Z (uint32 relative to the node corner), then for every present attribute
 * bit in ascending order its components (table `components`), then one column per
 * extra dimension (n records of its size). Values are little-endian; floats are
 * stored as their IEEE-754 bits, so NaN payloads survive.
 */
#include <inttypes.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <string.h>

#include "core/byte_planes.h"
#include "core/bytes.h"
#include "core/octahedral.h"
#include "format/strata.h"

/* One column of a known attribute: which sta_point field, how many bytes. */
typedef struct component {
    uint32_t bit;        // STA_STRATA_ATTR_* it belongs to
    size_t field_offset; // offsetof(sta_point, field)
    uint8_t size;        // bytes per value: 1, 2, 4 or 8
} component;

#define SPLAT_FIELD   SIZE_MAX
#define FIELD_SIZE(f) sizeof(((sta_point *)0)->f)
#define COMPONENT(bit, f, n)                                                                       \
 {                                                                                                 \
  bit, offsetof(sta_point, f), n                                                                   \
 }

_Static_assert(FIELD_SIZE(intensity) == 2, "intensity");
_Static_assert(FIELD_SIZE(scan_angle) == 2, "scan_angle");
_Static_assert(FIELD_SIZE(point_source_id) == 2, "point_source_id");
_Static_assert(FIELD_SIZE(gps_time) == 8, "gps_time");
_Static_assert(FIELD_SIZE(red) == 2 && FIELD_SIZE(nir) == 2, "colour");
_Static_assert(FIELD_SIZE(normal) == 12, "normal");
_Static_assert(FIELD_SIZE(wave_byte_offset) == 8 && FIELD_SIZE(wave_packet_size) == 4 &&
                   FIELD_SIZE(wave_return_location) == 4 && FIELD_SIZE(wave_xt) == 4,
               "wave packet");

// Columns of each known attribute, in bit order and, within a bit, in storage order.
static const component components[] = {
    COMPONENT(STA_STRATA_ATTR_INTENSITY, intensity, 2),
    COMPONENT(STA_STRATA_ATTR_RETURNS, return_number, 1),
    COMPONENT(STA_STRATA_ATTR_RETURNS, number_of_returns, 1),
    COMPONENT(STA_STRATA_ATTR_CLASSIFICATION, classification, 1),
    COMPONENT(STA_STRATA_ATTR_CLASSIFICATION, classification_flags, 1),
    COMPONENT(STA_STRATA_ATTR_SCAN_ANGLE, scan_angle, 2),
    COMPONENT(STA_STRATA_ATTR_USER_DATA, user_data, 1),
    COMPONENT(STA_STRATA_ATTR_POINT_SOURCE_ID, point_source_id, 2),
    COMPONENT(STA_STRATA_ATTR_SCAN_FLAGS, scan_direction_flag, 1),
    COMPONENT(STA_STRATA_ATTR_SCAN_FLAGS, edge_of_flight_line, 1),
    COMPONENT(STA_STRATA_ATTR_GPS_TIME, gps_time, 8),
    COMPONENT(STA_STRATA_ATTR_RGB, red, 2),
    COMPONENT(STA_STRATA_ATTR_RGB, green, 2),
    COMPONENT(STA_STRATA_ATTR_RGB, blue, 2),
    COMPONENT(STA_STRATA_ATTR_NIR, nir, 2),
    COMPONENT(STA_STRATA_ATTR_WAVE_PACKET, wave_descriptor_index, 1),
    COMPONENT(STA_STRATA_ATTR_WAVE_PACKET, wave_byte_offset, 8),
    COMPONENT(STA_STRATA_ATTR_WAVE_PACKET, wave_packet_size, 4),
    COMPONENT(STA_STRATA_ATTR_WAVE_PACKET, wave_return_location, 4),
    COMPONENT(STA_STRATA_ATTR_WAVE_PACKET, wave_xt, 4),
    COMPONENT(STA_STRATA_ATTR_WAVE_PACKET, wave_yt, 4),
    COMPONENT(STA_STRATA_ATTR_WAVE_PACKET, wave_zt, 4),
    { STA_STRATA_ATTR_NORMAL, offsetof(sta_point, normal) + 0 * sizeof(float), 4 },
    { STA_STRATA_ATTR_NORMAL, offsetof(sta_point, normal) + 1 * sizeof(float), 4 },
    { STA_STRATA_ATTR_NORMAL, offsetof(sta_point, normal) + 2 * sizeof(float), 4 },
    COMPONENT(STA_STRATA_ATTR_SCANNER_CHANNEL, scanner_channel, 1),
    // SPLAT (1.3): octahedral u, v and binary16 radius, converted from normal[] and radius
    // (core/octahedral.h) rather than copied; SPLAT_FIELD marks them.
    { STA_STRATA_ATTR_SPLAT, SPLAT_FIELD, 2 },
    { STA_STRATA_ATTR_SPLAT, SPLAT_FIELD, 2 },
    { STA_STRATA_ATTR_SPLAT, SPLAT_FIELD, 2 },
    COMPONENT(STA_STRATA_ATTR_MIRROR, mirror, 1),
};
#define COMPONENT_COUNT (sizeof(components) / sizeof(components[0]))

// sta_attr bit and the on-disk bit it maps to.
static const struct {
    uint32_t mem;
    uint32_t disk;
} attr_map[] = {
    { STA_ATTR_INTENSITY, STA_STRATA_ATTR_INTENSITY },
    { STA_ATTR_RETURNS, STA_STRATA_ATTR_RETURNS },
    { STA_ATTR_CLASSIFICATION, STA_STRATA_ATTR_CLASSIFICATION },
    { STA_ATTR_SCAN_ANGLE, STA_STRATA_ATTR_SCAN_ANGLE },
    { STA_ATTR_USER_DATA, STA_STRATA_ATTR_USER_DATA },
    { STA_ATTR_POINT_SOURCE_ID, STA_STRATA_ATTR_POINT_SOURCE_ID },
    { STA_ATTR_SCAN_FLAGS, STA_STRATA_ATTR_SCAN_FLAGS },
    { STA_ATTR_GPS_TIME, STA_STRATA_ATTR_GPS_TIME },
    { STA_ATTR_RGB, STA_STRATA_ATTR_RGB },
    { STA_ATTR_NIR, STA_STRATA_ATTR_NIR },
    { STA_ATTR_WAVE_PACKET, STA_STRATA_ATTR_WAVE_PACKET },
    { STA_ATTR_NORMAL, STA_STRATA_ATTR_NORMAL },
    { STA_ATTR_SCANNER_CHANNEL, STA_STRATA_ATTR_SCANNER_CHANNEL },
    { STA_ATTR_SPLAT, STA_STRATA_ATTR_SPLAT },
    { STA_ATTR_MIRROR, STA_STRATA_ATTR_MIRROR },
};

uint32_t sta_strata_attributes_from_sta_attr(uint32_t sta_attr_mask)
{
    uint32_t out = 0;
    for (size_t i = 0; i < sizeof(attr_map) / sizeof(attr_map[0]); i++) {
        if (sta_attr_mask & attr_map[i].mem) {
            out |= attr_map[i].disk;
        }
    }
    return out;
}

uint32_t sta_strata_attributes_to_sta_attr(uint32_t strata_mask)
{
    uint32_t out = 0;
    for (size_t i = 0; i < sizeof(attr_map) / sizeof(attr_map[0]); i++) {
        if (strata_mask & attr_map[i].disk) {
            out |= attr_map[i].mem;
        }
    }
    return out;
}

uint16_t sta_strata_attr_size(uint32_t bit)
{
    uint16_t size = 0;
    for (size_t i = 0; i < COMPONENT_COUNT; i++) {
        if (components[i].bit == bit) {
            size = (uint16_t)(size + components[i].size);
        }
    }
    return size;
}

uint16_t sta_strata_extra_type_size(uint8_t data_type)
{
    static const uint8_t scalar[11] = { 0, 1, 1, 2, 2, 4, 4, 8, 8, 4, 8 };
    if (data_type >= 1 && data_type <= 10) {
        return scalar[data_type];
    }
    if (data_type >= 11 && data_type <= 20) {
        return (uint16_t)(2 * scalar[data_type - 10]);
    }
    if (data_type >= 21 && data_type <= 30) {
        return (uint16_t)(3 * scalar[data_type - 20]);
    }
    return 0;
}

sta_status sta_strata_layout_init(sta_strata_layout *layout, uint32_t attributes,
                                  const sta_strata_extra_dim *extra_dims, uint32_t extra_dim_count,
                                  sta_error *err)
{
    memset(layout, 0, sizeof(*layout));
    attributes &= ~STA_STRATA_ATTR_EXTRA;
    if (attributes & ~STA_STRATA_ATTR_KNOWN) {
        return sta_fail(err, STA_ERR_ARG, "strata layout: unknown attribute bits 0x%08" PRIx32,
                        attributes & ~STA_STRATA_ATTR_KNOWN);
    }
    if (extra_dim_count > STA_STRATA_MAX_EXTRA_DIMS) {
        return sta_fail(err, STA_ERR_ARG,
                        "strata layout: %" PRIu32 " extra dimensions (at most %u)", extra_dim_count,
                        STA_STRATA_MAX_EXTRA_DIMS);
    }
    if (extra_dim_count > 0 && !extra_dims) {
        return sta_fail(err, STA_ERR_ARG, "strata layout: extra dimensions missing");
    }
    uint32_t extra_size = 0;
    for (uint32_t i = 0; i < extra_dim_count; i++) {
        const sta_strata_extra_dim *d = &extra_dims[i];
        uint16_t type_size = sta_strata_extra_type_size(d->data_type);
        if (d->size_bytes == 0 || d->data_type > 30 ||
            (type_size != 0 && type_size != d->size_bytes)) {
            return sta_fail(err, STA_ERR_ARG,
                            "strata layout: extra dimension %" PRIu32
                            " '%.32s' has type %u and %u bytes",
                            i, d->name, d->data_type, d->size_bytes);
        }
        extra_size += d->size_bytes;
    }
    if (extra_size > UINT16_MAX) {
        return sta_fail(err, STA_ERR_ARG,
                        "strata layout: extra dimensions take %" PRIu32 " bytes (at most 65535)",
                        extra_size);
    }
    uint32_t record = STA_STRATA_POSITION_SIZE;
    for (int b = 0; b < STA_STRATA_ATTR_BITS; b++) {
        uint32_t bit = 1u << b;
        if (attributes & bit) {
            layout->attr_size[b] = sta_strata_attr_size(bit);
        }
    }
    if (extra_dim_count > 0) {
        attributes |= STA_STRATA_ATTR_EXTRA;
        layout->attr_size[13] = (uint16_t)extra_size;
    }
    for (int b = 0; b < STA_STRATA_ATTR_BITS; b++) {
        record += layout->attr_size[b];
    }
    layout->attributes = attributes;
    layout->extra_dims = extra_dims;
    layout->extra_dim_count = extra_dim_count;
    layout->extra_size = extra_size;
    layout->record_size = record;
    return STA_OK;
}

unsigned sta_strata_level_cap(const sta_strata_geometry *geometry)
{
    unsigned cap = geometry->root_size_log2[0];
    for (int a = 1; a < 3; a++) {
        if (geometry->root_size_log2[a] < cap) {
            cap = geometry->root_size_log2[a];
        }
    }
    return cap;
}

void sta_strata_node_grid_bounds(const sta_strata_geometry *geometry, sta_strata_key key,
                                 int64_t out_corner[3], int64_t out_size[3])
{
    const uint32_t cell[3] = { key.x, key.y, key.z };
    for (int a = 0; a < 3; a++) {
        unsigned shift = (unsigned)geometry->root_size_log2[a] - key.level;
        out_size[a] = (int64_t)1 << shift;
        out_corner[a] = geometry->root_corner[a] + (int64_t)cell[a] * out_size[a];
    }
}

void sta_strata_node_real_bounds(const sta_strata_geometry *geometry, sta_strata_key key,
                                 double out_min[3], double out_max[3])
{
    int64_t corner[3], size[3];
    sta_strata_node_grid_bounds(geometry, key, corner, size);
    for (int a = 0; a < 3; a++) {
        out_min[a] = (double)corner[a] * geometry->grid.scale[a] + geometry->grid.offset[a];
        out_max[a] =
            (double)(corner[a] + size[a]) * geometry->grid.scale[a] + geometry->grid.offset[a];
    }
}

double sta_strata_node_spacing(const sta_strata_geometry *geometry, unsigned level)
{
    double edge = 0.0;
    for (int a = 0; a < 3; a++) {
        double e = ldexp(geometry->grid.scale[a], (int)geometry->root_size_log2[a] - (int)level);
        if (e > edge) {
            edge = e;
        }
    }
    return edge / (double)(geometry->grid_cells ? geometry->grid_cells : 1);
}

sta_status sta_strata_choose_root(const sta_grid *grid, const int32_t min[3], const int32_t max[3],
                                  int64_t out_corner[3], uint8_t out_size_log2[3], sta_error *err)
{
    double extent_m = 0.0;
    for (int a = 0; a < 3; a++) {
        if (min[a] > max[a] || !(grid->scale[a] > 0.0) || !isfinite(grid->scale[a])) {
            return sta_fail(err, STA_ERR_ARG,
                            "strata root: axis %d has bounds %" PRId32 "..%" PRId32 " and scale %g",
                            a, min[a], max[a], grid->scale[a]);
        }
        double e = (double)((int64_t)max[a] - min[a] + 1) * grid->scale[a];
        if (e > extent_m) {
            extent_m = e;
        }
    }
    for (int a = 0; a < 3; a++) {
        int64_t extent = (int64_t)max[a] - min[a] + 1;
        unsigned k = 0;
        while (k < STA_STRATA_MAX_ROOT_LOG2 &&
               (((int64_t)1 << k) < extent || ldexp(grid->scale[a], (int)k) < extent_m)) {
            k++;
        }
        int64_t size = (int64_t)1 << k;
        int64_t corner = min[a] - (size - extent) / 2;
        if (corner < INT32_MIN) {
            corner = INT32_MIN;
        }
        if (corner + size > (int64_t)INT32_MAX + 1) {
            corner = (int64_t)INT32_MAX + 1 - size;
        }
        out_corner[a] = corner;
        out_size_log2[a] = (uint8_t)k;
    }
    return STA_OK;
}

const char *sta_strata_node_label(char *buf, size_t size, uint32_t index, sta_strata_key key)
{
    snprintf(buf, size, "node %" PRIu32 " (level %u, %" PRIu32 "/%" PRIu32 "/%" PRIu32 ")", index,
             key.level, key.x, key.y, key.z);
    return buf;
}

// Stores one column of `count` values of `size` bytes read from each point's field.
static void store_column(uint8_t *out, const sta_point *points, size_t count, size_t field_offset,
                         uint8_t size)
{
    const uint8_t *base = (const uint8_t *)points + field_offset;
    switch (size) {
    case 1:
        for (size_t i = 0; i < count; i++) {
            out[i] = base[i * sizeof(sta_point)];
        }
        break;
    case 2:
        for (size_t i = 0; i < count; i++) {
            uint16_t v;
            memcpy(&v, base + i * sizeof(sta_point), sizeof(v));
            sta_store_u16le(out + 2 * i, v);
        }
        break;
    case 4:
        for (size_t i = 0; i < count; i++) {
            uint32_t v;
            memcpy(&v, base + i * sizeof(sta_point), sizeof(v));
            sta_store_u32le(out + 4 * i, v);
        }
        break;
    default:
        for (size_t i = 0; i < count; i++) {
            uint64_t v;
            memcpy(&v, base + i * sizeof(sta_point), sizeof(v));
            sta_store_u64le(out + 8 * i, v);
        }
        break;
    }
}

// Loads one column into each point's field (the inverse of store_column).
static void load_column(sta_point *points, const uint8_t *in, size_t count, size_t field_offset,
                        uint8_t size)
{
    uint8_t *base = (uint8_t *)points + field_offset;
    switch (size) {
    case 1:
        for (size_t i = 0; i < count; i++) {
            base[i * sizeof(sta_point)] = in[i];
        }
        break;
    case 2:
        for (size_t i = 0; i < count; i++) {
            uint16_t v = sta_load_u16le(in + 2 * i);
            memcpy(base + i * sizeof(sta_point), &v, sizeof(v));
        }
        break;
    case 4:
        for (size_t i = 0; i < count; i++) {
            uint32_t v = sta_load_u32le(in + 4 * i);
            memcpy(base + i * sizeof(sta_point), &v, sizeof(v));
        }
        break;
    default:
        for (size_t i = 0; i < count; i++) {
            uint64_t v = sta_load_u64le(in + 8 * i);
            memcpy(base + i * sizeof(sta_point), &v, sizeof(v));
        }
        break;
    }
}

// The SPLAT attribute's three u16 columns from / into normal[] and radius.
static void store_splat(uint8_t *out, const sta_point *points, size_t count)
{
    for (size_t i = 0; i < count; i++) {
        uint16_t v[3];
        sta_splat_pack(points[i].normal, points[i].radius, v);
        for (int k = 0; k < 3; k++) {
            sta_store_u16le(out + (size_t)k * 2 * count + 2 * i, v[k]);
        }
    }
}

static void load_splat(sta_point *points, const uint8_t *in, size_t count)
{
    for (size_t i = 0; i < count; i++) {
        uint16_t v[3];
        for (int k = 0; k < 3; k++) {
            v[k] = sta_load_u16le(in + (size_t)k * 2 * count + 2 * i);
        }
        sta_splat_unpack(v, points[i].normal, &points[i].radius);
    }
}

static int32_t coordinate(const sta_point *p, int axis)
{
    return axis == 0 ? p->X : axis == 1 ? p->Y : p->Z;
}

sta_status sta_strata_encode_points(const sta_strata_layout *layout, const sta_point *points,
                                    const uint8_t *extra, size_t count, const int64_t corner[3],
                                    uint8_t *out, sta_error *err)
{
    uint8_t *pos = out;
    for (int a = 0; a < 3; a++) {
        for (size_t i = 0; i < count; i++) {
            int64_t rel = (int64_t)coordinate(&points[i], a) - corner[a];
            if (rel < 0 || rel > (int64_t)UINT32_MAX) {
                return sta_fail(
                    err, STA_ERR_ARG,
                    "strata encode: point %zu at grid (%" PRId32 ", %" PRId32 ", %" PRId32
                    ") is not within 2^32 above the corner (%" PRId64 ", %" PRId64 ", %" PRId64 ")",
                    i, points[i].X, points[i].Y, points[i].Z, corner[0], corner[1], corner[2]);
            }
            sta_store_u32le(pos + i * 4, (uint32_t)rel);
        }
        pos += count * 4;
    }
    for (size_t c = 0; c < COMPONENT_COUNT; c++) {
        if ((layout->attributes & components[c].bit) && components[c].bit < STA_STRATA_ATTR_EXTRA) {
            store_column(pos, points, count, components[c].field_offset, components[c].size);
            pos += count * components[c].size;
        }
    }
    if (layout->attributes & STA_STRATA_ATTR_EXTRA) {
        size_t at = 0;
        for (uint32_t d = 0; d < layout->extra_dim_count; d++) {
            size_t size = layout->extra_dims[d].size_bytes;
            for (size_t i = 0; i < count; i++) {
                memcpy(pos + i * size, extra + i * layout->extra_size + at, size);
            }
            pos += count * size;
            at += size;
        }
    }
    for (size_t c = 0; c < COMPONENT_COUNT; c++) { // bits above EXTRA follow its columns
        if (!(layout->attributes & components[c].bit) ||
            components[c].bit < STA_STRATA_ATTR_EXTRA) {
            continue;
        }
        if (components[c].field_offset == SPLAT_FIELD) { // three columns from one conversion
            store_splat(pos, points, count);
            pos += count * 6;
            c += 2;
            continue;
        }
        store_column(pos, points, count, components[c].field_offset, components[c].size);
        pos += count * components[c].size;
    }
    return STA_OK;
}

sta_status sta_strata_decode_points(const sta_strata_layout *layout, const uint8_t *raw,
                                    size_t count, const int64_t corner[3], sta_point *out_points,
                                    uint8_t *out_extra, sta_error *err)
{
    if (count > 0) {
        memset(out_points, 0, count * sizeof(*out_points));
    }
    const uint8_t *pos = raw;
    for (int a = 0; a < 3; a++) {
        for (size_t i = 0; i < count; i++) {
            int64_t v = corner[a] + (int64_t)sta_load_u32le(pos + i * 4);
            if (v < INT32_MIN || v > INT32_MAX) {
                return sta_fail(err, STA_ERR_FORMAT,
                                "strata decode: point %zu axis %d: %" PRId64
                                " is outside the int32 range",
                                i, a, v);
            }
            int32_t *dst = a == 0 ? &out_points[i].X : a == 1 ? &out_points[i].Y : &out_points[i].Z;
            *dst = (int32_t)v;
        }
        pos += count * 4;
    }
    // Walk the bits in order: known bits fill fields, unknown ones are skipped.
    for (int b = 0; b < STA_STRATA_ATTR_BITS; b++) {
        uint32_t bit = 1u << b;
        if (!(layout->attributes & bit)) {
            continue;
        }
        if (bit == STA_STRATA_ATTR_EXTRA) {
            size_t at = 0;
            for (uint32_t d = 0; d < layout->extra_dim_count; d++) {
                size_t size = layout->extra_dims[d].size_bytes;
                for (size_t i = 0; i < count; i++) {
                    memcpy(out_extra + i * layout->extra_size + at, pos + i * size, size);
                }
                pos += count * size;
                at += size;
            }
            continue;
        }
        if (!(bit & STA_STRATA_ATTR_KNOWN)) {
            pos += count * layout->attr_size[b];
            continue;
        }
        for (size_t c = 0; c < COMPONENT_COUNT; c++) {
            if (components[c].bit == bit && components[c].field_offset == SPLAT_FIELD) {
                load_splat(out_points, pos, count);
                pos += count * 6;
                break;
            }
            if (components[c].bit == bit) {
                load_column(out_points, pos, count, components[c].field_offset, components[c].size);
                pos += count * components[c].size;
            }
        }
    }
    return STA_OK;
}

size_t sta_strata_column_offset(const sta_strata_layout *layout, uint32_t bit, size_t count)
{
    if (!(layout->attributes & bit) || (bit & (bit - 1)) != 0) {
        return SIZE_MAX;
    }
    size_t offset = STA_STRATA_POSITION_SIZE * count;
    for (int b = 0; b < STA_STRATA_ATTR_BITS && (1u << b) != bit; b++) {
        if (layout->attributes & (1u << b)) {
            offset += (size_t)layout->attr_size[b] * count;
        }
    }
    return offset;
}

// Calls visit(element size, column byte offset, element count) for every column of the
// layout, in payload order (X, Y, Z, then attribute bits ascending, the extra dimensions
// at the EXTRA bit).
typedef void (*column_visitor)(size_t element_size, size_t offset, size_t count, const uint8_t *in,
                               uint8_t *out);

static void walk_columns(const sta_strata_layout *layout, size_t count, const uint8_t *in,
                         uint8_t *out, column_visitor visit)
{
    size_t pos = 0;
    for (int axis = 0; axis < 3; axis++) {
        visit(4, pos, count, in, out);
        pos += 4 * count;
    }
    for (int bit_index = 0; bit_index < STA_STRATA_ATTR_BITS; bit_index++) {
        uint32_t bit = 1u << bit_index;
        if (!(layout->attributes & bit)) {
            continue;
        }
        if (bit == STA_STRATA_ATTR_EXTRA) {
            for (uint32_t d = 0; d < layout->extra_dim_count; d++) {
                const sta_strata_extra_dim *dim = &layout->extra_dims[d];
                size_t element = dim->data_type >= 1 && dim->data_type <= 10
                                     ? sta_strata_extra_type_size(dim->data_type)
                                     : 1;
                element = element > 0 && dim->size_bytes % element == 0 ? element : 1;
                visit(element, pos, count * (dim->size_bytes / element), in, out);
                pos += count * dim->size_bytes;
            }
            continue;
        }
        bool known = false;
        for (size_t c = 0; c < COMPONENT_COUNT; c++) {
            if (components[c].bit == bit) {
                visit(components[c].size, pos, count, in, out);
                pos += count * components[c].size;
                known = true;
            }
        }
        if (!known) { // a later version's attribute: plain bytes
            visit(1, pos, count * layout->attr_size[bit_index], in, out);
            pos += count * layout->attr_size[bit_index];
        }
    }
}

// A column's byte planes (core/byte_planes.c: register transposes, about twice as
// fast as a byte at a time).
static void shuffle_column(size_t element, size_t offset, size_t count, const uint8_t *in,
                           uint8_t *out)
{
    if (element == 1) {
        memcpy(out + offset, in + offset, count);
        return;
    }
    sta_byte_planes_split(in + offset, count, element, out + offset);
}

static void unshuffle_column(size_t element, size_t offset, size_t count, const uint8_t *in,
                             uint8_t *out)
{
    if (element == 1) {
        memcpy(out + offset, in + offset, count);
        return;
    }
    sta_byte_planes_join(in + offset, count, element, out + offset);
}

void sta_strata_shuffle(const sta_strata_layout *layout, size_t count, const uint8_t *raw,
                        uint8_t *out)
{
    walk_columns(layout, count, raw, out, shuffle_column);
}

void sta_strata_unshuffle(const sta_strata_layout *layout, size_t count, const uint8_t *shuffled,
                          uint8_t *out)
{
    walk_columns(layout, count, shuffled, out, unshuffle_column);
}
