/* SPDX-License-Identifier: MIT
 * Moving float images between the CPU (sta_image) and GL textures, and dispatching
 * 2D compute work. Main thread (GL) only.
 */
#ifndef STA_RENDER_GL_IMAGE_H
#define STA_RENDER_GL_IMAGE_H

#include <epoxy/gl.h>

#include "core/status.h"
#include "render/ref/image.h"

/* Creates a float texture (1 level) holding `image`: internal format GL_R32F,
 * GL_RG32F, GL_RGB32F or GL_RGBA32F by channel count (RGB images become RGBA32F
 * with alpha 1, since image load/store has no RGB formats). Row 0 goes to texture
 * row 0. */
sta_status sta_gl_texture_from_image(const sta_image *image, GLuint *out_texture, sta_error *err);

/* Creates an empty float texture with `levels` mip levels (1 = no pyramid) of
 * `channels` (1, 2 or 4) floats. */
sta_status sta_gl_texture_create(int width, int height, int channels, int levels,
                                 GLuint *out_texture, sta_error *err);

/* The format of HPR's label textures: STA_LABEL_* (0..3) are exact in a 16-bit float,
 * which halves the labels' traffic against R32F (issue 15, fourteenth round, third part
 * of docs/BENCHMARKS.md). Readers bind them with this format (r16f in the shaders). */
#define STA_GL_LABEL_FORMAT GL_R16F

/* An empty label texture (1 level, STA_GL_LABEL_FORMAT); read back with
 * sta_gl_texture_to_image and 1 channel. */
sta_status sta_gl_label_texture_create(int width, int height, GLuint *out_texture, sta_error *err);

/* A label texture holding a 1-channel `image` of STA_LABEL_* values. */
sta_status sta_gl_label_texture_from_image(const sta_image *image, GLuint *out_texture,
                                           sta_error *err);

/* An empty RGBA8 texture (1 level): the pipeline's filled colour (screen_space.h). */
sta_status sta_gl_texture_create_rgba8(int width, int height, GLuint *out_texture, sta_error *err);

/* An RGBA8 texture holding a 4-channel `image` (each value clamped and rounded to 8 bits
 * by GL, as sta_unorm8 does). */
sta_status sta_gl_texture_rgba8_from_image(const sta_image *image, GLuint *out_texture,
                                           sta_error *err);

/* Reads level `level` of a float or RGBA8 texture into `out` (allocated here with `channels`
 * per pixel; the level's own size). */
sta_status sta_gl_texture_to_image(GLuint texture, int level, int channels, sta_image *out,
                                   sta_error *err);

/* glDispatchCompute over width x height pixels in STA_WORKGROUP_SIZE_X x _Y groups,
 * followed by a barrier for image and texture reads. */
void sta_gl_dispatch_2d(int width, int height);

/* The GL internal format for 1, 2 or 4 float channels. */
GLenum sta_gl_float_format(int channels);

#endif
