/* SPDX-License-Identifier: MIT
 * Reading any supported point file (LAS, PLY; LAZ later) through one interface.
 *
 * A reader yields batches of points in file order with bounded memory; what the file
 * is and holds is described by sta_cloud_info. The format is chosen by the file's
 * magic bytes, not its name.
 */
#ifndef STA_IO_CLOUD_H
#define STA_IO_CLOUD_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "core/point.h"
#include "core/status.h"

typedef enum sta_cloud_kind {
    STA_CLOUD_LAS = 1,
    STA_CLOUD_PLY = 2,
} sta_cloud_kind;

/* One VLR or EVLR as found in the file (its payload stays in the file). */
typedef struct sta_vlr_info {
    char user_id[17];     /* NUL-terminated (16 chars in the file) */
    uint16_t record_id;   /* as stored */
    uint64_t length;      /* payload bytes (EVLRs: 64-bit) */
    uint64_t data_offset; /* file offset of the payload */
    char description[33]; /* NUL-terminated (32 chars in the file) */
    bool is_extended;     /* true for an EVLR after the point data */
} sta_vlr_info;

/* One extra dimension described by the Extra Bytes VLR (LASF_Spec/4), or an opaque
 * run of undeclared trailing bytes (data_type 0, name "undeclared"). */
typedef struct sta_extra_dim {
    char name[33];        /* NUL-terminated */
    char description[33]; /* NUL-terminated */
    uint8_t data_type;    /* LAS code: 0 opaque, 1..10 scalars, 11..30 deprecated tuples */
    uint8_t options;      /* bit 0 no_data, 1 min, 2 max, 3 scale, 4 offset */
    int component_count;  /* 1, or 2..3 for the deprecated tuple types */
    size_t offset_bytes;  /* position within the point's extra bytes */
    size_t size_bytes;    /* bytes per point for the whole dimension */
    double scale[3];      /* 1 when not given */
    double offset[3];     /* 0 when not given */
    double no_data[3];    /* meaningful when options bit 0 is set */
} sta_extra_dim;

/* What a source file is and declares. Owned by its reader. */
typedef struct sta_cloud_info {
    sta_cloud_kind kind;
    const char *path;              /* as opened (for messages) */
    int version_major;             /* LAS 1; PLY 1 */
    int version_minor;             /* LAS 0..4; PLY 0 */
    int point_format;              /* LAS 0..10; PLY -1 */
    uint16_t header_size;          /* LAS header size as written; PLY 0 */
    uint32_t offset_to_point_data; /* LAS; for PLY the body's offset */
    uint16_t record_length;        /* LAS point record length; PLY bytes per vertex (binary) */
    uint64_t point_count;          /* the count the reader will yield */
    uint64_t header_point_count;   /* as declared (64-bit field when present) */
    uint32_t legacy_point_count;   /* LAS legacy 32-bit field */
    uint64_t points_by_return[15]; /* as declared (legacy or 64-bit fields) */
    sta_grid grid;                 /* PLY: chosen by the reader, see ply.h */
    double header_min[3];          /* declared bounds (not trusted); PLY: from a scan */
    double header_max[3];
    uint16_t file_source_id;
    uint16_t global_encoding;
    char system_identifier[33];
    char generating_software[33];
    uint16_t creation_day;
    uint16_t creation_year;
    uint32_t attributes; /* sta_attr bits present in the points */
    size_t extra_size;   /* extra bytes per point (see sta_point_batch) */
    sta_vlr_info *vlrs;  /* VLRs then EVLRs in file order */
    size_t vlr_count;
    sta_extra_dim *extra_dims; /* decoded Extra Bytes VLR (+ undeclared tail) */
    size_t extra_dim_count;
    const char *crs_wkt;          /* OGC WKT from a VLR/EVLR, NUL-terminated, or NULL */
    bool has_geotiff_crs;         /* GeoKeyDirectory (LASF_Projection/34735) present */
    bool has_waveform_packets;    /* formats 4, 5, 9, 10: wave packet fields read */
    bool has_internal_waveform;   /* global encoding bit 1 */
    uint64_t waveform_data_start; /* LAS 1.3+ start of waveform data record, or 0 */
    uint64_t skipped_point_count; /* points missing from a salvaged truncated file */
} sta_cloud_info;

/* Options for opening. Zero means default. */
typedef struct sta_read_options {
    bool salvage_truncated; /* read the complete records of a truncated file (and say
                               how many were missing) instead of failing */
} sta_read_options;

typedef struct sta_cloud_reader sta_cloud_reader;

/* Opens `path`, detects its format and validates its header against the file.
 * Errors name the file, the field and the values (STA_ERR_FORMAT for broken or lying
 * files, STA_ERR_UNSUPPORTED for LAZ items not decoded yet (point14, wave packets) and unknown
 * formats, STA_ERR_IO). On success *out_reader is owned by the caller (sta_cloud_close). `options`
 * may be NULL. */
sta_status sta_cloud_open(const char *path, const sta_read_options *options,
                          sta_cloud_reader **out_reader, sta_error *err);

/* As sta_cloud_open, over bytes the caller keeps alive until close (fuzzing, tests).
 * `name` is used in messages. */
sta_status sta_cloud_open_memory(const uint8_t *data, size_t size, const char *name,
                                 const sta_read_options *options, sta_cloud_reader **out_reader,
                                 sta_error *err);

/* The file's description; valid until close. */
const sta_cloud_info *sta_cloud_reader_info(const sta_cloud_reader *reader);

/* Fills `batch` (initialised with extra_size == info->extra_size) with up to its
 * capacity of the next points; batch->count == 0 at the end of the points.
 * A record that cannot be decoded is an error naming the file and the point index. */
sta_status sta_cloud_read(sta_cloud_reader *reader, sta_point_batch *batch, sta_error *err);

/* As sta_cloud_read, but only X, Y and Z of each point are set (the other fields and
 * the extra bytes are left as they were): cheaper for a pass that needs positions
 * only (the converter's count). Formats without a faster way read everything. */
sta_status sta_cloud_read_positions(sta_cloud_reader *reader, sta_point_batch *batch,
                                    sta_error *err);

/* Makes the next read start at point `index` (0 <= index <= point_count). */
sta_status sta_cloud_seek(sta_cloud_reader *reader, uint64_t index, sta_error *err);

/* Closes the reader and frees its info; NULL is a no-op. */
void sta_cloud_close(sta_cloud_reader *reader);

/* The human name of a LAS extra-bytes data type code ("uint16", "double", ...); defined
 * with the Extra Bytes decoder (las_extra.c). */
const char *sta_extra_type_name(uint8_t data_type);

#endif
