/* SPDX-License-Identifier: MIT
 * Readout overlay: CPU text image -> texture -> blit (see hud_overlay.h). */
#include "render/hud_overlay.h"

#include <epoxy/gl.h>
#include <string.h>

#include "core/alloc.h"

#define MARGIN_PX  8 /* from the window's corner */
#define PADDING_PX 4 /* around the text inside the box */

sta_status sta_hud_overlay_init(sta_hud_overlay *o, sta_error *err)
{
    memset(o, 0, sizeof(*o));
    return sta_hud_font_open(NULL, 0.0f, &o->font, err);
}

static void release_gl(sta_hud_overlay *o)
{
    if (o->framebuffer) {
        glDeleteFramebuffers(1, &o->framebuffer);
    }
    if (o->texture) {
        glDeleteTextures(1, &o->texture);
    }
    o->framebuffer = o->texture = 0;
}

sta_status sta_hud_overlay_draw(sta_hud_overlay *o, const char *const *lines, size_t count,
                                int window_w, int window_h, sta_error *err)
{
    int text_w = 0;
    for (size_t i = 0; i < count; i++) {
        int w = sta_hud_text_width(o->font, lines[i]);
        text_w = w > text_w ? w : text_w;
    }
    int w = text_w + 2 * PADDING_PX, h = (int)count * sta_hud_line_height(o->font) + 2 * PADDING_PX;
    w = w < window_w - MARGIN_PX ? w : window_w - MARGIN_PX;
    h = h < window_h - MARGIN_PX ? h : window_h - MARGIN_PX;
    if (count == 0 || w <= 0 || h <= 0) {
        return STA_OK;
    }
    if (w != o->width || h != o->height) {
        release_gl(o);
        sta_free(o->pixels);
        o->pixels = sta_alloc_array((size_t)w * (size_t)h, 4);
        if (!o->pixels) {
            o->width = o->height = 0;
            return sta_fail(err, STA_ERR_NOMEM, "out of memory for a %dx%d readout", w, h);
        }
        o->width = w;
        o->height = h;
        glCreateTextures(GL_TEXTURE_2D, 1, &o->texture);
        glTextureStorage2D(o->texture, 1, GL_RGBA8, w, h);
        glCreateFramebuffers(1, &o->framebuffer);
        glNamedFramebufferTexture(o->framebuffer, GL_COLOR_ATTACHMENT0, o->texture, 0);
    }
    memset(o->pixels, 0, (size_t)w * (size_t)h * 4);
    sta_hud_draw_lines(o->font, o->pixels, w, h, PADDING_PX, PADDING_PX, lines, count);
    glTextureSubImage2D(o->texture, 0, 0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, o->pixels);
    // The image's first row is its top: blit it flipped to the window's top-left.
    glBlitNamedFramebuffer(o->framebuffer, 0, 0, 0, w, h, MARGIN_PX, window_h - MARGIN_PX,
                           MARGIN_PX + w, window_h - MARGIN_PX - h, GL_COLOR_BUFFER_BIT,
                           GL_NEAREST);
    return STA_OK;
}

void sta_hud_overlay_fill_rects(const sta_hud_rect *rects, size_t count, int window_h)
{
    if (count == 0) {
        return;
    }
    const GLuint window_framebuffer = 0; // the default framebuffer
    glEnable(GL_SCISSOR_TEST);
    for (size_t i = 0; i < count; i++) {
        const sta_hud_rect *r = &rects[i];
        glScissor(r->x, window_h - r->y - r->h, r->w, r->h); // GL rows count from the bottom
        const GLfloat colour[4] = { r->rgb[0] / 255.0f, r->rgb[1] / 255.0f, r->rgb[2] / 255.0f,
                                    1.0f };
        glClearNamedFramebufferfv(window_framebuffer, GL_COLOR, 0, colour);
    }
    glDisable(GL_SCISSOR_TEST);
}

void sta_hud_overlay_release(sta_hud_overlay *o)
{
    release_gl(o);
    sta_free(o->pixels);
    sta_hud_font_close(o->font);
    memset(o, 0, sizeof(*o));
}
