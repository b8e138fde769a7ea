/* SPDX-License-Identifier: MIT
 * An offscreen framebuffer: RGBA8 colour and 32-bit float depth (reverse-Z).
 */
#ifndef STA_RENDER_TARGET_H
#define STA_RENDER_TARGET_H

#include <epoxy/gl.h>
#include <stdint.h>

#include "core/status.h"

typedef struct sta_render_target {
    GLuint framebuffer;
    GLuint colour; /* GL_RGBA8 texture */
    GLuint depth;  /* GL_DEPTH_COMPONENT32F texture */
    int width_px, height_px;
} sta_render_target;

/* Creates (or resizes) the target. */
sta_status sta_render_target_resize(sta_render_target *target, int width_px, int height_px,
                                    sta_error *err);

void sta_render_target_release(sta_render_target *target);

/* Binds it and clears colour to `background` (RGB 0..1) and depth to 0 (far). */
void sta_render_target_begin(sta_render_target *target, const float background[3]);

/* Reads colour as RGBA8, top row first (width * height * 4 bytes). */
void sta_render_target_read_rgba(const sta_render_target *target, uint8_t *out);

/* Reads depth (reverse-Z: 1 at the near plane, 0 = nothing drawn), top row first. */
void sta_render_target_read_depth(const sta_render_target *target, float *out);

/* Reads the depth of the width x height block whose lower-left texel is (x, y), GL
 * order (rows from the bottom, bottom row first); the block must lie inside. */
void sta_render_target_read_depth_block(const sta_render_target *target, int x, int y, int width_px,
                                        int height_px, float *out);

/* Copies the colour to the default framebuffer (the window), same size, no scaling. */
void sta_render_target_present(const sta_render_target *target);

#endif
