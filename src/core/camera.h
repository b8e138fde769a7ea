/* SPDX-License-Identifier: MIT
 * A perspective camera in world coordinates (double), Z up, with the matrices the
 * renderer needs in float: a view rotation without translation (positions are made
 * camera-relative in double first) and a reverse-Z infinite-far projection.
 */
#ifndef STA_CORE_CAMERA_H
#define STA_CORE_CAMERA_H

#include <stdbool.h>

/* The world axis that points up (sta_camera.up_axis). Yaw and pitch are angles in the
 * camera's z-up frame: with +Z up that is the world; with +Y up the frame's x, y, z are
 * the world's x, -z, y (a rotation by -90 deg about x), so yaw turns about world +Y. */
#define STA_CAMERA_UP_Z 0
#define STA_CAMERA_UP_Y 1

typedef struct sta_camera {
    double position[3]; /* world (real) coordinates, metres */
    double yaw;         /* radians around up; 0 looks along +X, pi/2 along the frame's +Y
                           (world +Y when z is up, world -Z when y is up) */
    double pitch;       /* radians; positive looks up, within (-pi/2, pi/2) */
    double fov_y;       /* vertical field of view, radians */
    double near_m;      /* near plane distance, metres (> 0); the far plane is at infinity */
    int width_px;       /* viewport */
    int height_px;
    int up_axis; /* STA_CAMERA_UP_Z (0, the default) or STA_CAMERA_UP_Y */
} sta_camera;

/* A world direction in the camera's z-up frame, and back (the identity for +Z up). */
void sta_camera_to_frame(const sta_camera *camera, const double world[3], double out_frame[3]);
void sta_camera_from_frame(const sta_camera *camera, const double frame[3], double out_world[3]);

/* Unit view direction, right and up vectors in world coordinates. */
void sta_camera_basis(const sta_camera *camera, double forward[3], double right[3], double up[3]);

/* Column-major 4x4 view rotation (world direction -> camera space, camera looks
 * down -Z), no translation. */
void sta_camera_view_rotation(const sta_camera *camera, float out[16]);

/* Column-major 4x4 reverse-Z infinite projection for glClipControl(ZERO_TO_ONE):
 * depth 1 at the near plane, approaching 0 at infinity. */
void sta_camera_projection(const sta_camera *camera, float out[16]);

/* Projects a world point: pixel coordinates (origin top-left, x right, y down,
 * pixel centres at +0.5) and depth in camera space (metres along the view axis).
 * Returns false when the point is behind the near plane. Computed in double. */
bool sta_camera_project(const sta_camera *camera, const double world[3], double *out_x_px,
                        double *out_y_px, double *out_depth_m);

/* Frustum planes (a, b, c, d with a*x + b*y + c*z + d >= 0 inside) in world
 * coordinates: near, far (at `far_m`), left, right, bottom, top. */
typedef struct sta_frustum {
    double planes[6][4];
} sta_frustum;

void sta_camera_frustum(const sta_camera *camera, double far_m, sta_frustum *out_frustum);

/* Pixels per metre at distance `distance_m` along the view axis. */
double sta_camera_pixels_per_metre(const sta_camera *camera, double distance_m);

/* Places the camera to see a box whole: looking from `yaw`/`pitch` at its centre. */
void sta_camera_frame_box(sta_camera *camera, const double min[3], const double max[3]);

#endif
