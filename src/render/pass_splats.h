/* SPDX-License-Identifier: MIT
 * The splat pass (issue 12): every point of the draw list as an oriented round disk, from
 * its normal and radius (the splat arena of render/gpu_cache.h) times a runtime scale,
 * into the same render target as the geometry pass (colour, reverse-Z depth, point id).
 * Each disk is a square in its own plane with the fragments outside the unit circle
 * discarded, so the depth test is per fragment: crossing disks cut each other exactly,
 * unlike fat screen-aligned points. Shaded in the fragment shader with the normal
 * (headlight Blinn-Phong, the screen-space pipeline's light), so no screen-space pass
 * runs after it. Two ways to make the squares, measured on llvmpipe
 * (docs/BENCHMARKS.md): instanced quads (four vertices per point, attributes per
 * instance), a geometry shader on GL_POINTS, and pulled quads (six vertices per point
 * in a plain draw, reading the arenas through texture buffers). render/ref/splat_ref.h is the CPU
 * twin. Main thread (GL) only.
 */
#ifndef STA_RENDER_PASS_SPLATS_H
#define STA_RENDER_PASS_SPLATS_H

#include <epoxy/gl.h>
#include <stdbool.h>

#include "core/camera.h"
#include "core/status.h"
#include "render/geometry_colours.h"
#include "render/gpu_cache.h"
#include "render/ref/splat_ref.h"
#include "render/target.h"
#include "stream/gpu_points.h"

typedef enum sta_splat_method {
    STA_SPLAT_DEFAULT = 0, /* resolved to STA_SPLAT_DEFAULT_METHOD */
    STA_SPLAT_INSTANCED,   /* a triangle strip of 4 vertices per instance (point) */
    STA_SPLAT_GEOMETRY,    /* GL_POINTS, a geometry shader emits the square */
    STA_SPLAT_PULLED,      /* 6 vertices per point in one plain draw, each reading its
                              point from the arenas (texture buffers): no instancing */
    STA_SPLAT_METHOD_COUNT
} sta_splat_method;

/* The geometry shader: the fastest of the three on llvmpipe, instanced quads 1.3-1.5x
 * and pulled quads 1.1-1.4x slower at 0.2-4 M splats, 1080p (docs/BENCHMARKS.md). The
 * default where no GL renderer is known (sta_splat_default_method). */
#define STA_SPLAT_DEFAULT_METHOD STA_SPLAT_GEOMETRY

/* The default method on the GL `renderer` (GL_RENDERER's string; NULL: unknown): the
 * geometry shader on Mesa's software rasterisers (llvmpipe, softpipe), instanced quads
 * elsewhere, on a GPU (on an NVIDIA H100 the geometry shader took 1.39x the instanced
 * quads' time at 30 M and at 6.9 M splats, docs/BENCHMARKS.md). No GL. */
int sta_splat_default_method(const char *renderer);

typedef struct sta_splat_options {
    int method;          /* sta_splat_method (0: STA_SPLAT_DEFAULT_METHOD) */
    float scale;         /* radius factor (0: STA_SPLAT_DEFAULT_SCALE) */
    float min_radius_px; /* smallest radius on screen (0: STA_SPLAT_DEFAULT_MIN_RADIUS_PX) */
    bool unlit;          /* plain colours, no shading */
} sta_splat_options;

void sta_splat_options_defaults(sta_splat_options *options);

/* "instanced", "geometry", "pulled"; -1 when unknown; and back. */
int sta_splat_method_from_name(const char *name);
const char *sta_splat_method_name(int method);

typedef struct sta_pass_splats {
    int method; /* resolved */
    GLuint program;
    GLuint vao;
    GLint u_node_origin, u_step, u_view_rotation, u_projection, u_colour_mode, u_elevation,
        u_intensity_scale, u_node_slot, u_arena_offset, u_splat_scale, u_default_radius,
        u_min_radius_px, u_pixel_angle, u_light, u_lit, u_hide_flags;
    GLuint points_texture, splats_texture; /* pulled: views of the arenas */
    GLuint points_viewed;                  /* the arena buffer they view ... */
    uint32_t arenas_generation;            /* ... and its cache's generation then */
} sta_pass_splats;

/* Builds the program of `method` (0: the default). */
sta_status sta_pass_splats_init(sta_pass_splats *pass, int method, sta_error *err);

/* A zeroed pass is a no-op. */
void sta_pass_splats_release(sta_pass_splats *pass);

/* Clears `target` and draws nodes `draw[0..count)` as splats; `cache` must hold splats
 * (has_splats). Points stored without a radius get `default_radius_m`. */
sta_status sta_pass_splats_draw(sta_pass_splats *pass, const sta_splat_options *options,
                                const sta_camera *camera, const sta_geometry_colours *colours,
                                const sta_gpu_cache *cache, const sta_gpu_node_frame *frames,
                                const uint32_t *draw, size_t count, float default_radius_m,
                                sta_render_target *target, sta_error *err);

#endif
