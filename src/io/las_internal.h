/* SPDX-License-Identifier: MIT
 * Internal to the LAS reader (las.c, las_header.c, las_vlr.c, las_extra.c,
 * las_points.c): the reader object, the raw header fields that do not go into
 * sta_cloud_info, and the steps of opening.
 *
 * Design: opening runs the steps in order (header, VLRs, point data and EVLRs, extra
 * bytes); each checks what it reads against the map's size and what the earlier
 * steps found, and fails with a message naming the file, the field and the values.
 * After opening, every point record lies inside the map, so reading never checks a
 * bound again: it decodes with the format's decoder chosen once at open.
 */
#ifndef STA_IO_LAS_INTERNAL_H
#define STA_IO_LAS_INTERNAL_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "io/las.h"

/* Sizes fixed by the LAS specification. */
enum {
    STA_LAS_HEADER_SIZE_10 = 227,              /* LAS 1.0-1.2 public header block */
    STA_LAS_HEADER_SIZE_13 = 235,              /* LAS 1.3 (adds start of waveform data) */
    STA_LAS_HEADER_SIZE_14 = 375,              /* LAS 1.4 (EVLRs, 64-bit counts) */
    STA_LAS_VLR_HEADER_SIZE = 54,              /* VLR header before its payload */
    STA_LAS_EVLR_HEADER_SIZE = 60,             /* EVLR header (64-bit length) */
    STA_LAS_EXTRA_BYTES_DESCRIPTOR_SIZE = 192, /* one Extra Bytes VLR entry */
    STA_LAS_MAX_POINT_FORMAT = 10,
};

/* Decodes `count` records starting at `src` (`stride` bytes apart) into `dst`. */
typedef void (*sta_las_decode_fn)(const uint8_t *src, size_t stride, sta_point *dst, size_t count);

/* Header fields that steer opening but have no place in sta_cloud_info. */
typedef struct sta_las_header {
    uint32_t number_of_vlrs;         /* as stored (not trusted) */
    uint8_t point_format_byte;       /* as stored, compression bits included */
    uint64_t start_of_first_evlr;    /* LAS 1.4, else 0 */
    uint32_t number_of_evlrs;        /* LAS 1.4, else 0 */
    uint64_t start_of_waveform_data; /* LAS 1.3+, else 0 */
    bool is_compressed;              /* LAZ hook: format byte bit 7 or 6 set */
} sta_las_header;

/* The reader behind sta_cloud_ops. */
typedef struct sta_las_reader {
    sta_cloud_info info;       /* what the file declares; vlrs/extra_dims owned */
    const sta_file_map *map;   /* borrowed; outlives the reader */
    const uint8_t *point_data; /* first record in the map */
    size_t record_length;      /* bytes per record (format size + extra) */
    size_t format_size;        /* bytes of the format's own fields */
    uint64_t next_index;       /* next point to read, <= info.point_count */
    sta_las_decode_fn decode;  /* decoder of info.point_format */
    char *wkt;                 /* owned copy behind info.crs_wkt, or NULL */
    struct sta_laz *laz;       /* LAZ hook: decoder of compressed points, or NULL */
    uint8_t *laz_records;      /* LAZ hook: raw records of one decoding step, owned */
} sta_las_reader;

/* Parses and checks the public header block (version, sizes, format, scale, offset,
 * counts) into reader->info and *out_header. LAZ gives STA_ERR_UNSUPPORTED. */
sta_status sta_las_parse_header(sta_las_reader *reader, sta_las_header *out_header, sta_error *err);

/* Walks the VLRs between the header and the point data into info.vlrs. Refuses a
 * LASzip VLR (STA_ERR_UNSUPPORTED). A VLR count or length that overshoots
 * offset_to_point_data is an error; with options->salvage_truncated the whole VLRs
 * before it are kept with a warning (the points start at offset_to_point_data). */
sta_status sta_las_read_vlrs(sta_las_reader *reader, const sta_las_header *header,
                             const sta_read_options *options, sta_error *err);

/* Walks the EVLRs (LAS 1.4) or the waveform data packet record (LAS 1.3), which must
 * start at or after `point_data_end`, appending them to info.vlrs. When salvaging a
 * truncated file, records past the end of the file are dropped with a warning. */
sta_status sta_las_read_evlrs(sta_las_reader *reader, const sta_las_header *header,
                              uint64_t point_data_end, const sta_read_options *options,
                              sta_error *err);

/* Finds the WKT and GeoTIFF records among info.vlrs (copies the WKT). */
sta_status sta_las_read_crs(sta_las_reader *reader, sta_error *err);

/* Decodes the Extra Bytes VLR into info.extra_dims and describes undeclared trailing
 * bytes. Descriptors that do not fit the records are dropped with a warning. */
sta_status sta_las_read_extra_bytes(sta_las_reader *reader, sta_error *err);

/* The decoder of `point_format` (0..10). */
sta_las_decode_fn sta_las_decoder(int point_format);

/* The sta_attr bits that `point_format` (0..10) carries. */
uint32_t sta_las_format_attributes(int point_format);

/* Copies at most `size` bytes of a fixed-width, possibly unterminated text field
 * into `out` (capacity size + 1), without trailing spaces, and NUL-terminates it. */
void sta_las_copy_text(char *out, const uint8_t *field, size_t size);

enum {
    /* Capacity for sta_las_printable of a text field of up to 32 bytes. */
    STA_LAS_PRINTABLE_SIZE = 4 * 32 + 1,
};

/* Writes `text` (a field copied from a file) into `out` (capacity
 * STA_LAS_PRINTABLE_SIZE) for messages: printable ASCII as is, every other byte and
 * the backslash as \xNN. Returns `out`. */
const char *sta_las_printable(char *out, const char *text);

/* ---- LAZ hook (laz_reader.c) ---- */

/* For a compressed file (header->is_compressed): parses the LASzip VLR among
 * info.vlrs, sets point_count and opens the decoder (reader->laz). */
sta_status sta_las_open_laz(sta_las_reader *reader, const sta_las_header *header,
                            const sta_read_options *options, sta_error *err);

/* las_read for LAZ: decodes the next records and converts them with reader->decode. */
sta_status sta_las_read_laz(sta_las_reader *reader, sta_point_batch *batch, sta_error *err);

/* Frees reader->laz and its buffer (no-op when not LAZ). */
void sta_las_close_laz(sta_las_reader *reader);

#endif
