/* SPDX-License-Identifier: MIT
 * Camera navigation maths for the viewer, in double and without GL or windows, so it
 * can be tested: orbiting with pitch limits, fly speed with smooth acceleration, and
 * the eased move that centres a double-clicked point.
 */
#ifndef STA_CORE_NAVIGATION_H
#define STA_CORE_NAVIGATION_H

#include <stdbool.h>

#include "core/camera.h"

/* Default orbit limits: the camera's elevation above the orbit centre, degrees. The
 * minimum of 0 keeps the camera from sinking below the centre's horizon, so orbiting a
 * point on the ground never looks at the scene from underneath. */
#define STA_ORBIT_DEFAULT_PITCH_MIN_DEG 0.0
#define STA_ORBIT_DEFAULT_PITCH_MAX_DEG 89.0

/* Seconds of the eased move of a double-click. */
#define STA_NAV_FOCUS_SECONDS 0.35

/* Rotates the camera around `pivot` by d_yaw, d_pitch (radians), keeping its distance,
 * with its elevation above the pivot clamped to [pitch_min, pitch_max] (radians), and
 * turns it to look at the pivot. */
void sta_nav_orbit(sta_camera *camera, const double pivot[3], double d_yaw, double d_pitch,
                   double pitch_min, double pitch_max);

/* Fly speed in metres per second: half the distance to the surface ahead per second, so
 * that flying towards a surface slows down before it (never faster than the scene's
 * size per two seconds, never slower than 5 cm/s). */
double sta_nav_fly_speed(double surface_distance_m, double scene_size_m);

/* Smooth acceleration: the fraction of full speed after `dt_s` more seconds of holding a
 * key (time constant 0.3 s), or 0 once no key is held. */
double sta_nav_ramp(double fraction, bool moving, double dt_s);

/* The camera that looks straight at `point` from `from`'s side at `distance_factor`
 * times the current distance (the point at the centre of the screen). */
void sta_nav_focus(const sta_camera *from, const double point[3], double distance_factor,
                   sta_camera *out);

/* The camera a fraction t (0..1) of the way from `a` to `b`, eased in and out
 * (smoothstep): positions straight, yaw the short way round, pitch and field of view
 * linear. Viewport and near plane come from `a`. */
void sta_nav_blend(const sta_camera *a, const sta_camera *b, double t, sta_camera *out);

#endif
