/* SPDX-License-Identifier: MIT
 * Packed point records. Native byte order: the records never leave this machine
 * (temporary files only). */
#include "record.h"

#include <string.h>

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
    if (layout->extra_size && extra) {
        memcpy(extra, in, layout->extra_size);
    }
}
