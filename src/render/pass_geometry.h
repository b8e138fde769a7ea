/* SPDX-License-Identifier: MIT
 * The geometry pass: one pixel per point of the nodes the streamer lists, into the
 * render target's colour, reverse-Z depth and point id. Two rasterisers fill the same
 * target: GL_POINTS with a depth test (shaders/geometry.*), and a compute-shader
 * rasteriser (render/raster_compute.h), 2-4x faster on llvmpipe.
 * Positions arrive node-relative (16-bit) and are placed relative to the camera with
 * the node corner minus the camera position computed in double, so the GPU only sees
 * small numbers wherever the scene sits on Earth. Points may be wider than a pixel
 * (render/point_size.h): round, with a depth per fragment, in both rasterisers (GL_POINTS
 * through a second program, geometry_wide.*). Main thread (GL) only.
 */
#ifndef STA_RENDER_PASS_GEOMETRY_H
#define STA_RENDER_PASS_GEOMETRY_H

#include <epoxy/gl.h>
#include <stdbool.h>

#include "core/camera.h"
#include "core/status.h"
#include "render/footprint_uniforms.h"
#include "render/geometry_colours.h"
#include "render/gpu_cache.h"
#include "render/point_size.h"
#include "render/raster_compute.h"
#include "render/target.h"
#include "stream/gpu_points.h"

/* Which rasteriser draws the points. */
typedef enum sta_raster_method {
    STA_RASTER_DEFAULT = 0, /* resolved to STA_RASTER_DEFAULT_METHOD */
    STA_RASTER_COMPUTE,     /* compute shader, atomics per pixel, then a resolve */
    STA_RASTER_POINTS,      /* GL_POINTS and the depth test */
} sta_raster_method;

/* The compute rasteriser: 2.2x (1 M points) and 3.8x (5 M) less CPU time than GL_POINTS
 * on llvmpipe at 1920x1080 (docs/BENCHMARKS.md), and the faster path on GPUs (Schütz et
 * al. 2021). */
#define STA_RASTER_DEFAULT_METHOD STA_RASTER_COMPUTE

typedef struct sta_geometry_options {
    int raster;               /* sta_raster_method (0: STA_RASTER_DEFAULT_METHOD) */
    bool force_32bit_atomics; /* the two-pass compute path even with 64-bit atomics */
} sta_geometry_options;

void sta_geometry_options_defaults(sta_geometry_options *options);

/* What the pass runs, and why (for the log). */
typedef struct sta_geometry_choice {
    int raster;       /* STA_RASTER_COMPUTE or STA_RASTER_POINTS */
    bool packed;      /* compute: one pass with 64-bit atomics (else two 32-bit passes) */
    char reason[160]; /* one line: the method and why */
} sta_geometry_choice;

/* The choice for `options` (defaults resolved) on a driver that has, or lacks,
 * GL_ARB_shader_atomic_int64. No GL. */
void sta_geometry_choose(const sta_geometry_options *options, bool has_atomic_int64,
                         sta_geometry_choice *out_choice);

/* "compute", "points"; -1 when unknown; and the name of a method. */
int sta_raster_method_from_name(const char *name);
const char *sta_raster_method_name(int method);

typedef struct sta_pass_geometry {
    sta_geometry_choice choice;
    GLuint program;
    GLuint vao;
    GLint u_node_origin, u_step, u_view_rotation, u_projection, u_colour_mode, u_elevation,
        u_intensity_scale, u_node_slot, u_arena_offset, u_hide_flags, u_clip_plane;
    sta_raster_compute compute; /* when choice.raster is STA_RASTER_COMPUTE */
    /* GL_POINTS for points wider than a pixel (geometry_wide.*). */
    GLuint wide_program;
    GLint w_node_origin, w_step, w_spacing, w_view_rotation, w_projection, w_size, w_colour_mode,
        w_elevation, w_intensity_scale, w_node_slot, w_arena_offset, w_hide_flags, w_clip_plane;
    sta_footprint_uniforms w_footprint;
    sta_point_size point_size; /* one pixel until set */
    GLuint class_out;          /* GL_POINTS: R8UI point classes written too (0: none) */
} sta_pass_geometry;

/* Builds the chosen rasteriser (`options` may be NULL: defaults) and logs the choice and
 * its reason once (info level). */
sta_status sta_pass_geometry_init(sta_pass_geometry *pass, const sta_geometry_options *options,
                                  sta_error *err);

/* GL_POINTS path: clears `target`, sets the depth test and the program's view and colour
 * uniforms, and binds the program and its vertex array, ready for per-node draws (the
 * live Katz pass draws its own buffer this way). */
void sta_pass_geometry_begin_points(const sta_pass_geometry *pass, const sta_camera *camera,
                                    const sta_geometry_colours *colours, sta_render_target *target);

/* Sets the size of the points drawn from the next draw on (`size` NULL: one pixel). */
void sta_pass_geometry_set_point_size(sta_pass_geometry *pass, const sta_point_size *size);

/* With the compute rasteriser, the next draws also write the camera-space position of
 * every pixel into `position_texture` (RGBA32F of the target's size, as the unproject
 * pass makes them from the depth: render/raster_compute.h) and each pixel's point class
 * into `class_texture` (R8UI), for `view`; 0 stops it. mark_classes (NULL: none): the
 * volumetric class set whose pixels the resolve marks (sta_raster_compute_set_position_out).
 * Returns whether they will (false with GL_POINTS: then run the unproject pass). */
bool sta_pass_geometry_set_position_out(sta_pass_geometry *pass, GLuint position_texture,
                                        GLuint class_texture, const sta_view_params *view,
                                        const uint32_t *mark_classes);

/* With GL_POINTS, the next draws of one-pixel points also write each pixel's point
 * class into `class_texture` (R8UI of the target's size), so that the volumetric mark
 * need not look it up through the point ids; 0 stops it. Returns whether they will
 * (false with the compute rasteriser: sta_pass_geometry_set_position_out). */
bool sta_pass_geometry_set_class_out(sta_pass_geometry *pass, GLuint class_texture);

/* A zeroed pass is a no-op. */
void sta_pass_geometry_release(sta_pass_geometry *pass);

/* Clears `target` and draws nodes `draw[0..count)` (resident in `cache`, with their
 * dequantisation in `frames`, indexed by node). Ties in depth go to the first point in
 * draw order (node order of `draw`, then point order), with either rasteriser. */
sta_status sta_pass_geometry_draw(sta_pass_geometry *pass, const sta_camera *camera,
                                  const sta_geometry_colours *colours, const sta_gpu_cache *cache,
                                  const sta_gpu_node_frame *frames, const uint32_t *draw,
                                  size_t count, sta_render_target *target, sta_error *err);

#endif
