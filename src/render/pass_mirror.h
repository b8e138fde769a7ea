/* SPDX-License-Identifier: MIT
 * Mirror rendering (docs/MIRRORS.md): for each mirror the camera sees from the front,
 * one extra pass draws the scene from the reflected camera (mirror/mirror_camera.h,
 * double precision, then camera-relative floats as everywhere) into an offscreen
 * target, keeping only what lies in front of the mirror (the geometry pass's clip
 * plane; ghosts stay hidden), and a compute pass textures it onto the mirror's outline
 * in the frame (shaders/mirror_composite.comp). The reflected view is drawn with the
 * raw geometry pass; the composite runs after the screen-space pipeline, on the
 * finished colour (so the pipeline's fill never reaches into the mirror).
 */
#ifndef STA_RENDER_PASS_MIRROR_H
#define STA_RENDER_PASS_MIRROR_H

#include "mirror/mirror.h"
#include "render/pass_geometry.h"
#include "render/target.h"

typedef struct sta_pass_mirror {
    GLuint program;
    GLint u_size, u_to_world, u_tan, u_near, u_plane, u_centre, u_axis_u, u_axis_v, u_outline,
        u_count, u_background, u_has_filled;
    sta_render_target reflected; /* the reflected view */
} sta_pass_mirror;

sta_status sta_pass_mirror_init(sta_pass_mirror *pass, sta_error *err);
void sta_pass_mirror_release(sta_pass_mirror *pass);

/* Draws mirror `m` into `target` (which holds the frame of `camera`): the reflected
 * view `reflected` (sta_mirror_reflect_camera) through `geometry` with `colours`'s
 * mode and hidden flags, then the composite. The draw list is the frame's (whose cut
 * serves the reflected view too: sta_streamer_set_extra_views). */
sta_status sta_pass_mirror_draw(sta_pass_mirror *pass, const sta_mirror *m,
                                const sta_camera *camera, const sta_camera *reflected,
                                const sta_geometry_colours *colours, sta_pass_geometry *geometry,
                                const sta_gpu_cache *cache, const sta_gpu_node_frame *frames,
                                const uint32_t *draw, size_t count, GLuint filled_position,
                                sta_render_target *target, sta_error *err);

#endif
