/* SPDX-License-Identifier: MIT
 * Internal to the PLY reader: the parsed header and a cursor that decodes element
 * records in ASCII or binary. Shared by the point reader (ply.c) and the mesh loader
 * (ply_mesh.c); implemented in ply_header.c.
 *
 * Design: the cursor reads straight from the borrowed bytes of a map, never past
 * `size`, and never relies on a NUL terminator. Record reads return a sta_ply_read
 * code instead of an error message, because only the caller knows the context a good
 * message needs (how many vertices were complete, whether salvage is on);
 * sta_ply_describe_read turns a code into that message's detail.
 */
#ifndef STA_IO_PLY_INTERNAL_H
#define STA_IO_PLY_INTERNAL_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "core/status.h"

typedef enum sta_ply_format {
    STA_PLY_ASCII = 1,
    STA_PLY_BINARY_LE,
    STA_PLY_BINARY_BE
} sta_ply_format;

typedef enum sta_ply_type {
    STA_PLY_INT8 = 1,
    STA_PLY_UINT8,
    STA_PLY_INT16,
    STA_PLY_UINT16,
    STA_PLY_INT32,
    STA_PLY_UINT32,
    STA_PLY_FLOAT32,
    STA_PLY_FLOAT64
} sta_ply_type;

#define STA_PLY_NAME_SIZE 128 /* longest element or property name + 1 */

typedef struct sta_ply_property {
    char name[STA_PLY_NAME_SIZE]; /* NUL-terminated */
    sta_ply_type type;            /* scalar type, or the item type of a list */
    sta_ply_type count_type;      /* list count type (an integer type); 0 for a scalar */
} sta_ply_property;

typedef struct sta_ply_element {
    char name[STA_PLY_NAME_SIZE]; /* NUL-terminated */
    uint64_t count;               /* records as declared */
    sta_ply_property *properties; /* property_count, in record order */
    size_t property_count;        /* >= 1 when count > 0 */
    size_t record_size;           /* binary bytes per record; 0 when it has a list */
    size_t min_record_size;       /* binary bytes of the smallest record (empty lists) */
} sta_ply_element;

typedef struct sta_ply_header {
    sta_ply_format format;
    sta_ply_element *elements; /* element_count, in file order */
    size_t element_count;
    size_t body_offset;  /* first byte after the end_header line */
    uint64_t line_count; /* lines in the header, end_header included */
} sta_ply_header;

/* Parses the header at the start of `data` (`size` bytes, not NUL-terminated).
 * Errors (STA_ERR_FORMAT) name `path`, the header line and what is wrong; on success
 * the caller releases *out_header. */
sta_status sta_ply_header_parse(const uint8_t *data, size_t size, const char *path,
                                sta_ply_header *out_header, sta_error *err);

/* Frees the header's arrays; a zeroed header is a no-op. */
void sta_ply_header_release(sta_ply_header *header);

/* Index of the first element called `name`, or -1. */
long sta_ply_header_find(const sta_ply_header *header, const char *name);

/* Index of the first property of `element` called `name`, or -1. */
long sta_ply_element_find(const sta_ply_element *element, const char *name);

/* Bytes of one binary value of `type` (1, 2, 4 or 8). */
size_t sta_ply_type_size(sta_ply_type type);

/* The PLY name of `type` ("uchar", "float", ...). */
const char *sta_ply_type_name(sta_ply_type type);

/* The value of `type` stored at `p` in the given byte order. */
double sta_ply_load_binary(const uint8_t *p, sta_ply_type type, bool big_endian);

/* Outcome of a record read. */
typedef enum sta_ply_read {
    STA_PLY_READ_OK = 0,
    STA_PLY_READ_END_OF_FILE,     /* the bytes end inside the record (truncation) */
    STA_PLY_READ_LIST_PAST_END,   /* binary list whose items would pass the end of the file */
    STA_PLY_READ_TOO_FEW_FIELDS,  /* ASCII: the line ends before the record does */
    STA_PLY_READ_TOO_MANY_FIELDS, /* ASCII: fields left on the line after the record */
    STA_PLY_READ_NOT_A_NUMBER,    /* ASCII: a field that does not parse */
    STA_PLY_READ_OUT_OF_RANGE,    /* ASCII: an integer field outside its type */
    STA_PLY_READ_BAD_COUNT        /* list count negative, fractional or beyond its line */
} sta_ply_read;

/* True for the codes a truncated file produces (the record is incomplete). */
bool sta_ply_read_is_truncation(sta_ply_read result);

/* A reading position in the body. Plain data: copy it to remember a position. */
typedef struct sta_ply_cursor {
    const uint8_t *data;   /* whole file, borrowed */
    size_t size;           /* bytes in data */
    sta_ply_format format; /* of the file */
    size_t pos;            /* next byte to read */
    size_t record_pos;     /* where the record being read starts (for messages) */
    uint64_t line;         /* ASCII: 1-based file line of the record being read */
    size_t line_end;       /* ASCII: end of the record's line (its '\n' or size) */
    bool line_terminated;  /* ASCII: a '\n' ends the line (false: end of file) */
    size_t token_pos;      /* ASCII: last field looked at (for messages) */
    size_t token_length;
    double bad_value; /* the value a failed read rejected (for messages) */
} sta_ply_cursor;

/* A cursor at the start of the body. */
void sta_ply_cursor_init(sta_ply_cursor *cursor, const uint8_t *data, size_t size,
                         const sta_ply_header *header);

/* Starts a record (ASCII: skips blank lines and finds the record's line). */
sta_ply_read sta_ply_record_begin(sta_ply_cursor *cursor);

/* Reads one value of `type` (ASCII: the next field of the line). */
sta_ply_read sta_ply_read_scalar(sta_ply_cursor *cursor, sta_ply_type type, double *out_value);

/* Reads the count of list property `property`; a binary count is checked against the
 * bytes left, an ASCII one against the fields left on the line. */
sta_ply_read sta_ply_read_count(sta_ply_cursor *cursor, const sta_ply_property *property,
                                uint64_t *out_count);

/* Skips `count` items of list property `property` (ASCII items are still validated). */
sta_ply_read sta_ply_skip_items(sta_ply_cursor *cursor, const sta_ply_property *property,
                                uint64_t count);

/* Ends a record (ASCII: no fields may be left on its line). */
sta_ply_read sta_ply_record_end(sta_ply_cursor *cursor);

/* Reads one whole record of `element`: scalars into values[i] (may be NULL to skip),
 * lists skipped (values[i] gets the count). On failure *out_property is the index of
 * the property being read, or property_count when the record's start or end failed. */
sta_ply_read sta_ply_read_record(sta_ply_cursor *cursor, const sta_ply_element *element,
                                 double *values, size_t *out_property);

/* Writes into `buffer` what went wrong, without the file name: which record of
 * `element` (index `record`), which property (may be NULL), the ASCII line or binary
 * byte offset, the offending field or value. */
void sta_ply_describe_read(const sta_ply_cursor *cursor, sta_ply_read result,
                           const sta_ply_element *element, uint64_t record,
                           const sta_ply_property *property, char *buffer, size_t buffer_size);

#endif
