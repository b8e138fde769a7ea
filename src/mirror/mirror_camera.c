/* SPDX-License-Identifier: MIT
 * The reflected camera (mirror_camera.h), in double. */
#include "mirror/mirror_camera.h"

#include <math.h>

bool sta_mirror_reflect_camera(const sta_mirror *m, const sta_camera *camera, sta_camera *out)
{
    if (!(sta_mirror_signed_distance(m, camera->position) > 0.0)) {
        return false;
    }
    const double up_frame[3] = { 0.0, 0.0, 1.0 };
    double up[3];
    sta_camera_from_frame(camera, up_frame, up);
    double n_up = m->normal[0] * up[0] + m->normal[1] * up[1] + m->normal[2] * up[2];
    if (fabs(n_up) > STA_MIRROR_VERTICAL_TOLERANCE) {
        return false; // the reflected camera would roll, which sta_camera cannot
    }
    double forward[3], right[3], cam_up[3], reflected[3], frame[3];
    sta_camera_basis(camera, forward, right, cam_up);
    sta_mirror_reflect_direction(m, forward, reflected);
    sta_camera_to_frame(camera, reflected, frame);
    *out = *camera;
    sta_mirror_reflect_point(m, camera->position, out->position);
    out->yaw = atan2(frame[1], frame[0]);
    out->pitch = asin(fmax(-1.0, fmin(1.0, frame[2])));
    return true;
}
