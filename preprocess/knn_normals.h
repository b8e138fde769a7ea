/* SPDX-License-Identifier: MIT
 * Normals and splat radii of one chunk's points by exact neighbour search
 * (strata-convert --normals --normals-method knn; the default is moment_normals.h), and
 * the types both methods share.
 *
 * Design: the K nearest neighbours of each of the chunk's points among the chunk and
 * its halo (points of neighbouring chunks within a margin, preprocess/halo.h), exactly,
 * from knn_grid.h. The normal is the eigenvector of the smallest eigenvalue of the
 * neighbourhood's covariance (Kopp's hybrid solver, core/eigen3.h), oriented by the
 * rule of docs/CONVERTER.md ("Normals"). A neighbourhood that is nearly linear, or
 * whose plane holds the line of sight to the scanner path (one profile of a dense scan
 * line), or thick across its plane, is widened and fitted again over about 6 K points
 * (adaptive neighbourhoods): from the exact moments of the cells of a box centred on the
 * point (cell_moments.h), or, where that box is still thick (foliage, volumes), the
 * exact 6 K nearest. Degenerate
 * neighbourhoods (fewer than 3 distinct points, collinear) get the up axis. The radius
 * is the mean distance to the nearest STA_NORMALS_RADIUS_K neighbours (the splatting
 * notes' 8-10) whatever K. Results go into each record's SPLAT bytes.
 */
#ifndef STA_PREPROCESS_KNN_NORMALS_H
#define STA_PREPROCESS_KNN_NORMALS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "core/status.h"
#include "record.h"
#include "trajectory.h"

#define STA_NORMALS_DEFAULT_K 10 /* neighbours (issue 12: "8-10 nearest") */
#define STA_NORMALS_MAX_K     64 /* = STA_KNN_MAX (knn_grid.h) */
#define STA_NORMALS_RADIUS_K  10 /* the splat radius: mean distance to this many neighbours */

/* How the normals are found (docs/CONVERTER.md "Normals"). */
typedef enum sta_normals_method {
    STA_NORMALS_MOMENTS = 0,     /* boxes of cell moments sized by the data (moment_normals.h) */
    STA_NORMALS_KNN = 1,         /* the exact K nearest, widened where needed (this file) */
    STA_NORMALS_MOMENTS_FINE = 2 /* moments from base cells half as wide everywhere, no
                                    spheres (the default refines only rough points): ~1.4x
                                    the default's CPU */
} sta_normals_method;

/* Where one chunk's normals are computed; grid units are the output grid's integers. */
typedef struct sta_normals_chunk {
    int k;                            /* neighbours, 3..STA_NORMALS_MAX_K */
    sta_normals_method method;        /* 0: STA_NORMALS_MOMENTS */
    int base_level;                   /* moments: the finest cells are 2^base_level grid
                                         units (sta_moment_normals_base_level), the same
                                         for every chunk of a scene */
    double scale[3];                  /* metres per grid unit */
    int64_t box_min[3];               /* the chunk's box, grid units, inclusive */
    int64_t box_max[3];               /* exclusive */
    int64_t scene_min[3];             /* tight bounds of all points (nothing lies beyond) */
    int64_t scene_max[3];             /* inclusive */
    double margin;                    /* halo margin around the box, metres */
    int up_axis;                      /* 2: +Z, 1: +Y */
    double scene_centre[3];           /* grid units: vertical surfaces face away from its up-axis
                                         line when there is no trajectory */
    const sta_trajectory *trajectory; /* usable scanner path, or NULL: vertical surfaces
                                         face the centroid of their GPS-time bin */
    bool decide_each_point;           /* tests: the moments' level passes decide each point
                                         alone, not once a base cell (the reference) */
    bool keep_base_boxes;             /* tests: no base-level candidate skips its base box
                                         (moment_normals.c's skips_base; the reference) */
} sta_normals_chunk;

/* What happened, summed over chunks. */
typedef struct sta_normals_stats {
    uint64_t points;        /* normals computed */
    uint64_t degenerate;    /* fallback normal (fewer than 3 distinct points, collinear) */
    uint64_t beyond_halo;   /* neighbourhood wider than the halo: may miss a neighbour */
    uint64_t widened;       /* neighbourhood widened beyond K (nearly linear, thick or edge-on) */
    uint64_t widened_exact; /* of which fitted over the exact widest K nearest (not a box) */
    uint64_t skipped_base;  /* moments: base-level candidates that skipped their base box */
} sta_normals_stats;

/* Computes a normal and radius for each of the `count` records (layout with
 * STA_ATTR_SPLAT) from them and the `halo_count` halo positions (3 x int32 each) and
 * stores them in the records' SPLAT bytes. Adds to `stats`. Called through
 * sta_normals_compute (moment_normals.h), which checks the arguments. */
sta_status sta_knn_normals_compute(const sta_normals_chunk *chunk, const sta_record_layout *layout,
                                   uint8_t *records, size_t count, const int32_t *halo,
                                   size_t halo_count, sta_normals_stats *stats, sta_error *err);

/* The widest neighbourhood a point's K = k neighbourhood is widened to. */
int sta_normals_widest_k(int k);

/* Bytes of scratch memory sta_knn_normals_compute needs for `points` points (own + halo). */
size_t sta_knn_normals_memory_bytes(size_t points);

#endif
