/* SPDX-License-Identifier: MIT
 * CPU twin of the pyramidal normal estimator (shaders/normals_pyramid_level.comp and
 * shaders/normals_pyramid_gather.comp).
 *
 * Based on: H. Bouchiba et al., "Raw point cloud deferred shading through screen space
 * pyramidal operators", Eurographics 2018, section 3.3. docs/PULLPUSH.md states every
 * choice made here.
 *
 * 1. On every level of the filled pull-push pyramid (level 0: the filled output), a
 *    normal per texel from the cross product of the differences between neighbouring
 *    points: central differences where both neighbours exist, one-sided otherwise,
 *    oriented towards the camera. A neighbour more than jump_ratio times as far from
 *    the point as the other neighbour and as the texel's footprint (2^l * depth /
 *    pixels per metre at unit depth) lies across a depth discontinuity: the near side
 *    alone is used (one-sided).
 * 2. Per target pixel with a filled point p (w > 0): radius r_px = r_n * pixels per
 *    metre at depth -p.z, r_n = radius_s0 * s0; fractional level
 *    lambda = clamp(log2(max(r_px, 1)), 0, count - 1); bilinear interpolation inside
 *    levels floor(lambda) and floor(lambda) + 1 (clamped), each normalised, then
 *    linear interpolation between them by the fraction of lambda; normalised and
 *    oriented towards the camera.
 * 3. No mixing across depth discontinuities: a texel of level l >= 1 takes part only
 *    when p lies within plane_tolerance texel footprints (2^l * depth / pixels per
 *    metre at unit depth) of the texel's tangent plane (its normal through its point).
 *    Where no texel of the two levels passes, the next finer level that has one is
 *    used, down to level 0 (the pixel's own normal, whose plane holds p). Two levels
 *    whose normals disagree (dot below 1 - spread: a crease, or a second surface inside
 *    the coarser level's radius) are not mixed: the finer one is used (issue 15,
 *    fifteenth round). The finer level la itself is checked the same way against the
 *    level below it, la - 1, when that is no finer than the anchor level a of step 4
 *    (sta_normals_anchor_level, at every resolution): where they disagree by more than
 *    fine_spread, la's normal fades into la - 1's (its texels reached a crease or a sparse
 *    face's surroundings that la - 1's do not; issue 15, sixteenth round).
 * At half resolution (half_resolution; issue 20: the gather is most of the pass's cost,
 * and it is per pixel):
 * 4. Steps 2-3 on the anchors only, the pixels (s i, s j) with s = 2^a, a the anchor level
 *    (sta_normals_anchor_level: 1 below 1080 px of view height, 2 from 1080, 3 from 2160;
 *    issue 15, eleventh round), giving a ceil(W / s) x ceil(H / s) image of normals and
 *    their tangent planes.
 * 5. Every pixel with a point p: bilinear interpolation of the anchors around it (anchor
 *    (i, j) sits at pixel (s i, s j): weights k / s per axis; clamped at the far borders),
 *    counting only anchors whose tangent plane passes within plane_tolerance texel
 *    footprints of p at level max(a, floor(lambda)) (step 3's finer level at p, at
 *    least level a, the anchors' spacing); where none does, the normal of the anchor of non-zero
 * weight whose plane passes nearest to p (the first in row order on ties; none where no anchor has
 * one); normalised and oriented towards the camera.
 */
#ifndef STA_RENDER_REF_NORMALS_PYRAMID_REF_H
#define STA_RENDER_REF_NORMALS_PYRAMID_REF_H

#include <stdbool.h>

#include "core/status.h"
#include "render/ref/image.h"
#include "render/ref/pullpush_ref.h"
#include "render/ref/screen_space.h"

/* Default metric radius r_n, in units of the view's s0 (sta_normals_pyramid_params_defaults). */
#define STA_NORMALS_PYRAMID_DEFAULT_RADIUS_S0       3.0f
/* Default plane test: a texel's tangent plane may miss the pixel's point by this many
 * texel footprints (step 3 above). 0.25 since issue 15's eighth round: with the fill on
 * one surface at depth edges, a tighter test gains on every normal median and on the
 * closed models' p95 (docs/BENCHMARKS.md); 0.5 before. */
#define STA_NORMALS_PYRAMID_DEFAULT_PLANE_TOLERANCE 0.25f
/* Default agreement test of step 3: two levels' normals are mixed only when their dot
 * product is at least 1 - spread (0.01: about 8 degrees apart). Chosen on the street and
 * the closed models (issue 15, fifteenth round, docs/BENCHMARKS.md). */
#define STA_NORMALS_PYRAMID_DEFAULT_SPREAD          0.01f
/* Default check of step 3's finer level against the level below it: mixed in from a dot
 * product below 1 - fine_spread (0.03: about 14 degrees), alone at 1 - 2 fine_spread.
 * Wider than spread: the level below is noisier, and at 0.01 the street's medians rose 5 %
 * and the far view's p95 3.1 -> 4.8 degrees (issue 15, sixteenth round, docs/BENCHMARKS.md). */
#define STA_NORMALS_PYRAMID_DEFAULT_FINE_SPREAD     0.03f
/* Default jump ratio of step 1. */
#define STA_NORMALS_PYRAMID_DEFAULT_JUMP_RATIO      2.5f
/* Steps 4-5: the anchors are the pixels whose x and y are multiples of 2^a, a = the
 * anchor level: 1 (every even pixel) below this view height, one more for each doubling
 * of it (1080 px: every 4th pixel), up to STA_NORMALS_ANCHOR_MAX_LEVEL. The anchors then
 * keep about the same angular spacing: the gather on every 4th pixel at 1920x1080 gave
 * the errors of every even pixel there to 0.6 %, on every 4th pixel of 960x540 it did
 * not (issue 15, eleventh round, docs/BENCHMARKS.md). */
#define STA_NORMALS_ANCHOR_HEIGHT_PX                540
#define STA_NORMALS_ANCHOR_MAX_LEVEL                3

/* The anchor level of steps 4-5 for a view `height_px` pixels high (above). */
static inline int sta_normals_anchor_level(int height_px)
{
    int level = 1;
    while (level < STA_NORMALS_ANCHOR_MAX_LEVEL &&
           height_px >= (STA_NORMALS_ANCHOR_HEIGHT_PX << level)) {
        level++;
    }
    return level;
}

/* Zero (or negative) fields mean their defaults. */
typedef struct sta_normals_pyramid_params {
    float radius_s0;       /* metric radius r_n in units of the view's s0; <= 0 (or NaN):
                              STA_NORMALS_PYRAMID_DEFAULT_RADIUS_S0 */
    float plane_tolerance; /* step 3, in texel footprints; <= 0 (or NaN):
                              STA_NORMALS_PYRAMID_DEFAULT_PLANE_TOLERANCE; +INFINITY turns
                              the test off (the estimator before issue 15) */
    float jump_ratio;      /* step 1; below 1 (or NaN): STA_NORMALS_PYRAMID_DEFAULT_JUMP_RATIO;
                              +INFINITY: no jump test (before issue 15) */
    float spread;          /* step 3's agreement test; <= 0 (or NaN):
                              STA_NORMALS_PYRAMID_DEFAULT_SPREAD; +INFINITY turns it off
                              (the estimator before issue 15's fifteenth round) */
    float fine_spread;     /* step 3's check of the finer level against the one below; <= 0
                              (or NaN): STA_NORMALS_PYRAMID_DEFAULT_FINE_SPREAD; +INFINITY
                              turns it off (before issue 15's sixteenth round) */
    bool half_resolution;  /* steps 4-5 instead of 2-3 on every pixel (default false) */
} sta_normals_pyramid_params;

/* Fills the zero (or negative, or NaN) fields of `config` with the defaults above, in
 * place; other fields stay as they are. */
void sta_normals_pyramid_params_defaults(sta_normals_pyramid_params *config);

/* r_n times H / (2 tan(fov_y / 2)), so that r_px = result / depth. params must have
 * been through sta_normals_pyramid_params_defaults. The GL pass passes exactly this
 * float to its shader. */
static inline float sta_normals_pyramid_radius_px_m(const sta_view_params *view,
                                                    const sta_normals_pyramid_params *params)
{
    float ppm_scale = (float)view->height_px / (2.0f * tanf(0.5f * view->fov_y));
    return params->radius_s0 * view->s0 * ppm_scale;
}

/* A level-l texel's footprint per metre of depth: 2^l / (H / (2 tan(fov_y / 2))). The GL
 * pass passes exactly this float to its shaders. */
static inline float sta_normals_pyramid_texel_m(const sta_view_params *view, int level)
{
    float ppm_scale = (float)view->height_px / (2.0f * tanf(0.5f * view->fov_y));
    return (float)(1 << level) / ppm_scale;
}

/* plane_tolerance / (H / (2 tan(fov_y / 2))): a level-l texel's tolerance in metres is
 * result * 2^l * depth. The GL pass passes exactly this float to its shader. */
static inline float sta_normals_pyramid_plane_tolerance_m(const sta_view_params *view,
                                                          const sta_normals_pyramid_params *params)
{
    float ppm_scale = (float)view->height_px / (2.0f * tanf(0.5f * view->fov_y));
    return params->plane_tolerance / ppm_scale;
}

/* 1 - spread: the least dot product of two levels' normals that are mixed (step 3;
 * -INFINITY with the test off).
 * The GL pass passes exactly this float to its shader. */
static inline float sta_normals_pyramid_coherence(const sta_normals_pyramid_params *params)
{
    return 1.0f - params->spread;
}

/* 1 - fine_spread, the same for step 3's check of the finer level (-INFINITY: off). The GL
 * pass passes exactly this float to its shader. */
static inline float sta_normals_pyramid_fine_coherence(const sta_normals_pyramid_params *params)
{
    return 1.0f - params->fine_spread;
}

/* Normals of one level from its points (4 channels, w > 0 where a point is): `out` is
 * an initialised 4-channel image of the same size, receiving xyz unit normals facing
 * the camera with w = 1, or zeros where none can be made. jump_ratio (INFINITY: no
 * jump test) and texel_m (sta_normals_pyramid_texel_m): step 1. */
void sta_normals_pyramid_level_ref(const sta_image *points, float jump_ratio, float texel_m,
                                   sta_image *out);

/* The whole estimator. params: NULL for the defaults. levels: the pull-push pyramid
 * of the same view (levels 1..count-1); filled_position: the pull-push output (level
 * 0). out_normal: initialised 4-channel image of the view size, written per
 * screen_space.h (xyz unit normal facing the camera, w = 1 valid / 0 none). Errors:
 * STA_ERR_ARG for sizes that do not match the view, STA_ERR_NOMEM. */
sta_status sta_normals_pyramid_ref(const sta_view_params *view,
                                   const sta_normals_pyramid_params *params,
                                   const sta_pullpush_levels *levels,
                                   const sta_image *filled_position, sta_image *out_normal,
                                   sta_error *err);

#endif
