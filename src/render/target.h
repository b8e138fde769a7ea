/* SPDX-License-Identifier: MIT
 * An offscreen framebuffer: RGBA8 colour, 32-bit float depth (reverse-Z) and the id of
 * the point drawn in each pixel (node slot and index in the node, for picking).
 */
#ifndef STA_RENDER_TARGET_H
#define STA_RENDER_TARGET_H

#include <epoxy/gl.h>
#include <stdint.h>

#include "core/status.h"

/* Both halves of the id of a pixel where no point was drawn. */
#define STA_TARGET_NO_POINT UINT32_C(0xFFFFFFFF)

typedef struct sta_render_target {
    GLuint framebuffer;
    GLuint colour; /* GL_RGBA8 texture */
    GLuint depth;  /* GL_DEPTH_COMPONENT32F texture */
    GLuint id;     /* GL_RG32UI texture: node slot, point index; STA_TARGET_NO_POINT: none */
    int width_px, height_px;
} sta_render_target;

/* Creates (or resizes) the target. */
sta_status sta_render_target_resize(sta_render_target *target, int width_px, int height_px,
                                    sta_error *err);

void sta_render_target_release(sta_render_target *target);

/* Binds it and clears colour to `background` (RGB 0..1), depth to 0 (far) and ids to
 * STA_TARGET_NO_POINT. */
void sta_render_target_begin(sta_render_target *target, const float background[3]);

/* Binds it for drawing (whole viewport) without clearing. */
void sta_render_target_bind(sta_render_target *target);

/* Reads colour as RGBA8, top row first (width * height * 4 bytes). */
void sta_render_target_read_rgba(const sta_render_target *target, uint8_t *out);

/* Reads depth (reverse-Z: 1 at the near plane, 0 = nothing drawn), top row first. */
void sta_render_target_read_depth(const sta_render_target *target, float *out);

/* Reads the ids as (node slot, point index) pairs, top row first (width * height * 2). */
void sta_render_target_read_ids(const sta_render_target *target, uint32_t *out);

/* Reads the depth of the width x height block whose lower-left texel is (x, y), GL
 * order (rows from the bottom, bottom row first); the block must lie inside. */
void sta_render_target_read_depth_block(const sta_render_target *target, int x, int y, int width_px,
                                        int height_px, float *out);

/* Copies the colour to the default framebuffer (the window), same size, no scaling. */
void sta_render_target_present(const sta_render_target *target);

#endif
