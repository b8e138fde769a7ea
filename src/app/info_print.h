/* SPDX-License-Identifier: MIT
 * strata-info's output: text summary, JSON and CSV points of a LAS/PLY file.
 */
#ifndef STA_APP_INFO_PRINT_H
#define STA_APP_INFO_PRINT_H

#include <stdio.h>

#include "io/cloud.h"
#include "io/cloud_stats.h"

/* Human-readable summary of the header and the scanned statistics. */
void sta_info_print_text(FILE *out, const sta_cloud_info *info, const sta_cloud_stats *stats);

/* The same as one JSON object (keys documented in docs/TOOLS.md). */
void sta_info_print_json(FILE *out, const sta_cloud_info *info, const sta_cloud_stats *stats);

/* The CSV header line of --points. */
void sta_info_print_points_header(FILE *out,
                                  uint32_t attr); /* sta_attr: SPLAT adds nx,ny,nz,radius */

/* One CSV row of --points: real-world coordinates (shortest exact decimals) and the
 * fields of `attr` (sta_attr bits); the others are left empty. */
void sta_info_print_point_row(FILE *out, const sta_grid *grid, uint32_t attr, const sta_point *p);

/* Points [start, start + count) as CSV with the fixed header line; fields the file
 * lacks are left empty. Coordinates are real-world, shortest exact decimals. */
sta_status sta_info_print_points(FILE *out, sta_cloud_reader *reader, uint64_t start,
                                 uint64_t count, sta_error *err);

#endif
