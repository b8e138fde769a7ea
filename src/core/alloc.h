/* SPDX-License-Identifier: MIT
 * Allocation with overflow checks and a test hook that fails the Nth allocation.
 *
 * All project code allocates through these functions so tests can prove that every
 * failure path cleans up (see sta_alloc_fail_after).
 */
#ifndef STA_CORE_ALLOC_H
#define STA_CORE_ALLOC_H

#include <stddef.h>

/* malloc that honours the test hook. Returns NULL on failure. */
void *sta_malloc(size_t size);

/* calloc-like: zeroed memory for count elements of size bytes; NULL when the product
 * overflows size_t or memory is short. */
void *sta_calloc(size_t count, size_t size);

/* Uninitialised array of count elements of size bytes; NULL on overflow or failure. */
void *sta_alloc_array(size_t count, size_t size);

/* Resizes an array to count elements; on failure returns NULL and leaves ptr valid. */
void *sta_realloc_array(void *ptr, size_t count, size_t size);

/* Releases memory from any of the above; NULL is a no-op. */
void sta_free(void *ptr);

/* Duplicates a NUL-terminated string; NULL on failure. */
char *sta_strdup(const char *text);

/* Test hook: the allocation after `count` successful ones fails (and all after it),
 * until sta_alloc_fail_after(-1) switches the hook off. Not thread-safe: tests only. */
void sta_alloc_fail_after(long count);

#endif
