/* SPDX-License-Identifier: MIT
 * Checks for tests that build LAZ files with the test encoder: read a LAZ file (bytes
 * in memory) back through the product's LAS/LAZ reader and compare its raw records.
 */
#ifndef STA_TESTS_LAZENC_CHECK_H
#define STA_TESTS_LAZENC_CHECK_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "core/point.h"
#include "io/laz_internal.h"

/* The LAZ files of ../shared/data/laz and their uncompressed LAS twins (paths relative
 * to the shared data folder; the list of its README). */
typedef struct lazcheck_twin {
    const char *laz;
    const char *las;
} lazcheck_twin;

extern const lazcheck_twin lazcheck_twins[];
extern const size_t lazcheck_twin_count;

/* The raw point records of a LAS file's bytes (the 64-bit count for LAS 1.4). */
typedef struct lazcheck_records {
    const uint8_t *records;
    uint64_t count;
    size_t length; /* bytes per record */
    int format;    /* point data format 0-10 */
} lazcheck_records;

bool lazcheck_las_records(const uint8_t *las, size_t size, lazcheck_records *out);

/* The LASzip VLR of LAZ bytes, read directly (no support checks). */
bool lazcheck_find_vlr(const uint8_t *laz, size_t size, sta_laz_vlr *out);

/* Opens `laz` (named `name` in messages) with the LAS reader, decodes all records and
 * fails the test unless they equal `expected` byte for byte. */
void lazcheck_expect_records(const uint8_t *laz, size_t size, const char *name,
                             const lazcheck_records *expected);

/* Decodes `laz` through the reader; returns false with the reader's message in
 * `message` on an error. *identical: all records equal `expected`. Never fails the
 * test itself (for damaged files). */
bool lazcheck_try_decode(const uint8_t *laz, size_t size, const char *name,
                         const lazcheck_records *expected, bool *identical, char *message,
                         size_t message_size);

/* Every field of two points equal (GPS time bit for bit). */
bool lazcheck_same_point(const sta_point *a, const sta_point *b);

/* Reads both files (full paths) through the generic reader: same count, format,
 * attributes and extra dimensions, every point field and extra byte equal. */
void lazcheck_expect_same_points(const char *laz_path, const char *las_path);

#endif
