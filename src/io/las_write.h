/* SPDX-License-Identifier: MIT
 * LAS writer: versions 1.2 and 1.4, point data record formats 0-10 (the wave packet
 * fields of formats 4, 5, 9, 10 are written as given; no waveform data is written).
 *
 * Design: the writer streams. Records are encoded into a 4 MiB buffer that is written
 * with large write() calls; nothing grows with the point count. The file is written
 * to PATH.tmp-<pid>-<n> and renamed to PATH only by a successful close, after the
 * header has been rewritten with the true point count, points by return and the
 * bounds of the written points. A failed call or sta_las_writer_abort removes the
 * temporary file, so PATH never holds a partial file.
 *
 * Records follow the reader's conventions (io/point.h), so writing then reading
 * gives back the same sta_point fields:
 * - formats 0-5: the classification byte holds classification (0..31) in bits 0-4
 *   and classification_flags bits 0-2 (synthetic, key-point, withheld) in bits 5-7;
 *   the overlap flag (bit 3) cannot be stored and is dropped. scan_angle (units of
 *   0.006 degree) is written as whole degrees, round(scan_angle * 0.006), clamped
 *   to -128..127.
 * - formats 6-10: classification is the full byte, classification_flags bits 0-3,
 *   scanner_channel 0..3, scan_angle as is.
 */
#ifndef STA_IO_LAS_WRITE_H
#define STA_IO_LAS_WRITE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "core/point.h"
#include "core/status.h"

/* One VLR (or, in LAS 1.4, EVLR) to write as given, e.g. a CRS record. */
typedef struct sta_las_vlr_record {
    const char *user_id;     /* at most 16 bytes */
    uint16_t record_id;      /* as the specification or the source numbers it */
    const char *description; /* at most 32 bytes; NULL means "" */
    const uint8_t *data;     /* size bytes, borrowed until open returns */
    uint64_t size;           /* payload bytes; <= 65535 unless extended */
    bool extended;           /* LAS 1.4: written as an EVLR after the points */
} sta_las_vlr_record;

/* How to write. Zero means default (see each field). */
typedef struct sta_las_write_options {
    int version_minor;               /* 2 or 4 (LAS 1.2 or 1.4); 0 means 4 */
    int point_format;                /* 0..3 for 1.2; 0..10 for 1.4 */
    sta_grid grid;                   /* scale > 0 and finite, offsets finite */
    const char *system_identifier;   /* at most 32 bytes; NULL means "OTHER" */
    const char *generating_software; /* at most 32 bytes; NULL means "strata" */
    const char *wkt;                 /* OGC WKT, written as the LASF_Projection/2112 VLR
                                        (1.4: global encoding bit 4 is set); NULL: none */
    bool gps_time_adjusted;          /* global encoding bit 0: adjusted standard GPS time */
    bool wkt_crs;                    /* LAS 1.4: global encoding bit 4 (the CRS is WKT),
                                        for a WKT record given in vlrs */
    uint16_t file_source_id;         /* as stored */
    uint16_t creation_day;           /* day of year 1..366, or 0 (unknown) */
    uint16_t creation_year;          /* e.g. 2024, or 0 (unknown) */
    const sta_las_vlr_record *vlrs;  /* written in order, before the WKT VLR (copied) */
    size_t vlr_count;                /* entries of vlrs */
    size_t extra_size;               /* bytes appended to every record (LAS extra bytes;
                                        describe them with a LASF_Spec/4 record in vlrs) */
} sta_las_write_options;

typedef struct sta_las_writer sta_las_writer;

/* Validates `options` (borrowed; strings are copied), creates the temporary file
 * beside `path` and writes a provisional header and the VLRs. On success *out_writer
 * is owned by the caller and must be finished with sta_las_writer_close or
 * sta_las_writer_abort. Errors: STA_ERR_ARG for bad options, STA_ERR_IO naming
 * `path` when the file cannot be created or written, STA_ERR_NOMEM. */
sta_status sta_las_writer_open(const char *path, const sta_las_write_options *options,
                               sta_las_writer **out_writer, sta_error *err);

/* Encodes and appends `count` points (borrowed). A value the point format cannot
 * hold (classification > 31 or return numbers > 7 in formats 0-5, return numbers
 * > 15, scanner_channel > 3) is STA_ERR_ARG naming the file and the point index;
 * so is exceeding 2^32 - 1 points in LAS 1.2. After a failure only
 * sta_las_writer_abort (or close, which then fails) may follow. Not thread-safe. */
sta_status sta_las_writer_write(sta_las_writer *writer, const sta_point *points, size_t count,
                                sta_error *err);

/* As sta_las_writer_write, each record followed by its extra_size bytes from `extra`
 * (count * extra_size bytes, row-wise; NULL writes zeros). */
sta_status sta_las_writer_write_extra(sta_las_writer *writer, const sta_point *points,
                                      const uint8_t *extra, size_t count, sta_error *err);

/* Points written so far. */
uint64_t sta_las_writer_point_count(const sta_las_writer *writer);

/* Flushes, rewrites the header (point counts, points by return, bounds from the
 * written points) and renames the temporary file to the path given to open. Frees
 * the writer in every case; on failure the temporary file is removed and PATH is
 * untouched. NULL is a no-op returning STA_OK. */
sta_status sta_las_writer_close(sta_las_writer *writer, sta_error *err);

/* Removes the temporary file and frees the writer; PATH is untouched. NULL: no-op. */
void sta_las_writer_abort(sta_las_writer *writer);

#endif
