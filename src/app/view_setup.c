/* SPDX-License-Identifier: MIT
 * Initial camera and colour. */
#include "app/view_setup.h"

#include <math.h>
#include <string.h>

#include "render/bindings.h"

static const double degrees = 3.14159265358979323846 / 180.0;

void sta_view_initial_camera(const sta_view_args *args, const sta_strata_info *info,
                             const double frame_min[3], const double frame_max[3], sta_camera *c)
{
    c->width_px = args->width_px;
    c->height_px = args->height_px;
    c->fov_y = args->camera[5] * degrees;
    if (args->has_camera) {
        for (int a = 0; a < 3; a++) {
            double centre = 0.5 * (info->bounds_min[a] + info->bounds_max[a]);
            c->position[a] = args->camera[a] + (args->camera_relative ? centre : 0.0);
        }
        c->yaw = args->camera[3] * degrees;
        c->pitch = args->camera[4] * degrees;
        double extent = 0.0;
        for (int a = 0; a < 3; a++) {
            double e = info->bounds_max[a] - info->bounds_min[a];
            extent = e > extent ? e : extent;
        }
        // Near plane: small against the scene, but never below a millimetre.
        c->near_m = extent * 1e-5 > 1e-3 ? extent * 1e-5 : 1e-3;
        return;
    }
    c->yaw = 45.0 * degrees;
    c->pitch = -30.0 * degrees;
    sta_camera_frame_box(c, frame_min, frame_max);
}

int sta_view_initial_colour(const sta_view_args *args, const sta_strata_info *info)
{
    if (args->colour_mode >= 0) {
        return args->colour_mode;
    }
    return (info->layout.attributes & STA_STRATA_ATTR_RGB) ? STA_COLOUR_RGB : STA_COLOUR_ELEVATION;
}

void sta_view_pipeline_options(const sta_view_args *args, sta_pipeline_options *out)
{
    memset(out, 0, sizeof(*out));
    out->mode = args->pipeline;
    out->normals = args->normals;
    out->samples = args->samples;
    out->smooth = args->smooth;
    out->hpr_exhaustive = args->hpr_exhaustive;
    out->hpr_radius_px = args->hpr_radius_px;
    out->hpr_threshold = (float)args->hpr_threshold;
    out->s0_m = (float)args->s0_m;
}
