/* SPDX-License-Identifier: MIT
 * A small streaming JSON writer: nesting, commas and string escaping handled, numbers
 * printed with the shortest text that reads back to the same double.
 */
#ifndef STA_CORE_JSON_OUT_H
#define STA_CORE_JSON_OUT_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

enum {
    STA_JSON_MAX_DEPTH = 32
};

typedef struct sta_json_out {
    FILE *file;                           /* borrowed */
    int depth;                            /* open objects/arrays */
    bool needs_comma[STA_JSON_MAX_DEPTH]; /* per level: an element was written */
    bool after_key;                       /* a key was written, its value comes next */
    bool pretty;                          /* newline + indent per element */
} sta_json_out;

void sta_json_init(sta_json_out *json, FILE *file, bool pretty);
void sta_json_begin_object(sta_json_out *json);
void sta_json_end_object(sta_json_out *json);
void sta_json_begin_array(sta_json_out *json);
void sta_json_end_array(sta_json_out *json);
/* Writes "key": inside an object; the next call writes its value. */
void sta_json_key(sta_json_out *json, const char *key);
void sta_json_string(sta_json_out *json, const char *text);
/* Like sta_json_string for a byte buffer of `size` bytes (may contain NULs). */
void sta_json_string_n(sta_json_out *json, const char *text, size_t size);
/* Finite numbers in shortest round-trip form; NaN and infinities as null. */
void sta_json_double(sta_json_out *json, double value);
void sta_json_int(sta_json_out *json, int64_t value);
void sta_json_uint(sta_json_out *json, uint64_t value);
void sta_json_bool(sta_json_out *json, bool value);
void sta_json_null(sta_json_out *json);
/* Ends the document with a newline. */
void sta_json_finish(sta_json_out *json);

/* Writes into `buffer` the shortest "%.*g" text of `value` that reads back exactly
 * (1 to 17 significant digits). Returns `buffer`. For CSV and messages as well. */
const char *sta_format_double(double value, char *buffer, size_t size);

#endif
