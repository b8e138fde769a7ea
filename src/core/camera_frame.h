/* SPDX-License-Identifier: MIT
 * Default views from a sample of the scene's points: which way the scene is long, and
 * how far back the camera must stand for the points to fill the view.
 */
#ifndef STA_CORE_CAMERA_FRAME_H
#define STA_CORE_CAMERA_FRAME_H

#include <stddef.h>

#include "core/camera.h"

/* The principal horizontal direction of `points` (count xyz triples, world metres) in the
 * camera's z-up frame (its up_axis), as a yaw in radians, and in *out_elongation
 * (may be NULL) the ratio of the standard deviations along it and across it (1 for
 * round or fewer than 2 points; 1e6 at most). */
double sta_camera_points_long_yaw(const sta_camera *camera, const double *points, size_t count,
                                  double *out_elongation);

/* Fit, then centre across the view and fit again, this many times in all. */
#define STA_CAMERA_FRAME_ROUNDS 3

/* How sta_camera_frame_points frames points. */
typedef struct sta_camera_frame_rule {
    /* Share (0..1] of the points inside each edge of the view. */
    double keep;
    /* > 0: an edge also takes in the points beyond that share up to the first whose
     * distance requirement jumps by more than this times the share's distance: a model's
     * extremity (ear tips, horns) runs on in small steps and stays in view, a stray point
     * far out is cut. 0: the share alone. */
    double stray_gap;
    /* > 0: the points framed stay at least this many pixels inside every edge (clear of
     * a border band), at most a quarter of the view's width or height. */
    double margin_px;
} sta_camera_frame_rule;

/* Places the camera (yaw, pitch, fov and viewport as set) to look at `centre`, moved
 * across the view so that what it frames is centred, from the smallest distance at
 * which, for each of the four edges of the view, the points `rule` keeps lie on its inner
 * side, plus a 5 % margin or the rule's margin in pixels, whichever stands farther back;
 * sets the near plane from that distance. With no points the camera stands 1 m back. */
void sta_camera_frame_points(sta_camera *camera, const double centre[3], const double *points,
                             size_t count, const sta_camera_frame_rule *rule);

#endif
