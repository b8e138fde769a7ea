/* SPDX-License-Identifier: MIT
 * A ground model for colouring points by their height above ground (no GL).
 *
 * How the ground is found: from a uniform subsample of the scene (the top levels of the
 * LOD tree, about a million points), on a grid of square cells sized for about eight
 * sampled points per cell (at most 1024 cells a side):
 * - when at least 1 % of the sample is classified ground (ASPRS class 2), a cell's
 *   ground is the lowest class-2 point in it;
 * - otherwise the lowest point of each cell, then a morphological opening with a
 *   square window STA_GROUND_OPENING_M wide (the lowest within the window, then the
 *   highest of those): roofs and canopies narrower than the window sink to the terrain
 *   beside them, while planar slopes come back unchanged;
 * - cells with nothing take the mean of their filled neighbours, ring by ring, then
 *   relax to the harmonic fill (the mean of their four neighbours), which keeps a planar
 *   slope planar across holes and under buildings.
 * Heights above ground are then z minus the ground bilinearly interpolated at (x, y).
 */
#ifndef STA_STREAM_GROUND_H
#define STA_STREAM_GROUND_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "core/status.h"
#include "format/strata_reader.h"
#include "stream/lod_tree.h"

/* Points sampled from the tree's top levels. */
#define STA_GROUND_SAMPLE_POINTS 1000000
/* Without ground classes: the opening's window, metres (wider than most buildings). */
#define STA_GROUND_OPENING_M     25.0

typedef struct sta_ground {
    double min[2];        /* world x, y of the grid's corner, metres */
    double cell_m;        /* cell edge, metres */
    int width, height;    /* cells */
    float *z;             /* width * height ground heights, metres above z_origin, row-major */
    double z_origin;      /* world z the heights are relative to (float precision) */
    bool from_class;      /* true: from class-2 points; false: lowest points, eroded */
    size_t sampled;       /* points the model was built from */
    double height_span_m; /* 98th percentile of the samples' heights above ground, in
                             2..100 m: the top of the height colour ramp */
} sta_ground;

/* One sampled point: world coordinates and its ASPRS class. */
typedef struct sta_ground_sample {
    double xyz[3];
    uint8_t classification;
} sta_ground_sample;

/* Builds the model from sampled points (the rule above). STA_ERR_ARG without points. */
sta_status sta_ground_from_samples(const sta_ground_sample *samples, size_t count, sta_ground *out,
                                   sta_error *err);

/* Builds the model from a .strata scene: decodes nodes level by level, from the root,
 * until STA_GROUND_SAMPLE_POINTS points. */
sta_status sta_ground_build(const sta_strata_reader *reader, const sta_lod_tree *tree,
                            sta_ground *out, sta_error *err);

/* Ground height (world z) at world (x, y), bilinear between cell centres, clamped at
 * the grid's edges. */
double sta_ground_at(const sta_ground *ground, double x, double y);

/* A zeroed model is a no-op. */
void sta_ground_release(sta_ground *ground);

#endif
