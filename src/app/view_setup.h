/* SPDX-License-Identifier: MIT
 * What window and headless viewing share: the initial camera and colour mode.
 */
#ifndef STA_APP_VIEW_SETUP_H
#define STA_APP_VIEW_SETUP_H

#include "app/view_options.h"
#include "core/camera.h"
#include "format/strata.h"

/* The camera the arguments ask for (or the whole scene, from the south-west). */
void sta_view_initial_camera(const sta_view_args *args, const sta_strata_info *info,
                             sta_camera *out_camera);

/* The colour mode asked for, or the best default for the scene's attributes. */
int sta_view_initial_colour(const sta_view_args *args, const sta_strata_info *info);

#endif
