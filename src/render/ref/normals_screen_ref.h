/* SPDX-License-Identifier: MIT
 * Screen-space normals of Schiffner et al. (local derivatives, plane fits, covariance
 * tensor) and their optional smoothing pass: the parameters shared with the GL pass
 * (render/pass_normals_screen.h) and the CPU twins of shaders/normals_screen.comp and
 * shaders/normals_smooth.comp.
 *
 * Based on: D. Schiffner, M. Ritter, W. Benger, "Fast Normal Approximation of Point
 * Clouds in Screen Space", WSCG 2015 (sec. 3: sampling schemes, LD, plane
 * approximation, tensor information, smoothing). docs/NORMALS.md gives the exact
 * sample offsets, weights and thresholds.
 *
 * Input: a position buffer (screen_space.h: RGBA32F camera space; w > 0 marks a valid
 * position: 1 from unproject, the coverage from pull-push). Output: a normal buffer
 * (RGBA32F, xyz a unit camera-space normal with dot(n, -p) >= 0, w = 1; all zero where
 * no normal could be estimated). Out-of-image samples count as missing.
 */
#ifndef STA_RENDER_REF_NORMALS_SCREEN_REF_H
#define STA_RENDER_REF_NORMALS_SCREEN_REF_H

#include "core/status.h"
#include "render/ref/image.h"
#include "render/ref/screen_space.h"

/* Estimators (Schiffner et al.'s names). */
typedef enum sta_normals_screen_method {
    STA_NORMALS_SCREEN_DEFAULT = 0, /* resolves to STA_NORMALS_SCREEN_DEFAULT_METHOD */
    STA_NORMALS_SCREEN_LD = 1,      /* local derivatives: right/up differences */
    STA_NORMALS_SCREEN_PD = 2,      /* plane fit from diagonal (opposite) sample pairs */
    STA_NORMALS_SCREEN_PC = 3,      /* plane fit from counter-clockwise sample fans */
    STA_NORMALS_SCREEN_TI = 4,      /* tensor information: weighted covariance eigenvector */
    STA_NORMALS_SCREEN_METHOD_COUNT = 5
} sta_normals_screen_method;

/* Defaults (sta_normals_screen_params_defaults, sta_normals_screen_max_distance2). */
#define STA_NORMALS_SCREEN_DEFAULT_METHOD      STA_NORMALS_SCREEN_TI
#define STA_NORMALS_SCREEN_DEFAULT_SAMPLES     9
#define STA_NORMALS_SCREEN_DEFAULT_DISTANCE_S0 5.0f /* max_distance_m = this * view s0 */

/* Zero fields mean the defaults (sta_normals_screen_params_defaults). max_distance_m's
 * default depends on the view: it stays 0 after sta_normals_screen_params_defaults and
 * sta_normals_screen_max_distance2 derives it where used. */
typedef struct sta_normals_screen_params {
    int method;           /* sta_normals_screen_method; 0: STA_NORMALS_SCREEN_DEFAULT_METHOD */
    int samples;          /* sampling scheme: 5, 9, 17 or 25 samples;
                             0: STA_NORMALS_SCREEN_DEFAULT_SAMPLES; LD ignores it */
    float max_distance_m; /* neighbours farther than this from the centre (3D, metres) are
                             rejected; 0: derived, STA_NORMALS_SCREEN_DEFAULT_DISTANCE_S0 *
                             view s0 (no limit when s0 <= 0); < 0: no limit */
} sta_normals_screen_params;

/* Fills method and samples of `config` with their defaults where they are zero, in
 * place; other fields stay as they are. max_distance_m stays 0 when it is 0 (its
 * default needs the view). */
void sta_normals_screen_params_defaults(sta_normals_screen_params *config);

/* Validates `config`, before or after sta_normals_screen_params_defaults. Errors:
 * STA_ERR_ARG for an unknown method, a sample count other than 0/5/9/17/25, or a NaN
 * distance. */
sta_status sta_normals_screen_params_check(const sta_normals_screen_params *config, sta_error *err);

/* The squared distance limit the twin and the shader compare with: max_distance_m^2,
 * with 0 resolved from the view's s0 as documented above, and FLT_MAX when there is no
 * limit. */
float sta_normals_screen_max_distance2(const sta_view_params *view,
                                       const sta_normals_screen_params *config);

/* "LD", "PD", "PC", "TI" (or "?") for reports. */
const char *sta_normals_screen_method_name(int method);

/* Estimates normals. position: 4 channels; out: an initialised 4-channel image of the
 * same size, overwritten. view supplies s0 for the default distance. Errors:
 * STA_ERR_ARG for bad parameters or image shapes. */
sta_status sta_normals_screen_ref(const sta_view_params *view,
                                  const sta_normals_screen_params *params,
                                  const sta_image *position, sta_image *out, sta_error *err);

/* The smoothing (correction) pass: each pixel with a valid position gets the
 * renormalised weighted mean of the valid normals in its 3x3 neighbourhood whose
 * positions lie within the maximum distance (weights 4 centre, 2 edge, 1 corner), so
 * it also fills pixels where the estimator found none. normal and out: 4-channel
 * images of the position's size; out must not alias normal. Errors: STA_ERR_ARG. */
sta_status sta_normals_smooth_ref(const sta_view_params *view,
                                  const sta_normals_screen_params *params,
                                  const sta_image *position, const sta_image *normal,
                                  sta_image *out, sta_error *err);

#endif
