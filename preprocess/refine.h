/* SPDX-License-Identifier: MIT
 * Splits chunks that are too large for the memory budget (after distribution): a
 * dense counting cell is re-counted on a finer grid and its records are moved into
 * smaller chunks appended to the temporary file. The merge phase later rebuilds the
 * nodes above the new chunks like any other.
 */
#ifndef STA_PREPROCESS_REFINE_H
#define STA_PREPROCESS_REFINE_H

#include <stdint.h>

#include "distribute.h"
#include "record.h"

/* Replaces every chunk of more than `chunk_capacity` points (that is above the
 * deepest level) by sub-chunks of at most that many points where the octree allows.
 * `fd`/`path` is the temporary file holding `*io_record_count` records; new regions
 * are appended and the count updated. `buffer_bytes` bounds the memory used. The
 * plan's chunk_of_cell map is not updated (distribution is over). */
sta_status sta_refine_chunks(sta_chunk_plan *plan, const sta_record_layout *layout, int fd,
                             const char *path, uint64_t chunk_capacity, size_t buffer_bytes,
                             uint64_t *io_record_count, sta_error *err);

#endif
