/* SPDX-License-Identifier: MIT
 * Staged stores (gl_staged.h). */
#include "render/gl_staged.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int forced = -1;
static int decided = -1;

static bool renderer_is_software(void)
{
    const char *renderer = (const char *)glGetString(GL_RENDERER);
    return renderer && (strstr(renderer, "llvmpipe") || strstr(renderer, "softpipe"));
}

int sta_gl_staged_stores_from_env(const char *value)
{
    if (!value) {
        return -1;
    }
    if (strcmp(value, "0") == 0 || strcmp(value, "1") == 0) {
        return value[0] == '1';
    }
    fprintf(stderr, "strata: STRATA_STAGED_STORES=%s is neither 0 nor 1; the renderer decides\n",
            value);
    return -1;
}

bool sta_gl_staged_stores(void)
{
    if (forced >= 0) {
        return forced != 0;
    }
    if (decided < 0) {
        decided = sta_gl_staged_stores_from_env(getenv("STRATA_STAGED_STORES"));
        if (decided < 0) {
            decided = renderer_is_software() ? 1 : 0;
        }
    }
    return decided != 0;
}

void sta_gl_staged_stores_force(int on)
{
    forced = on < 0 ? -1 : on != 0;
}

const char *sta_gl_staged_define(bool staged)
{
    return staged ? "#define STA_STAGED_STORES 1\n" : "";
}

// The bytes of one range of width x height vec4s, rounded up to the offset alignment.
static GLsizeiptr range_bytes(GLint alignment, int width, int height)
{
    GLsizeiptr bytes = (GLsizeiptr)width * (GLsizeiptr)height * 4 * (GLsizeiptr)sizeof(float);
    return (bytes + alignment - 1) / alignment * alignment;
}

sta_status sta_gl_staging_bind(sta_gl_staging *staging, GLuint first_binding, int count, int width,
                               int height, sta_error *err)
{
    if (staging->alignment <= 0) {
        glGetIntegerv(GL_SHADER_STORAGE_BUFFER_OFFSET_ALIGNMENT, &staging->alignment);
        if (staging->alignment <= 0) {
            staging->alignment = 256;
        }
    }
    GLsizeiptr range = range_bytes(staging->alignment, width, height);
    GLsizeiptr bytes = range * count;
    if (bytes > staging->bytes) {
        GLuint buffer = 0;
        glCreateBuffers(1, &buffer);
        glNamedBufferStorage(buffer, bytes, NULL, 0);
        if (glGetError() != GL_NO_ERROR) {
            glDeleteBuffers(1, &buffer);
            return sta_fail(err, STA_ERR_GL, "cannot allocate a %lld-byte staging buffer",
                            (long long)bytes);
        }
        GLint alignment = staging->alignment;
        sta_gl_staging_release(staging);
        staging->buffer = buffer;
        staging->bytes = bytes;
        staging->alignment = alignment;
    }
    for (int i = 0; i < count; i++) {
        glBindBufferRange(GL_SHADER_STORAGE_BUFFER, first_binding + (GLuint)i, staging->buffer,
                          range * i, range);
    }
    return STA_OK;
}

void sta_gl_staging_copy(const sta_gl_staging *staging, int index, GLuint texture, int x, int y,
                         int width, int height)
{
    // The range's offset as sta_gl_staging_bind laid it out.
    GLsizeiptr offset = range_bytes(staging->alignment, width, height) * index;
    glMemoryBarrier(GL_PIXEL_BUFFER_BARRIER_BIT);
    glBindBuffer(GL_PIXEL_UNPACK_BUFFER, staging->buffer);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
    glTextureSubImage2D(texture, 0, x, y, width, height, GL_RGBA, GL_FLOAT, (const void *)offset);
    glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
}

void sta_gl_staging_release(sta_gl_staging *staging)
{
    if (staging->buffer) {
        glDeleteBuffers(1, &staging->buffer);
    }
    staging->buffer = 0;
    staging->bytes = 0;
    staging->alignment = 0;
}
