/* SPDX-License-Identifier: MIT
 * What window and headless viewing share: the initial camera and colour mode.
 */
#ifndef STA_APP_VIEW_SETUP_H
#define STA_APP_VIEW_SETUP_H

#include "app/view_options.h"
#include "core/camera.h"
#include "format/strata.h"
#include "mirror/mirror_set.h"
#include "render/pass_splats.h"
#include "render/pipeline.h"
#include "render/scene.h"

#define STA_VIEW_DEFAULT_YAW_DEG   45.0  /* default view from the south-west */
#define STA_VIEW_DEFAULT_PITCH_DEG -30.0 /* 30 degrees from above */
#define STA_VIEW_ELONGATED_RATIO   1.5   /* longer / shorter horizontal side beyond this */
#define STA_VIEW_ALONG_PITCH_DEG   -20.0 /* a corridor: along its axis, this far down */
#define STA_VIEW_CORRIDOR_DEPTH    0.25  /* elongated, and its height over its width above this */
#define STA_VIEW_CORRIDOR_OPEN     0.15  /* and its middle third at most this much upper half */
#define STA_VIEW_ACROSS_TURN_DEG   25.0  /* other elongated: this far from square-on */
#define STA_VIEW_FRAME_GROW        0.5   /* the robust box grown by this share per side */
#define STA_VIEW_FRAME_KEEP        0.995 /* share of the sample inside each view edge */
#define STA_VIEW_FRAME_STRAY_GAP   0.05  /* and beyond it, but for strays (not a corridor) */
#define STA_VIEW_FRAME_CLEAR_PX    8.0   /* not a corridor: this far inside the border band */

/* The camera the arguments ask for, or a default one: yaw and pitch from
 * sta_view_default_direction on the weighted sample (sta_view_sample_build) of the points
 * inside the robust bounds `frame_min`..`frame_max` grown by STA_VIEW_FRAME_GROW; backed
 * off until STA_VIEW_FRAME_KEEP of the points fill the view: for a corridor the weighted
 * sample's, around its mean; otherwise the root node's, around the bounds' centre, with
 * the points beyond that share that run on in steps of at most STA_VIEW_FRAME_STRAY_GAP of
 * the distance (a model's ear tips and horns; sta_camera_frame_points), clear of the
 * screen passes' border band by STA_VIEW_FRAME_CLEAR_PX (the box itself when the file
 * cannot be read). Its up axis is the
 * file's (info->up_axis): given yaw and pitch are about it too. `why` (may be NULL)
 * gets sta_view_direction_describe's line for a default camera, "" for a given one. */
void sta_view_initial_camera(const sta_view_args *args, const sta_strata_info *info,
                             const double frame_min[3], const double frame_max[3],
                             sta_camera *out_camera, char *why, size_t why_size);

/* The default direction for points seen by `camera` (its up axis), yaw and pitch in
 * radians. Points whose horizontal spread is more than STA_VIEW_ELONGATED_RATIO times
 * longer one way than across are elongated. A corridor is
 * elongated, the 5-95 % spread of its heights more than STA_VIEW_CORRIDOR_DEPTH times
 * that across its axis, and open above the axis: at most STA_VIEW_CORRIDOR_OPEN of the
 * points of the middle third across it lie in the upper half of the heights (a street
 * between facades; not an elongated model). It is seen along its axis from its end,
 * STA_VIEW_ALONG_PITCH_DEG from above, looking west when the axis runs east-west (yaw in
 * [90, 270) degrees). Other elongated scenes (an airborne strip, the dragon) are seen
 * across the long axis, STA_VIEW_ACROSS_TURN_DEG off square-on, so that it spans the
 * width; the rest from the south-west (yaw 45 degrees); both STA_VIEW_DEFAULT_PITCH_DEG
 * from above. */
typedef struct sta_view_direction {
    double yaw, pitch;
    bool along;        /* a corridor, seen along its axis (framed on the weighted sample) */
    double axis_yaw;   /* the points' principal horizontal axis (sta_camera_points_long_yaw) */
    double elongation; /* spread along it over spread across it */
} sta_view_direction;

/* One line saying which default view `d` is and why, e.g. "a corridor (axis -19.5 deg,
 * elongation 2.44): along it from its end, 20 deg from above". */
void sta_view_direction_describe(const sta_view_direction *d, char *out, size_t size);

sta_view_direction sta_view_default_direction(const sta_camera *camera, const double *points,
                                              size_t count);

/* The `--camera=X,Y,Z,YAW,PITCH,FOV` option that gives `camera` back, so that a default
 * view can be given again and changed: the world position exactly (the shortest text that
 * reads back to the same double), the angles in degrees to a nanodegree. */
void sta_view_camera_option(const sta_camera *camera, char *out, size_t size);

/* The screen-space pipeline options the arguments ask for. */
void sta_view_pipeline_options(const sta_view_args *args, sta_pipeline_options *out);

/* Factor of one [ or ] press on the splat radius. */
#define STA_VIEW_SPLAT_SCALE_STEP 1.25f

/* The pipeline's name for the readout and title, with the point size where it applies
 * and is not one pixel, and the splat scale when splats are drawn at another scale than
 * 1: "shaded", "edl, points 3 px", "splats x1.25". */
void sta_view_pipeline_label(int mode, const sta_point_size *size, float splat_scale,
                             char *out_text, size_t text_size);

/* The splat pass's options from the command line. */
void sta_view_splat_options(const sta_view_args *args, sta_splat_options *out);

/* Opens the scene with the command line's streamer options; --mirrors is loaded into
 * `mirrors` (which must outlive the scene) and classifies ghosts at load; ghosts are
 * hidden unless --show-ghosts. Errors name the file. */
sta_status sta_view_open_scene(const sta_view_args *args, sta_mirror_set *mirrors,
                               sta_scene **out_scene, sta_error *err);

/* The colour mode asked for, or the best default for the scene's attributes. */
int sta_view_initial_colour(const sta_view_args *args, const sta_strata_info *info);

#endif
