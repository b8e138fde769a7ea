/* SPDX-License-Identifier: MIT
 * Offscreen framebuffer. */
#include "render/target.h"

#include <string.h>

#include "core/alloc.h"

sta_status sta_render_target_resize(sta_render_target *t, int width_px, int height_px,
                                    sta_error *err)
{
    if (t->framebuffer && t->width_px == width_px && t->height_px == height_px) {
        return STA_OK;
    }
    if (width_px <= 0 || height_px <= 0 || width_px > 16384 || height_px > 16384) {
        return sta_fail(err, STA_ERR_ARG, "image size %dx%d is outside 1..16384", width_px,
                        height_px);
    }
    sta_render_target_release(t);
    glCreateTextures(GL_TEXTURE_2D, 1, &t->colour);
    glTextureStorage2D(t->colour, 1, GL_RGBA8, width_px, height_px);
    glCreateTextures(GL_TEXTURE_2D, 1, &t->depth);
    glTextureStorage2D(t->depth, 1, GL_DEPTH_COMPONENT32F, width_px, height_px);
    glCreateTextures(GL_TEXTURE_2D, 1, &t->id);
    glTextureStorage2D(t->id, 1, GL_RG32UI, width_px, height_px);
    glCreateFramebuffers(1, &t->framebuffer);
    glNamedFramebufferTexture(t->framebuffer, GL_COLOR_ATTACHMENT0, t->colour, 0);
    glNamedFramebufferTexture(t->framebuffer, GL_COLOR_ATTACHMENT1, t->id, 0);
    const GLenum buffers[2] = { GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1 };
    glNamedFramebufferDrawBuffers(t->framebuffer, 2, buffers);
    glNamedFramebufferTexture(t->framebuffer, GL_DEPTH_ATTACHMENT, t->depth, 0);
    GLenum state = glCheckNamedFramebufferStatus(t->framebuffer, GL_FRAMEBUFFER);
    t->width_px = width_px;
    t->height_px = height_px;
    if (state != GL_FRAMEBUFFER_COMPLETE) {
        sta_render_target_release(t);
        return sta_fail(err, STA_ERR_GL, "framebuffer %dx%d incomplete (0x%x)", width_px, height_px,
                        (unsigned)state);
    }
    return STA_OK;
}

void sta_render_target_release(sta_render_target *t)
{
    if (t->framebuffer) {
        glDeleteFramebuffers(1, &t->framebuffer);
        glDeleteTextures(1, &t->colour);
        glDeleteTextures(1, &t->depth);
        glDeleteTextures(1, &t->id);
    }
    memset(t, 0, sizeof(*t));
}

void sta_render_target_bind(sta_render_target *t)
{
    glBindFramebuffer(GL_FRAMEBUFFER, t->framebuffer);
    glViewport(0, 0, t->width_px, t->height_px);
}

void sta_render_target_begin(sta_render_target *t, const float background[3])
{
    sta_render_target_bind(t);
    const float colour[4] = { background[0], background[1], background[2], 1.0f };
    const float far_depth = 0.0f;
    glClearNamedFramebufferfv(t->framebuffer, GL_COLOR, 0, colour);
    glClearNamedFramebufferfv(t->framebuffer, GL_DEPTH, 0, &far_depth);
    const GLuint no_point[4] = { STA_TARGET_NO_POINT, STA_TARGET_NO_POINT, 0, 0 };
    glClearNamedFramebufferuiv(t->framebuffer, GL_COLOR, 1, no_point);
}

// glReadPixels returns the bottom row first: flip rows in place.
static void flip_rows(uint8_t *data, int width_bytes, int height)
{
    uint8_t *row = sta_malloc((size_t)width_bytes);
    if (!row) {
        return;
    }
    for (int y = 0; y < height / 2; y++) {
        uint8_t *a = data + (size_t)y * (size_t)width_bytes;
        uint8_t *b = data + (size_t)(height - 1 - y) * (size_t)width_bytes;
        memcpy(row, a, (size_t)width_bytes);
        memcpy(a, b, (size_t)width_bytes);
        memcpy(b, row, (size_t)width_bytes);
    }
    sta_free(row);
}

void sta_render_target_read_rgba(const sta_render_target *t, uint8_t *out)
{
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glGetTextureImage(t->colour, 0, GL_RGBA, GL_UNSIGNED_BYTE, t->width_px * t->height_px * 4, out);
    flip_rows(out, t->width_px * 4, t->height_px);
}

void sta_render_target_read_depth(const sta_render_target *t, float *out)
{
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glGetTextureImage(t->depth, 0, GL_DEPTH_COMPONENT, GL_FLOAT,
                      t->width_px * t->height_px * (int)sizeof(float), out);
    flip_rows((uint8_t *)out, t->width_px * (int)sizeof(float), t->height_px);
}

void sta_render_target_read_ids(const sta_render_target *t, uint32_t *out)
{
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glGetTextureImage(t->id, 0, GL_RG_INTEGER, GL_UNSIGNED_INT,
                      t->width_px * t->height_px * 2 * (int)sizeof(uint32_t), out);
    flip_rows((uint8_t *)out, t->width_px * 2 * (int)sizeof(uint32_t), t->height_px);
}

void sta_render_target_read_depth_block(const sta_render_target *t, int x, int y, int width_px,
                                        int height_px, float *out)
{
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glGetTextureSubImage(t->depth, 0, x, y, 0, width_px, height_px, 1, GL_DEPTH_COMPONENT, GL_FLOAT,
                         width_px * height_px * (int)sizeof(float), out);
}

void sta_render_target_present(const sta_render_target *t)
{
    // Mesa's window-system drawables learn a new window size when the viewport of the
    // default framebuffer is set; without this a resized window keeps its old size and
    // shows the blit shifted by the change in height.
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glViewport(0, 0, t->width_px, t->height_px);
    glBlitNamedFramebuffer(t->framebuffer, 0, 0, 0, t->width_px, t->height_px, 0, 0, t->width_px,
                           t->height_px, GL_COLOR_BUFFER_BIT, GL_NEAREST);
}
