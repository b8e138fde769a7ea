/* SPDX-License-Identifier: MIT
 * Hidden point removal (HPR) in screen space: the CPU twin of shaders/hpr_*.comp, and
 * the definitions both sides share (pyramid sizes, parameters, level thresholds).
 *
 * Two operators label every pixel of a position buffer (screen_space.h) as VISIBLE or
 * HIDDEN (points) and BACKGROUND or HOLE (empty pixels):
 * - pyramidal and adaptive: a min-depth point pyramid, a neighbourhood level picked per
 *   pixel from a coarse depth (eq. 1), the 8-texel ring around the pixel's ancestor at
 *   every level 0..l (Figure 3);
 * - exhaustive: every pixel within a fixed square radius at full resolution.
 * Both take, in 8 sectors around the pixel, the minimum occlusion value
 * 1 - dot((y - x) / |y - x|, -y / |y|) of the neighbours y (each sector starts at 1,
 * fully open, so it counts at most 1), and call the pixel open when the mean of the 8
 * minima reaches a threshold. Issue 15 added: ring candidates landing farther than
 * STA_HPR_CUT_FACTOR K / z pixels from the pixel are dropped (a per-pixel decision),
 * and for empty pixels a sector whose neighbourhood leaves the image and that nothing
 * closes is unknown, not open (surfaces run on to the image edge); unless block_gaps, an
 * empty pixel's candidates close sectors by where they land, within 2^level pixels (hole and
 * background part along the points, not the pyramid's blocks). docs/HPR.md gives every
 * rule.
 *
 * Based on: H. Bouchiba, J.-E. Deschaud, F. Goulette, "Raw point cloud deferred
 * shading through screen space pyramidal operators", Eurographics 2018 (short), section 3.1,
 * eq. 1, Figure 3; R. Pintus, E. Gobbetti, M. Agus, "Real-time rendering of massive
 * unstructured raw point clouds using screen-space operators", VAST 2011 (the
 * exhaustive operator).
 */
#ifndef STA_RENDER_REF_HPR_REF_H
#define STA_RENDER_REF_HPR_REF_H

#include <stdbool.h>

#include "core/status.h"
#include "render/ref/image.h"
#include "render/ref/screen_space.h"

#define STA_HPR_MAX_LEVELS           16       /* pyramid levels; images up to 32768 px a side */
#define STA_HPR_DEFAULT_THRESHOLD    0.1f     /* mean sector occlusion of an open pixel */
#define STA_HPR_DEFAULT_S_HPR_FACTOR 10.0f    /* s_hpr = 10 s0 (the paper's value) */
#define STA_HPR_DEFAULT_COARSE_LEVEL 4        /* the paper's coarse depth level */
#define STA_HPR_DEFAULT_FAR_M        1.0e6f   /* depth given to background pixels, metres */
#define STA_HPR_MIN_LENGTH2_M2       1.0e-24f /* |y - x|^2 or |y|^2 below: neighbour skipped */
/* Sector borders lie at 22.5 deg + k 45 deg; tan(22.5 deg) ~ 408 / 985 (error 3.6e-7),
 * a ratio of integers so that the shader and the twin pick the same sector. */
#define STA_HPR_SECTOR_TAN_NUM       408
#define STA_HPR_SECTOR_TAN_DEN       985
#define STA_HPR_SQRT_HALF            0.70710678f /* sector directions on the diagonals */
/* Exhaustive operator: the image-border test of empty pixels looks this far, in
 * pixels: the radius, but at least 1.5 (the 8 direct neighbours always take part) and
 * at most 32. (The pyramidal operator counts the ring texels outside the image.) */
#define STA_HPR_MIN_REACH_PX         1.5f
#define STA_HPR_MAX_REACH_PX         32.0f
/* Pyramidal operator: ring candidates (levels >= 1) landing farther than this many
 * neighbourhood radii K / z from the pixel are dropped (per-pixel decision). */
#define STA_HPR_CUT_FACTOR           2.0f
/* Pyramidal operator, empty pixels: candidates of levels >= 1 count within this many
 * top-level blocks 2^level of the pixel at most (and within the cut above), where the
 * rings hold a candidate from every non-empty block whatever the pixel's place in its
 * ancestor blocks (issue 15, part 2, docs/HPR.md). */
#define STA_HPR_EMPTY_CUT_BLOCKS     1.0f
/* Pyramidal operator, empty pixels: a pixel without unknown sectors whose open sectors
 * form one run of at most this many also takes its top level's 5 x 5 texels within
 * twice the reach before it is called background: on a sparsely sampled surface (points
 * several pixels apart) a wedge finds no candidate within 2^level, in a gap more do
 * (issue 15, part 2, sixteenth round: sparse surfaces; docs/HPR.md "Empty pixels"). */
#define STA_HPR_EMPTY_WIDEN_OPEN     1
/* Pyramidal operator, empty pixels at the image border: the border rule (unknown sectors
 * left out of the mean) makes a hole only beside the data. When a flank of the unknown
 * sectors (an unknown sector next to a known one: for the top border, left and right) has
 * no candidate landing within 22.5 deg of its axis, also among its top level's 5 x 5
 * texels within twice the reach, and no candidate lands within this many neighbourhood
 * radii K / z (0.2: 2 s0 at the coarse depth), the unknown sectors count as open: the pixel
 * lies in open space between a silhouette and the border, not in a surface running
 * off-screen, whose points lie along the border beside it (issue 15, part 2, twentieth
 * round; docs/HPR.md "Empty pixels"). */
#define STA_HPR_EMPTY_NEAR_RADII     0.2f
/* ... and never nearer than this many pixels (small views, where K / z is a few pixels). */
#define STA_HPR_EMPTY_NEAR_MIN_PX    3.0f
/* Pyramidal operator, empty pixels: a candidate landing within this tangent of a sector's
 * axis closes the three sectors around that axis, not two (points on a regular grid
 * land on the axes, and rounding would pick either pair). */
#define STA_HPR_AXIS_TOL             0.015625f
/* Pyramidal operator, empty pixels: a sector is unknown (left out of the mean) when its
 * wedge leaves the image within the candidates' reach, but not farther than this, in
 * views up to STA_HPR_BORDER_HEIGHT_PX high, in proportion to the height above
 * (sta_hpr_empty_border_px): the border band, where surfaces running off-screen are to be
 * filled. 16 px (the band) left black triangles 11-25 px from the border where a
 * sparse surface's points lie farther apart than the band (README view, lower left); 24
 * px left some; 32 px at 1080 px of height too (the points lie farther apart in pixels);
 * the whole reach (up to 128 px) filled whole scan shadows that touch the image border
 * (street view 0's corner: depth p95 under the glass rule 2.76 -> 3.00 %); 32 px at 540:
 * 2.63 -> 2.70 % (docs/BENCHMARKS.md "Sixteenth round"). */
#define STA_HPR_EMPTY_BORDER_PX      32.0f
#define STA_HPR_BORDER_HEIGHT_PX     540
/* Sparse operator: a point copies its anchors' label only when every anchor's depth is
 * within this fraction of its own (no depth edge in the 2 x 2 neighbourhood). 0.005:
 * the error of the full operator to 0.3 % at the cost of 0.02 (docs/BENCHMARKS.md). */
#define STA_HPR_SPARSE_DEPTH_TAU     0.005f
/* Sparse operator: the operator runs on the pixels whose x and y are multiples of
 * this; copy steps with the strides STRIDE / 2, ..., 2, 1 fill the grids in between
 * (issue 15, eighth round: 8 cost 5 % less than 4 and the same errors, 16 no less). */
#define STA_HPR_ANCHOR_STRIDE        8
/* From this view height on the anchors lie STA_HPR_ANCHOR_STRIDE_HD apart (copy steps
 * 8, 4, 2, 1): at 1080 px the stride-16 anchors are as far apart in angle as the stride-8
 * ones at 540 px (issue 15, thirteenth round, docs/BENCHMARKS.md). */
#define STA_HPR_ANCHOR_STRIDE_HD     16
#define STA_HPR_ANCHOR_HD_HEIGHT_PX  1080
/* Pyramidal operator: a neighbour closes a sector only when it lies nearer than the
 * pixel's point by more than this many s0 (issue 15, part 2). Noise makes a surface
 * rough in depth, and the paper's operator let a point's own surface neighbours, a few
 * centimetres nearer, hide it (the far road, facades along the street); 1.5 s0 keeps
 * them (docs/HPR.md, docs/BENCHMARKS.md "Sixth round"). */
#define STA_HPR_OCCLUDER_GAP_S0      1.5f
/* Pyramidal operator: a marked point (a volumetric class, position w =
 * STA_POSITION_W_MARKED) closes a sector only when it lands within this many s0 of the
 * pixel's centre, measured on screen at the marked point's depth. Scattered returns
 * (canopy) hide what lies right behind them, but the gaps between them are no surface
 * (issue 15, fourteenth round, docs/HPR.md). */
#define STA_HPR_MARKED_REACH_S0      8.0f
/* Pyramidal operator, own-surface rule: a point whose direct neighbours (at least
 * STA_HPR_SURFACE_MIN_POINTS of the 8, spread so that the least-squares system's
 * determinant is at least STA_HPR_SURFACE_MIN_DET px^4) fit a plane through it, in
 * inverse depth over the screen, within STA_HPR_SURFACE_FIT_S0 s0 (root of the summed
 * squared residuals) lies on a surface; a neighbour then closes a sector only when it
 * lies nearer than that surface where it lands by more than
 * STA_HPR_SURFACE_FRONT_SHARE times that tolerance. Along a facade seen at a grazing
 * angle the facade's own nearer points no longer hide it. 6 s0 / 3 s0 from a sweep
 * (1.5 ... 48 s0) on the street: F1 rises up to 12 s0 and flattens, the bunny's far
 * view loses from 8 s0 on (issue 15, fourteenth round, second part, docs/HPR.md). */
#define STA_HPR_SURFACE_FIT_S0       6.0f
#define STA_HPR_SURFACE_FRONT_SHARE  0.5f
#define STA_HPR_SURFACE_MIN_POINTS   5
#define STA_HPR_SURFACE_MIN_DET      1.0f
/* Pyramidal operator, see-through returns (position w = STA_POSITION_W_SEE_THROUGH,
 * screen_space.h: window glass answers some pulses and lets the rest into the room):
 * they close a point's sectors only when a solid candidate is near, an occluding
 * (unmarked, not see-through) one of ring levels 0 .. STA_HPR_SOLID_LEVELS whose occlusion
 * value is below STA_HPR_SOLID_VALUE: a room point seen through the glass stays, one
 * behind the wall beside the window does not. Empty pixels take them as any point.
 * Levels 0 / 1 / 2 / 3 on street views 0 and 1: F1 0.9653 / 0.9690, 0.9645 / 0.9705,
 * 0.9644 / 0.9711, 0.9629 / 0.9713 (main 0.9615 / 0.9715; issue 15, sixteenth round,
 * docs/HPR.md). */
#define STA_HPR_SOLID_LEVELS         2
#define STA_HPR_SOLID_VALUE          0.5f

/* The empty pixels' border band for a view `height_px` pixels high (above). */
static inline float sta_hpr_empty_border_px(int height_px)
{
    return height_px > STA_HPR_BORDER_HEIGHT_PX
               ? STA_HPR_EMPTY_BORDER_PX * (float)height_px / (float)STA_HPR_BORDER_HEIGHT_PX
               : STA_HPR_EMPTY_BORDER_PX;
}

/* The sparse operator's anchor stride for a view `height_px` pixels high (above). */
static inline int sta_hpr_anchor_stride(int height_px)
{
    return height_px >= STA_HPR_ANCHOR_HD_HEIGHT_PX ? STA_HPR_ANCHOR_STRIDE_HD
                                                    : STA_HPR_ANCHOR_STRIDE;
}

/* Parameters. Zero means default (resolved by sta_hpr_params_defaults). A negative
 * threshold makes every pixel open (HPR off). s_hpr's default depends on the view: it
 * stays 0 after sta_hpr_params_defaults and sta_hpr_s_hpr_m derives it where used. */
typedef struct sta_hpr_params {
    float threshold;       /* a pixel is open when its mean sector occlusion >= this;
                              0: STA_HPR_DEFAULT_THRESHOLD */
    float s_hpr;           /* metric size of the neighbourhood (eq. 1), metres; 0: derived,
                              STA_HPR_DEFAULT_S_HPR_FACTOR * view s0 (sta_hpr_s_hpr_m) */
    int coarse_level;      /* pyramid level giving the coarse depth (eq. 1);
                              <= 0: STA_HPR_DEFAULT_COARSE_LEVEL */
    float far_m;           /* depth of background pixels, metres; <= 0 or not finite:
                              STA_HPR_DEFAULT_FAR_M */
    float occluder_gap_s0; /* pyramidal operator: a neighbour occludes only when its
                              depth is below the pixel's by more than this many s0;
                              0: STA_HPR_OCCLUDER_GAP_S0; < 0: every neighbour (the
                              paper's operator). The exhaustive operator has no gap */
    float marked_reach_s0; /* pyramidal operator: a marked point (volumetric class)
                              occludes only within this many s0 of the pixel's centre;
                              0: STA_HPR_MARKED_REACH_S0; < 0: at any distance, as an
                              unmarked point. The exhaustive operator has no reach */
    float surface_fit_s0;  /* pyramidal operator: the own-surface tolerance in s0 (above);
                              0: STA_HPR_SURFACE_FIT_S0; < 0: off (a neighbour is compared
                              with the pixel's depth only). The exhaustive operator has none */
    bool sparse;           /* pyramidal operator on the even (x, y) anchors, the other pixels
                              copy agreeing anchors or are refined (sta_hpr_ref_sparse_labels);
                              false (default): every pixel */
    bool block_gaps;       /* pyramidal operator: an empty pixel's hole / background decision
                              by ring position, along the pyramid's blocks (the rule before
                              issue 15 part 2; gaps' borders step along block lines); false
                              (default): per pixel, sectors by where candidates land
                              (docs/HPR.md "Empty pixels: sectors by landing") */
    bool no_see_through;   /* pyramidal operator: the positions hold no see-through returns
                              (from depth: only the compute rasteriser's resolve writes
                              them), so the see-through rule is left out (the pass compiles
                              programs without it) and a position with w =
                              STA_POSITION_W_SEE_THROUGH counts as any drawn point; false
                              (default): the rule on */
} sta_hpr_params;

/* Fills threshold, coarse_level, far_m, occluder_gap_s0 and marked_reach_s0 of `config` with their
 * defaults where they are zero (or, as documented above, out of range), in place; other fields stay
 * as they are. s_hpr stays 0 when it is 0 (its default needs the view). */
void sta_hpr_params_defaults(sta_hpr_params *config);

/* s_hpr in metres: config->s_hpr, or STA_HPR_DEFAULT_S_HPR_FACTOR * view->s0 when it
 * is 0. */
float sta_hpr_s_hpr_m(const sta_view_params *view, const sta_hpr_params *config);

/* The occluder gap in metres (sta_hpr_params.occluder_gap_s0 times view->s0) of
 * `resolved` parameters; -FLT_MAX when the gap is off (negative) or s0 is not positive,
 * so that every neighbour takes part. A neighbour y of a pixel whose centre point has
 * depth d is a candidate only when -y.z < d - gap. */
float sta_hpr_occluder_gap_m(const sta_view_params *view, const sta_hpr_params *resolved);

/* A marked neighbour's reach as pixels times metres (`resolved`
 * marked_reach_s0 * view->s0 * the view's pixels per unit of y / d): at depth d it
 * reaches this / d pixels. FLT_MAX when the reach is off (negative) or s0 is not
 * positive. */
float sta_hpr_marked_reach_px_m(const sta_view_params *view, const sta_hpr_params *resolved);

/* The own-surface tolerance in metres (surface_fit_s0 * view->s0); 0 when the rule is
 * off (negative) or s0 is not positive. */
float sta_hpr_surface_tol_m(const sta_view_params *view, const sta_hpr_params *resolved);

/* Number of pyramid levels for a width x height image, level 0 (the image) included:
 * max(2, 1 + ceil(log2(max(width, height)))), so the last level is 1 x 1 and level 1
 * always exists. 0 when a size is < 1 or the count would exceed STA_HPR_MAX_LEVELS. */
int sta_hpr_pyramid_levels(int width_px, int height_px);

/* Size of `level` along one axis: max(1, ceil(size / 2^level)). */
static inline int sta_hpr_level_size(int size_px, int level)
{
    return (size_px + (1 << level) - 1) >> level;
}

/* K = s_hpr h / (2 tan(fov_y / 2)) (0 when s_hpr is 0 or not finite): a pixel of
 * coarse depth z has the neighbourhood radius K / z pixels (eq. 1). `resolved`:
 * parameters after sta_hpr_params_defaults. */
float sta_hpr_radius_k(const sta_view_params *view, const sta_hpr_params *resolved);

/* The depths at which the adaptive level changes: out[l] (l = 1 .. level_count - 1) is
 * K 2^(0.5 - l) with K = sta_hpr_radius_k; a pixel of coarse depth z gets the largest
 * l with z <= out[l] (0 when none), i.e. round(log2(K / z)) clamped to
 * [0, level_count - 1], computed by comparisons so that shader and twin agree exactly.
 * out[0] = +inf (unused). `resolved`: parameters after sta_hpr_params_defaults; s_hpr
 * is sta_hpr_s_hpr_m of them. */
void sta_hpr_level_depths(const sta_view_params *view, const sta_hpr_params *resolved,
                          int level_count, float out_depth_m[STA_HPR_MAX_LEVELS]);

/* The sector (0..7, counter-clockwise from +x, each 45 deg wide and centred on a
 * multiple of 45 deg) of the screen direction (vx2, vy2), given in half pixels (twice
 * the direction between pixel centres, hence integers). (0, 0) gives 0. */
int sta_hpr_sector(int vx2, int vy2);

/* The point pyramid: levels[0] is a copy of the position image, levels[l] (RGBA, size
 * sta_hpr_level_size of level l-1's size) keeps, for each pixel (i, j), the point of
 * least depth among the points (w > 0.5) of level l-1's pixels {2i, 2i+1} x {2j, 2j+1}
 * inside level l-1 (first in the order (2i,2j), (2i+1,2j), (2i,2j+1), (2i+1,2j+1) on a
 * tie), or zeros when the block holds none. */
typedef struct sta_hpr_pyramid {
    int level_count;                      /* sta_hpr_pyramid_levels of level 0 */
    sta_image levels[STA_HPR_MAX_LEVELS]; /* [0, level_count) allocated */
} sta_hpr_pyramid;

/* Builds the pyramid of `position` (4 channels). Errors: STA_ERR_ARG (image too large
 * or not RGBA), STA_ERR_NOMEM. On failure *out is zeroed. */
sta_status sta_hpr_ref_build_pyramid(const sta_image *position, sta_hpr_pyramid *out,
                                     sta_error *err);

/* Frees the levels; a zeroed pyramid is a no-op. */
void sta_hpr_ref_pyramid_release(sta_hpr_pyramid *pyramid);

/* The pyramidal adaptive operator on a built pyramid. out_label: initialised 1-channel
 * image of level 0's size, receives STA_LABEL_*. out_mean, out_level (may be NULL;
 * 1 channel, same size): each pixel's mean sector occlusion and neighbourhood level,
 * for tests and inspection. view: width_px/height_px must be the image's size. */
void sta_hpr_ref_pyramid_labels(const sta_view_params *view, const sta_hpr_params *params,
                                const sta_hpr_pyramid *pyramid, sta_image *out_label,
                                sta_image *out_mean, sta_image *out_level);

/* The sparse operator's copy steps (twin of hpr_sparse_classify.comp): `full_label`
 * holds the pyramidal labels of every pixel (the anchors and the refined pixels get
 * exactly those). On the grids of pixels whose x and y are multiples of
 * sta_hpr_anchor_stride(height) / 2, ..., 2, 1 in turn: each pixel of the grid that is
 * not one of its anchors (x and y multiples of twice the grid's step) copies the label of its
 * up to 4 nearest anchors (clamped to the grid) of its own kind (point: visible /
 * hidden; empty: hole / background) when there is at least one, they all agree and,
 * for a point, each one's depth is within STA_HPR_SPARSE_DEPTH_TAU of its own; else it
 * keeps its full label (refined). In all steps but the last every point is refined. A
 * step's anchors carry the labels of the steps before. out_label: same size. Returns
 * the refined pixel count (all steps). */
int sta_hpr_ref_sparse_labels(const sta_image *position, const sta_image *full_label,
                              sta_image *out_label);

/* Builds the pyramid and labels `position` with it (the whole pyramidal operator). */
sta_status sta_hpr_ref_pyramid(const sta_view_params *view, const sta_hpr_params *params,
                               const sta_image *position, sta_image *out_label, sta_error *err);

/* The exhaustive operator: neighbours are all pixels (dx, dy) != (0, 0) with |dx|, |dy|
 * <= radius_px inside the image. Uses params->threshold and far_m only. out_label and
 * out_mean (may be NULL) as above. */
void sta_hpr_ref_exhaustive(const sta_view_params *view, const sta_hpr_params *params,
                            int radius_px, const sta_image *position, sta_image *out_label,
                            sta_image *out_mean);

#endif
