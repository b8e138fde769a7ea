/* SPDX-License-Identifier: MIT
 * GPU residency policy. */
#include "stream/residency.h"

#include <string.h>

#include "core/alloc.h"
#include "stream/gpu_points.h"

sta_status sta_residency_init(sta_residency *r, uint32_t node_count, uint64_t bytes_cap,
                              sta_error *err)
{
    memset(r, 0, sizeof(*r));
    r->entries = sta_calloc(node_count ? node_count : 1, sizeof(*r->entries));
    r->resident = sta_calloc(node_count ? node_count : 1, sizeof(*r->resident));
    if (!r->entries || !r->resident) {
        sta_residency_release(r);
        return sta_fail(err, STA_ERR_NOMEM, "out of memory for the residency of %u nodes",
                        node_count);
    }
    r->node_count = node_count;
    r->bytes_cap = bytes_cap;
    r->point_bytes = STA_GPU_POINT_SIZE;
    r->frame = 1;
    return STA_OK;
}

void sta_residency_release(sta_residency *r)
{
    sta_free(r->entries);
    sta_free(r->resident);
    memset(r, 0, sizeof(*r));
}

void sta_residency_begin_frame(sta_residency *r)
{
    r->frame++;
}

static void evict_at(sta_residency *r, uint32_t slot)
{
    sta_residency_entry *e = &r->entries[r->resident[slot]];
    r->bytes_used -= (uint64_t)e->count * r->point_bytes;
    e->is_resident = false;
    e->count = 0;
    r->resident[slot] = r->resident[--r->resident_count];
    r->evictions++;
}

void sta_residency_evict_all(sta_residency *r, uint32_t *evicted, size_t *evicted_count)
{
    while (r->resident_count > 0) {
        evicted[(*evicted_count)++] = r->resident[r->resident_count - 1];
        evict_at(r, r->resident_count - 1);
    }
}

bool sta_residency_admit(sta_residency *r, uint32_t node, uint32_t count, uint32_t *evicted,
                         size_t *evicted_count)
{
    uint64_t bytes = (uint64_t)count * r->point_bytes;
    if (bytes > r->bytes_cap || r->entries[node].is_resident) {
        return false;
    }
    while (r->bytes_used + bytes > r->bytes_cap) {
        uint32_t victim = UINT32_MAX;
        uint64_t oldest = r->frame;
        for (uint32_t i = 0; i < r->resident_count; i++) {
            uint64_t f = r->entries[r->resident[i]].last_frame;
            if (f < oldest) {
                oldest = f;
                victim = i;
            }
        }
        if (victim == UINT32_MAX) {
            return false;
        }
        evicted[(*evicted_count)++] = r->resident[victim];
        evict_at(r, victim);
    }
    sta_residency_entry *e = &r->entries[node];
    e->is_resident = true;
    e->count = count;
    e->last_frame = r->frame;
    r->bytes_used += bytes;
    r->resident[r->resident_count++] = node;
    return true;
}
