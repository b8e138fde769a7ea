/* SPDX-License-Identifier: MIT
 * Facts about a point file that only its points can tell: actual bounds (header
 * bounds are not trusted), return and class histograms, GPS time range, colour depth.
 */
#ifndef STA_IO_CLOUD_STATS_H
#define STA_IO_CLOUD_STATS_H

#include <stdint.h>

#include "io/cloud.h"

typedef struct sta_cloud_stats {
    uint64_t point_count;    /* points read */
    double min[3], max[3];   /* actual real-world bounds; 0 when no points */
    uint64_t by_return[16];  /* points per return_number (0..15) */
    uint64_t by_class[256];  /* points per classification */
    double gps_min, gps_max; /* over finite GPS times (0 when none) */
    uint64_t gps_nan_count;  /* GPS times that are NaN or infinite */
    uint16_t rgb_max;        /* largest red, green or blue value */
    int colour_bits;         /* 8 when every colour value <= 255, else 16; 0 = none */
    uint16_t intensity_min, intensity_max;
} sta_cloud_stats;

/* Reads every point of `reader` from the first (seeking to 0 before and after) and
 * fills `out_stats`. Bounded memory (one batch). */
sta_status sta_cloud_scan_stats(sta_cloud_reader *reader, sta_cloud_stats *out_stats,
                                sta_error *err);

#endif
