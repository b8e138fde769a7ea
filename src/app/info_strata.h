/* SPDX-License-Identifier: MIT
 * strata-info for .strata files: tree statistics and --verify.
 */
#ifndef STA_APP_INFO_STRATA_H
#define STA_APP_INFO_STRATA_H

#include <stdbool.h>
#include <stdio.h>

#include "core/status.h"

/* True when the file starts with the .strata magic. */
bool sta_info_is_strata(const char *path);

/* Prints the header and per-level statistics of a .strata file (text or JSON); with
 * `verify`, checks every checksum and the nested-octree invariants first and fails
 * on the first violation. */
sta_status sta_info_strata(FILE *out, const char *path, bool json, bool verify, bool progress,
                           sta_error *err);

/* Measures, on one thread, how fast the nodes of a .strata file are (a) checked and
 * decompressed (zstd alone) and (b) decoded and converted to the viewer's GPU layout
 * (what a loader thread does), and prints points/s and MB/s for each. */
sta_status sta_info_strata_decode_speed(FILE *out, const char *path, sta_error *err);

#endif
