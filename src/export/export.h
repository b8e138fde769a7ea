/* SPDX-License-Identifier: MIT
 * strata-export as a library call: the points of a .strata scene, or a selection of
 * them, back out as a LAS file with their original integers.
 *
 * Design: nodes are read in file order (the node table's breadth-first order, each
 * node's points in payload order) through the format's reader, one node at a time
 * with one decoder; nodes are skipped by the streamer's selection terms
 * (stream/clip.h: box, polygon, level, spacing) before they are decoded, points by
 * the same terms after. Passing points go through a fixed batch to the LAS writer,
 * which writes under a temporary name and renames only on success, so memory is
 * bounded by the largest node and a failed export leaves nothing behind.
 */
#ifndef STA_EXPORT_EXPORT_H
#define STA_EXPORT_EXPORT_H

#include <stdbool.h>
#include <stdint.h>

#include "core/status.h"
#include "stream/clip.h"

/* Config: zero means default. */
typedef struct sta_export_options {
    const char *input;   /* .strata scene */
    const char *output;  /* .las path (".laz" is refused: see docs/EXPORT.md) */
    sta_clip clip;       /* selection; zeroed: the whole scene */
    uint64_t max_points; /* 0: no limit; else stop after this many (coarse levels first) */
    int version_minor;   /* 0: 2 when the point format is 0-3, else 4; or 2, 4 */
    bool force;          /* overwrite an existing output */
    bool progress;       /* draw a progress line on stderr */
} sta_export_options;

/* What the export did. */
typedef struct sta_export_report {
    uint64_t points_written;
    uint64_t points_read;  /* points of the nodes decoded */
    uint32_t nodes_read;   /* nodes decoded */
    uint32_t nodes_culled; /* nodes skipped without decoding */
    int point_format;      /* LAS point data record format written */
    int version_minor;     /* LAS 1.x written */
    uint32_t extra_size;   /* extra bytes per record */
} sta_export_report;

/* The LAS point format (0-10) that holds exactly the fields in `sta_attr_mask`
 * (sta_attr bits): the format the scene's LAS input had, since the LAS reader sets
 * exactly its format's fields. */
int sta_export_point_format(uint32_t sta_attr_mask);

/* Runs the export. On failure nothing is left under `output` (nor a temporary file)
 * and the message names the file and what is wrong. `report` may be NULL.
 * Errors: STA_ERR_ARG (options, existing output without force), STA_ERR_IO,
 * STA_ERR_FORMAT (damaged scene), STA_ERR_UNSUPPORTED (.laz output), STA_ERR_NOMEM. */
sta_status sta_export(const sta_export_options *options, sta_export_report *report, sta_error *err);

#endif
