/* SPDX-License-Identifier: MIT
 * Camera navigation maths. */
#include "core/navigation.h"

#include <math.h>

static double length3(const double v[3])
{
    return sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
}

static void look_at(sta_camera *c, const double target[3])
{
    double d[3] = { target[0] - c->position[0], target[1] - c->position[1],
                    target[2] - c->position[2] };
    double len = length3(d);
    if (len <= 0) {
        return;
    }
    c->yaw = atan2(d[1], d[0]);
    c->pitch = asin(fmax(-1.0, fmin(1.0, d[2] / len)));
}

void sta_nav_orbit(sta_camera *c, const double pivot[3], double d_yaw, double d_pitch,
                   double pitch_min, double pitch_max)
{
    double offset[3] = { c->position[0] - pivot[0], c->position[1] - pivot[1],
                         c->position[2] - pivot[2] };
    double radius = length3(offset);
    if (radius <= 0) {
        return;
    }
    double yaw = atan2(offset[1], offset[0]) + d_yaw;
    double pitch = asin(fmax(-1.0, fmin(1.0, offset[2] / radius))) + d_pitch;
    pitch = fmax(pitch_min, fmin(pitch_max, pitch));
    c->position[0] = pivot[0] + radius * cos(pitch) * cos(yaw);
    c->position[1] = pivot[1] + radius * cos(pitch) * sin(yaw);
    c->position[2] = pivot[2] + radius * sin(pitch);
    look_at(c, pivot);
}

double sta_nav_fly_speed(double surface_distance_m, double scene_size_m)
{
    double cap = scene_size_m > 0 ? 0.5 * scene_size_m : (double)INFINITY;
    double speed = 0.5 * surface_distance_m;
    if (!(speed > 0.05)) { // also NaN
        speed = 0.05;
    }
    return fmax(0.05, fmin(speed, cap));
}

double sta_nav_ramp(double fraction, bool moving, double dt_s)
{
    if (!moving) {
        return 0.0;
    }
    double step = 1.0 - exp(-fmax(0.0, dt_s) / 0.3);
    return fraction + (1.0 - fraction) * step;
}

void sta_nav_focus(const sta_camera *from, const double point[3], double distance_factor,
                   sta_camera *out)
{
    *out = *from;
    double d[3] = { point[0] - from->position[0], point[1] - from->position[1],
                    point[2] - from->position[2] };
    double len = length3(d);
    if (len <= 0) {
        return;
    }
    for (int a = 0; a < 3; a++) {
        out->position[a] = point[a] - d[a] * distance_factor;
    }
    look_at(out, point);
}

void sta_nav_blend(const sta_camera *a, const sta_camera *b, double t, sta_camera *out)
{
    t = fmax(0.0, fmin(1.0, t));
    double s = t * t * (3.0 - 2.0 * t);
    *out = *a;
    for (int i = 0; i < 3; i++) {
        out->position[i] = a->position[i] + (b->position[i] - a->position[i]) * s;
    }
    double dyaw = remainder(b->yaw - a->yaw, 2.0 * M_PI);
    out->yaw = a->yaw + dyaw * s;
    out->pitch = a->pitch + (b->pitch - a->pitch) * s;
    out->fov_y = a->fov_y + (b->fov_y - a->fov_y) * s;
}
