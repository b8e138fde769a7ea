/* SPDX-License-Identifier: MIT
 * A small streaming JSON writer. */
#include "core/json_out.h"

#include <inttypes.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

void sta_json_init(sta_json_out *json, FILE *file, bool pretty)
{
    memset(json, 0, sizeof(*json));
    json->file = file;
    json->pretty = pretty;
}

static void indent(sta_json_out *json)
{
    fputc('\n', json->file);
    for (int i = 0; i < json->depth; i++) {
        fputs("  ", json->file);
    }
}

// Emits the separator that must precede a new value or key at the current level.
static void before_value(sta_json_out *json)
{
    if (json->after_key) {
        json->after_key = false;
        return;
    }
    if (json->depth > 0) {
        if (json->needs_comma[json->depth]) {
            fputc(',', json->file);
        }
        json->needs_comma[json->depth] = true;
        if (json->pretty) {
            indent(json);
        }
    }
}

static void open_level(sta_json_out *json, char bracket)
{
    before_value(json);
    fputc(bracket, json->file);
    if (json->depth + 1 < STA_JSON_MAX_DEPTH) {
        json->depth++;
        json->needs_comma[json->depth] = false;
    }
}

static void close_level(sta_json_out *json, char bracket)
{
    bool had_elements = json->needs_comma[json->depth];
    if (json->depth > 0) {
        json->depth--;
    }
    if (json->pretty && had_elements) {
        indent(json);
    }
    fputc(bracket, json->file);
}

void sta_json_begin_object(sta_json_out *json)
{
    open_level(json, '{');
}

void sta_json_end_object(sta_json_out *json)
{
    close_level(json, '}');
}

void sta_json_begin_array(sta_json_out *json)
{
    open_level(json, '[');
}

void sta_json_end_array(sta_json_out *json)
{
    close_level(json, ']');
}

static void write_escaped(FILE *file, const char *text, size_t size)
{
    fputc('"', file);
    for (size_t i = 0; i < size; i++) {
        unsigned char c = (unsigned char)text[i];
        switch (c) {
        case '"':
            fputs("\\\"", file);
            break;
        case '\\':
            fputs("\\\\", file);
            break;
        case '\n':
            fputs("\\n", file);
            break;
        case '\r':
            fputs("\\r", file);
            break;
        case '\t':
            fputs("\\t", file);
            break;
        default:
            if (c < 0x20 || c == 0x7f) {
                fprintf(file, "\\u%04x", c);
            } else {
                fputc(c, file);
            }
        }
    }
    fputc('"', file);
}

void sta_json_key(sta_json_out *json, const char *key)
{
    before_value(json);
    write_escaped(json->file, key, strlen(key));
    fputs(json->pretty ? ": " : ":", json->file);
    json->after_key = true;
}

void sta_json_string(sta_json_out *json, const char *text)
{
    sta_json_string_n(json, text, strlen(text));
}

void sta_json_string_n(sta_json_out *json, const char *text, size_t size)
{
    before_value(json);
    write_escaped(json->file, text, size);
}

const char *sta_format_double(double value, char *buffer, size_t size)
{
    if (!isfinite(value)) {
        snprintf(buffer, size, "%s", isnan(value) ? "nan" : (value > 0 ? "inf" : "-inf"));
        return buffer;
    }
    // Plain decimals for ordinary magnitudes (coordinates read best that way),
    // exponent form for the very large and very small.
    double magnitude = fabs(value);
    if (magnitude == 0.0 || (magnitude >= 1e-5 && magnitude < 1e16)) {
        for (int decimals = 0; decimals <= 24; decimals++) {
            snprintf(buffer, size, "%.*f", decimals, value);
            if (strtod(buffer, NULL) == value) {
                return buffer;
            }
        }
    }
    for (int digits = 1; digits <= 17; digits++) {
        snprintf(buffer, size, "%.*g", digits, value);
        if (strtod(buffer, NULL) == value) {
            break;
        }
    }
    return buffer;
}

void sta_json_double(sta_json_out *json, double value)
{
    before_value(json);
    if (!isfinite(value)) {
        fputs("null", json->file);
        return;
    }
    char text[40];
    fputs(sta_format_double(value, text, sizeof(text)), json->file);
}

void sta_json_int(sta_json_out *json, int64_t value)
{
    before_value(json);
    fprintf(json->file, "%" PRId64, value);
}

void sta_json_uint(sta_json_out *json, uint64_t value)
{
    before_value(json);
    fprintf(json->file, "%" PRIu64, value);
}

void sta_json_bool(sta_json_out *json, bool value)
{
    before_value(json);
    fputs(value ? "true" : "false", json->file);
}

void sta_json_null(sta_json_out *json)
{
    before_value(json);
    fputs("null", json->file);
}

void sta_json_finish(sta_json_out *json)
{
    fputc('\n', json->file);
}
