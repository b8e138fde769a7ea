/* SPDX-License-Identifier: MIT
 * The rehash the converter's open-addressing tables share when they double. */
#include "key_slots.h"

#include <string.h>

#include "core/alloc.h"

enum {
    MAX_VALUE_ARRAYS = 4
};

bool sta_key_slots_double(uint64_t **keys, size_t *capacity, void *const values[],
                          const size_t sizes[], void *grown[], int count)
{
    size_t old = *capacity, slots = 2 * old;
    uint64_t *new_keys = sta_calloc(slots, sizeof(*new_keys));
    char *arrays[MAX_VALUE_ARRAYS] = { NULL };
    bool ok = new_keys && count <= MAX_VALUE_ARRAYS;
    for (int i = 0; i < count && ok; i++) {
        ok = !values[i] || (arrays[i] = sta_alloc_array(slots, sizes[i]));
    }
    if (!ok) {
        sta_free(new_keys);
        for (int i = 0; i < count && i < MAX_VALUE_ARRAYS; i++) {
            sta_free(arrays[i]);
        }
        return false;
    }
    for (size_t s = 0; s < old; s++) {
        uint64_t key = (*keys)[s];
        if (key != 0) {
            size_t u = sta_key_slot(new_keys, slots, key);
            new_keys[u] = key;
            for (int i = 0; i < count; i++) {
                if (arrays[i]) {
                    memcpy(arrays[i] + u * sizes[i], (const char *)values[i] + s * sizes[i],
                           sizes[i]);
                }
            }
        }
    }
    sta_free(*keys);
    *keys = new_keys;
    for (int i = 0; i < count; i++) {
        sta_free(values[i]);
        grown[i] = arrays[i];
    }
    *capacity = slots;
    return true;
}
