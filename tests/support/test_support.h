/* SPDX-License-Identifier: MIT
 * Shared helpers for the cmocka tests: one ctest per case, honest skips, paths.
 *
 * Each test binary ends with STA_TEST_MAIN(tests). ctest runs it once per case with
 * the case name as argv[1]; a case that calls STA_TEST_SKIP exits with 77, which
 * ctest reports as skipped with the printed reason (SKIP_RETURN_CODE 77).
 */
#ifndef STA_TEST_SUPPORT_H
#define STA_TEST_SUPPORT_H

#include <setjmp.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

/* The shared test data folder (../shared/data beside the checkout, or
 * $STA_SHARED_DATA), or NULL when it is absent. */
const char *sta_test_shared_data(void);

/* Joins the shared data folder and `relative` into a static buffer; NULL when the
 * folder is absent. Not reentrant. */
const char *sta_test_shared_path(const char *relative);

/* A fresh private temporary folder for this process (removed at exit). */
const char *sta_test_tmpdir(void);

/* Joins sta_test_tmpdir() and `name` into a static buffer. Not reentrant. */
const char *sta_test_tmp_path(const char *name);

/* Marks the running case skipped with a reason printed to stderr. */
void sta_test_mark_skipped(const char *reason);

/* Reads a whole file into a malloc'ed buffer (test failure if it cannot). */
uint8_t *sta_test_read_file(const char *path, size_t *out_size);

/* True when the two files hold the same bytes (fails the test if one cannot be read). */
bool sta_test_files_equal(const char *a, const char *b);

/* Writes bytes to a file (test failure if it cannot). */
void sta_test_write_file(const char *path, const void *data, size_t size);

/* Skip the current case with a reason; returns from the test function. */
#define STA_TEST_SKIP(reason)                                                                      \
 do {                                                                                              \
  sta_test_mark_skipped(reason);                                                                   \
  skip();                                                                                          \
 } while (0)

/* Skip unless ../shared/data is present. */
#define STA_TEST_REQUIRE_SHARED_DATA()                                                             \
 do {                                                                                              \
  if (!sta_test_shared_data()) {                                                                   \
   STA_TEST_SKIP("../shared/data is absent (set STA_SHARED_DATA to its path)");                    \
  }                                                                                                \
 } while (0)

/* A small deterministic generator for test data: uniform in [0, 1), 24 bits. */
static inline float sta_test_frand(uint64_t *state)
{
    *state = *state * 6364136223846793005ull + 1442695040888963407ull;
    return (float)(*state >> 40) / 16777216.0f;
}

/* The converter tests' integer generator (a 32-bit LCG's top 24 bits). */
static inline uint32_t sta_test_next_random(uint32_t *state)
{
    *state = *state * 1664525u + 1013904223u;
    return *state >> 8;
}

/* Random grid points in a box of `side` grid units from `corner`, a fifth of them on a few
 * shared positions (duplicates); with `plane`, half of the others on a tilted plane (a
 * surface's cells). */
void sta_test_random_grid(int32_t (*grid)[3], size_t n, const int32_t corner[3], int32_t side,
                          uint32_t seed, bool plane);

/* The front 160 degrees of a pole of 110 grid units' radius around `centre` (axis z), in
 * a box 100 units tall: 21 rings of 60 points, rounded to the grid, into d (room for
 * 1260). Returns the count. The sphere and quadric fit tests share it. */
size_t sta_test_pole_side(int64_t (*d)[3], const double centre[3]);

/* A tilted plane z = 100 + (x - 10) / 4 + (y - 10) / 6 sampled exactly on a 40 x 40
 * lattice 12 units apart, into d (room for 1600), and its unit normal (up). Returns the
 * count. The sphere and quadric fit tests share it. */
size_t sta_test_tilted_plane(int64_t (*d)[3], double normal[3]);

/* This process's resident bytes now (/proc/self/statm), or -1 when they cannot be read;
 * with sta_test_peak_growth, how much a forked child's peak resident set grew over it. */
double sta_test_resident_bytes(void);
double sta_test_peak_growth(double start_bytes);

int sta_test_run(const char *group, const struct CMUnitTest *tests, size_t count, int argc,
                 char **argv);

#define STA_TEST_MAIN(tests)                                                                       \
 int main(int argc, char **argv)                                                                   \
 {                                                                                                 \
  return sta_test_run(__FILE__, tests, sizeof(tests) / sizeof(tests[0]), argc, argv);              \
 }

#endif
