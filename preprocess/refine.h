/* SPDX-License-Identifier: MIT
 * Splits chunks that are too large for the memory budget (after distribution): a
 * dense counting cell is re-counted on a finer grid and its records are moved into
 * smaller chunks (new run lists of the temporary runs). The merge phase later rebuilds the
 * nodes above the new chunks like any other.
 */
#ifndef STA_PREPROCESS_REFINE_H
#define STA_PREPROCESS_REFINE_H

#include <stdint.h>

#include "distribute.h"
#include "record.h"

/* Replaces every chunk of more than `chunk_capacity` points (that is above the
 * deepest level) by sub-chunks of at most that many points where the octree allows.
 * The sub-chunks' records go to new run lists of `runs` (in the order they had) and
 * the split chunk's list is discarded, so temporary disk holds each record once.
 * `buffer_bytes` bounds the memory used. The plan's chunk_of_cell map is not updated
 * (distribution is over). */
sta_status sta_refine_chunks(sta_chunk_plan *plan, const sta_record_layout *layout,
                             sta_temp_runs *runs, uint64_t chunk_capacity, size_t buffer_bytes,
                             sta_error *err);

#endif
