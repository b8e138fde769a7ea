/* SPDX-License-Identifier: MIT
 * strata-info --points for .strata files: points as CSV in file order.
 */
#ifndef STA_APP_INFO_STRATA_POINTS_H
#define STA_APP_INFO_STRATA_POINTS_H

#include <stdint.h>
#include <stdio.h>

#include "core/status.h"

/* Prints points [start, start + count) of the .strata file `path` as --points CSV
 * (the same columns as for LAS). File order is the node table's order (breadth-first:
 * the root, then level 1, ...; coarse points first) and, within a node, the order
 * of its payload. Nodes before `start` are skipped without decoding. Errors name the
 * file and the node: STA_ERR_IO, STA_ERR_FORMAT, STA_ERR_NOMEM. */
sta_status sta_info_strata_points(FILE *out, const char *path, uint64_t start, uint64_t count,
                                  sta_error *err);

#endif
