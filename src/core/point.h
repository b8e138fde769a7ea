/* SPDX-License-Identifier: MIT
 * One point as every reader yields it, and batches of them.
 *
 * Coordinates stay exact: the integers X, Y, Z of the source's grid, with the grid
 * (scale, offset) carried by the reader's info. Real-world coordinates are
 * X * scale + offset, computed in double only when needed (sta_grid_apply).
 * Which fields carry meaning is told by the info's attribute mask (sta_attr);
 * absent fields are zero.
 */
#ifndef STA_CORE_POINT_H
#define STA_CORE_POINT_H

#include <stddef.h>
#include <stdint.h>

#include "core/status.h"

/* Attribute bits: which fields of sta_point a source really has. */
typedef enum sta_attr {
    STA_ATTR_INTENSITY = 1u << 0,        /* intensity */
    STA_ATTR_RETURNS = 1u << 1,          /* return_number, number_of_returns */
    STA_ATTR_CLASSIFICATION = 1u << 2,   /* classification, classification_flags */
    STA_ATTR_SCAN_ANGLE = 1u << 3,       /* scan_angle */
    STA_ATTR_USER_DATA = 1u << 4,        /* user_data */
    STA_ATTR_POINT_SOURCE_ID = 1u << 5,  /* point_source_id */
    STA_ATTR_SCAN_FLAGS = 1u << 6,       /* scan_direction_flag, edge_of_flight_line */
    STA_ATTR_GPS_TIME = 1u << 7,         /* gps_time */
    STA_ATTR_RGB = 1u << 8,              /* red, green, blue */
    STA_ATTR_NIR = 1u << 9,              /* nir */
    STA_ATTR_WAVE_PACKET = 1u << 10,     /* wave_* fields */
    STA_ATTR_NORMAL = 1u << 11,          /* normal[3] (PLY) */
    STA_ATTR_SCANNER_CHANNEL = 1u << 12, /* scanner_channel (LAS 1.4 formats 6-10) */
    STA_ATTR_SPLAT = 1u << 13,           /* normal[3] and radius from strata-convert --normals */
    STA_ATTR_MIRROR = 1u << 15           /* mirror (strata-convert --mirrors) */
} sta_attr;

/* The integer grid of a source: real = integer * scale + offset, per axis. */
typedef struct sta_grid {
    double scale[3];  /* > 0 and finite */
    double offset[3]; /* finite */
} sta_grid;

/* One point. Field names follow the LAS 1.4 specification. */
typedef struct sta_point {
    int32_t X, Y, Z;                 /* integer coordinates on the source grid */
    uint16_t intensity;              /* as stored */
    uint8_t return_number;           /* 0..15 as stored (0 is invalid but kept) */
    uint8_t number_of_returns;       /* 0..15 as stored */
    uint8_t classification;          /* 0..255 (formats 0-5: the 5-bit class only) */
    uint8_t classification_flags;    /* bit 0 synthetic, 1 key-point, 2 withheld, 3 overlap */
    uint8_t scanner_channel;         /* 0..3 */
    uint8_t scan_direction_flag;     /* 0 or 1 */
    uint8_t edge_of_flight_line;     /* 0 or 1 */
    uint8_t user_data;               /* as stored */
    int16_t scan_angle;              /* LAS 1.4 units of 0.006 degree; formats 0-5 store
                                        whole degrees, converted here (deg / 0.006) */
    uint16_t point_source_id;        /* as stored */
    uint16_t red, green, blue;       /* as stored (8-bit writers use 0..255) */
    uint16_t nir;                    /* as stored */
    double gps_time;                 /* as stored, may be NaN in broken files */
    float normal[3];                 /* unit normal from PLY nx/ny/nz, else 0 */
    float radius;                    /* splat radius in metres (strata-convert --normals), else 0 */
    uint8_t mirror;                  /* 0 real, k ghost seen through mirror k-1 (--mirrors) */
    uint8_t wave_descriptor_index;   /* wave packet descriptor index */
    uint64_t wave_byte_offset;       /* byte offset to waveform data */
    uint32_t wave_packet_size;       /* bytes */
    float wave_return_location;      /* picoseconds */
    float wave_xt, wave_yt, wave_zt; /* parametric line */
} sta_point;

/* A batch of points read from one source. Zero-initialise, then sta_point_batch_init.
 * `extra` holds `extra_size` bytes per point (the record's bytes beyond its point
 * format: declared extra dimensions and undeclared trailing bytes, raw). */
typedef struct sta_point_batch {
    sta_point *points;    /* capacity elements, count valid */
    uint8_t *extra;       /* capacity * extra_size bytes, count * extra_size valid */
    size_t count;         /* points in the batch */
    size_t capacity;      /* points it can hold */
    size_t extra_size;    /* bytes of extra data per point (may be 0) */
    uint64_t first_index; /* index in the source of points[0] */
} sta_point_batch;

/* Allocates room for `capacity` points and `extra_size` extra bytes per point. */
sta_status sta_point_batch_init(sta_point_batch *batch, size_t capacity, size_t extra_size,
                                sta_error *err);

/* Frees the arrays; a zeroed batch is a no-op. */
void sta_point_batch_release(sta_point_batch *batch);

/* The lower-case name of one sta_attr bit ("intensity", "rgb", ...); NULL if unknown. */
const char *sta_attr_name(uint32_t bit);

/* Real-world coordinate of integer `value` on axis `axis` (0 x, 1 y, 2 z). */
static inline double sta_grid_apply(const sta_grid *grid, int axis, int32_t value)
{
    return (double)value * grid->scale[axis] + grid->offset[axis];
}

#endif
