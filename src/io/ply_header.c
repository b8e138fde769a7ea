/* SPDX-License-Identifier: MIT
 * PLY 1.0 syntax: the header (elements and their properties) and a cursor that
 * decodes element records in ASCII, binary little endian and binary big endian.
 *
 * Design: everything is read from borrowed, bounds-checked bytes that need no NUL
 * terminator. Header lines end with LF or CRLF. ASCII records are one per line, fields
 * separated by blanks; a field is copied to a small buffer before strtod so parsing
 * never runs past the line. Binary values are loaded through memcpy helpers.
 */
#include "io/ply_internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/alloc.h"
#include "core/array.h"
#include "core/bytes.h"

#define MAX_HEADER_TOKENS 8
#define MAX_FIELD_LENGTH  127 // longest ASCII number we parse

typedef struct token {
    const uint8_t *text;
    size_t length;
} token;

static const struct {
    const char *name;
    sta_ply_type type;
} type_names[] = {
    { "char", STA_PLY_INT8 },       { "int8", STA_PLY_INT8 },       { "uchar", STA_PLY_UINT8 },
    { "uint8", STA_PLY_UINT8 },     { "short", STA_PLY_INT16 },     { "int16", STA_PLY_INT16 },
    { "ushort", STA_PLY_UINT16 },   { "uint16", STA_PLY_UINT16 },   { "int", STA_PLY_INT32 },
    { "int32", STA_PLY_INT32 },     { "uint", STA_PLY_UINT32 },     { "uint32", STA_PLY_UINT32 },
    { "float", STA_PLY_FLOAT32 },   { "float32", STA_PLY_FLOAT32 }, { "double", STA_PLY_FLOAT64 },
    { "float64", STA_PLY_FLOAT64 },
};

size_t sta_ply_type_size(sta_ply_type type)
{
    switch (type) {
    case STA_PLY_INT8:
    case STA_PLY_UINT8:
        return 1;
    case STA_PLY_INT16:
    case STA_PLY_UINT16:
        return 2;
    case STA_PLY_INT32:
    case STA_PLY_UINT32:
    case STA_PLY_FLOAT32:
        return 4;
    case STA_PLY_FLOAT64:
        return 8;
    }
    return 1;
}

const char *sta_ply_type_name(sta_ply_type type)
{
    static const char *const names[] = { "?",   "char", "uchar", "short", "ushort",
                                         "int", "uint", "float", "double" };
    return (unsigned)type < sizeof(names) / sizeof(names[0]) ? names[type] : "?";
}

static bool is_float_type(sta_ply_type type)
{
    return type == STA_PLY_FLOAT32 || type == STA_PLY_FLOAT64;
}

static bool is_blank(uint8_t ch)
{
    return ch == ' ' || ch == '\t' || ch == '\r';
}

// Splits a line into blank-separated tokens; returns how many there are (only the
// first `max` are stored).
static size_t split_tokens(const uint8_t *line, size_t length, token *out, size_t max)
{
    size_t count = 0;
    size_t i = 0;
    while (i < length) {
        while (i < length && is_blank(line[i])) {
            i++;
        }
        if (i == length) {
            break;
        }
        size_t start = i;
        while (i < length && !is_blank(line[i])) {
            i++;
        }
        if (count < max) {
            out[count].text = line + start;
            out[count].length = i - start;
        }
        count++;
    }
    return count;
}

static bool token_is(token t, const char *word)
{
    size_t n = strlen(word);
    return t.length == n && memcmp(t.text, word, n) == 0;
}

// Copies up to 40 bytes of `text` into `out` for a message, printable ASCII only.
static void quote_bytes(const uint8_t *text, size_t length, char *out, size_t out_size)
{
    size_t limit = length > 40 ? 40 : length;
    size_t n = 0;
    for (size_t i = 0; i < limit && n + 4 < out_size; i++) {
        uint8_t ch = text[i];
        out[n++] = (ch >= 0x20 && ch < 0x7f) ? (char)ch : '?';
    }
    if (limit < length && n + 4 < out_size) {
        memcpy(out + n, "...", 3);
        n += 3;
    }
    out[n] = '\0';
}

static bool parse_type(token t, sta_ply_type *out)
{
    for (size_t i = 0; i < sizeof(type_names) / sizeof(type_names[0]); i++) {
        if (token_is(t, type_names[i].name)) {
            *out = type_names[i].type;
            return true;
        }
    }
    return false;
}

static bool parse_count(token t, uint64_t *out)
{
    if (t.length == 0) {
        return false;
    }
    uint64_t value = 0;
    for (size_t i = 0; i < t.length; i++) {
        uint8_t ch = t.text[i];
        if (ch < '0' || ch > '9') {
            return false;
        }
        unsigned digit = (unsigned)(ch - '0');
        if (value > (UINT64_MAX - digit) / 10) {
            return false;
        }
        value = value * 10 + digit;
    }
    *out = value;
    return true;
}

static bool copy_name(token t, char *out)
{
    if (t.length >= STA_PLY_NAME_SIZE) {
        return false;
    }
    memcpy(out, t.text, t.length);
    out[t.length] = '\0';
    return true;
}

void sta_ply_header_release(sta_ply_header *header)
{
    for (size_t i = 0; i < header->element_count; i++) {
        sta_free(header->elements[i].properties);
    }
    sta_free(header->elements);
    memset(header, 0, sizeof(*header));
}

long sta_ply_header_find(const sta_ply_header *header, const char *name)
{
    for (size_t i = 0; i < header->element_count; i++) {
        if (strcmp(header->elements[i].name, name) == 0) {
            return (long)i;
        }
    }
    return -1;
}

long sta_ply_element_find(const sta_ply_element *element, const char *name)
{
    for (size_t i = 0; i < element->property_count; i++) {
        if (strcmp(element->properties[i].name, name) == 0) {
            return (long)i;
        }
    }
    return -1;
}

// Parser state for one header.
typedef struct header_parser {
    const char *path;
    uint64_t line;
    size_t element_capacity;
    size_t property_capacity; // of the last element
    bool has_format;
} header_parser;

static sta_status add_element(header_parser *hp, sta_ply_header *h, const token *t, size_t n,
                              sta_error *err)
{
    char text[64];
    uint64_t count = 0;
    if (n != 3) {
        return sta_fail(err, STA_ERR_FORMAT,
                        "%s: header line %llu: expected \"element NAME COUNT\", found %zu words",
                        hp->path, (unsigned long long)hp->line, n);
    }
    if (!parse_count(t[2], &count)) {
        quote_bytes(t[2].text, t[2].length, text, sizeof(text));
        return sta_fail(err, STA_ERR_FORMAT,
                        "%s: header line %llu: element count \"%s\" is not a non-negative "
                        "integer",
                        hp->path, (unsigned long long)hp->line, text);
    }
    if (sta_array_reserve((void **)&h->elements, &hp->element_capacity, h->element_count + 1,
                          sizeof(*h->elements), 4, NULL) != STA_OK) {
        return sta_fail(err, STA_ERR_NOMEM, "%s: out of memory for the PLY header", hp->path);
    }
    sta_ply_element *e = &h->elements[h->element_count];
    memset(e, 0, sizeof(*e));
    if (!copy_name(t[1], e->name)) {
        return sta_fail(err, STA_ERR_FORMAT, "%s: header line %llu: element name too long",
                        hp->path, (unsigned long long)hp->line);
    }
    e->count = count;
    h->element_count++;
    hp->property_capacity = 0;
    return STA_OK;
}

static sta_status add_property(header_parser *hp, sta_ply_header *h, const token *t, size_t n,
                               sta_error *err)
{
    char text[64];
    if (h->element_count == 0) {
        return sta_fail(err, STA_ERR_FORMAT, "%s: header line %llu: property before any element",
                        hp->path, (unsigned long long)hp->line);
    }
    sta_ply_element *e = &h->elements[h->element_count - 1];
    sta_ply_property p = { 0 };
    bool is_list = n >= 2 && token_is(t[1], "list");
    if ((is_list && n != 5) || (!is_list && n != 3)) {
        return sta_fail(err, STA_ERR_FORMAT,
                        "%s: header line %llu: expected \"property TYPE NAME\" or \"property "
                        "list COUNT_TYPE ITEM_TYPE NAME\", found %zu words",
                        hp->path, (unsigned long long)hp->line, n);
    }
    size_t type_at = is_list ? 3 : 1;
    if (is_list) {
        if (!parse_type(t[2], &p.count_type) || is_float_type(p.count_type)) {
            quote_bytes(t[2].text, t[2].length, text, sizeof(text));
            return sta_fail(err, STA_ERR_FORMAT,
                            "%s: header line %llu: list count type \"%s\" is not an integer "
                            "type",
                            hp->path, (unsigned long long)hp->line, text);
        }
    }
    if (!parse_type(t[type_at], &p.type)) {
        quote_bytes(t[type_at].text, t[type_at].length, text, sizeof(text));
        return sta_fail(err, STA_ERR_FORMAT, "%s: header line %llu: unknown property type \"%s\"",
                        hp->path, (unsigned long long)hp->line, text);
    }
    if (!copy_name(t[n - 1], p.name)) {
        return sta_fail(err, STA_ERR_FORMAT, "%s: header line %llu: property name too long",
                        hp->path, (unsigned long long)hp->line);
    }
    if (sta_array_reserve((void **)&e->properties, &hp->property_capacity, e->property_count + 1,
                          sizeof(*e->properties), 8, NULL) != STA_OK) {
        return sta_fail(err, STA_ERR_NOMEM, "%s: out of memory for the PLY header", hp->path);
    }
    e->properties[e->property_count++] = p;
    return STA_OK;
}

static sta_status set_format(header_parser *hp, sta_ply_header *h, const token *t, size_t n,
                             sta_error *err)
{
    char text[64];
    if (hp->has_format) {
        return sta_fail(err, STA_ERR_FORMAT, "%s: header line %llu: second format line", hp->path,
                        (unsigned long long)hp->line);
    }
    if (n != 3) {
        return sta_fail(err, STA_ERR_FORMAT,
                        "%s: header line %llu: expected \"format TYPE 1.0\", found %zu words",
                        hp->path, (unsigned long long)hp->line, n);
    }
    if (token_is(t[1], "ascii")) {
        h->format = STA_PLY_ASCII;
    } else if (token_is(t[1], "binary_little_endian")) {
        h->format = STA_PLY_BINARY_LE;
    } else if (token_is(t[1], "binary_big_endian")) {
        h->format = STA_PLY_BINARY_BE;
    } else {
        quote_bytes(t[1].text, t[1].length, text, sizeof(text));
        return sta_fail(err, STA_ERR_FORMAT,
                        "%s: header line %llu: unknown format \"%s\" (expected ascii, "
                        "binary_little_endian or binary_big_endian)",
                        hp->path, (unsigned long long)hp->line, text);
    }
    if (!token_is(t[2], "1.0") && !token_is(t[2], "1")) {
        quote_bytes(t[2].text, t[2].length, text, sizeof(text));
        return sta_fail(err, STA_ERR_FORMAT,
                        "%s: header line %llu: unknown PLY version \"%s\" (expected 1.0)", hp->path,
                        (unsigned long long)hp->line, text);
    }
    hp->has_format = true;
    return STA_OK;
}

// Checks each element and computes its binary record sizes.
static sta_status finish_elements(const header_parser *hp, sta_ply_header *h, sta_error *err)
{
    for (size_t i = 0; i < h->element_count; i++) {
        sta_ply_element *e = &h->elements[i];
        if (e->count > 0 && e->property_count == 0) {
            return sta_fail(err, STA_ERR_FORMAT,
                            "%s: element \"%s\" declares %llu records but no properties", hp->path,
                            e->name, (unsigned long long)e->count);
        }
        size_t fixed = 0;
        bool has_list = false;
        for (size_t j = 0; j < e->property_count; j++) {
            const sta_ply_property *p = &e->properties[j];
            if (p->count_type) {
                has_list = true;
                fixed += sta_ply_type_size(p->count_type);
            } else {
                fixed += sta_ply_type_size(p->type);
            }
        }
        e->min_record_size = fixed;
        e->record_size = has_list ? 0 : fixed;
    }
    return STA_OK;
}

sta_status sta_ply_header_parse(const uint8_t *data, size_t size, const char *path,
                                sta_ply_header *out_header, sta_error *err)
{
    sta_ply_header h = { 0 };
    header_parser hp = { .path = path };
    sta_status status = STA_OK;
    bool ended = false;
    size_t pos = 0;
    memset(out_header, 0, sizeof(*out_header));
    while (pos < size && !ended) {
        const uint8_t *line = data + pos;
        const uint8_t *newline = memchr(line, '\n', size - pos);
        size_t length = newline ? (size_t)(newline - line) : size - pos;
        pos += length + (newline ? 1 : 0);
        hp.line++;
        token t[MAX_HEADER_TOKENS];
        size_t n = split_tokens(line, length, t, MAX_HEADER_TOKENS);
        if (hp.line == 1) {
            if (n != 1 || !token_is(t[0], "ply")) {
                status = sta_fail(err, STA_ERR_FORMAT,
                                  "%s: not a PLY file (the first line is not \"ply\")", path);
                goto out_fail;
            }
            continue;
        }
        if (n == 0 || token_is(t[0], "comment") || token_is(t[0], "obj_info")) {
            continue;
        }
        if (token_is(t[0], "format")) {
            status = set_format(&hp, &h, t, n, err);
        } else if (token_is(t[0], "element")) {
            status = add_element(&hp, &h, t, n, err);
        } else if (token_is(t[0], "property")) {
            status = add_property(&hp, &h, t, n, err);
        } else if (token_is(t[0], "end_header") && n == 1) {
            ended = true;
        } else {
            char text[64];
            quote_bytes(t[0].text, t[0].length, text, sizeof(text));
            status = sta_fail(err, STA_ERR_FORMAT,
                              "%s: header line %llu: unknown keyword \"%s\" (expected "
                              "format, comment, obj_info, element, property or end_header)",
                              path, (unsigned long long)hp.line, text);
        }
        if (status != STA_OK) {
            goto out_fail;
        }
    }
    if (!ended) {
        status =
            sta_fail(err, STA_ERR_FORMAT, "%s: PLY header has no end_header line (%llu lines read)",
                     path, (unsigned long long)hp.line);
        goto out_fail;
    }
    if (!hp.has_format) {
        status = sta_fail(err, STA_ERR_FORMAT, "%s: PLY header has no format line", path);
        goto out_fail;
    }
    status = finish_elements(&hp, &h, err);
    if (status != STA_OK) {
        goto out_fail;
    }
    h.body_offset = pos;
    h.line_count = hp.line;
    *out_header = h;
    return STA_OK;
out_fail:
    sta_ply_header_release(&h);
    return status;
}

/* ---- records ---------------------------------------------------------------------- */

bool sta_ply_read_is_truncation(sta_ply_read result)
{
    return result == STA_PLY_READ_END_OF_FILE || result == STA_PLY_READ_LIST_PAST_END;
}

void sta_ply_cursor_init(sta_ply_cursor *cursor, const uint8_t *data, size_t size,
                         const sta_ply_header *header)
{
    memset(cursor, 0, sizeof(*cursor));
    cursor->data = data;
    cursor->size = size;
    cursor->format = header->format;
    cursor->pos = header->body_offset;
    cursor->line = header->line_count + 1;
}

static float load_f32be(const uint8_t *p)
{
    uint32_t bits = sta_load_u32be(p);
    float value;
    memcpy(&value, &bits, sizeof(value));
    return value;
}

static double load_f64be(const uint8_t *p)
{
    uint64_t bits = sta_load_u64be(p);
    double value;
    memcpy(&value, &bits, sizeof(value));
    return value;
}

double sta_ply_load_binary(const uint8_t *p, sta_ply_type type, bool big_endian)
{
    switch (type) {
    case STA_PLY_INT8:
        return (double)(int8_t)p[0];
    case STA_PLY_UINT8:
        return (double)p[0];
    case STA_PLY_INT16:
        return (double)(int16_t)(big_endian ? sta_load_u16be(p) : sta_load_u16le(p));
    case STA_PLY_UINT16:
        return (double)(big_endian ? sta_load_u16be(p) : sta_load_u16le(p));
    case STA_PLY_INT32:
        return (double)(int32_t)(big_endian ? sta_load_u32be(p) : sta_load_u32le(p));
    case STA_PLY_UINT32:
        return (double)(big_endian ? sta_load_u32be(p) : sta_load_u32le(p));
    case STA_PLY_FLOAT32:
        return (double)(big_endian ? load_f32be(p) : sta_load_f32le(p));
    case STA_PLY_FLOAT64:
        return big_endian ? load_f64be(p) : sta_load_f64le(p);
    }
    return 0.0;
}

static bool integer_fits(double value, sta_ply_type type)
{
    double lo = 0.0;
    double hi = 0.0;
    switch (type) {
    case STA_PLY_INT8:
        lo = -128.0;
        hi = 127.0;
        break;
    case STA_PLY_UINT8:
        hi = 255.0;
        break;
    case STA_PLY_INT16:
        lo = -32768.0;
        hi = 32767.0;
        break;
    case STA_PLY_UINT16:
        hi = 65535.0;
        break;
    case STA_PLY_INT32:
        lo = -2147483648.0;
        hi = 2147483647.0;
        break;
    case STA_PLY_UINT32:
        hi = 4294967295.0;
        break;
    case STA_PLY_FLOAT32:
    case STA_PLY_FLOAT64:
        return true;
    }
    if (!(value >= lo && value <= hi)) { // also false for NaN
        return false;
    }
    return (double)(int64_t)value == value; // whole: exact in int64 within the range
}

// ASCII: moves to the next field of the current line.
static sta_ply_read next_field(sta_ply_cursor *c)
{
    while (c->pos < c->line_end && is_blank(c->data[c->pos])) {
        c->pos++;
    }
    if (c->pos >= c->line_end) {
        return c->line_terminated ? STA_PLY_READ_TOO_FEW_FIELDS : STA_PLY_READ_END_OF_FILE;
    }
    c->token_pos = c->pos;
    while (c->pos < c->line_end && !is_blank(c->data[c->pos])) {
        c->pos++;
    }
    c->token_length = c->pos - c->token_pos;
    return STA_PLY_READ_OK;
}

// Decimal fields of at most 19 significant digits and a small exponent, parsed
// exactly: an integer mantissa below 2^53 and a power of ten up to 1e22 are both exact
// doubles, so one multiplication or division rounds correctly (Clinger's fast path).
// Returns false for anything else, which then goes to strtod.
static bool parse_simple_decimal(const uint8_t *s, size_t n, double *out)
{
    static const double powers[] = { 1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                                     1e8,  1e9,  1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
                                     1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22 };
    size_t i = 0;
    bool negative = false;
    uint64_t mantissa = 0;
    int digits = 0; // significant digits in mantissa
    int exponent = 0;
    bool any_digit = false;
    if (i < n && (s[i] == '-' || s[i] == '+')) {
        negative = s[i] == '-';
        i++;
    }
    for (int part = 0; part < 2; part++) { // integer part, then fraction
        for (; i < n && s[i] >= '0' && s[i] <= '9'; i++) {
            if (digits >= 19) {
                return false;
            }
            mantissa = mantissa * 10 + (uint64_t)(s[i] - '0');
            digits += mantissa != 0;
            exponent -= part;
            any_digit = true;
        }
        if (part == 0) {
            if (i < n && s[i] == '.') {
                i++;
            } else {
                break;
            }
        }
    }
    if (!any_digit) {
        return false;
    }
    if (i < n && (s[i] == 'e' || s[i] == 'E')) {
        i++;
        int sign = 1;
        int value = 0;
        if (i < n && (s[i] == '-' || s[i] == '+')) {
            sign = s[i] == '-' ? -1 : 1;
            i++;
        }
        size_t first_digit = i;
        for (; i < n && s[i] >= '0' && s[i] <= '9'; i++) {
            if (value > 1000) {
                return false;
            }
            value = value * 10 + (s[i] - '0');
        }
        if (i == first_digit) {
            return false;
        }
        exponent += sign * value;
    }
    if (i != n || mantissa > (1ull << 53) || exponent < -22 || exponent > 22) {
        return false;
    }
    double value = (double)mantissa;
    value = exponent < 0 ? value / powers[-exponent] : value * powers[exponent];
    *out = negative ? -value : value;
    return true;
}

// ASCII: parses the field just found; a field cut by the end of the file is truncation.
static sta_ply_read parse_field(sta_ply_cursor *c, double *out)
{
    char text[MAX_FIELD_LENGTH + 1];
    bool at_end = !c->line_terminated && c->token_pos + c->token_length == c->size;
    if (parse_simple_decimal(c->data + c->token_pos, c->token_length, out)) {
        return STA_PLY_READ_OK;
    }
    if (c->token_length <= MAX_FIELD_LENGTH) {
        memcpy(text, c->data + c->token_pos, c->token_length);
        text[c->token_length] = '\0';
        char *end = NULL;
        double value = strtod(text, &end);
        if (end == text + c->token_length) {
            *out = value;
            return STA_PLY_READ_OK;
        }
    }
    return at_end ? STA_PLY_READ_END_OF_FILE : STA_PLY_READ_NOT_A_NUMBER;
}

sta_ply_read sta_ply_record_begin(sta_ply_cursor *c)
{
    c->record_pos = c->pos;
    if (c->format != STA_PLY_ASCII) {
        return STA_PLY_READ_OK;
    }
    for (;;) {
        if (c->pos >= c->size) {
            return STA_PLY_READ_END_OF_FILE;
        }
        const uint8_t *newline = memchr(c->data + c->pos, '\n', c->size - c->pos);
        size_t end = newline ? (size_t)(newline - c->data) : c->size;
        size_t p = c->pos;
        while (p < end && is_blank(c->data[p])) {
            p++;
        }
        if (p < end) {
            c->pos = p;
            c->line_end = end;
            c->line_terminated = newline != NULL;
            return STA_PLY_READ_OK;
        }
        // A blank line between records is tolerated.
        if (!newline) {
            c->pos = c->size;
            return STA_PLY_READ_END_OF_FILE;
        }
        c->pos = end + 1;
        c->line++;
    }
}

sta_ply_read sta_ply_read_scalar(sta_ply_cursor *c, sta_ply_type type, double *out_value)
{
    if (c->format != STA_PLY_ASCII) {
        size_t bytes = sta_ply_type_size(type);
        if (c->size - c->pos < bytes) {
            return STA_PLY_READ_END_OF_FILE;
        }
        *out_value = sta_ply_load_binary(c->data + c->pos, type, c->format == STA_PLY_BINARY_BE);
        c->pos += bytes;
        return STA_PLY_READ_OK;
    }
    sta_ply_read r = next_field(c);
    if (r != STA_PLY_READ_OK) {
        return r;
    }
    double value = 0.0;
    r = parse_field(c, &value);
    if (r != STA_PLY_READ_OK) {
        return r;
    }
    if (!is_float_type(type) && !integer_fits(value, type)) {
        c->bad_value = value;
        return STA_PLY_READ_OUT_OF_RANGE;
    }
    *out_value = value;
    return STA_PLY_READ_OK;
}

sta_ply_read sta_ply_read_count(sta_ply_cursor *c, const sta_ply_property *property,
                                uint64_t *out_count)
{
    double value = 0.0;
    sta_ply_read r = sta_ply_read_scalar(c, property->count_type, &value);
    if (r == STA_PLY_READ_OUT_OF_RANGE) {
        return STA_PLY_READ_BAD_COUNT; // bad_value holds it; the message says why
    }
    if (r != STA_PLY_READ_OK) {
        return r;
    }
    if (value < 0.0) {
        c->bad_value = value;
        return STA_PLY_READ_BAD_COUNT;
    }
    uint64_t count = (uint64_t)value; // integral and <= UINT32_MAX: checked by type
    size_t item_size = sta_ply_type_size(property->type);
    if (c->format != STA_PLY_ASCII) {
        if (count > (c->size - c->pos) / item_size) {
            c->bad_value = value;
            return STA_PLY_READ_LIST_PAST_END;
        }
    } else if (count > (c->line_end - c->pos + 1) / 2) {
        // Each item needs a blank and at least one character.
        c->bad_value = value;
        return c->line_terminated ? STA_PLY_READ_BAD_COUNT : STA_PLY_READ_END_OF_FILE;
    }
    *out_count = count;
    return STA_PLY_READ_OK;
}

sta_ply_read sta_ply_skip_items(sta_ply_cursor *c, const sta_ply_property *property, uint64_t count)
{
    if (c->format != STA_PLY_ASCII) {
        // sta_ply_read_count checked that the items fit in the bytes left.
        c->pos += (size_t)count * sta_ply_type_size(property->type);
        return STA_PLY_READ_OK;
    }
    for (uint64_t i = 0; i < count; i++) {
        double value;
        sta_ply_read r = sta_ply_read_scalar(c, property->type, &value);
        if (r != STA_PLY_READ_OK) {
            return r;
        }
    }
    return STA_PLY_READ_OK;
}

sta_ply_read sta_ply_record_end(sta_ply_cursor *c)
{
    if (c->format != STA_PLY_ASCII) {
        return STA_PLY_READ_OK;
    }
    while (c->pos < c->line_end && is_blank(c->data[c->pos])) {
        c->pos++;
    }
    if (c->pos < c->line_end) {
        sta_ply_read r = next_field(c);
        (void)r; // records the extra field for the message
        return STA_PLY_READ_TOO_MANY_FIELDS;
    }
    c->pos = c->line_terminated ? c->line_end + 1 : c->line_end;
    c->line++;
    return STA_PLY_READ_OK;
}

sta_ply_read sta_ply_read_record(sta_ply_cursor *c, const sta_ply_element *element, double *values,
                                 size_t *out_property)
{
    *out_property = element->property_count;
    c->record_pos = c->pos;
    if (c->format != STA_PLY_ASCII && element->record_size > 0) {
        // Fixed-size binary record: one bounds check for all of it.
        if (c->size - c->pos < element->record_size) {
            return STA_PLY_READ_END_OF_FILE;
        }
        if (!values) {
            c->pos += element->record_size;
            return STA_PLY_READ_OK;
        }
    }
    sta_ply_read r = sta_ply_record_begin(c);
    if (r != STA_PLY_READ_OK) {
        return r;
    }
    for (size_t i = 0; i < element->property_count; i++) {
        const sta_ply_property *p = &element->properties[i];
        double value = 0.0;
        *out_property = i;
        if (p->count_type) {
            uint64_t count = 0;
            r = sta_ply_read_count(c, p, &count);
            if (r == STA_PLY_READ_OK) {
                r = sta_ply_skip_items(c, p, count);
            }
            value = (double)count;
        } else {
            r = sta_ply_read_scalar(c, p->type, &value);
        }
        if (r != STA_PLY_READ_OK) {
            return r;
        }
        if (values) {
            values[i] = value;
        }
    }
    *out_property = element->property_count;
    return sta_ply_record_end(c);
}

void sta_ply_describe_read(const sta_ply_cursor *c, sta_ply_read result,
                           const sta_ply_element *element, uint64_t record,
                           const sta_ply_property *property, char *buffer, size_t buffer_size)
{
    char where[200];
    char field[64];
    const char *name = property ? property->name : "";
    unsigned long long index = (unsigned long long)record;
    if (c->format == STA_PLY_ASCII) {
        snprintf(where, sizeof(where), "line %llu (%s %llu)", (unsigned long long)c->line,
                 element->name, index);
    } else {
        snprintf(where, sizeof(where), "%s %llu at byte %zu", element->name, index, c->record_pos);
    }
    quote_bytes(c->data ? c->data + c->token_pos : NULL, c->data ? c->token_length : 0, field,
                sizeof(field));
    switch (result) {
    case STA_PLY_READ_OK:
        snprintf(buffer, buffer_size, "%s: no error", where);
        break;
    case STA_PLY_READ_END_OF_FILE:
        snprintf(buffer, buffer_size, "%s is cut off by the end of the file%s%s%s", where,
                 property ? " in property \"" : "", name, property ? "\"" : "");
        break;
    case STA_PLY_READ_LIST_PAST_END:
        snprintf(buffer, buffer_size,
                 "%s: list \"%s\" has count %.15g, more %s items than the %zu bytes left in "
                 "the file hold",
                 where, name, c->bad_value, sta_ply_type_name(property->type), c->size - c->pos);
        break;
    case STA_PLY_READ_TOO_FEW_FIELDS:
        snprintf(buffer, buffer_size, "%s: too few fields, property \"%s\" is missing", where,
                 name);
        break;
    case STA_PLY_READ_TOO_MANY_FIELDS:
        snprintf(buffer, buffer_size,
                 "%s: more fields than the %zu properties of element \"%s\" (extra field "
                 "\"%s\")",
                 where, element->property_count, element->name, field);
        break;
    case STA_PLY_READ_NOT_A_NUMBER:
        snprintf(buffer, buffer_size, "%s: property \"%s\": field \"%s\" is not a number", where,
                 name, field);
        break;
    case STA_PLY_READ_OUT_OF_RANGE:
        snprintf(buffer, buffer_size, "%s: property \"%s\": value %.15g is not a %s", where, name,
                 c->bad_value, property ? sta_ply_type_name(property->type) : "?");
        break;
    case STA_PLY_READ_BAD_COUNT: {
        double v = c->bad_value;
        sta_ply_type count_type = property ? property->count_type : STA_PLY_UINT32;
        char why[64];
        if (!(v >= 0.0)) {
            snprintf(why, sizeof(why), "negative");
        } else if (v != floor(v)) {
            snprintf(why, sizeof(why), "not a whole number");
        } else if (!integer_fits(v, count_type)) {
            snprintf(why, sizeof(why), "too large for a %s", sta_ply_type_name(count_type));
        } else {
            snprintf(why, sizeof(why), "larger than the fields left on the line");
        }
        snprintf(buffer, buffer_size, "%s: list \"%s\": count %.15g is %s", where, name, v, why);
        break;
    }
    }
}
