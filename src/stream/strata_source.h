/* SPDX-License-Identifier: MIT
 * The node source of a .strata file: a worker checks a node's checksum, decompresses it
 * (one zstd decoder per worker) and converts it to the GPU layout.
 */
#ifndef STA_STREAM_STRATA_SOURCE_H
#define STA_STREAM_STRATA_SOURCE_H

#include "format/strata_reader.h"
#include "mirror/mirror_set.h"
#include "stream/clip.h"
#include "stream/node_source.h"

typedef struct sta_strata_source {
    sta_node_source source;          /* what the loader uses */
    const sta_strata_reader *reader; /* borrowed: must outlive the source */
    int colour_shift;                /* 8 for 16-bit colour, 0 for 8-bit */
    const sta_clip *clip;            /* borrowed or NULL; set before loading starts:
                                        only the points it keeps are loaded */
    const sta_mirror_set *mirrors;   /* borrowed or NULL; set before loading starts:
                                        flags ghosts when the file has no MIRROR bit */
} sta_strata_source;

/* Fills `source` (caller-owned, must stay in place while used) for `reader`. */
void sta_strata_source_init(sta_strata_source *source, const sta_strata_reader *reader,
                            int colour_shift);

#endif
