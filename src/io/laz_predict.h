/* SPDX-License-Identifier: MIT
 * Predictors shared by the point10 and point14 LAZ decoders, inline: they run for
 * every point. */
#ifndef STA_IO_LAZ_PREDICT_H
#define STA_IO_LAZ_PREDICT_H

#include <stdbool.h>
#include <stdint.h>
#include <string.h>

// Streaming median of the last five values (initially five zeros); the median is v[2].
typedef struct median5 {
    int32_t v[5];
    bool high; // whether the next value replaces from the top
} median5;

static inline void sta_laz_median_init(median5 *m)
{
    memset(m->v, 0, sizeof(m->v));
    m->high = true;
}

static inline void sta_laz_median_add(median5 *m, int32_t x)
{
    int32_t *v = m->v;
    if (m->high) {
        if (x < v[2]) {
            v[4] = v[3];
            v[3] = v[2];
            if (x < v[0]) {
                v[2] = v[1];
                v[1] = v[0];
                v[0] = x;
            } else if (x < v[1]) {
                v[2] = v[1];
                v[1] = x;
            } else {
                v[2] = x;
            }
        } else {
            if (x < v[3]) {
                v[4] = v[3];
                v[3] = x;
            } else {
                v[4] = x;
            }
            m->high = false;
        }
    } else {
        if (v[2] < x) {
            v[0] = v[1];
            v[1] = v[2];
            if (v[4] < x) {
                v[2] = v[3];
                v[3] = v[4];
                v[4] = x;
            } else if (v[3] < x) {
                v[2] = v[3];
                v[3] = x;
            } else {
                v[2] = x;
            }
        } else {
            if (v[1] < x) {
                v[0] = v[1];
                v[1] = x;
            } else {
                v[0] = x;
            }
            m->high = true;
        }
    }
}

// The low byte of a predicted-plus-corrected value (LAZ byte arithmetic wraps).
static inline uint8_t sta_laz_fold_u8(int32_t value)
{
    return (uint8_t)(value & 0xff);
}

static inline int32_t sta_laz_clamp_u8(int32_t value)
{
    return value < 0 ? 0 : (value > 255 ? 255 : value);
}

#endif
