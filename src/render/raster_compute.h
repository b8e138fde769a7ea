/* SPDX-License-Identifier: MIT
 * The compute rasteriser of the geometry pass: every point of the frame's draw list,
 * read from the GPU cache's arena, projected in a compute shader and kept per pixel by
 * atomics; a resolve draw then writes the kept point's colour, depth and id into the
 * render target, so the screen-space passes read it as they read GL_POINTS' output.
 *
 * Design: per frame the CPU writes a node table (camera-relative origin, step, arena
 * offset, count, first draw-order index, node slot per drawn node) and a batch list
 * (one entry per STA_RASTER_BATCH_POINTS points of a node) and dispatches the batch
 * list indirectly: one dispatch per step for all nodes. A point's draw-order index is
 * its batch's number times STA_RASTER_BATCH_POINTS plus its place in the batch
 * (increasing in draw order, with gaps), so the resolve finds the point through the
 * batch list. With 64-bit atomics one step keeps (depth << 32 | ~draw-order index) per
 * pixel; without, a depth step (atomicMax of the depth's bits: reverse-Z floats >= 0
 * order like their bits) is followed by a payload step (atomicMin of the draw-order
 * index among the points at that depth). The depth step leaves a bit mask per
 * invocation of the points that were not behind the pixel's depth when they came: the
 * only ones that can be nearest at the end, since depths only grow, so the payload step
 * reads and projects only those (half the payload step's time on the demo street). The
 * resolve writes every pixel (background where empty), so the target is not cleared.
 * Either way the nearest point wins and ties go to the first in draw order, as with
 * GL_POINTS and GL_GREATER.
 *
 * Based on: Schütz, Kerbl, Wimmer, "Rendering Point Clouds with Compute Shaders and
 * Vertex Order Optimization", CGF 40(4), 2021, §4 (atomic depth and payload, resolve).
 * Main thread (GL) only.
 */
#ifndef STA_RENDER_RASTER_COMPUTE_H
#define STA_RENDER_RASTER_COMPUTE_H

#include <epoxy/gl.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "core/camera.h"
#include "core/status.h"
#include "render/bindings.h"
#include "render/footprint_uniforms.h"
#include "render/geometry_colours.h"
#include "render/gpu_cache.h"
#include "render/ref/screen_space.h"
#include "render/target.h"
#include "stream/gpu_points.h"

/* The resolve program of one colour mode and its uniforms. */
/* Words of a class set (= STA_VOLUMETRIC_CLASS_WORDS). */
#define STA_RASTER_MARK_CLASS_WORDS 8

typedef struct sta_raster_resolve {
    GLuint program; /* 0: not built yet */
    GLint u_view_rotation, u_projection, u_size, u_elevation, u_intensity_scale, u_background;
    GLint u_unproject_size, u_tan_half, u_near, u_mark_classes; /* the position variant's */
} sta_raster_resolve;

/* Point programs: [STA_RASTER_VARIANTS * step + variant]: one-pixel points without a
 * clip plane, wider points, one-pixel points with a clip plane (built on first use). */
#define STA_RASTER_VARIANTS 3
#define STA_RASTER_PROGRAMS (2 * STA_RASTER_VARIANTS)

typedef struct sta_raster_compute {
    bool is_packed; /* one pass with 64-bit atomics */
    int steps;      /* 1: packed; 2: depth, then payload */
    GLuint points_program[STA_RASTER_PROGRAMS];
    GLuint vao;                      /* empty, for the resolve triangle */
    GLuint points_texture;           /* texture buffer view of the arena */
    GLuint arena_viewed;             /* arena buffer the view shows ... */
    uint32_t arena_generation;       /* ... and its cache's generation then */
    GLuint nodes, batches, indirect; /* per-frame tables */
    GLuint near_batches;             /* the batches, nearest node first: the point steps' order */
    GLuint depth, payload;           /* per-pixel buffers */
    GLuint candidates;               /* two-pass: a candidate mask per invocation */
    size_t node_bytes, batch_bytes, candidate_bytes; /* buffer capacities */
    size_t near_batch_bytes;                         /* its capacity */
    int width_px, height_px;                         /* size of the per-pixel buffers */
    int subpixel_bits;                               /* GL_SUBPIXEL_BITS: the node rows' snap */
    GLint max_texels;                                /* GL_MAX_TEXTURE_BUFFER_SIZE */
    void *node_table;                                /* CPU copy of the tables, reused */
    size_t node_table_capacity;                      /* entries */
    uint32_t *batch_table;                           /* 2 per batch */
    size_t batch_table_capacity;                     /* batches */
    uint32_t *near_table;                            /* near_batches' CPU copy, 2 per batch */
    size_t near_table_capacity;                      /* batches */
    void *near_keys;                                 /* node order: distance, node */
    size_t near_keys_capacity;                       /* entries */
    GLint u_view_rotation[STA_RASTER_PROGRAMS], u_projection[STA_RASTER_PROGRAMS],
        u_size[STA_RASTER_PROGRAMS], u_hide_flags[STA_RASTER_PROGRAMS],
        u_clip_plane[STA_RASTER_PROGRAMS];
    sta_footprint_uniforms footprint[STA_RASTER_PROGRAMS];
    /* The resolve per colour mode (a constant there: llvmpipe would run every mode's
     * branch), built when the mode is first drawn, from these defines. */
    sta_raster_resolve resolve[STA_COLOUR_MODE_COUNT][2]; /* [mode][writes positions] */
    char resolve_defines[256];
    /* sta_raster_compute_set_position_out: RGBA32F texture the resolve also writes the
     * camera-space positions into (0: none), and the unproject uniforms for it. */
    GLuint position_out, class_out; /* class_out: R8UI */
    float unproject_size[2], unproject_tan_half[2], unproject_near;
    uint32_t mark_classes[STA_RASTER_MARK_CLASS_WORDS]; /* the volumetric set (0: none) */
} sta_raster_compute;

/* The #extension lines that give the current context's shaders atomicMax on uint64_t
 * in buffers (GL_ARB_shader_atomic_int64, or NVIDIA's GL_NV_shader_atomic_int64), or
 * NULL where it has none. */
const char *sta_raster_int64_extensions(void);

/* Builds the programs: the packed one-pass variant when `packed` (needs
 * sta_raster_int64_extensions()), the two-pass one otherwise. */
sta_status sta_raster_compute_init(sta_raster_compute *raster, bool packed, sta_error *err);

/* A zeroed rasteriser is a no-op. */
void sta_raster_compute_release(sta_raster_compute *raster);

/* From the next draw on, the resolve also writes each pixel's camera-space position
 * into `position_texture` (RGBA32F of the target's size; 0: stop), exactly as the
 * unproject pass (render/pass_unproject.h) would from the depth it writes, for `view`
 * (the target's size and the camera's fov and near plane): attached to the target as a
 * third colour output for the resolve draw only (a fragment output: an image store there
 * cost llvmpipe as much as the unproject pass it saves); and each pixel's point class
 * into `class_texture` (R8UI, 0 where no point), a fourth output. mark_classes (NULL:
 * none; STA_RASTER_MARK_CLASS_WORDS words, bit c % 32 of word c / 32): the positions of
 * points of those classes get w = STA_POSITION_W_MARKED, the volumetric mark
 * (render/ref/volumetric_ref.h) done in the resolve. */
void sta_raster_compute_set_position_out(sta_raster_compute *raster, GLuint position_texture,
                                         GLuint class_texture, const sta_view_params *view,
                                         const uint32_t *mark_classes);

/* Rasterises nodes `draw[0..count)` into `target` (cleared first) with `footprint`
 * (render/point_size.h; all zero: one pixel per point); same contract as
 * sta_pass_geometry_draw. Errors: out of memory, an arena larger than a texture buffer
 * can show. */
sta_status sta_raster_compute_draw(sta_raster_compute *raster, const sta_camera *camera,
                                   const sta_geometry_colours *colours,
                                   const sta_raster_ref_footprint *footprint,
                                   const sta_gpu_cache *cache, const sta_gpu_node_frame *frames,
                                   const uint32_t *draw, size_t count, sta_render_target *target,
                                   sta_error *err);

#endif
