/* SPDX-License-Identifier: MIT
 * The ground model (stream/ground.h) as an R32F texture for the height-above-ground
 * colour mode, and the uniforms that place it camera-relative. GL: main thread only.
 */
#ifndef STA_RENDER_GROUND_TEXTURE_H
#define STA_RENDER_GROUND_TEXTURE_H

#include <epoxy/gl.h>
#include <stdbool.h>

#include "core/camera.h"
#include "core/status.h"
#include "stream/ground.h"

typedef struct sta_ground_texture {
    GLuint texture;       /* 0 until uploaded */
    double corner[2];     /* world x, y of the grid's corner */
    double size_m[2];     /* the grid's width and height, metres */
    double z_origin;      /* world z the texture's heights are relative to */
    double height_span_m; /* top of the colour ramp */
} sta_ground_texture;

/* Uploads `ground` (replacing what was there). */
sta_status sta_ground_texture_upload(sta_ground_texture *texture, const sta_ground *ground,
                                     sta_error *err);

/* Binds the texture and sets u_ground_frame and u_ground_height of `program` (in use)
 * for `camera`; with nothing uploaded (or a NULL texture) binds none. */
void sta_ground_texture_use(const sta_ground_texture *texture, GLuint program,
                            const sta_camera *camera);

/* A zeroed texture is a no-op. */
void sta_ground_texture_release(sta_ground_texture *texture);

#endif
