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

#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include "io/point.h"

typedef struct sta_record_layout {
    uint32_t attributes; /* sta_attr bits stored */
    size_t extra_size;   /* raw extra bytes per point, stored last */
    size_t size;         /* bytes per record */
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

/* The position of a packed record without unpacking the rest. */
static inline void sta_record_position(const uint8_t *record, int32_t out_xyz[3])
{
    memcpy(out_xyz, record, 3 * sizeof(int32_t));
}

#endif
