/* SPDX-License-Identifier: MIT
 * The geometry pass: one pixel per point of the nodes the streamer lists, into the
 * render target's colour and reverse-Z depth (GL_POINTS through shaders/geometry.*).
 * Positions arrive node-relative (16-bit) and are placed relative to the camera with
 * the node corner minus the camera position computed in double, so the GPU only sees
 * small numbers wherever the scene sits on Earth. Main thread (GL) only.
 */
#ifndef STA_RENDER_PASS_GEOMETRY_H
#define STA_RENDER_PASS_GEOMETRY_H

#include <epoxy/gl.h>

#include "core/camera.h"
#include "core/status.h"
#include "render/gpu_cache.h"
#include "render/target.h"
#include "stream/gpu_points.h"

typedef struct sta_pass_geometry {
    GLuint program;
    GLuint vao;
    GLint u_node_origin, u_step, u_view_rotation, u_projection, u_colour_mode, u_elevation,
        u_intensity_scale;
} sta_pass_geometry;

/* What the colour modes need to know about the scene. */
typedef struct sta_geometry_colours {
    int mode;              /* STA_COLOUR_* of render/bindings.h */
    double elevation_min;  /* metres: bottom of the elevation ramp */
    double elevation_span; /* metres: height of the elevation ramp (> 0) */
    float intensity_scale; /* 1 / largest intensity */
} sta_geometry_colours;

sta_status sta_pass_geometry_init(sta_pass_geometry *pass, sta_error *err);

/* A zeroed pass is a no-op. */
void sta_pass_geometry_release(sta_pass_geometry *pass);

/* Clears `target` and draws nodes `draw[0..count)` (resident in `cache`, with their
 * dequantisation in `frames`, indexed by node). */
void sta_pass_geometry_draw(const sta_pass_geometry *pass, const sta_camera *camera,
                            const sta_geometry_colours *colours, const sta_gpu_cache *cache,
                            const sta_gpu_node_frame *frames, const uint32_t *draw, size_t count,
                            sta_render_target *target);

#endif
