/* SPDX-License-Identifier: MIT
 * The block-line ratio of the hole-or-background decision (gap_blocks.h).
 */
#include "bench/gap_blocks.h"

#include <math.h>
#include <stdbool.h>
#include <stdint.h>

#include "render/ref/screen_space.h"

// 1 for HOLE, 0 for BACKGROUND, -1 for a point's label (labels compared within 0.5).
static int empty_kind(const sta_image *label, int x, int y)
{
    float l = label->data[((size_t)y * (size_t)label->width + (size_t)x) * (size_t)label->channels];
    if (fabsf(l - STA_LABEL_HOLE) < 0.5f) {
        return 1;
    }
    return fabsf(l - STA_LABEL_BACKGROUND) < 0.5f ? 0 : -1;
}

double sta_eval_gap_block_ratio(const sta_image *label, int block)
{
    if (!label || !label->data || block < 2) {
        return (double)NAN;
    }
    // [0]: across odd lines, [1]: across block lines.
    uint64_t pairs[2] = { 0, 0 }, changes[2] = { 0, 0 };
    for (int y = 0; y < label->height; y++) {
        for (int x = 0; x < label->width; x++) {
            int here = empty_kind(label, x, y);
            if (here < 0) {
                continue;
            }
            // The pair (x, y) - (x + 1, y) straddles line x + 1; (x, y) - (x, y + 1) line y + 1.
            const int next[2][2] = { { x + 1, y }, { x, y + 1 } };
            for (int d = 0; d < 2; d++) {
                int nx = next[d][0], ny = next[d][1];
                if (nx >= label->width || ny >= label->height) {
                    continue;
                }
                int there = empty_kind(label, nx, ny);
                int line = d == 0 ? nx : ny;
                bool odd = line % 2 == 1, on_block = line % block == 0;
                if (there < 0 || (!odd && !on_block)) {
                    continue;
                }
                pairs[on_block]++;
                changes[on_block] += here != there;
            }
        }
    }
    if (pairs[0] == 0 || pairs[1] == 0 || changes[0] == 0) {
        return (double)NAN;
    }
    double off = (double)changes[0] / (double)pairs[0];
    double on = (double)changes[1] / (double)pairs[1];
    return on / off;
}
