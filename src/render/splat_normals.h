/* SPDX-License-Identifier: MIT
 * The normals the splat pass drew, per pixel: for the benchmark's normal error of the
 * splats method (the screen-space pipeline has its normal buffer; splats are shaded in
 * their fragment shader and keep none). Each pixel's point id (render target) picks
 * its record in the splat arena (read back once), decoded as the shader decodes it.
 * Main thread (GL) only.
 */
#ifndef STA_RENDER_SPLAT_NORMALS_H
#define STA_RENDER_SPLAT_NORMALS_H

#include "core/camera.h"
#include "core/status.h"
#include "render/gpu_cache.h"
#include "render/ref/image.h"
#include "render/target.h"

/* Fills `out` (initialised here: target size, 4 channels, row 0 at the bottom as GL
 * textures) with the unit camera-space normal of the splat in each pixel, turned to
 * face the camera, w = 1; zeros where nothing was drawn. `cache` must hold splats. */
sta_status sta_splat_normal_image(const sta_gpu_cache *cache, const sta_render_target *target,
                                  const sta_camera *camera, sta_image *out, sta_error *err);

#endif
