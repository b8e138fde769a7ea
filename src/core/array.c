/* SPDX-License-Identifier: MIT
 * Growable arrays. */
#include "core/array.h"

#include <assert.h>
#include <stdint.h>
#include <string.h>

#include "core/alloc.h"

sta_status sta_array_reserve(void **items, size_t *capacity, size_t needed, size_t item_size,
                             size_t first_count, sta_error *err)
{
    assert(items && capacity && item_size > 0);
    if (needed <= *capacity) {
        return STA_OK;
    }
    if (needed > SIZE_MAX / item_size) {
        return sta_fail(err, STA_ERR_NOMEM,
                        "out of memory: %zu elements of %zu bytes exceed the address space", needed,
                        item_size);
    }
    size_t grown = first_count;
    if (*capacity) {
        grown = *capacity <= SIZE_MAX / 2 ? *capacity * 2 : SIZE_MAX;
    }
    if (grown < needed || grown > SIZE_MAX / item_size) {
        grown = needed;
    }
    void *old;
    memcpy(&old, items, sizeof(old));
    void *fresh = sta_realloc_array(old, grown, item_size);
    if (!fresh) {
        return sta_fail(err, STA_ERR_NOMEM, "out of memory for %zu elements of %zu bytes", grown,
                        item_size);
    }
    memcpy(items, &fresh, sizeof(fresh));
    *capacity = grown;
    return STA_OK;
}
