/* SPDX-License-Identifier: MIT
 * Internal: small numeric helpers for the synth hot paths.
 */
#ifndef STA_SYNTH_MATH_H
#define STA_SYNTH_MATH_H

#include <stdint.h>

/* floor(x) as an integer, for |x| < 2^62 (no libm call: baseline x86-64 has no
 * rounding instruction, and floor() showed up in profiles). */
static inline int64_t sta_floor_i64(double x)
{
    int64_t i = (int64_t)x; // truncates towards zero
    return (double)i > x ? i - 1 : i;
}

#endif
