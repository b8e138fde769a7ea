/* SPDX-License-Identifier: MIT
 * Text into an RGBA image with stb_truetype (see hud_text.h). */
#include "render/hud_text.h"

#include <stb_truetype.h>
#include <string.h>

#include "core/alloc.h"
#include "core/file_map.h"

#define PADDING_PX 4   /* box margin around the text */
#define BOX_ALPHA  160 /* of 255: how dark the box behind the text is */
#define GLYPH_MAX  128 /* largest glyph bitmap edge, pixels */

struct sta_hud_font {
    sta_file_map map;    /* the font file's bytes (stb_truetype reads them in place) */
    stbtt_fontinfo info; /* parsed tables */
    float scale;         /* font units to pixels */
    int ascent_px;       /* baseline below the line's top */
    int line_px;         /* line advance */
    uint8_t glyph[GLYPH_MAX * GLYPH_MAX]; /* scratch coverage bitmap */
};

sta_status sta_hud_font_open(const char *path, float pixel_height, sta_hud_font **out_font,
                             sta_error *err)
{
    *out_font = NULL;
    path = path ? path : STA_HUD_DEFAULT_FONT;
    pixel_height = pixel_height > 0.0f ? pixel_height : STA_HUD_DEFAULT_PIXEL_HEIGHT;
    if (pixel_height > GLYPH_MAX / 2) {
        return sta_fail(err, STA_ERR_ARG, "%s: text height %g px above %d", path,
                        (double)pixel_height, GLYPH_MAX / 2);
    }
    sta_hud_font *f = sta_calloc(1, sizeof(*f));
    if (!f) {
        return sta_fail(err, STA_ERR_NOMEM, "%s: out of memory", path);
    }
    sta_status status = sta_file_map_open(path, &f->map, err);
    if (status != STA_OK) {
        sta_free(f);
        return status;
    }
    int offset = stbtt_GetFontOffsetForIndex(f->map.data, 0);
    if (offset < 0 || !stbtt_InitFont(&f->info, f->map.data, offset)) {
        sta_hud_font_close(f);
        return sta_fail(err, STA_ERR_FORMAT, "%s: not a TrueType font", path);
    }
    f->scale = stbtt_ScaleForPixelHeight(&f->info, pixel_height);
    int ascent, descent, gap;
    stbtt_GetFontVMetrics(&f->info, &ascent, &descent, &gap);
    f->ascent_px = (int)(ascent * f->scale + 0.5f);
    f->line_px = (int)((ascent - descent + gap) * f->scale + 0.5f);
    *out_font = f;
    return STA_OK;
}

void sta_hud_font_close(sta_hud_font *font)
{
    if (font) {
        sta_file_map_close(&font->map);
        sta_free(font);
    }
}

int sta_hud_line_height(const sta_hud_font *font)
{
    return font->line_px;
}

static int printable(unsigned char c)
{
    return c >= 32 && c < 127 ? c : '?';
}

int sta_hud_text_width(const sta_hud_font *font, const char *text)
{
    float x = 0.0f;
    for (const unsigned char *c = (const unsigned char *)text; *c; c++) {
        int advance, lsb;
        stbtt_GetCodepointHMetrics(&font->info, printable(*c), &advance, &lsb);
        x += (float)advance * font->scale;
        if (c[1]) {
            x += font->scale *
                 (float)stbtt_GetCodepointKernAdvance(&font->info, printable(*c), printable(c[1]));
        }
    }
    return (int)(x + 0.999f);
}

// Darkens the box [x0, x1) x [y0, y1) (clipped) by BOX_ALPHA.
static void draw_box(uint8_t *rgba, int width, int height, int x0, int y0, int x1, int y1)
{
    x0 = x0 < 0 ? 0 : x0;
    y0 = y0 < 0 ? 0 : y0;
    x1 = x1 > width ? width : x1;
    y1 = y1 > height ? height : y1;
    for (int y = y0; y < y1; y++) {
        for (int x = x0; x < x1; x++) {
            uint8_t *p = rgba + 4 * ((size_t)y * (size_t)width + (size_t)x);
            for (int k = 0; k < 3; k++) {
                p[k] = (uint8_t)(p[k] * (255 - BOX_ALPHA) / 255);
            }
            p[3] = 255;
        }
    }
}

// Blends one glyph's coverage (white) at (gx, gy), clipped.
static void blend_glyph(const uint8_t *glyph, int gw, int gh, uint8_t *rgba, int width, int height,
                        int gx, int gy)
{
    for (int j = 0; j < gh; j++) {
        int y = gy + j;
        if (y < 0 || y >= height) {
            continue;
        }
        for (int i = 0; i < gw; i++) {
            int x = gx + i;
            unsigned a = glyph[j * gw + i];
            if (x < 0 || x >= width || a == 0) {
                continue;
            }
            uint8_t *p = rgba + 4 * ((size_t)y * (size_t)width + (size_t)x);
            for (int k = 0; k < 3; k++) {
                p[k] = (uint8_t)((p[k] * (255 - a) + 255 * a) / 255);
            }
        }
    }
}

static void draw_text(sta_hud_font *font, uint8_t *rgba, int width, int height, int x, int y,
                      const char *text)
{
    float pen = (float)x;
    int baseline = y + font->ascent_px;
    for (const unsigned char *c = (const unsigned char *)text; *c; c++) {
        int cp = printable(*c);
        int advance, lsb, x0, y0, x1, y1;
        stbtt_GetCodepointHMetrics(&font->info, cp, &advance, &lsb);
        stbtt_GetCodepointBitmapBox(&font->info, cp, font->scale, font->scale, &x0, &y0, &x1, &y1);
        int gw = x1 - x0, gh = y1 - y0;
        if (gw > 0 && gh > 0 && gw <= GLYPH_MAX && gh <= GLYPH_MAX) {
            stbtt_MakeCodepointBitmap(&font->info, font->glyph, gw, gh, gw, font->scale,
                                      font->scale, cp);
            blend_glyph(font->glyph, gw, gh, rgba, width, height, (int)(pen + 0.5f) + x0,
                        baseline + y0);
        }
        pen += (float)advance * font->scale;
        if (c[1]) {
            pen += font->scale *
                   (float)stbtt_GetCodepointKernAdvance(&font->info, cp, printable(c[1]));
        }
    }
}

void sta_hud_fill_rects(uint8_t *rgba, int width, int height, const sta_hud_rect *rects,
                        size_t count)
{
    for (size_t i = 0; i < count; i++) {
        const sta_hud_rect *r = &rects[i];
        int x0 = r->x < 0 ? 0 : r->x, y0 = r->y < 0 ? 0 : r->y;
        int x1 = r->x + r->w > width ? width : r->x + r->w;
        int y1 = r->y + r->h > height ? height : r->y + r->h;
        for (int y = y0; y < y1; y++) {
            for (int x = x0; x < x1; x++) {
                uint8_t *p = rgba + 4 * ((size_t)y * (size_t)width + (size_t)x);
                memcpy(p, r->rgb, 3);
                p[3] = 255;
            }
        }
    }
}

void sta_hud_draw_lines(sta_hud_font *font, uint8_t *rgba, int width, int height, int x, int y,
                        const char *const *lines, size_t count)
{
    if (count == 0) {
        return;
    }
    int box_w = 0;
    for (size_t i = 0; i < count; i++) {
        int w = sta_hud_text_width(font, lines[i]);
        box_w = w > box_w ? w : box_w;
    }
    int box_h = (int)count * font->line_px;
    draw_box(rgba, width, height, x - PADDING_PX, y - PADDING_PX, x + box_w + PADDING_PX,
             y + box_h + PADDING_PX);
    for (size_t i = 0; i < count; i++) {
        draw_text(font, rgba, width, height, x, y + (int)i * font->line_px, lines[i]);
    }
}
