/* SPDX-License-Identifier: MIT
 * Growable arrays: room for more elements by doubling, with overflow checks.
 *
 * The caller keeps the element pointer, the count and the capacity in its own struct;
 * this module only grows the storage, so the array keeps its element type.
 */
#ifndef STA_CORE_ARRAY_H
#define STA_CORE_ARRAY_H

#include <stddef.h>

#include "core/status.h"

/* Makes room for at least `needed` elements of `item_size` bytes (> 0) in the array *items,
 * which has room for *capacity elements (an empty array is NULL with capacity 0). Does
 * nothing when `needed` fits. Otherwise the new capacity is the larger of `needed` and twice
 * *capacity (`first_count` when *capacity is 0; just `needed` when twice would overflow),
 * so n appends copy O(n) elements; the first *capacity elements are kept and *items and
 * *capacity are updated together.
 *
 * `items` is the address of the caller's element pointer, cast: `(void **)&list->items`.
 * It is read and written with memcpy, so any object pointer may stand behind it (POSIX gives
 * all object pointers one representation).
 *
 * Returns STA_OK, or STA_ERR_NOMEM when memory is short or the bytes for `needed` elements
 * overflow size_t; then *items and *capacity are unchanged and still valid, and err (may be
 * NULL) names the element count and size. Callers whose message must name a file pass NULL
 * and write their own. Allocates through core/alloc.h, so the test hook can fail it. The
 * caller guards the array against other threads. */
sta_status sta_array_reserve(void **items, size_t *capacity, size_t needed, size_t item_size,
                             size_t first_count, sta_error *err);

#endif
