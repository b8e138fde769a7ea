/* SPDX-License-Identifier: MIT
 * The .strata hierarchy file: types shared by writer and reader, the attribute
 * layout, node geometry and the column codec (docs/FORMAT.md is normative).
 *
 * A .strata file holds a nested octree over the integer grid of the input scene.
 * The root is a box of 2^root_size_log2[a] grid units per axis at root_corner; a node
 * at level L covers [corner, corner + 2^(root_size_log2[a] - L)) per axis. Positions
 * are stored as uint32 offsets from the node's corner, so every input coordinate
 * comes back bit for bit. A node's payload is column-wise: all X, all Y, all Z, then
 * each attribute's columns in ascending attribute-bit order, then one column per
 * extra dimension.
 */
#ifndef STA_FORMAT_STRATA_H
#define STA_FORMAT_STRATA_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "core/point.h"
#include "core/status.h"
#include "format/layout.h"

/* One extra dimension: a run of bytes per point with its LAS description. */
typedef struct sta_strata_extra_dim {
    char name[33];        /* NUL-terminated, at most 32 characters */
    char description[33]; /* NUL-terminated, at most 32 characters */
    uint8_t data_type;    /* LAS extra-bytes code: 0 opaque, 1..10 scalars, 11..30 tuples */
    uint16_t size_bytes;  /* bytes per point, >= 1 (must match the type for 1..10) */
    double scale[3];      /* per component; 1 when the source gives none */
    double offset[3];     /* per component; 0 when the source gives none */
} sta_strata_extra_dim;

/* What a payload holds per point besides X, Y, Z. Fill with sta_strata_layout_init. */
typedef struct sta_strata_layout {
    uint32_t attributes;                      /* STA_STRATA_ATTR_* bits present */
    uint16_t attr_size[STA_STRATA_ATTR_BITS]; /* bytes per point of each bit; 0 absent */
    const sta_strata_extra_dim *extra_dims;   /* borrowed; extra_dim_count entries */
    uint32_t extra_dim_count;                 /* 0..STA_STRATA_MAX_EXTRA_DIMS */
    uint32_t extra_size;                      /* sum of the extra dims' sizes */
    uint32_t record_size;                     /* 12 + sum of attr_size: bytes per point */
} sta_strata_layout;

/* Fills `layout` for `attributes` (STA_STRATA_ATTR_* bits; STA_STRATA_ATTR_EXTRA is
 * set or cleared from extra_dim_count) and the extra dimensions, which it borrows.
 * Errors: STA_ERR_ARG for unknown bits, too many or empty extra dimensions, a size
 * that does not match its LAS type, or extras larger than 65535 bytes per point. */
sta_status sta_strata_layout_init(sta_strata_layout *layout, uint32_t attributes,
                                  const sta_strata_extra_dim *extra_dims, uint32_t extra_dim_count,
                                  sta_error *err);

/* Maps sta_attr bits (io/point.h) to STA_STRATA_ATTR_* bits (never sets EXTRA). */
uint32_t sta_strata_attributes_from_sta_attr(uint32_t sta_attr_mask);

/* Maps STA_STRATA_ATTR_* bits back to sta_attr bits (EXTRA and unknown bits dropped). */
uint32_t sta_strata_attributes_to_sta_attr(uint32_t strata_mask);

/* Bytes per point of a known attribute bit's columns (0 for EXTRA and unknown bits). */
uint16_t sta_strata_attr_size(uint32_t bit);

/* Bytes per point of the LAS extra-bytes type `data_type` (1..30), 0 for opaque (0)
 * and unknown codes. */
uint16_t sta_strata_extra_type_size(uint8_t data_type);

/* Octree key: the node's level and its cell at that level (each < 2^level). Children
 * of (L, x, y, z) are (L+1, 2x+dx, 2y+dy, 2z+dz) in slot dx | dy << 1 | dz << 2. */
typedef struct sta_strata_key {
    uint8_t level;
    uint32_t x, y, z;
} sta_strata_key;

/* Where add_node put a payload; goes into the node's table entry unchanged. */
typedef struct sta_strata_payload {
    uint64_t offset;      /* file offset, multiple of the alignment; 0 when size is 0 */
    uint64_t stored_size; /* bytes in the file */
    uint64_t raw_size;    /* bytes decoded: point_count * record_size */
    uint64_t checksum;    /* XXH3-64 of the stored bytes */
    uint8_t compression;  /* STA_STRATA_COMPRESSION_NONE or _ZSTD */
} sta_strata_payload;

/* One node-table entry. Children are contiguous: child_mask bit s set means a child
 * in slot s, and the children are nodes first_child, first_child + 1, ... in
 * ascending slot order. Every child index is greater than its parent's (breadth-
 * first order is what the writer is meant to produce). */
typedef struct sta_strata_node {
    sta_strata_key key;
    uint8_t child_mask;         /* slots with a child */
    uint32_t first_child;       /* index of the first child; 0 when child_mask is 0 */
    uint32_t flags;             /* STA_STRATA_NODE_* (OVERFLOW only on leaves) */
    uint64_t point_count;       /* points in this node's payload */
    double spacing;             /* metres: largest node edge / grid_cells (the writer
                                   computes it; its input value is ignored) */
    sta_strata_payload payload; /* as returned by sta_strata_writer_add_* */
} sta_strata_node;

/* The root box and grid of a scene: what node geometry is derived from. */
typedef struct sta_strata_geometry {
    sta_grid grid;             /* real = integer * scale + offset */
    int64_t root_corner[3];    /* grid integers of the root's lowest corner */
    uint8_t root_size_log2[3]; /* root edge per axis = 2^n grid units, 0..32 */
    uint32_t grid_cells;       /* cells per axis of each node's grid, 1..65536 */
} sta_strata_geometry;

/* The deepest level a node may have: min over axes of root_size_log2. */
unsigned sta_strata_level_cap(const sta_strata_geometry *geometry);

/* Integer bounds of node `key`: corner (inclusive) and edge length per axis, in
 * grid units; a point p is inside when corner <= p < corner + size. The key must be
 * valid for the geometry (level <= cap, cell < 2^level). */
void sta_strata_node_grid_bounds(const sta_strata_geometry *geometry, sta_strata_key key,
                                 int64_t out_corner[3], int64_t out_size[3]);

/* Real-world box of node `key` in metres (or the grid's unit): out_min is the corner,
 * out_max the far corner (corner + size) through scale and offset. */
void sta_strata_node_real_bounds(const sta_strata_geometry *geometry, sta_strata_key key,
                                 double out_min[3], double out_max[3]);

/* The spacing the writer stores: largest real edge of the node / grid_cells. */
double sta_strata_node_spacing(const sta_strata_geometry *geometry, unsigned level);

/* Cell of a position inside a node along one axis: floor(rel * grid_cells / size)
 * with size = 2^size_log2 and rel < size. The converter must place points with this
 * same function so that `sta_strata_verify` agrees with it. */
static inline uint32_t sta_strata_cell_of(uint32_t rel, unsigned size_log2, uint32_t grid_cells)
{
    return (uint32_t)(((uint64_t)rel * grid_cells) >> size_log2);
}

/* Chooses a root box holding the integer bounds [min, max] (inclusive): per axis the
 * smallest power of two whose real edge reaches the largest real extent of the
 * scene (so the root is as cubic in metres as the grid allows), centred on the data
 * and kept inside the int32 range. Errors: STA_ERR_ARG when min > max or a scale is
 * not positive. */
sta_status sta_strata_choose_root(const sta_grid *grid, const int32_t min[3], const int32_t max[3],
                                  int64_t out_corner[3], uint8_t out_size_log2[3], sta_error *err);

/* What the header of an open file says (see sta_strata_reader_info), also what the
 * writer serialises. Counts and offsets are validated against the file. */
/* Which world axis points up (header field up_axis, since 1.2). The converter sets it
 * from the source: LAS is +Z; PLY models are usually +Y (docs/FORMAT.md). Values a
 * reader does not know read as +Z. */
#define STA_STRATA_UP_Z 0
#define STA_STRATA_UP_Y 1

typedef struct sta_strata_info {
    const char *path;             /* as opened (for messages) */
    uint16_t version_major;       /* 1 */
    uint16_t version_minor;       /* any; later minors only add skippable things */
    uint32_t header_size;         /* bytes of the fixed header */
    uint64_t file_size;           /* bytes */
    uint32_t flags;               /* 0 (incompatible features) */
    sta_strata_geometry geometry; /* grid, root box, grid cells */
    uint8_t max_level;            /* deepest node level */
    sta_strata_layout layout;     /* extra_dims owned by the reader */
    int32_t grid_min[3];          /* tight integer bounds of all points (0 if none) */
    int32_t grid_max[3];
    double bounds_min[3]; /* tight real bounds: grid_min * scale + offset */
    double bounds_max[3];
    uint64_t point_count;         /* all nodes together */
    uint32_t node_count;          /* >= 1; node 0 is the root */
    uint32_t node_entry_size;     /* bytes per table entry on disk */
    uint32_t payload_alignment;   /* power of two */
    uint64_t data_offset;         /* first byte where payloads may start */
    uint64_t table_offset;        /* node table (last in the file) */
    uint64_t header_checksum;     /* as stored */
    uint64_t table_checksum;      /* as stored */
    uint64_t extra_dims_checksum; /* as stored */
    char generator[33];           /* writing software, NUL-terminated */
    uint8_t up_axis;              /* STA_STRATA_UP_Z (0, also files before 1.2) or _Y */
    uint64_t source_offset;       /* LAS source block (1.2), 0 when none */
    uint64_t source_size;         /* bytes */
    uint64_t source_checksum;     /* as stored */
} sta_strata_info;

/* One VLR or EVLR of a LAS input, kept in the LAS source block. */
typedef struct sta_strata_las_record {
    char user_id[17];     /* NUL-terminated, at most 16 characters */
    uint16_t record_id;   /* as in the input */
    bool extended;        /* it was an EVLR */
    char description[33]; /* NUL-terminated, at most 32 characters */
    const uint8_t *data;  /* size bytes (borrowed: the writer copies, the reader maps) */
    uint64_t size;        /* payload bytes */
} sta_strata_las_record;

/* What a LAS input said besides its points (docs/FORMAT.md §4a): its header fields
 * and the records that describe its coordinate reference system, so that an export
 * writes them back. */
typedef struct sta_strata_las_source {
    uint8_t version_major, version_minor; /* LAS version of the input */
    uint8_t point_format;                 /* 0..10 */
    uint16_t global_encoding;             /* as stored (bit 0: adjusted GPS time) */
    uint16_t file_source_id;
    uint16_t creation_day;
    uint16_t creation_year;
    char system_identifier[33];           /* NUL-terminated */
    char generating_software[33];         /* NUL-terminated */
    const sta_strata_las_record *records; /* record_count entries (borrowed) */
    uint32_t record_count;
} sta_strata_las_source;

/* Bytes of the LAS source block that sta_strata_las_source_store writes. */
uint64_t sta_strata_las_source_size(const sta_strata_las_source *source);

/* Serialises `source` into `out` (sta_strata_las_source_size bytes). */
void sta_strata_las_source_store(const sta_strata_las_source *source, uint8_t *out);

/* Parses a LAS source block of `size` bytes; `name` is used in messages. On success
 * *out_records (out->record_count entries whose data point into `data`) is owned by
 * the caller (sta_free). Errors: STA_ERR_FORMAT naming the file and the record,
 * STA_ERR_NOMEM. */
sta_status sta_strata_las_source_parse(const uint8_t *data, uint64_t size, const char *name,
                                       sta_strata_las_source *out,
                                       sta_strata_las_record **out_records, sta_error *err);

/* Formats "node 17 (level 3, 5/2/7)" into buf (for messages); returns buf. */
const char *sta_strata_node_label(char *buf, size_t size, uint32_t index, sta_strata_key key);

/* Encodes `count` points into the column layout: out must hold count *
 * layout->record_size bytes. `extra` holds layout->extra_size bytes per point
 * (row-wise, dimensions in descriptor order) or is NULL when extra_size is 0.
 * `corner` is the node's corner; each coordinate minus the corner must lie in
 * [0, 2^32). Errors: STA_ERR_ARG naming the point that does not fit. */
sta_status sta_strata_encode_points(const sta_strata_layout *layout, const sta_point *points,
                                    const uint8_t *extra, size_t count, const int64_t corner[3],
                                    uint8_t *out, sta_error *err);

/* Decodes `count` points from the column layout `raw` (count * record_size bytes)
 * into `out_points` (count elements, absent fields zero) and, when extra_size > 0,
 * `out_extra` (count * extra_size bytes). Columns of attribute bits unknown to this
 * version are skipped. Errors: STA_ERR_FORMAT when corner + offset leaves the int32
 * range (naming the point). */
sta_status sta_strata_decode_points(const sta_strata_layout *layout, const uint8_t *raw,
                                    size_t count, const int64_t corner[3], sta_point *out_points,
                                    uint8_t *out_extra, sta_error *err);

/* Byte-shuffles a raw payload of `count` points (compression code 2): each column of
 * elements wider than one byte is transposed so byte k of every element is contiguous.
 * Element sizes: 4 for X, Y, Z; each known attribute component's size; an extra
 * dimension's scalar size for LAS types 1..10 (else 1); 1 for attribute bits unknown to
 * this version. `out` holds count * record_size bytes and must not overlap `raw`. */
void sta_strata_shuffle(const sta_strata_layout *layout, size_t count, const uint8_t *raw,
                        uint8_t *out);

/* Inverse of sta_strata_shuffle. */
void sta_strata_unshuffle(const sta_strata_layout *layout, size_t count, const uint8_t *shuffled,
                          uint8_t *out);

/* Byte offset within a raw payload of `count` points of the first column of
 * attribute `bit` (one STA_STRATA_ATTR_* bit); X is at 0, Y at 4 * count, Z at
 * 8 * count. Returns SIZE_MAX when the layout lacks the bit. Components of a multi-
 * column attribute follow one another, each count * component size bytes. */
size_t sta_strata_column_offset(const sta_strata_layout *layout, uint32_t bit, size_t count);

#endif
