/* SPDX-License-Identifier: MIT
 * Allocation with overflow checks and a test hook that fails the Nth allocation.
 *
 * All project code allocates through these functions so tests can prove that every
 * failure path cleans up (see sta_alloc_fail_after).
 */
#ifndef STA_CORE_ALLOC_H
#define STA_CORE_ALLOC_H

#include <stdbool.h>
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

/* A shared allowance of heap bytes that metered threads draw from (sta_alloc_meter_begin):
 * an allocation that would take more than is left fails (returns NULL) instead, so a pass
 * that handles NULL stops within the allowance. Bytes are malloc_usable_size's. */
typedef struct sta_alloc_pool {
    _Atomic long long left; /* bytes left; set it before any thread draws */
} sta_alloc_pool;

/* Takes `bytes` from the pool for memory the caller allocates itself; false (nothing
 * taken) when fewer are left. sta_alloc_pool_give returns them. */
bool sta_alloc_pool_take(sta_alloc_pool *pool, size_t bytes);
void sta_alloc_pool_give(sta_alloc_pool *pool, size_t bytes);

/* From now on this thread's allocations draw from `pool` and its frees return to it,
 * until sta_alloc_meter_end, which returns whether an allocation was refused and puts
 * the most bytes the thread held from the pool meanwhile in *out_peak (may be NULL). Memory
 * freed in between that was allocated before is not credited to the pool (the balance
 * is settled at the end). Not nested. */
void sta_alloc_meter_begin(sta_alloc_pool *pool);
bool sta_alloc_meter_end(size_t *out_peak);

/* Test hook: the allocation after `count` successful ones fails (and all after it),
 * until sta_alloc_fail_after(-1) switches the hook off. Not thread-safe: tests only. */
void sta_alloc_fail_after(long count);

#endif
