/* SPDX-License-Identifier: MIT
 * Allocation with overflow checks and a failure hook for tests. */
#include "core/alloc.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

// Remaining successful allocations before failures start; negative = hook off.
// Tests only, single-threaded by contract.
static long allocations_left = -1;

void sta_alloc_fail_after(long count)
{
    allocations_left = count;
}

static int hook_says_fail(void)
{
    if (allocations_left < 0) {
        return 0;
    }
    if (allocations_left == 0) {
        return 1;
    }
    allocations_left--;
    return 0;
}

void *sta_malloc(size_t size)
{
    if (hook_says_fail()) {
        return NULL;
    }
    return malloc(size ? size : 1);
}

void *sta_calloc(size_t count, size_t size)
{
    if (size && count > SIZE_MAX / size) {
        return NULL;
    }
    if (hook_says_fail()) {
        return NULL;
    }
    return calloc(count ? count : 1, size ? size : 1);
}

void *sta_alloc_array(size_t count, size_t size)
{
    if (size && count > SIZE_MAX / size) {
        return NULL;
    }
    return sta_malloc(count * size);
}

void *sta_realloc_array(void *ptr, size_t count, size_t size)
{
    if (size && count > SIZE_MAX / size) {
        return NULL;
    }
    if (hook_says_fail()) {
        return NULL;
    }
    size_t bytes = count * size;
    return realloc(ptr, bytes ? bytes : 1);
}

void sta_free(void *ptr)
{
    free(ptr);
}

char *sta_strdup(const char *text)
{
    size_t n = strlen(text) + 1;
    char *copy = sta_malloc(n);
    if (copy) {
        memcpy(copy, text, n);
    }
    return copy;
}
