/* SPDX-License-Identifier: MIT
 * On-disk layout of a .strata file, version 1.0 (docs/FORMAT.md is normative).
 *
 * The structs below document the byte layout and are checked by _Static_assert; code
 * never casts file bytes to them. Fields are read and written one by one through
 * the little-endian helpers of core/bytes.h at the STA_STRATA_*_OFF offsets.
 * Every multi-byte value is little-endian; there is no implicit padding.
 */
#ifndef STA_FORMAT_LAYOUT_H
#define STA_FORMAT_LAYOUT_H

#include <stddef.h>
#include <stdint.h>

#define STA_STRATA_MAGIC         "STRATA\r\n" /* 8 bytes, no NUL */
#define STA_STRATA_MAGIC_SIZE    8
#define STA_STRATA_VERSION_MAJOR 1
#define STA_STRATA_VERSION_MINOR                                                                   \
 3 /* 1.1: compression 2; 1.2: up axis, LAS source; 1.3: SPLAT, MIRROR */
#define STA_STRATA_HEADER_SIZE     384u   /* fixed header of version 1.0 */
#define STA_STRATA_HEADER_SIZE_MAX 65536u /* readers refuse larger headers */
#define STA_STRATA_EXTRA_DIM_SIZE  128u   /* one extra-dimension descriptor */
#define STA_STRATA_NODE_ENTRY_SIZE 80u    /* one node-table entry of version 1.0 */
#define STA_STRATA_NODE_ENTRY_MAX  4096u  /* readers refuse larger entries */
#define STA_STRATA_ALIGNMENT       64u    /* payload and table alignment written */
#define STA_STRATA_CHECKSUM_XXH3   1u     /* XXH3-64, seed 0 */
#define STA_STRATA_DEFAULT_CELLS   128u   /* grid cells per axis of a node */
#define STA_STRATA_MAX_CELLS       65536u /* grid_cells range is 1..65536 */
#define STA_STRATA_MAX_ROOT_LOG2   32u    /* root edge at most 2^32 grid units */
#define STA_STRATA_MAX_EXTRA_DIMS  1024u
#define STA_STRATA_ATTR_BITS       32  /* size of the attribute mask */
#define STA_STRATA_POSITION_SIZE   12u /* X, Y, Z as uint32 relative to the corner */

/* Compression codes of a node payload. */
#define STA_STRATA_COMPRESSION_NONE         0u
#define STA_STRATA_COMPRESSION_ZSTD         1u
/* zstd over byte-shuffled columns (1.1): in each column of n elements of e bytes, byte
 * k of every element is stored contiguously (all byte 0s, then all byte 1s, ...). */
#define STA_STRATA_COMPRESSION_ZSTD_SHUFFLE 2u

/* Node flags. Bit 0: a leaf at the depth cap whose points may share grid cells. */
#define STA_STRATA_NODE_OVERFLOW 1u

/* On-disk attribute bits (frozen; independent of the in-memory sta_attr values). Each
 * present bit adds its columns after X, Y, Z, in ascending bit order. */
#define STA_STRATA_ATTR_INTENSITY       (1u << 0)  /* u16 intensity */
#define STA_STRATA_ATTR_RETURNS         (1u << 1)  /* u8 return_number, u8 number_of_returns */
#define STA_STRATA_ATTR_CLASSIFICATION  (1u << 2)  /* u8 classification, u8 flags */
#define STA_STRATA_ATTR_SCAN_ANGLE      (1u << 3)  /* i16 scan_angle (0.006 degree) */
#define STA_STRATA_ATTR_USER_DATA       (1u << 4)  /* u8 user_data */
#define STA_STRATA_ATTR_POINT_SOURCE_ID (1u << 5)  /* u16 point_source_id */
#define STA_STRATA_ATTR_SCAN_FLAGS      (1u << 6)  /* u8 scan_direction, u8 edge_of_flight_line */
#define STA_STRATA_ATTR_GPS_TIME        (1u << 7)  /* f64 gps_time */
#define STA_STRATA_ATTR_RGB             (1u << 8)  /* u16 red, u16 green, u16 blue */
#define STA_STRATA_ATTR_NIR             (1u << 9)  /* u16 nir */
#define STA_STRATA_ATTR_WAVE_PACKET     (1u << 10) /* u8, u64, u32, f32 x4 (29 bytes) */
#define STA_STRATA_ATTR_NORMAL          (1u << 11) /* f32 nx, f32 ny, f32 nz */
#define STA_STRATA_ATTR_SCANNER_CHANNEL (1u << 12) /* u8 scanner_channel */
#define STA_STRATA_ATTR_EXTRA           (1u << 13) /* extra dimensions, one column each */
#define STA_STRATA_ATTR_SPLAT           (1u << 14) /* (1.3) u16 oct u, u16 oct v, u16 half radius */
#define STA_STRATA_ATTR_MIRROR          (1u << 15) /* u8 0 real, k ghost via mirror k-1 (1.3) */
#define STA_STRATA_ATTR_KNOWN           ((1u << 16) - 1u)

/* Fixed header, 384 bytes at file offset 0. */
typedef struct sta_strata_header_disk {
    uint8_t magic[8];             /*   0 "STRATA\r\n" */
    uint16_t version_major;       /*   8 1 */
    uint16_t version_minor;       /*  10 0 */
    uint32_t header_size;         /*  12 bytes of the header, >= 384 */
    uint64_t file_size;           /*  16 bytes of the whole file */
    uint64_t header_checksum;     /*  24 XXH3-64 of the header with this field zero */
    uint32_t flags;               /*  32 incompatible features; 0 in 1.0 */
    uint32_t checksum_algorithm;  /*  36 1 = XXH3-64 */
    uint32_t grid_cells;          /*  40 cells per axis of every node's grid */
    uint32_t payload_alignment;   /*  44 power of two, 64 when written */
    double scale[3];              /*  48 real = integer * scale + offset */
    double offset[3];             /*  72 */
    int64_t root_corner[3];       /*  96 grid integers of the root's lowest corner */
    uint8_t root_size_log2[3];    /* 120 root edge per axis = 2^n grid units */
    uint8_t max_level;            /* 123 deepest node level */
    uint32_t attributes;          /* 124 STA_STRATA_ATTR_* bits */
    uint16_t attr_sizes[32];      /* 128 bytes per point of each bit's columns */
    uint32_t record_size;         /* 192 12 + sum of attr_sizes */
    uint32_t extra_dim_count;     /* 196 descriptors after the header */
    int32_t grid_min[3];          /* 200 tight integer bounds of all points */
    int32_t grid_max[3];          /* 212 */
    double bounds_min[3];         /* 224 tight real bounds (grid_min * scale + offset) */
    double bounds_max[3];         /* 248 */
    uint64_t point_count;         /* 272 sum of the nodes' point counts */
    uint32_t node_count;          /* 280 >= 1 */
    uint32_t node_entry_size;     /* 284 bytes per node-table entry, >= 80 */
    uint64_t table_offset;        /* 288 node table, last in the file */
    uint64_t table_checksum;      /* 296 XXH3-64 of the node table */
    uint64_t extra_dims_checksum; /* 304 XXH3-64 of the descriptors */
    char generator[32];           /* 312 NUL-padded name of the writing software */
    uint8_t up_axis;              /* 344 (1.2) STA_STRATA_UP_*: 0 = +Z (also before 1.2) */
    uint8_t reserved_up[7];       /* 345 zero */
    uint64_t source_offset;       /* 352 (1.2) LAS source block, 0 when none */
    uint64_t source_size;         /* 360 (1.2) bytes of the block */
    uint64_t source_checksum;     /* 368 (1.2) XXH3-64 of the block */
    uint8_t reserved[8];          /* 376 zero */
} sta_strata_header_disk;

#define STA_STRATA_H_MAGIC_OFF           0
#define STA_STRATA_H_VERSION_MAJOR_OFF   8
#define STA_STRATA_H_VERSION_MINOR_OFF   10
#define STA_STRATA_H_HEADER_SIZE_OFF     12
#define STA_STRATA_H_FILE_SIZE_OFF       16
#define STA_STRATA_H_HEADER_CHECKSUM_OFF 24
#define STA_STRATA_H_FLAGS_OFF           32
#define STA_STRATA_H_CHECKSUM_ALGO_OFF   36
#define STA_STRATA_H_GRID_CELLS_OFF      40
#define STA_STRATA_H_ALIGNMENT_OFF       44
#define STA_STRATA_H_SCALE_OFF           48
#define STA_STRATA_H_OFFSET_OFF          72
#define STA_STRATA_H_ROOT_CORNER_OFF     96
#define STA_STRATA_H_ROOT_LOG2_OFF       120
#define STA_STRATA_H_MAX_LEVEL_OFF       123
#define STA_STRATA_H_ATTRIBUTES_OFF      124
#define STA_STRATA_H_ATTR_SIZES_OFF      128
#define STA_STRATA_H_RECORD_SIZE_OFF     192
#define STA_STRATA_H_EXTRA_COUNT_OFF     196
#define STA_STRATA_H_GRID_MIN_OFF        200
#define STA_STRATA_H_GRID_MAX_OFF        212
#define STA_STRATA_H_BOUNDS_MIN_OFF      224
#define STA_STRATA_H_BOUNDS_MAX_OFF      248
#define STA_STRATA_H_POINT_COUNT_OFF     272
#define STA_STRATA_H_NODE_COUNT_OFF      280
#define STA_STRATA_H_ENTRY_SIZE_OFF      284
#define STA_STRATA_H_TABLE_OFFSET_OFF    288
#define STA_STRATA_H_TABLE_CHECKSUM_OFF  296
#define STA_STRATA_H_EXTRA_CHECKSUM_OFF  304
#define STA_STRATA_H_GENERATOR_OFF       312
#define STA_STRATA_H_UP_AXIS_OFF         344
#define STA_STRATA_H_SOURCE_OFFSET_OFF   352
#define STA_STRATA_H_SOURCE_SIZE_OFF     360
#define STA_STRATA_H_SOURCE_CHECKSUM_OFF 368
#define STA_STRATA_H_RESERVED_OFF        376

_Static_assert(sizeof(sta_strata_header_disk) == STA_STRATA_HEADER_SIZE, "header size");
_Static_assert(offsetof(sta_strata_header_disk, version_major) == STA_STRATA_H_VERSION_MAJOR_OFF,
               "version_major");
_Static_assert(offsetof(sta_strata_header_disk, version_minor) == STA_STRATA_H_VERSION_MINOR_OFF,
               "version_minor");
_Static_assert(offsetof(sta_strata_header_disk, header_size) == STA_STRATA_H_HEADER_SIZE_OFF,
               "header_size");
_Static_assert(offsetof(sta_strata_header_disk, file_size) == STA_STRATA_H_FILE_SIZE_OFF,
               "file_size");
_Static_assert(offsetof(sta_strata_header_disk, header_checksum) ==
                   STA_STRATA_H_HEADER_CHECKSUM_OFF,
               "header_checksum");
_Static_assert(offsetof(sta_strata_header_disk, flags) == STA_STRATA_H_FLAGS_OFF, "flags");
_Static_assert(offsetof(sta_strata_header_disk, checksum_algorithm) ==
                   STA_STRATA_H_CHECKSUM_ALGO_OFF,
               "checksum_algorithm");
_Static_assert(offsetof(sta_strata_header_disk, grid_cells) == STA_STRATA_H_GRID_CELLS_OFF,
               "grid_cells");
_Static_assert(offsetof(sta_strata_header_disk, payload_alignment) == STA_STRATA_H_ALIGNMENT_OFF,
               "payload_alignment");
_Static_assert(offsetof(sta_strata_header_disk, scale) == STA_STRATA_H_SCALE_OFF, "scale");
_Static_assert(offsetof(sta_strata_header_disk, offset) == STA_STRATA_H_OFFSET_OFF, "offset");
_Static_assert(offsetof(sta_strata_header_disk, root_corner) == STA_STRATA_H_ROOT_CORNER_OFF,
               "root_corner");
_Static_assert(offsetof(sta_strata_header_disk, root_size_log2) == STA_STRATA_H_ROOT_LOG2_OFF,
               "root_size_log2");
_Static_assert(offsetof(sta_strata_header_disk, max_level) == STA_STRATA_H_MAX_LEVEL_OFF,
               "max_level");
_Static_assert(offsetof(sta_strata_header_disk, attributes) == STA_STRATA_H_ATTRIBUTES_OFF,
               "attributes");
_Static_assert(offsetof(sta_strata_header_disk, attr_sizes) == STA_STRATA_H_ATTR_SIZES_OFF,
               "attr_sizes");
_Static_assert(offsetof(sta_strata_header_disk, record_size) == STA_STRATA_H_RECORD_SIZE_OFF,
               "record_size");
_Static_assert(offsetof(sta_strata_header_disk, extra_dim_count) == STA_STRATA_H_EXTRA_COUNT_OFF,
               "extra_dim_count");
_Static_assert(offsetof(sta_strata_header_disk, grid_min) == STA_STRATA_H_GRID_MIN_OFF, "grid_min");
_Static_assert(offsetof(sta_strata_header_disk, grid_max) == STA_STRATA_H_GRID_MAX_OFF, "grid_max");
_Static_assert(offsetof(sta_strata_header_disk, bounds_min) == STA_STRATA_H_BOUNDS_MIN_OFF,
               "bounds_min");
_Static_assert(offsetof(sta_strata_header_disk, bounds_max) == STA_STRATA_H_BOUNDS_MAX_OFF,
               "bounds_max");
_Static_assert(offsetof(sta_strata_header_disk, point_count) == STA_STRATA_H_POINT_COUNT_OFF,
               "point_count");
_Static_assert(offsetof(sta_strata_header_disk, node_count) == STA_STRATA_H_NODE_COUNT_OFF,
               "node_count");
_Static_assert(offsetof(sta_strata_header_disk, node_entry_size) == STA_STRATA_H_ENTRY_SIZE_OFF,
               "node_entry_size");
_Static_assert(offsetof(sta_strata_header_disk, table_offset) == STA_STRATA_H_TABLE_OFFSET_OFF,
               "table_offset");
_Static_assert(offsetof(sta_strata_header_disk, table_checksum) == STA_STRATA_H_TABLE_CHECKSUM_OFF,
               "table_checksum");
_Static_assert(offsetof(sta_strata_header_disk, extra_dims_checksum) ==
                   STA_STRATA_H_EXTRA_CHECKSUM_OFF,
               "extra_dims_checksum");
_Static_assert(offsetof(sta_strata_header_disk, generator) == STA_STRATA_H_GENERATOR_OFF,
               "generator");
_Static_assert(offsetof(sta_strata_header_disk, up_axis) == STA_STRATA_H_UP_AXIS_OFF, "up_axis");
_Static_assert(offsetof(sta_strata_header_disk, source_offset) == STA_STRATA_H_SOURCE_OFFSET_OFF,
               "source_offset");
_Static_assert(offsetof(sta_strata_header_disk, source_size) == STA_STRATA_H_SOURCE_SIZE_OFF,
               "source_size");
_Static_assert(offsetof(sta_strata_header_disk, source_checksum) ==
                   STA_STRATA_H_SOURCE_CHECKSUM_OFF,
               "source_checksum");
_Static_assert(offsetof(sta_strata_header_disk, reserved) == STA_STRATA_H_RESERVED_OFF, "reserved");

/* The LAS source block (1.2, docs/FORMAT.md §4a): what a LAS input said besides its
 * points, so an export can write the same header fields and CRS records. */
typedef struct sta_strata_las_source_disk {
    uint8_t version_major;        /*  0 LAS version of the input */
    uint8_t version_minor;        /*  1 */
    uint8_t point_format;         /*  2 0..10 */
    uint8_t reserved0;            /*  3 zero */
    uint16_t global_encoding;     /*  4 as stored */
    uint16_t file_source_id;      /*  6 */
    uint16_t creation_day;        /*  8 */
    uint16_t creation_year;       /* 10 */
    char system_identifier[32];   /* 12 NUL-padded */
    char generating_software[32]; /* 44 NUL-padded */
    uint32_t record_count;        /* 76 records that follow */
} sta_strata_las_source_disk;

/* One record (a VLR or EVLR of the input) in the block; `size` payload bytes follow. */
typedef struct sta_strata_las_record_disk {
    char user_id[16];     /*  0 NUL-padded */
    uint16_t record_id;   /* 16 */
    uint16_t flags;       /* 18 bit 0: it was an EVLR */
    uint32_t reserved;    /* 20 zero */
    uint64_t size;        /* 24 payload bytes */
    char description[32]; /* 32 NUL-padded */
} sta_strata_las_record_disk;

#define STA_STRATA_LAS_SOURCE_SIZE 80u
#define STA_STRATA_LAS_RECORD_SIZE 64u
_Static_assert(sizeof(sta_strata_las_source_disk) == STA_STRATA_LAS_SOURCE_SIZE, "source");
_Static_assert(offsetof(sta_strata_las_source_disk, system_identifier) == 12, "system id");
_Static_assert(offsetof(sta_strata_las_source_disk, record_count) == 76, "record_count");
_Static_assert(sizeof(sta_strata_las_record_disk) == STA_STRATA_LAS_RECORD_SIZE, "record");
_Static_assert(offsetof(sta_strata_las_record_disk, size) == 24, "record size");
_Static_assert(offsetof(sta_strata_las_record_disk, description) == 32, "record description");

/* One extra-dimension descriptor, 128 bytes; extra_dim_count of them follow the
 * header at offset header_size, in the order of their columns. */
typedef struct sta_strata_extra_dim_disk {
    char name[32];        /*   0 NUL-padded (no NUL needed when 32 long) */
    char description[32]; /*  32 NUL-padded */
    uint8_t data_type;    /*  64 LAS extra-bytes type code 0..30 (0 = opaque bytes) */
    uint8_t reserved0;    /*  65 zero */
    uint16_t size;        /*  66 bytes per point, >= 1 */
    uint32_t reserved1;   /*  68 zero */
    double scale[3];      /*  72 as declared by the source (1 when none) */
    double offset[3];     /*  96 as declared by the source (0 when none) */
    uint64_t reserved2;   /* 120 zero */
} sta_strata_extra_dim_disk;

#define STA_STRATA_D_NAME_OFF        0
#define STA_STRATA_D_DESCRIPTION_OFF 32
#define STA_STRATA_D_DATA_TYPE_OFF   64
#define STA_STRATA_D_SIZE_OFF        66
#define STA_STRATA_D_SCALE_OFF       72
#define STA_STRATA_D_OFFSET_OFF      96

_Static_assert(sizeof(sta_strata_extra_dim_disk) == STA_STRATA_EXTRA_DIM_SIZE, "descriptor size");
_Static_assert(offsetof(sta_strata_extra_dim_disk, description) == STA_STRATA_D_DESCRIPTION_OFF,
               "description");
_Static_assert(offsetof(sta_strata_extra_dim_disk, data_type) == STA_STRATA_D_DATA_TYPE_OFF,
               "data_type");
_Static_assert(offsetof(sta_strata_extra_dim_disk, size) == STA_STRATA_D_SIZE_OFF, "size");
_Static_assert(offsetof(sta_strata_extra_dim_disk, scale) == STA_STRATA_D_SCALE_OFF, "scale");
_Static_assert(offsetof(sta_strata_extra_dim_disk, offset) == STA_STRATA_D_OFFSET_OFF, "offset");
_Static_assert(offsetof(sta_strata_extra_dim_disk, reserved2) == 120, "reserved2");

/* One node-table entry, 80 bytes (node_entry_size in the header may be larger in
 * later minor versions; readers use the first 80 bytes). */
typedef struct sta_strata_node_disk {
    uint8_t level;             /*  0 depth, root 0 */
    uint8_t child_mask;        /*  1 bit s set: child in slot s exists */
    uint8_t compression;       /*  2 STA_STRATA_COMPRESSION_* */
    uint8_t reserved0;         /*  3 zero */
    uint32_t flags;            /*  4 STA_STRATA_NODE_* */
    uint32_t x, y, z;          /*  8 cell of the node at its level, each < 2^level */
    uint32_t first_child;      /* 20 index of the child in the lowest set slot; 0 if none */
    uint64_t point_count;      /* 24 points in this node */
    uint64_t payload_offset;   /* 32 file offset of the stored payload */
    uint64_t payload_size;     /* 40 stored bytes */
    uint64_t raw_size;         /* 48 bytes after decompression = point_count * record_size */
    uint64_t payload_checksum; /* 56 XXH3-64 of the stored bytes */
    double spacing;            /* 64 metres: largest node edge / grid_cells */
    uint64_t reserved1;        /* 72 zero */
} sta_strata_node_disk;

#define STA_STRATA_N_LEVEL_OFF       0
#define STA_STRATA_N_CHILD_MASK_OFF  1
#define STA_STRATA_N_COMPRESSION_OFF 2
#define STA_STRATA_N_FLAGS_OFF       4
#define STA_STRATA_N_X_OFF           8
#define STA_STRATA_N_Y_OFF           12
#define STA_STRATA_N_Z_OFF           16
#define STA_STRATA_N_FIRST_CHILD_OFF 20
#define STA_STRATA_N_POINT_COUNT_OFF 24
#define STA_STRATA_N_OFFSET_OFF      32
#define STA_STRATA_N_SIZE_OFF        40
#define STA_STRATA_N_RAW_SIZE_OFF    48
#define STA_STRATA_N_CHECKSUM_OFF    56
#define STA_STRATA_N_SPACING_OFF     64

_Static_assert(sizeof(sta_strata_node_disk) == STA_STRATA_NODE_ENTRY_SIZE, "node entry size");
_Static_assert(offsetof(sta_strata_node_disk, flags) == STA_STRATA_N_FLAGS_OFF, "flags");
_Static_assert(offsetof(sta_strata_node_disk, x) == STA_STRATA_N_X_OFF, "x");
_Static_assert(offsetof(sta_strata_node_disk, y) == STA_STRATA_N_Y_OFF, "y");
_Static_assert(offsetof(sta_strata_node_disk, z) == STA_STRATA_N_Z_OFF, "z");
_Static_assert(offsetof(sta_strata_node_disk, first_child) == STA_STRATA_N_FIRST_CHILD_OFF,
               "first_child");
_Static_assert(offsetof(sta_strata_node_disk, point_count) == STA_STRATA_N_POINT_COUNT_OFF,
               "point_count");
_Static_assert(offsetof(sta_strata_node_disk, payload_offset) == STA_STRATA_N_OFFSET_OFF,
               "payload_offset");
_Static_assert(offsetof(sta_strata_node_disk, payload_size) == STA_STRATA_N_SIZE_OFF,
               "payload_size");
_Static_assert(offsetof(sta_strata_node_disk, raw_size) == STA_STRATA_N_RAW_SIZE_OFF, "raw_size");
_Static_assert(offsetof(sta_strata_node_disk, payload_checksum) == STA_STRATA_N_CHECKSUM_OFF,
               "payload_checksum");
_Static_assert(offsetof(sta_strata_node_disk, spacing) == STA_STRATA_N_SPACING_OFF, "spacing");
_Static_assert(offsetof(sta_strata_node_disk, reserved1) == 72, "reserved1");

#endif
