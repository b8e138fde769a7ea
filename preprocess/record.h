/* SPDX-License-Identifier: MIT
 * Packed point records for the converter's temporary files.
 *
 * Only the attributes the scene has are stored (see sta_attr), so a billion-point
 * conversion writes ~40 bytes a point to disk instead of a full sta_point. Positions
 * come first (3 x int32 on the output grid) so the octree builder reads them without
 * unpacking the rest.
 */
#ifndef STA_PREPROCESS_RECORD_H
#define STA_PREPROCESS_RECORD_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include "core/point.h"

/* Where one .strata payload column comes from in a packed record (see
 * sta_record_encode_columns). */
typedef struct sta_record_column {
    size_t offset; /* byte offset in the record */
    size_t size;   /* bytes per value */
    int bit;       /* -1: copy; 0 or 1: that bit of a packed flags byte, as a u8 */
} sta_record_column;

enum {
    STA_RECORD_MAX_COLUMNS = 32
};

typedef struct sta_record_layout {
    uint32_t attributes;                               /* sta_attr bits stored */
    size_t extra_size;                                 /* raw extra bytes per point, stored last */
    size_t size;                                       /* bytes per record */
    sta_record_column columns[STA_RECORD_MAX_COLUMNS]; /* attribute columns in .strata order */
    int column_count;
    int columns_before_extra; /* .strata puts the extra dimensions' columns here (bit 13) */
    int splat_column;         /* first SPLAT column, -1 when none (written after the extras) */
    size_t splat_offset;      /* byte offset of the SPLAT u16[3] in the record, when present */
    size_t gps_offset;        /* byte offset of the f64 GPS time, when present */
} sta_record_layout;

/* Computes the layout for the given attributes and extra bytes per point. */
void sta_record_layout_init(sta_record_layout *layout, uint32_t attributes, size_t extra_size);

/* Packs one point (and its `extra_size` extra bytes, may be NULL when 0) into `out`
 * (layout->size bytes). */
void sta_record_pack(const sta_record_layout *layout, const sta_point *point, const uint8_t *extra,
                     uint8_t *out);

/* Unpacks a record; fields not in the layout are zeroed. `extra` may be NULL. */
void sta_record_unpack(const sta_record_layout *layout, const uint8_t *record, sta_point *point,
                       uint8_t *extra);

/* Writes the .strata column payload (io order: X, Y, Z as uint32 above `corner`, then
 * the attribute columns in .strata bit order, then `extra_dim_count` extra-dimension
 * columns of `extra_dim_sizes` bytes) straight from `count` packed records, without
 * unpacking them: what sta_strata_encode_points would write for the same points.
 * Returns false when a position is not within 2^32 above the corner. */
bool sta_record_encode_columns(const sta_record_layout *layout, const uint8_t *records,
                               size_t count, const int64_t corner[3],
                               const uint16_t *extra_dim_sizes, uint32_t extra_dim_count,
                               uint8_t *out);

/* The position of a packed record without unpacking the rest. */
static inline void sta_record_position(const uint8_t *record, int32_t out_xyz[3])
{
    memcpy(out_xyz, record, 3 * sizeof(int32_t));
}

#endif
