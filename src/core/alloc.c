/* SPDX-License-Identifier: MIT
 * Allocation with overflow checks and a failure hook for tests. */
#include "core/alloc.h"

#include <malloc.h>
#include <stdatomic.h>
#include <stdbool.h>
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

// The metered thread's pool, the bytes it holds from it (negative when it freed older
// memory) and whether an allocation was refused (sta_alloc_meter_begin).
static _Thread_local sta_alloc_pool *meter;
static _Thread_local long long meter_held;
static _Thread_local long long meter_peak;
static _Thread_local bool meter_refused;

bool sta_alloc_pool_take(sta_alloc_pool *pool, size_t bytes)
{
    long long b = (long long)bytes;
    if (atomic_fetch_sub(&pool->left, b) < b) {
        atomic_fetch_add(&pool->left, b);
        return false;
    }
    return true;
}

void sta_alloc_pool_give(sta_alloc_pool *pool, size_t bytes)
{
    atomic_fetch_add(&pool->left, (long long)bytes);
}

void sta_alloc_meter_begin(sta_alloc_pool *pool)
{
    meter = pool;
    meter_held = meter_peak = 0;
    meter_refused = false;
}

bool sta_alloc_meter_end(size_t *out_peak)
{
    if (out_peak) {
        *out_peak = (size_t)meter_peak;
    }
    if (meter && meter_held < 0) { // (older memory freed: not the pool's to gain)
        atomic_fetch_add(&meter->left, meter_held);
    }
    meter = NULL;
    return meter_refused;
}

// Draws `bytes` (the request; settled to the usable size once allocated) for an
// allocation of the metered thread; false and marked refused when the pool is short.
static bool meter_draw(size_t bytes)
{
    if (!meter) {
        return true;
    }
    if (!sta_alloc_pool_take(meter, bytes)) {
        meter_refused = true;
        return false;
    }
    meter_held += (long long)bytes;
    meter_peak = meter_held > meter_peak ? meter_held : meter_peak;
    return true;
}

// After an allocation: the draw of `asked` becomes the block's usable size (or goes
// back when malloc failed).
static void *meter_settle(void *block, size_t asked)
{
    if (meter) {
        long long got = block ? (long long)malloc_usable_size(block) : 0;
        atomic_fetch_sub(&meter->left, got - (long long)asked);
        meter_held += got - (long long)asked;
        meter_peak = meter_held > meter_peak ? meter_held : meter_peak;
    }
    return block;
}

static void meter_release(void *block)
{
    if (meter && block) {
        long long bytes = (long long)malloc_usable_size(block);
        atomic_fetch_add(&meter->left, bytes);
        meter_held -= bytes;
    }
}

void *sta_malloc(size_t size)
{
    if (hook_says_fail()) {
        return NULL;
    }
    size = size ? size : 1;
    if (!meter_draw(size)) {
        return NULL;
    }
    return meter_settle(malloc(size), size);
}

void *sta_calloc(size_t count, size_t size)
{
    if (size && count > SIZE_MAX / size) {
        return NULL;
    }
    if (hook_says_fail()) {
        return NULL;
    }
    count = count ? count : 1, size = size ? size : 1;
    if (!meter_draw(count * size)) {
        return NULL;
    }
    return meter_settle(calloc(count, size), count * size);
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
    bytes = bytes ? bytes : 1;
    if (!meter) {
        return realloc(ptr, bytes);
    }
    // Metered: the new size is drawn first, the old block's returned after the move.
    size_t old = ptr ? malloc_usable_size(ptr) : 0;
    if (!meter_draw(bytes)) {
        return NULL;
    }
    void *moved = realloc(ptr, bytes);
    if (!moved) {
        return meter_settle(NULL, bytes);
    }
    atomic_fetch_add(&meter->left, (long long)old);
    meter_held -= (long long)old;
    return meter_settle(moved, bytes);
}

void sta_free(void *ptr)
{
    meter_release(ptr);
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
