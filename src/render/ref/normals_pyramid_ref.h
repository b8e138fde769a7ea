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
 *    oriented towards the camera.
 * 2. Per target pixel with a filled point p (w > 0): radius r_px = r_n * pixels per
 *    metre at depth -p.z, r_n = radius_s0 * s0; fractional level
 *    lambda = clamp(log2(max(r_px, 1)), 0, count - 1); bilinear interpolation inside
 *    levels floor(lambda) and floor(lambda) + 1 (clamped), each normalised, then
 *    linear interpolation between them by the fraction of lambda; normalised and
 *    oriented towards the camera.
 */
#ifndef STA_RENDER_REF_NORMALS_PYRAMID_REF_H
#define STA_RENDER_REF_NORMALS_PYRAMID_REF_H

#include "core/status.h"
#include "render/ref/image.h"
#include "render/ref/pullpush_ref.h"
#include "render/ref/screen_space.h"

/* Default metric radius r_n, in units of the view's s0 (sta_normals_pyramid_params_defaults). */
#define STA_NORMALS_PYRAMID_DEFAULT_RADIUS_S0 3.0f

/* Zero (or negative) fields mean their defaults. */
typedef struct sta_normals_pyramid_params {
    float radius_s0; /* metric radius r_n in units of the view's s0; <= 0 (or NaN):
                        STA_NORMALS_PYRAMID_DEFAULT_RADIUS_S0 */
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

/* Normals of one level from its points (4 channels, w > 0 where a point is): `out` is
 * an initialised 4-channel image of the same size, receiving xyz unit normals facing
 * the camera with w = 1, or zeros where none can be made. */
void sta_normals_pyramid_level_ref(const sta_image *points, sta_image *out);

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
