/* SPDX-License-Identifier: MIT
 * The camera a mirror reflects (render/pass_mirror.h draws its view): for a camera in
 * front of a mirror that contains the camera's up axis, the proper (yaw, pitch) camera
 * at the mirrored position looking along the mirrored direction. Its picture, flipped
 * left to right, is what the mirror shows: pixel x of the mirror is pixel W - 1 - x of
 * the reflected view (the reflection itself turns handedness, which a yaw/pitch
 * camera cannot; the flip restores it).
 */
#ifndef STA_MIRROR_MIRROR_CAMERA_H
#define STA_MIRROR_MIRROR_CAMERA_H

#include <stdbool.h>

#include "core/camera.h"
#include "mirror/mirror.h"

#define STA_MIRROR_VERTICAL_TOLERANCE 1e-6 /* |normal . up| below this: the mirror stands */

/* Fills `out` and returns true, or returns false when the camera is not in front of the
 * mirror or the mirror is not vertical (its normal not within
 * STA_MIRROR_VERTICAL_TOLERANCE of perpendicular to the camera's up axis). */
bool sta_mirror_reflect_camera(const sta_mirror *m, const sta_camera *camera, sta_camera *out);

#endif
