/* SPDX-License-Identifier: MIT
 * Packed point records. Native byte order: the records never leave this machine
 * (temporary files only). */
#include "record.h"

#include <string.h>

#include "core/octahedral.h"

// Bytes each attribute adds to a record, in storage order.
static const struct {
    uint32_t bit;
    size_t size;
} attribute_sizes[] = {
    { STA_ATTR_INTENSITY, 2 },
    { STA_ATTR_RETURNS, 2 },
    { STA_ATTR_CLASSIFICATION, 2 },
    { STA_ATTR_SCAN_ANGLE, 2 },
    { STA_ATTR_USER_DATA, 1 },
    { STA_ATTR_POINT_SOURCE_ID, 2 },
    { STA_ATTR_SCAN_FLAGS, 1 },
    { STA_ATTR_GPS_TIME, 8 },
    { STA_ATTR_RGB, 6 },
    { STA_ATTR_NIR, 2 },
    { STA_ATTR_WAVE_PACKET, 29 },
    { STA_ATTR_NORMAL, 12 },
    { STA_ATTR_SCANNER_CHANNEL, 1 },
    { STA_ATTR_SPLAT, 6 },
    { STA_ATTR_MIRROR, 1 },
};

// The values of each attribute in pack order, as .strata columns (same order: both
// follow the attribute bits; scan flags are one packed byte here, two columns there).
static const struct {
    uint32_t bit;
    uint8_t sizes[8]; /* column sizes, 0-terminated */
} attribute_columns[] = {
    { STA_ATTR_INTENSITY, { 2 } },
    { STA_ATTR_RETURNS, { 1, 1 } },
    { STA_ATTR_CLASSIFICATION, { 1, 1 } },
    { STA_ATTR_SCAN_ANGLE, { 2 } },
    { STA_ATTR_USER_DATA, { 1 } },
    { STA_ATTR_POINT_SOURCE_ID, { 2 } },
    { STA_ATTR_SCAN_FLAGS, { 1 } }, /* split below */
    { STA_ATTR_GPS_TIME, { 8 } },
    { STA_ATTR_RGB, { 2, 2, 2 } },
    { STA_ATTR_NIR, { 2 } },
    { STA_ATTR_WAVE_PACKET, { 1, 8, 4, 4, 4, 4, 4 } },
    { STA_ATTR_NORMAL, { 4, 4, 4 } },
    { STA_ATTR_SCANNER_CHANNEL, { 1 } },
    { STA_ATTR_SPLAT, { 2, 2, 2 } }, /* after the extra dimensions in .strata (bit 14) */
    { STA_ATTR_MIRROR, { 1 } },
};

void sta_record_layout_init(sta_record_layout *layout, uint32_t attributes, size_t extra_size)
{
    layout->attributes = 0;
    layout->extra_size = extra_size;
    layout->size = 12 + extra_size;
    for (size_t i = 0; i < sizeof(attribute_sizes) / sizeof(attribute_sizes[0]); i++) {
        if (attributes & attribute_sizes[i].bit) {
            layout->attributes |= attribute_sizes[i].bit;
            layout->size += attribute_sizes[i].size;
        }
    }
    size_t offset = 12;
    layout->column_count = 0;
    layout->columns_before_extra = -1;
    layout->splat_column = -1;
    for (size_t i = 0; i < sizeof(attribute_columns) / sizeof(attribute_columns[0]); i++) {
        if (!(layout->attributes & attribute_columns[i].bit)) {
            continue;
        }
        if (attribute_columns[i].bit == STA_ATTR_GPS_TIME) {
            layout->gps_offset = offset;
        }
        if (attribute_columns[i].bit == STA_ATTR_SPLAT) {
            layout->splat_column = layout->column_count;
            layout->splat_offset = offset;
        }
        // SPLAT and MIRROR (.strata bits 14, 15) are stored after the extra dimensions (13).
        if (attribute_columns[i].bit >= STA_ATTR_SPLAT && layout->columns_before_extra < 0) {
            layout->columns_before_extra = layout->column_count;
        }
        for (int c = 0; attribute_columns[i].sizes[c] != 0; c++) {
            size_t size = attribute_columns[i].sizes[c];
            if (attribute_columns[i].bit == STA_ATTR_SCAN_FLAGS) {
                // Direction and edge flags: bits 0 and 1 of one byte, two u8 columns.
                layout->columns[layout->column_count++] = (sta_record_column){ offset, 1, 0 };
                layout->columns[layout->column_count++] = (sta_record_column){ offset, 1, 1 };
            } else {
                layout->columns[layout->column_count++] = (sta_record_column){ offset, size, -1 };
            }
            offset += size;
        }
    }
    if (layout->columns_before_extra < 0) {
        layout->columns_before_extra = layout->column_count;
    }
}

/* Writes column `c` of `count` records at `pos`; returns the position after it. */
static uint8_t *encode_column(const sta_record_layout *layout, int c, const uint8_t *records,
                              size_t count, uint8_t *pos)
{
    const size_t rec = layout->size;
    const sta_record_column *col = &layout->columns[c];
    const uint8_t *src = records + col->offset;
    if (col->bit >= 0) {
        for (size_t i = 0; i < count; i++) {
            pos[i] = (uint8_t)((src[i * rec] >> col->bit) & 1u);
        }
    } else if (col->size == 1) {
        for (size_t i = 0; i < count; i++) {
            pos[i] = src[i * rec];
        }
    } else if (col->size == 2) {
        for (size_t i = 0; i < count; i++) {
            memcpy(pos + 2 * i, src + i * rec, 2);
        }
    } else if (col->size == 4) { // constant sizes: inlined moves, not a call per value
        for (size_t i = 0; i < count; i++) {
            memcpy(pos + 4 * i, src + i * rec, 4);
        }
    } else if (col->size == 8) {
        for (size_t i = 0; i < count; i++) {
            memcpy(pos + 8 * i, src + i * rec, 8);
        }
    } else {
        for (size_t i = 0; i < count; i++) {
            memcpy(pos + col->size * i, src + i * rec, col->size);
        }
    }
    pos += col->size * count;
    return pos;
}

bool sta_record_encode_columns(const sta_record_layout *layout, const uint8_t *records,
                               size_t count, const int64_t corner[3],
                               const uint16_t *extra_dim_sizes, uint32_t extra_dim_count,
                               uint8_t *out)
{
    const size_t rec = layout->size;
    uint8_t *pos = out;
    for (int a = 0; a < 3; a++) {
        for (size_t i = 0; i < count; i++) {
            int32_t v;
            memcpy(&v, records + i * rec + 4 * (size_t)a, sizeof(v));
            int64_t relative = (int64_t)v - corner[a];
            if (relative < 0 || relative > (int64_t)UINT32_MAX) {
                return false;
            }
            uint32_t u = (uint32_t)relative;
            memcpy(pos + 4 * i, &u, sizeof(u));
        }
        pos += 4 * count;
    }
    for (int c = 0; c < layout->columns_before_extra; c++) {
        pos = encode_column(layout, c, records, count, pos);
    }
    size_t at = rec - layout->extra_size;
    for (uint32_t d = 0; d < extra_dim_count; d++) {
        size_t size = extra_dim_sizes[d];
        for (size_t i = 0; i < count; i++) {
            memcpy(pos + i * size, records + i * rec + at, size);
        }
        pos += count * size;
        at += size;
    }
    for (int c = layout->columns_before_extra; c < layout->column_count; c++) {
        pos = encode_column(layout, c, records, count,
                            pos); // SPLAT, MIRROR (14, 15) after EXTRA (13)
    }
    return true;
}

#define PUT(field)                                                                                 \
 do {                                                                                              \
  memcpy(out, &(field), sizeof(field));                                                            \
  out += sizeof(field);                                                                            \
 } while (0)

#define GET(field)                                                                                 \
 do {                                                                                              \
  memcpy(&(field), in, sizeof(field));                                                             \
  in += sizeof(field);                                                                             \
 } while (0)

void sta_record_pack(const sta_record_layout *layout, const sta_point *p, const uint8_t *extra,
                     uint8_t *out)
{
    const uint32_t a = layout->attributes;
    PUT(p->X);
    PUT(p->Y);
    PUT(p->Z);
    if (a & STA_ATTR_INTENSITY) {
        PUT(p->intensity);
    }
    if (a & STA_ATTR_RETURNS) {
        PUT(p->return_number);
        PUT(p->number_of_returns);
    }
    if (a & STA_ATTR_CLASSIFICATION) {
        PUT(p->classification);
        PUT(p->classification_flags);
    }
    if (a & STA_ATTR_SCAN_ANGLE) {
        PUT(p->scan_angle);
    }
    if (a & STA_ATTR_USER_DATA) {
        PUT(p->user_data);
    }
    if (a & STA_ATTR_POINT_SOURCE_ID) {
        PUT(p->point_source_id);
    }
    if (a & STA_ATTR_SCAN_FLAGS) {
        uint8_t flags =
            (uint8_t)((p->scan_direction_flag & 1) | ((p->edge_of_flight_line & 1) << 1));
        PUT(flags);
    }
    if (a & STA_ATTR_GPS_TIME) {
        PUT(p->gps_time);
    }
    if (a & STA_ATTR_RGB) {
        PUT(p->red);
        PUT(p->green);
        PUT(p->blue);
    }
    if (a & STA_ATTR_NIR) {
        PUT(p->nir);
    }
    if (a & STA_ATTR_WAVE_PACKET) {
        PUT(p->wave_descriptor_index);
        PUT(p->wave_byte_offset);
        PUT(p->wave_packet_size);
        PUT(p->wave_return_location);
        PUT(p->wave_xt);
        PUT(p->wave_yt);
        PUT(p->wave_zt);
    }
    if (a & STA_ATTR_NORMAL) {
        PUT(p->normal);
    }
    if (a & STA_ATTR_SCANNER_CHANNEL) {
        PUT(p->scanner_channel);
    }
    if (a & STA_ATTR_SPLAT) {
        // A point without a normal or a radius (--normals computes them later, over these
        // bytes) packs to zeros: the fallback normal (0, 0, 1) and a zero half float.
        uint16_t splat[3] = { 0, 0, 0 };
        if (p->normal[0] != 0.0f || p->normal[1] != 0.0f || p->normal[2] != 0.0f ||
            p->radius != 0.0f) {
            sta_splat_pack(p->normal, p->radius, splat);
        }
        PUT(splat);
    }
    if (a & STA_ATTR_MIRROR) {
        PUT(p->mirror);
    }
    if (layout->extra_size) {
        memcpy(out, extra, layout->extra_size);
    }
}

void sta_record_unpack(const sta_record_layout *layout, const uint8_t *in, sta_point *p,
                       uint8_t *extra)
{
    const uint32_t a = layout->attributes;
    memset(p, 0, sizeof(*p));
    GET(p->X);
    GET(p->Y);
    GET(p->Z);
    if (a & STA_ATTR_INTENSITY) {
        GET(p->intensity);
    }
    if (a & STA_ATTR_RETURNS) {
        GET(p->return_number);
        GET(p->number_of_returns);
    }
    if (a & STA_ATTR_CLASSIFICATION) {
        GET(p->classification);
        GET(p->classification_flags);
    }
    if (a & STA_ATTR_SCAN_ANGLE) {
        GET(p->scan_angle);
    }
    if (a & STA_ATTR_USER_DATA) {
        GET(p->user_data);
    }
    if (a & STA_ATTR_POINT_SOURCE_ID) {
        GET(p->point_source_id);
    }
    if (a & STA_ATTR_SCAN_FLAGS) {
        uint8_t flags;
        GET(flags);
        p->scan_direction_flag = flags & 1;
        p->edge_of_flight_line = (flags >> 1) & 1;
    }
    if (a & STA_ATTR_GPS_TIME) {
        GET(p->gps_time);
    }
    if (a & STA_ATTR_RGB) {
        GET(p->red);
        GET(p->green);
        GET(p->blue);
    }
    if (a & STA_ATTR_NIR) {
        GET(p->nir);
    }
    if (a & STA_ATTR_WAVE_PACKET) {
        GET(p->wave_descriptor_index);
        GET(p->wave_byte_offset);
        GET(p->wave_packet_size);
        GET(p->wave_return_location);
        GET(p->wave_xt);
        GET(p->wave_yt);
        GET(p->wave_zt);
    }
    if (a & STA_ATTR_NORMAL) {
        GET(p->normal);
    }
    if (a & STA_ATTR_SCANNER_CHANNEL) {
        GET(p->scanner_channel);
    }
    if (a & STA_ATTR_SPLAT) {
        uint16_t splat[3];
        GET(splat);
        sta_splat_unpack(splat, p->normal, &p->radius);
    }
    if (a & STA_ATTR_MIRROR) {
        GET(p->mirror);
    }
    if (layout->extra_size && extra) {
        memcpy(extra, in, layout->extra_size);
    }
}
