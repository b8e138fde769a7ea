/* SPDX-License-Identifier: MIT
 * The readout in the window: text lines drawn on the CPU (render/hud_text.h) into a
 * small image, uploaded to a texture and blitted onto the window's top-left corner
 * after the frame is presented. One per window; main thread (GL).
 */
#ifndef STA_RENDER_HUD_OVERLAY_H
#define STA_RENDER_HUD_OVERLAY_H

#include <stddef.h>
#include <stdint.h>

#include "core/status.h"
#include "render/hud_text.h"

typedef struct sta_hud_overlay {
    sta_hud_font *font;
    unsigned texture;     /* GL texture name, 0 until the first draw */
    unsigned framebuffer; /* read framebuffer with the texture attached */
    int width, height;    /* texture size */
    uint8_t *pixels;      /* width * height * 4 */
} sta_hud_overlay;

/* Loads the default font. Errors: as sta_hud_font_open. */
sta_status sta_hud_overlay_init(sta_hud_overlay *overlay, sta_error *err);

/* Draws `count` lines onto the default framebuffer (window_w x window_h), top-left.
 * Errors: STA_ERR_NOMEM. */
sta_status sta_hud_overlay_draw(sta_hud_overlay *overlay, const char *const *lines, size_t count,
                                int window_w, int window_h, sta_error *err);

/* Fills rectangles (top-left pixel coordinates) on the default framebuffer of height
 * `window_h`: scissored clears, no shader. */
void sta_hud_overlay_fill_rects(const sta_hud_rect *rects, size_t count, int window_h);

/* Frees GL objects and memory; a zeroed overlay is a no-op. */
void sta_hud_overlay_release(sta_hud_overlay *overlay);

#endif
