/* SPDX-License-Identifier: MIT
 * Offline visibility reference: the hidden point removal (HPR) operator of Katz et al.
 * (spherical flipping, then the convex hull of the flipped points and the viewpoint,
 * computed with Qhull's reentrant library), optionally with the random perturbation of
 * Braga et al. Used by the benchmark to score the screen-space HPR pass; not real time.
 *
 * Based on: S. Katz, A. Tal, R. Basri, "Direct Visibility of Point Sets", ACM TOG 26(3),
 * 2007 (spherical flipping, eq. 1; visible iff the flipped point is on the hull);
 * R. Braga et al. (PUC-Rio), "Evaluating the visibility algorithm of point-based graphics
 * for real-time applications", section 4 (perturbation of 0.01 of the sphere radius).
 * Decisions on degenerate input and the Qhull options are in docs/KATZ.md.
 */
#ifndef STA_VISIBILITY_KATZ_HPR_H
#define STA_VISIBILITY_KATZ_HPR_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "core/status.h"

/* Default R / max ||p_i - C|| (Katz's 10^gamma with gamma = 2), see docs/KATZ.md. */
#define STA_KATZ_DEFAULT_RADIUS_FACTOR 100.0

/* With an absolute radius (radius_m), R is at least this many times the farthest point:
 * the sphere must hold every point for the flip to turn near into far. */
#define STA_KATZ_MIN_RADIUS_FACTOR 2.0

/* Default seed of the perturbation. */
#define STA_KATZ_DEFAULT_SEED 1

/* Braga et al.'s perturbation: each coordinate moves by up to 0.01 of the model's radius. */
#define STA_KATZ_BRAGA_PERTURBATION 0.01

/* Parameters. Zero means default (sta_katz_params_defaults); the default perturbation
 * is none, so the defaults give the exact operator. */
typedef struct sta_katz_params {
    double radius_factor; /* R = radius_factor * max ||p_i - C|| (Katz: 10^gamma); > 1, or
                             0 for STA_KATZ_DEFAULT_RADIUS_FACTOR; unused when radius_m > 0 */
    double radius_m;      /* 0 (the default): R from radius_factor; else R itself, in input
                             units (at least STA_KATZ_MIN_RADIUS_FACTOR times the farthest
                             point); sta_katz_view_radius gives it for a rendered view */
    double perturbation;  /* 0 (the default): none; else each coordinate moves by a uniform
                             random amount in [-a, a], a = perturbation * the model's radius
                             (half the diagonal of its bounding box); in [0, 1]; Braga et
                             al.: STA_KATZ_BRAGA_PERTURBATION */
    uint64_t seed;        /* seed of the perturbation (splitmix64); 0: STA_KATZ_DEFAULT_SEED */
} sta_katz_params;

/* Degenerate-input handling that a call used (bits of sta_katz_stats.degenerate). */
enum {
    STA_KATZ_AT_VIEWPOINT = 1u << 0, /* points exactly at the viewpoint: visible, not hulled */
    STA_KATZ_DUPLICATES = 1u << 1,   /* repeated points: hulled once, flag copied */
    STA_KATZ_FEW_POINTS = 1u << 2,   /* fewer than 4 distinct points: all visible, no hull */
    STA_KATZ_PLANE = 1u << 3,        /* flipped points and viewpoint in one plane: 2-d hull */
    STA_KATZ_LINE = 1u << 4,         /* all on one line through the viewpoint: 1-d hull */
    STA_KATZ_JOGGLE = 1u << 5,       /* Qhull reported a precision error; rerun with "QJ" */
};

/* What a call did and what it cost. */
typedef struct sta_katz_stats {
    double hull_ms;            /* wall time inside Qhull (all attempts), milliseconds */
    double hull_cpu_ms;        /* CPU time of this thread inside Qhull, milliseconds */
    double total_ms;           /* wall time of the whole call, milliseconds */
    double radius;             /* R used, in input units */
    double perturbation_abs;   /* a: half-width of the perturbation, input units (0: none) */
    size_t hull_input_count;   /* distinct points given to the hull, viewpoint not counted */
    size_t hull_vertex_count;  /* of those, hull vertices (visible), viewpoint not counted */
    size_t duplicate_count;    /* points equal to an earlier one; they take its flag */
    size_t at_viewpoint_count; /* points exactly at the viewpoint (visible, not hulled) */
    size_t visible_count;      /* flags set in out_visible */
    int hull_dim;              /* 3, 2 (STA_KATZ_PLANE), 1 (STA_KATZ_LINE) or 0 (no hull) */
    unsigned degenerate;       /* STA_KATZ_* bits */
    char qhull_options[32];    /* the Qhull command of the hull that was used ("" if none) */
} sta_katz_stats;

/* Fills the zero fields of `config` with their defaults, in place (radius_factor,
 * seed; perturbation's default is 0); other fields stay as they are. A zeroed struct
 * becomes the exact operator. */
void sta_katz_params_defaults(sta_katz_params *config);

/* Katz's sphere radius for points sampled on a pixel grid (docs/KATZ.md, "Choosing R"):
 * R = depth_tolerance_m / pixel_angle_rad^2. With spherical flipping, a point between two
 * neighbours an angle a apart on either side stays a hull vertex while it lies less than
 * about R a^2 / 2 behind their mean depth (the flipped sheet has radius ~2R); so R sets the
 * depth step, at the sampling's angular pitch, that still counts as one surface. A fixed
 * ratio R / max ||p - C|| therefore hides ever more of a surface as the pitch shrinks (4x
 * less tolerance per doubling of resolution): the recall loss of Katz at large image
 * sizes. depth_tolerance_m: the depth roughness to accept as surface (metres, > 0), e.g.
 * a few sampling spacings plus the noise; pixel_angle_rad: the angle of one pixel
 * (vertical field of view / height, > 0). Returns 0 for arguments out of range. */
double sta_katz_view_radius(double depth_tolerance_m, double pixel_angle_rad);

/* Marks which of `count` points are visible from `viewpoint` by HPR: out_visible[i] is 1
 * when the spherically flipped point i is a vertex of the convex hull of all flipped
 * points and the viewpoint, else 0. Points exactly at the viewpoint are visible; equal
 * points get the same flag; fewer than 4 distinct points are all visible; flat and
 * collinear configurations use a hull of lower dimension (docs/KATZ.md).
 * points: borrowed, count xyz triples (NULL when count is 0); viewpoint: xyz;
 * params: NULL for all defaults (the exact operator); out_visible: count bytes, written only
 * on success; out_stats: may be NULL. Deterministic for given inputs and seed.
 * Returns STA_ERR_ARG for NaN or infinite coordinates (naming the point and value),
 * bad parameters or more than INT_MAX - 1 points; STA_ERR_NOMEM; STA_ERR_UNSUPPORTED
 * when Qhull fails even with joggle (with Qhull's message). Qhull prints nothing and
 * never exits the process. Thread-safe: each call owns its Qhull context. */
sta_status sta_katz_visible(const double (*points)[3], size_t count, const double viewpoint[3],
                            const sta_katz_params *params, uint8_t *out_visible,
                            sta_katz_stats *out_stats, sta_error *err);

#endif
