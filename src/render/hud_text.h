/* SPDX-License-Identifier: MIT
 * The on-screen readout's text: lines drawn into an RGBA image on the CPU with
 * stb_truetype (Debian libstb-dev) and the DejaVu Sans Mono font (fonts-dejavu-core).
 * No GL: headless frames burn it into the image before writing it (--hud); the window
 * uploads the same image as an overlay (render/hud_overlay.h).
 */
#ifndef STA_RENDER_HUD_TEXT_H
#define STA_RENDER_HUD_TEXT_H

#include <stddef.h>
#include <stdint.h>

#include "core/status.h"

/* The font used when none is given (Debian's fonts-dejavu-core). */
#define STA_HUD_DEFAULT_FONT         "/usr/share/fonts/truetype/dejavu/DejaVuSansMono.ttf"
/* Text height in pixels when none is given. */
#define STA_HUD_DEFAULT_PIXEL_HEIGHT 14.0f

typedef struct sta_hud_font sta_hud_font;

/* Loads a TrueType font (NULL: STA_HUD_DEFAULT_FONT) for text `pixel_height` pixels
 * high (0: STA_HUD_DEFAULT_PIXEL_HEIGHT). Errors: STA_ERR_IO, STA_ERR_FORMAT naming
 * the file (not a font stb_truetype can read), STA_ERR_NOMEM. */
sta_status sta_hud_font_open(const char *path, float pixel_height, sta_hud_font **out_font,
                             sta_error *err);

/* Frees the font; NULL is a no-op. */
void sta_hud_font_close(sta_hud_font *font);

/* Height of one line, pixels. */
int sta_hud_line_height(const sta_hud_font *font);

/* Width of `text` in pixels. */
int sta_hud_text_width(const sta_hud_font *font, const char *text);

/* (The font's glyph scratch buffer is used: one thread per font at a time.)
 * Draws `count` lines with their top-left corner at (x, y) into `rgba` (width x height
 * pixels, top row first, 4 bytes each), white on a translucent dark box so that the
 * text reads over any scene; clipped at the image's borders. Characters outside
 * printable ASCII are drawn as '?'. */
void sta_hud_draw_lines(sta_hud_font *font, uint8_t *rgba, int width, int height, int x, int y,
                        const char *const *lines, size_t count);

/* A filled rectangle of the readout's markers (measurement vertices and edges), in
 * pixels from the top-left corner. */
typedef struct sta_hud_rect {
    int x, y, w, h;
    uint8_t rgb[3];
} sta_hud_rect;

/* Fills `count` rectangles into `rgba` (width x height, top row first), clipped. */
void sta_hud_fill_rects(uint8_t *rgba, int width, int height, const sta_hud_rect *rects,
                        size_t count);

#endif
