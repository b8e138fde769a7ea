/* SPDX-License-Identifier: MIT
 * Binding points, attribute locations and workgroup sizes shared by C and GLSL.
 * sta_gl_program_create injects each of these into every shader as a #define, so
 * the numbers live only here.
 *
 * Binding names: STA_<SHADER>_{IMAGE,SAMPLER}_<ROLE>. <SHADER> is the shader's file
 * name (hpr_occlusion.comp: HPR_OCCLUSION); a binding declared in a .glsl library
 * shared by the steps of one pass, or a layout that all the shaders of one pass share
 * (pull-push), takes the pass's name. IMAGE is an image unit (image2D in GLSL,
 * glBindImageTexture in C), SAMPLER a texture unit (sampler2D, glBindTextureUnit):
 * the two are separate number spaces, so an IMAGE and a SAMPLER of one shader may
 * share a number. BUFFER is a shader storage buffer binding (a third space). Within one
 * shader and one space the numbers are distinct.
 */
#ifndef STA_RENDER_BINDINGS_H
#define STA_RENDER_BINDINGS_H

#include "render/ref/screen_space.h" /* STA_HPR_BACKGROUND_OPEN_SECTORS */

#define STA_ATTRIB_POSITION_INTENSITY 0 /* uvec4: qx, qy, qz, intensity */
#define STA_ATTRIB_COLOUR_CLASS       1 /* uvec4: r, g, b, classification */
#define STA_ATTRIB_RETURNS            2 /* uvec4: return number, number of returns, 0, 0 */
#define STA_ATTRIB_SPLAT              3 /* uvec2: octahedral normal, half radius (splats) */

#define STA_WORKGROUP_SIZE_X 8
#define STA_WORKGROUP_SIZE_Y 8

/* Colour modes of the geometry pass. */
#define STA_COLOUR_RGB            0
#define STA_COLOUR_INTENSITY      1
#define STA_COLOUR_ELEVATION      2
#define STA_COLOUR_CLASSIFICATION 3
#define STA_COLOUR_RETURN_NUMBER  4
#define STA_COLOUR_HEIGHT         5 /* height above ground (stream/ground.h) */
#define STA_COLOUR_MODE_COUNT     6

/* Fragment outputs of the geometry pass (geometry.frag, raster_resolve.frag): the
 * render target's colour attachments (render/target.h). */
#define STA_GEOMETRY_OUT_COLOUR     0 /* RGBA8 colour */
#define STA_GEOMETRY_OUT_ID         1 /* RG32UI: node slot, point index */
#define STA_GEOMETRY_OUT_POSITION   2 /* RGBA32F: camera-space position (compute resolve) */
#define STA_GEOMETRY_OUT_CLASS      3 /* R8UI: the point's class (compute resolve) */
/* The ground model for STA_COLOUR_HEIGHT (geometry_colour.glsl; unit 0 is the raster's). */
#define STA_GEOMETRY_SAMPLER_GROUND 1 /* R32F: ground height per cell */
#define STA_SPLAT_SAMPLER_POINTS    0 /* pulled splats: usamplerBuffer RGBA32UI, points */
#define STA_SPLAT_SAMPLER_SPLATS    2 /* pulled splats: usamplerBuffer RG32UI, splats */

/* Compute rasteriser (raster_common.glsl, raster_points.comp, raster_resolve.*). */
#define STA_RASTER_SAMPLER_POINTS    0 /* usamplerBuffer RGBA32UI: the node arena */
#define STA_RASTER_BUFFER_BATCHES    0 /* uvec2 per workgroup: node table index, first point */
#define STA_RASTER_BUFFER_NODES      1 /* the frame's node table */
#define STA_RASTER_BUFFER_DEPTH      2 /* uint per pixel (uint64 when packed) */
#define STA_RASTER_BUFFER_PAYLOAD    3 /* uint per pixel: draw-order index (two-pass only) */
#define STA_RASTER_BUFFER_CANDIDATES 4 /* uint per invocation: its candidates (two-pass) */
#define STA_RASTER_WORKGROUP_SIZE    128
#define STA_RASTER_BATCH_POINTS      4096        /* points per workgroup */
#define STA_RASTER_NO_POINT          0xFFFFFFFFu /* empty payload */
#define STA_RASTER_STEP_DEPTH        0           /* two-pass: depth */
#define STA_RASTER_STEP_PAYLOAD      1           /* two-pass: payload at that depth */
#define STA_RASTER_STEP_PACKED       2           /* one pass, 64-bit atomics */

/* Unproject (unproject.comp). */
#define STA_UNPROJECT_SAMPLER_DEPTH   0 /* reverse-Z depth */
#define STA_UNPROJECT_IMAGE_POSITION  0 /* RGBA32F out: camera-space positions */
#define STA_UNPROJECT_IMAGE_CLASS     1 /* R8UI point classes (STA_UNPROJECT_MARK) */
#define STA_UNPROJECT_IMAGE_TILES     2 /* R32UI out: 1 per tile with a marked pixel (MARK) */
#define STA_UNPROJECT_BUFFER_POSITION 0 /* vec4 per pixel out (STA_STAGED_STORES, gl_staged.h) */

/* Colour conversion of the pipeline's input (colour_to_float.comp). */
#define STA_COLOUR_TO_FLOAT_SAMPLER_COLOUR8 0 /* RGBA8 colour of the geometry pass */
#define STA_COLOUR_TO_FLOAT_IMAGE_COLOUR    0 /* RGBA32F out */

/* Debug views of the pipeline's buffers (display.comp). */
#define STA_DISPLAY_IMAGE_POSITION      0 /* RGBA32F */
#define STA_DISPLAY_IMAGE_COLOUR        1 /* RGBA32F */
#define STA_DISPLAY_IMAGE_LABEL         2 /* R16F, STA_LABEL_* */
#define STA_DISPLAY_IMAGE_NORMAL        3 /* RGBA32F */
#define STA_DISPLAY_IMAGE_OUT           4 /* RGBA8 out */
#define STA_DISPLAY_IMAGE_FILLED_COLOUR 5 /* RGBA8 pull-push colour, alpha 1: the overlay's */

/* HPR point pyramid, one level per dispatch (hpr_pyramid.comp). */
#define STA_HPR_PYRAMID_IMAGE_SRC  0 /* RGBA32F level l - 1 */
#define STA_HPR_PYRAMID_IMAGE_DST  1 /* RGBA32F out: level l */
#define STA_HPR_PYRAMID_BUFFER_DST 0 /* vec4 per texel out: level l (STA_STAGED_STORES) */

/* HPR pyramidal occlusion (hpr_occlusion.comp). Positions and pyramid are read as images,
 * not sampled: llvmpipe's imageLoad costs ~2.5x less than its texelFetch (issue 15,
 * fourteenth round). */
#define STA_HPR_OCCLUSION_IMAGE_LABEL    0 /* R16F out */
#define STA_HPR_OCCLUSION_IMAGE_POSITION 1 /* RGBA32F level 0 */
#define STA_HPR_OCCLUSION_IMAGE_PYRAMID  2 /* RGBA32F levels >= 1 side by side (pass_hpr.h) */
#define STA_HPR_OCCLUSION_BUFFER_LIST    0 /* HPR_REFINE: the pixels to refine */

/* Sparse HPR copy step (hpr_sparse_classify.comp); the label and position units are the
 * occlusion's (bound once for the anchors, the copy steps and the refinements). */
#define STA_HPR_SPARSE_CLASSIFY_IMAGE_LABEL     0 /* R16F: anchors in, the rest out */
#define STA_HPR_SPARSE_CLASSIFY_IMAGE_POSITION  1 /* RGBA32F */
#define STA_HPR_SPARSE_CLASSIFY_BUFFER_LIST     0 /* the pixels to refine (appended) */
#define STA_HPR_SPARSE_CLASSIFY_BUFFER_DISPATCH 1 /* the refinement's indirect dispatch */

/* HPR exhaustive occlusion (hpr_exhaustive.comp). */
#define STA_HPR_EXHAUSTIVE_SAMPLER_POSITION 0
#define STA_HPR_EXHAUSTIVE_IMAGE_LABEL      0 /* R16F out */

/* Pull-push (pullpush_pull.comp, pullpush_push.comp): one layout for both, so that a
 * level bound for one dispatch stays valid for the next. */
#define STA_PULLPUSH_IMAGE_OUT_POSITION    0 /* level written: pull's coarse, push's own */
#define STA_PULLPUSH_IMAGE_OUT_COLOUR      1
#define STA_PULLPUSH_IMAGE_FINE_POSITION   2 /* pull's fine level; push's input (level 0) */
#define STA_PULLPUSH_IMAGE_FINE_COLOUR     3 /* pull's fine level above level 0 */
#define STA_PULLPUSH_IMAGE_LABEL           4 /* R16F HPR labels of the input */
#define STA_PULLPUSH_IMAGE_COARSE_POSITION 5 /* push: the pushed level l + 1 */
#define STA_PULLPUSH_IMAGE_COARSE_COLOUR   6
#define STA_PULLPUSH_IMAGE_LAST            6 /* highest image unit above */
#define STA_PULLPUSH_SAMPLER_INPUT_COLOUR  1 /* RGBA32F or RGBA8 input colour */
#define STA_PULLPUSH_BUFFER_OUT_POSITION   0 /* vec4 per texel out (STA_STAGED_STORES) */
#define STA_PULLPUSH_BUFFER_OUT_COLOUR     1 /* vec4 per texel out (STA_STAGED_STORES) */

/* Screen-space normals (normals_screen.comp) and their smoothing (normals_smooth.comp). */
#define STA_NORMALS_SCREEN_IMAGE_NORMAL   0 /* RGBA32F out */
#define STA_NORMALS_SCREEN_IMAGE_POSITION 1
#define STA_NORMALS_SMOOTH_IMAGE_SMOOTHED 0 /* RGBA32F out */
#define STA_NORMALS_SMOOTH_IMAGE_POSITION 1
#define STA_NORMALS_SMOOTH_IMAGE_NORMAL   2

/* Pyramidal normals (normals_pyramid_level.comp, normals_pyramid_gather.comp); POINTS
 * is declared by their shared library pullpush_normals.glsl. */
#define STA_NORMALS_PYRAMID_IMAGE_POINTS          1 /* RGBA32F points of the level */
#define STA_NORMALS_PYRAMID_LEVEL_IMAGE_ATLAS     0 /* RGBA32F out: normals of levels >= 1 */
#define STA_NORMALS_PYRAMID_LEVEL_BUFFER_ATLAS    0 /* vec4 per texel out (STA_STAGED_STORES) */
#define STA_NORMALS_PYRAMID_GATHER_IMAGE_NORMAL   0 /* RGBA32F out */
#define STA_NORMALS_PYRAMID_GATHER_IMAGE_ATLAS    2
#define STA_NORMALS_PYRAMID_UPSAMPLE_IMAGE_NORMAL 0 /* RGBA32F out */
/* normals_upsample.glsl, in normals_pyramid_upsample.comp and shade.comp
 * (STA_SHADE_UPSAMPLE): above every image unit of both */
#define STA_NORMALS_UPSAMPLE_IMAGE_HALF           5 /* RGBA32F anchors: normal, plane offset */
#define STA_NORMALS_PYRAMID_IMAGE_LAST            5 /* highest image unit above */

/* Blinn-Phong shading (shade.comp). */
#define STA_SHADE_IMAGE_POSITION 0
#define STA_SHADE_IMAGE_COLOUR   1
#define STA_SHADE_IMAGE_NORMAL   2
#define STA_SHADE_IMAGE_OUT      3 /* RGBA8 out */

/* Mirror composite (render/pass_mirror.c, shaders/mirror_composite.comp). */
#define STA_MIRROR_IMAGE_OUT               0  /* RGBA8 frame colour, read and written */
#define STA_MIRROR_SAMPLER_DEPTH           0  /* the frame's depth */
#define STA_MIRROR_SAMPLER_REFLECTED       1  /* the reflected view's colour */
#define STA_MIRROR_SAMPLER_REFLECTED_DEPTH 2  /* its depth (0: nothing drawn) */
#define STA_MIRROR_SAMPLER_FILLED          3  /* the pipeline's filled positions, when it ran */
#define STA_MIRROR_OUTLINE_MAX             64 /* = STA_MIRROR_MAX_VERTICES */

/* Eye-dome lighting (edl.comp). */
#define STA_EDL_IMAGE_POSITION 0
#define STA_EDL_IMAGE_COLOUR   1
#define STA_EDL_IMAGE_OUT      3 /* RGBA8 out */

/* Volumetric classes shown as points (volumetric_mark.comp, volumetric_overlay.comp). */
#define STA_VOLUMETRIC_MARK_IMAGE_ID         0 /* RG32UI point ids (render/target.h) */
#define STA_VOLUMETRIC_MARK_IMAGE_POSITION   4 /* RGBA32F camera-space positions, w updated */
#define STA_VOLUMETRIC_MARK_IMAGE_CLASS      5 /* R8UI point classes (STA_VOLUMETRIC_CLASS_IMAGE) */
#define STA_VOLUMETRIC_MARK_BUFFER_ARENA     0 /* the GPU cache's arena */
#define STA_VOLUMETRIC_MARK_BUFFER_NODES     1 /* uvec2 per node slot: offset, count */
#define STA_VOLUMETRIC_OVERLAY_IMAGE_OUT     1 /* RGBA8, written where marked */
/* The overlay's tile list (volumetric_tiles.comp writes it, volumetric_overlay.comp reads
 * it; the first three words are the overlay's indirect dispatch). */
#define STA_VOLUMETRIC_TILES_BUFFER_LIST     0
#define STA_VOLUMETRIC_TILES_IMAGE_FLAGS     5 /* R32UI tiles with a marked pixel (VW_FLAGS) */
#define STA_VOLUMETRIC_OVERLAY_BUFFER_TILES  0
/* volumetric_window.glsl, in volumetric_overlay.comp (and the positions of
 * volumetric_tiles.comp): above the image units of both */
#define STA_VOLUMETRIC_WINDOW_IMAGE_POSITION 4 /* RGBA32F positions, marked: w = 2 */
#define STA_VOLUMETRIC_WINDOW_SAMPLER_COLOUR 0 /* the geometry pass's colour (RGBA8 or float) */

/* Every define above, as "name value" pairs for the shader preamble. */
#define STA_BINDING_DEFINES                                                                        \
 X(STA_ATTRIB_POSITION_INTENSITY)                                                                  \
 X(STA_ATTRIB_COLOUR_CLASS)                                                                        \
 X(STA_ATTRIB_RETURNS)                                                                             \
 X(STA_ATTRIB_SPLAT)                                                                               \
 X(STA_WORKGROUP_SIZE_X)                                                                           \
 X(STA_WORKGROUP_SIZE_Y)                                                                           \
 X(STA_COLOUR_RGB)                                                                                 \
 X(STA_COLOUR_INTENSITY)                                                                           \
 X(STA_COLOUR_ELEVATION)                                                                           \
 X(STA_COLOUR_CLASSIFICATION)                                                                      \
 X(STA_COLOUR_RETURN_NUMBER)                                                                       \
 X(STA_COLOUR_HEIGHT)                                                                              \
 X(STA_GEOMETRY_OUT_COLOUR)                                                                        \
 X(STA_GEOMETRY_OUT_ID)                                                                            \
 X(STA_GEOMETRY_OUT_POSITION)                                                                      \
 X(STA_GEOMETRY_OUT_CLASS)                                                                         \
 X(STA_SPLAT_SAMPLER_POINTS)                                                                       \
 X(STA_SPLAT_SAMPLER_SPLATS)                                                                       \
 X(STA_GEOMETRY_SAMPLER_GROUND)                                                                    \
 X(STA_RASTER_SAMPLER_POINTS)                                                                      \
 X(STA_RASTER_BUFFER_BATCHES)                                                                      \
 X(STA_RASTER_BUFFER_NODES)                                                                        \
 X(STA_RASTER_BUFFER_DEPTH)                                                                        \
 X(STA_RASTER_BUFFER_PAYLOAD)                                                                      \
 X(STA_RASTER_BUFFER_CANDIDATES)                                                                   \
 X(STA_RASTER_WORKGROUP_SIZE)                                                                      \
 X(STA_RASTER_BATCH_POINTS)                                                                        \
 X(STA_RASTER_NO_POINT)                                                                            \
 X(STA_RASTER_STEP_DEPTH)                                                                          \
 X(STA_RASTER_STEP_PAYLOAD)                                                                        \
 X(STA_RASTER_STEP_PACKED)                                                                         \
 X(STA_HPR_BACKGROUND_OPEN_SECTORS)                                                                \
 X(STA_UNPROJECT_SAMPLER_DEPTH)                                                                    \
 X(STA_UNPROJECT_IMAGE_POSITION)                                                                   \
 X(STA_UNPROJECT_IMAGE_CLASS)                                                                      \
 X(STA_UNPROJECT_IMAGE_TILES)                                                                      \
 X(STA_UNPROJECT_BUFFER_POSITION)                                                                  \
 X(STA_COLOUR_TO_FLOAT_SAMPLER_COLOUR8)                                                            \
 X(STA_COLOUR_TO_FLOAT_IMAGE_COLOUR)                                                               \
 X(STA_DISPLAY_IMAGE_POSITION)                                                                     \
 X(STA_DISPLAY_IMAGE_COLOUR)                                                                       \
 X(STA_DISPLAY_IMAGE_LABEL)                                                                        \
 X(STA_DISPLAY_IMAGE_NORMAL)                                                                       \
 X(STA_DISPLAY_IMAGE_OUT)                                                                          \
 X(STA_DISPLAY_IMAGE_FILLED_COLOUR)                                                                \
 X(STA_HPR_PYRAMID_IMAGE_SRC)                                                                      \
 X(STA_HPR_PYRAMID_IMAGE_DST)                                                                      \
 X(STA_HPR_PYRAMID_BUFFER_DST)                                                                     \
 X(STA_HPR_OCCLUSION_IMAGE_LABEL)                                                                  \
 X(STA_HPR_OCCLUSION_IMAGE_POSITION)                                                               \
 X(STA_HPR_OCCLUSION_IMAGE_PYRAMID)                                                                \
 X(STA_HPR_OCCLUSION_BUFFER_LIST)                                                                  \
 X(STA_HPR_SPARSE_CLASSIFY_IMAGE_LABEL)                                                            \
 X(STA_HPR_SPARSE_CLASSIFY_IMAGE_POSITION)                                                         \
 X(STA_HPR_SPARSE_CLASSIFY_BUFFER_LIST)                                                            \
 X(STA_HPR_SPARSE_CLASSIFY_BUFFER_DISPATCH)                                                        \
 X(STA_HPR_EXHAUSTIVE_SAMPLER_POSITION)                                                            \
 X(STA_HPR_EXHAUSTIVE_IMAGE_LABEL)                                                                 \
 X(STA_PULLPUSH_IMAGE_OUT_POSITION)                                                                \
 X(STA_PULLPUSH_IMAGE_OUT_COLOUR)                                                                  \
 X(STA_PULLPUSH_IMAGE_FINE_POSITION)                                                               \
 X(STA_PULLPUSH_IMAGE_FINE_COLOUR)                                                                 \
 X(STA_PULLPUSH_IMAGE_LABEL)                                                                       \
 X(STA_PULLPUSH_IMAGE_COARSE_POSITION)                                                             \
 X(STA_PULLPUSH_IMAGE_COARSE_COLOUR)                                                               \
 X(STA_PULLPUSH_IMAGE_LAST)                                                                        \
 X(STA_PULLPUSH_SAMPLER_INPUT_COLOUR)                                                              \
 X(STA_PULLPUSH_BUFFER_OUT_POSITION)                                                               \
 X(STA_PULLPUSH_BUFFER_OUT_COLOUR)                                                                 \
 X(STA_NORMALS_SCREEN_IMAGE_NORMAL)                                                                \
 X(STA_NORMALS_SCREEN_IMAGE_POSITION)                                                              \
 X(STA_NORMALS_SMOOTH_IMAGE_SMOOTHED)                                                              \
 X(STA_NORMALS_SMOOTH_IMAGE_POSITION)                                                              \
 X(STA_NORMALS_SMOOTH_IMAGE_NORMAL)                                                                \
 X(STA_NORMALS_PYRAMID_IMAGE_POINTS)                                                               \
 X(STA_NORMALS_PYRAMID_LEVEL_IMAGE_ATLAS)                                                          \
 X(STA_NORMALS_PYRAMID_LEVEL_BUFFER_ATLAS)                                                         \
 X(STA_NORMALS_PYRAMID_GATHER_IMAGE_NORMAL)                                                        \
 X(STA_NORMALS_PYRAMID_GATHER_IMAGE_ATLAS)                                                         \
 X(STA_NORMALS_PYRAMID_UPSAMPLE_IMAGE_NORMAL)                                                      \
 X(STA_NORMALS_UPSAMPLE_IMAGE_HALF)                                                                \
 X(STA_NORMALS_PYRAMID_IMAGE_LAST)                                                                 \
 X(STA_SHADE_IMAGE_POSITION)                                                                       \
 X(STA_SHADE_IMAGE_COLOUR)                                                                         \
 X(STA_SHADE_IMAGE_NORMAL)                                                                         \
 X(STA_SHADE_IMAGE_OUT)                                                                            \
 X(STA_MIRROR_IMAGE_OUT)                                                                           \
 X(STA_MIRROR_SAMPLER_DEPTH)                                                                       \
 X(STA_MIRROR_SAMPLER_REFLECTED)                                                                   \
 X(STA_MIRROR_SAMPLER_REFLECTED_DEPTH)                                                             \
 X(STA_MIRROR_SAMPLER_FILLED)                                                                      \
 X(STA_MIRROR_OUTLINE_MAX)                                                                         \
 X(STA_EDL_IMAGE_POSITION)                                                                         \
 X(STA_EDL_IMAGE_COLOUR)                                                                           \
 X(STA_EDL_IMAGE_OUT)                                                                              \
 X(STA_VOLUMETRIC_MARK_IMAGE_ID)                                                                   \
 X(STA_VOLUMETRIC_MARK_IMAGE_POSITION)                                                             \
 X(STA_VOLUMETRIC_MARK_IMAGE_CLASS)                                                                \
 X(STA_VOLUMETRIC_MARK_BUFFER_ARENA)                                                               \
 X(STA_VOLUMETRIC_MARK_BUFFER_NODES)                                                               \
 X(STA_VOLUMETRIC_OVERLAY_IMAGE_OUT)                                                               \
 X(STA_VOLUMETRIC_TILES_BUFFER_LIST)                                                               \
 X(STA_VOLUMETRIC_TILES_IMAGE_FLAGS)                                                               \
 X(STA_VOLUMETRIC_OVERLAY_BUFFER_TILES)                                                            \
 X(STA_VOLUMETRIC_WINDOW_IMAGE_POSITION)                                                           \
 X(STA_VOLUMETRIC_WINDOW_SAMPLER_COLOUR)

#endif
