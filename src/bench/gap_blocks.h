/* SPDX-License-Identifier: MIT
 * Block artefacts of the hole-or-background decision (issue 15, part 2): how much more
 * often hole and background change between neighbouring empty pixels across the lines
 * of the screen-space pyramids' blocks than across lines that are no block line of any
 * level. A decision made per block changes only on its block lines (square, stair-
 * stepped gaps); a decision per pixel changes as often there as elsewhere (ratio ~1).
 * CPU only, on HPR labels read back as an sta_image (screen_space.h's label values).
 */
#ifndef STA_BENCH_GAP_BLOCKS_H
#define STA_BENCH_GAP_BLOCKS_H

#include "render/ref/image.h"

/* Over the 4-neighbour pairs of empty pixels (labels HOLE or BACKGROUND) of `label`
 * (1 channel), the rate of hole/background changes across the lines x = block i and
 * y = block i (between x = block i - 1 and block i, likewise y) divided by the rate
 * across odd lines (between x = 2i and 2i + 1, likewise y: no block line of any level).
 * `block` a power of 2 of at least 2. NAN when there is no pair on either side or no
 * change across odd lines. */
double sta_eval_gap_block_ratio(const sta_image *label, int block);

#endif
