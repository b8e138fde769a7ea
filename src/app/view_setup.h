/* SPDX-License-Identifier: MIT
 * What window and headless viewing share: the initial camera and colour mode.
 */
#ifndef STA_APP_VIEW_SETUP_H
#define STA_APP_VIEW_SETUP_H

#include "app/view_options.h"
#include "core/camera.h"
#include "format/strata.h"
#include "render/pipeline.h"

/* The camera the arguments ask for, or one framing `frame_min`..`frame_max` (the
 * scene's robust bounds) from the south-west, 30 degrees from above. */
void sta_view_initial_camera(const sta_view_args *args, const sta_strata_info *info,
                             const double frame_min[3], const double frame_max[3],
                             sta_camera *out_camera);

/* The screen-space pipeline options the arguments ask for. */
void sta_view_pipeline_options(const sta_view_args *args, sta_pipeline_options *out);

/* The colour mode asked for, or the best default for the scene's attributes. */
int sta_view_initial_colour(const sta_view_args *args, const sta_strata_info *info);

#endif
