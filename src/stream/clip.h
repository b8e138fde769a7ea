/* SPDX-License-Identifier: MIT
 * The selection terms shared by the streamer and strata-export: a clip box, a 2D
 * polygon, class and return filters, and a level-of-detail limit.
 *
 * Design: one predicate for nodes (can a node's box hold a point that passes?) and
 * one for points (does it pass?). The node test is conservative: it may keep a node
 * with no passing point, never drop one that has some. All geometry is in the
 * scene's real coordinates (its CRS), in double; a point's real coordinate is its
 * grid integer through sta_grid_apply, so a test agrees with an exported file bit
 * for bit. A zeroed sta_clip keeps everything.
 */
#ifndef STA_STREAM_CLIP_H
#define STA_STREAM_CLIP_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "core/point.h"
#include "core/status.h"

/* Return filter bits besides the return numbers 1..15 (bits 1..15). */
enum {
    STA_CLIP_RETURN_FIRST = 1u << 16,  /* return_number == 1 */
    STA_CLIP_RETURN_LAST = 1u << 17,   /* return_number == number_of_returns */
    STA_CLIP_RETURN_SINGLE = 1u << 18, /* number_of_returns == 1 */
};

/* What to keep. Zero means keep everything (each term is off until set). */
typedef struct sta_clip {
    bool has_box;           /* keep points inside [box_min, box_max] (inclusive) */
    double box_min[3];      /* real-world corner, scene CRS */
    double box_max[3];      /* box_min <= box_max per axis */
    const double *polygon;  /* borrowed: polygon_count (x, y) pairs, real-world; a point
                               passes when inside by the even-odd rule; NULL: no polygon */
    size_t polygon_count;   /* vertices, >= 3 when polygon is set */
    bool has_classes;       /* keep only the classes set in class_mask */
    uint8_t class_mask[32]; /* bit c (byte c / 8, bit c % 8): keep classification c */
    uint32_t return_mask;   /* 0: all; else bits n (1..15) and STA_CLIP_RETURN_*: keep
                               a point matching any set term */
    bool has_max_level;     /* keep only nodes of level <= max_level */
    unsigned max_level;     /* deepest level kept */
    double min_spacing;     /* > 0: keep only nodes whose spacing is >= this (metres) */
} sta_clip;

/* True when every term is off (nothing is filtered). */
bool sta_clip_is_empty(const sta_clip *clip);

/* True when the clip filters individual points (box, polygon, classes or returns),
 * not only whole nodes by level or spacing. */
bool sta_clip_filters_points(const sta_clip *clip);

/* Sets or clears class `c` in the class filter (and turns it on). */
void sta_clip_set_class(sta_clip *clip, unsigned c, bool keep);

/* True when class `c` passes the class filter. */
bool sta_clip_keeps_class(const sta_clip *clip, unsigned c);

/* Whether a node of `level` and `spacing` whose real box is [min, max] may hold a
 * point that passes (conservative, see above). */
bool sta_clip_keeps_node(const sta_clip *clip, unsigned level, double spacing, const double min[3],
                         const double max[3]);

/* Whether point `p` (on `grid`) passes the box, polygon, class and return terms.
 * `attributes` are the source's sta_attr bits: a class or return filter drops every
 * point of a source without classes or returns. */
bool sta_clip_keeps_point(const sta_clip *clip, const sta_grid *grid, uint32_t attributes,
                          const sta_point *p);

/* Even-odd test of (x, y) against `count` vertices (x, y pairs). */
bool sta_clip_point_in_polygon(const double *polygon, size_t count, double x, double y);

/* Parses a class list "2,6,9-12" into the class filter (turning it on).
 * Errors: STA_ERR_ARG naming the text and what is wrong. */
sta_status sta_clip_parse_classes(sta_clip *clip, const char *text, sta_error *err);

/* Parses a return list "first,last,single,1,2" into return_mask.
 * Errors: STA_ERR_ARG naming the text and what is wrong. */
sta_status sta_clip_parse_returns(sta_clip *clip, const char *text, sta_error *err);

/* Parses a box "XMIN,YMIN,ZMIN,XMAX,YMAX,ZMAX" (real-world) into the box term.
 * Errors: STA_ERR_ARG (six finite numbers with min <= max are needed). */
sta_status sta_clip_parse_box(sta_clip *clip, const char *text, sta_error *err);

/* Reads a polygon file: one "x y" or "x,y" pair per line (blank lines and lines
 * starting with '#' are skipped), at least 3 vertices, in the scene's CRS. On
 * success *out_xy (count pairs) is owned by the caller (sta_free).
 * Errors: STA_ERR_IO, STA_ERR_FORMAT naming the file and line, STA_ERR_NOMEM. */
sta_status sta_clip_read_polygon(const char *path, double **out_xy, size_t *out_count,
                                 sta_error *err);

#endif
