/* SPDX-License-Identifier: MIT
 * Volumetric classes (vegetation) shown as points instead of a filled surface: a mark
 * step before HPR (fused into the unproject pass where the geometry pass wrote a class
 * image: pass_unproject.h) and an overlay after shading (the rule:
 * render/ref/volumetric_ref.h).
 */
#ifndef STA_RENDER_PASS_VOLUMETRIC_H
#define STA_RENDER_PASS_VOLUMETRIC_H

#include <epoxy/gl.h>
#include <stdbool.h>
#include <stdint.h>

#include "core/status.h"
#include "render/gpu_cache.h"
#include "render/ref/volumetric_ref.h"

typedef struct sta_volumetric_pass {
    GLuint mark_program, overlay_program;
    /* volumetric_tiles.comp, the overlay's tile list: [0] from the positions, [1] from
     * the unproject pass's tile flags (VW_FLAGS) */
    GLuint tiles_programs[2];
    GLint tiles_size[2];           /* their u_size */
    GLuint tile_buffer;            /* indirect dispatch, count, tiles; grown as needed */
    uint32_t tile_capacity;        /* tiles the buffer holds */
    GLuint tile_flags;             /* R32UI, a texel per tile (sta_volumetric_pass_tile_flags) */
    int flags_width, flags_height; /* the frame size it was made for */
    GLuint mark_image_program;     /* the mark reading a class image (STA_VOLUMETRIC_CLASS_IMAGE) */
    GLint mark_size, mark_classes, overlay_size;
    GLint mark_image_size, mark_image_classes;
    GLuint nodes_buffer;     /* uvec2 per node slot */
    uint32_t nodes_capacity; /* slots the buffer holds */
    uint32_t *host_nodes;    /* sta_volumetric_points_from_cache's table */
    uint32_t host_capacity;  /* slots it holds */
} sta_volumetric_pass;

/* Where the points behind the pixel ids live: the point-id texture (GL_RG32UI, same
 * size as the frame), the arena buffer and its node table (2 uint32 per slot: first
 * point, count; count 0 when not resident). */
typedef struct sta_volumetric_points {
    GLuint id_texture;
    GLuint arena;
    const uint32_t *nodes;
    uint32_t node_count;
} sta_volumetric_points;

/* Fills `out` from the GPU cache (its arena and residency; the table lives in `pass`
 * until the next call). */
sta_status sta_volumetric_points_from_cache(sta_volumetric_pass *pass, const sta_gpu_cache *cache,
                                            GLuint id_texture, sta_volumetric_points *out,
                                            sta_error *err);

sta_status sta_volumetric_pass_init(sta_volumetric_pass *pass, sta_error *err);
void sta_volumetric_pass_release(sta_volumetric_pass *pass);

/* The textures of one frame, all width x height. */
typedef struct sta_volumetric_frame {
    int width, height;
    GLuint position; /* RGBA32F camera-space positions (unproject); marked: w = 2 */
    GLuint colour;   /* the geometry pass's colour (RGBA8 or float): the marked
                        points' own colours, read by the overlay */
} sta_volumetric_frame;

/* Marks the pixels whose point has a class in `class_set` (position w set to
 * STA_POSITION_W_MARKED; before HPR). class_texture: 0 to look each
 * pixel's class up through its point id in `src`, or an R8UI image of the classes of the
 * points drawn (the compute rasteriser's, render/raster_compute.h): the same marks, one
 * image read instead of two dependent buffer reads a pixel. */
sta_status sta_volumetric_pass_mark(sta_volumetric_pass *pass, const sta_volumetric_points *src,
                                    const uint32_t class_set[STA_VOLUMETRIC_CLASS_WORDS],
                                    GLuint class_texture, const sta_volumetric_frame *frame,
                                    sta_error *err);

/* Binds the overlay window's inputs (volumetric_window.glsl) of `frame` to their units
 * (for the overlay pass and the shade pass's overlay variant). */
void sta_volumetric_window_bind(const sta_volumetric_frame *frame);

/* The pass's tile-flag texture for a width x height frame (R32UI, a texel per tile of
 * STA_WORKGROUP_SIZE_X x _Y pixels), cleared to 0, for the unproject pass's mark to set
 * where a pixel is marked (pass_unproject.h). Errors: STA_ERR_GL. */
sta_status sta_volumetric_pass_tile_flags(sta_volumetric_pass *pass, int width, int height,
                                          GLuint *out, sta_error *err);

/* Splats the marked points over `out` (RGBA8), after HPR: lists the tiles of
 * STA_WORKGROUP_SIZE_X x _Y pixels a splat can reach (from the tile flags when
 * `flags_set`, the unproject pass having set them this frame; else from the positions),
 * then runs the overlay on those only (one indirect dispatch). Errors: STA_ERR_GL. */
sta_status sta_volumetric_pass_overlay(sta_volumetric_pass *pass, const sta_volumetric_frame *frame,
                                       bool flags_set, GLuint out, sta_error *err);

#endif
