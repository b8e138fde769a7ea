/* SPDX-License-Identifier: MIT
 * Float images <-> GL textures. */
#include "render/gl_image.h"

#include <string.h>

#include "core/alloc.h"
#include "render/bindings.h"

GLenum sta_gl_float_format(int channels)
{
    switch (channels) {
    case 1:
        return GL_R32F;
    case 2:
        return GL_RG32F;
    default:
        return GL_RGBA32F;
    }
}

static GLenum pixel_format(int channels)
{
    switch (channels) {
    case 1:
        return GL_RED;
    case 2:
        return GL_RG;
    case 3:
        return GL_RGB;
    default:
        return GL_RGBA;
    }
}

static sta_status texture_create(int width, int height, GLenum format, int levels,
                                 GLuint *out_texture, sta_error *err)
{
    *out_texture = 0;
    if (width <= 0 || height <= 0 || levels < 1) {
        return sta_fail(err, STA_ERR_ARG, "texture %dx%d with %d levels is invalid", width, height,
                        levels);
    }
    GLuint texture;
    glCreateTextures(GL_TEXTURE_2D, 1, &texture);
    glTextureStorage2D(texture, levels, format, width, height);
    glTextureParameteri(texture, GL_TEXTURE_MIN_FILTER, GL_NEAREST_MIPMAP_NEAREST);
    glTextureParameteri(texture, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTextureParameteri(texture, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(texture, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    if (glGetError() != GL_NO_ERROR) {
        glDeleteTextures(1, &texture);
        return sta_fail(err, STA_ERR_GL, "cannot create a %dx%d texture", width, height);
    }
    *out_texture = texture;
    return STA_OK;
}

sta_status sta_gl_texture_create(int width, int height, int channels, int levels,
                                 GLuint *out_texture, sta_error *err)
{
    return texture_create(width, height, sta_gl_float_format(channels), levels, out_texture, err);
}

sta_status sta_gl_texture_create_rgba8(int width, int height, GLuint *out_texture, sta_error *err)
{
    return texture_create(width, height, GL_RGBA8, 1, out_texture, err);
}

sta_status sta_gl_label_texture_create(int width, int height, GLuint *out_texture, sta_error *err)
{
    return texture_create(width, height, STA_GL_LABEL_FORMAT, 1, out_texture, err);
}

sta_status sta_gl_label_texture_from_image(const sta_image *image, GLuint *out_texture,
                                           sta_error *err)
{
    if (image->channels != 1) {
        return sta_fail(err, STA_ERR_ARG, "a label texture needs a 1-channel image, not %d",
                        image->channels);
    }
    sta_status status = sta_gl_label_texture_create(image->width, image->height, out_texture, err);
    if (status == STA_OK) {
        glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
        glTextureSubImage2D(*out_texture, 0, 0, 0, image->width, image->height, GL_RED, GL_FLOAT,
                            image->data);
    }
    return status;
}

sta_status sta_gl_texture_rgba8_from_image(const sta_image *image, GLuint *out_texture,
                                           sta_error *err)
{
    if (image->channels != 4) {
        return sta_fail(err, STA_ERR_ARG, "an RGBA8 texture needs a 4-channel image, not %d",
                        image->channels);
    }
    sta_status status = sta_gl_texture_create_rgba8(image->width, image->height, out_texture, err);
    if (status == STA_OK) {
        glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
        glTextureSubImage2D(*out_texture, 0, 0, 0, image->width, image->height, GL_RGBA, GL_FLOAT,
                            image->data);
    }
    return status;
}

sta_status sta_gl_texture_from_image(const sta_image *image, GLuint *out_texture, sta_error *err)
{
    int channels = image->channels == 3 ? 4 : image->channels;
    sta_status status =
        sta_gl_texture_create(image->width, image->height, channels, 1, out_texture, err);
    if (status != STA_OK) {
        return status;
    }
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTextureSubImage2D(*out_texture, 0, 0, 0, image->width, image->height,
                        pixel_format(image->channels), GL_FLOAT, image->data);
    return STA_OK;
}

sta_status sta_gl_texture_to_image(GLuint texture, int level, int channels, sta_image *out,
                                   sta_error *err)
{
    GLint width = 0, height = 0;
    glGetTextureLevelParameteriv(texture, level, GL_TEXTURE_WIDTH, &width);
    glGetTextureLevelParameteriv(texture, level, GL_TEXTURE_HEIGHT, &height);
    sta_status status = sta_image_init(out, width, height, channels, err);
    if (status != STA_OK) {
        return status;
    }
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    size_t bytes = (size_t)width * (size_t)height * (size_t)channels * sizeof(float);
    glGetTextureImage(texture, level, pixel_format(channels), GL_FLOAT, (GLsizei)bytes, out->data);
    if (glGetError() != GL_NO_ERROR) {
        sta_image_release(out);
        return sta_fail(err, STA_ERR_GL, "cannot read texture %u level %d", texture, level);
    }
    return STA_OK;
}

void sta_gl_dispatch_2d(int width, int height)
{
    glDispatchCompute((GLuint)((width + STA_WORKGROUP_SIZE_X - 1) / STA_WORKGROUP_SIZE_X),
                      (GLuint)((height + STA_WORKGROUP_SIZE_Y - 1) / STA_WORKGROUP_SIZE_Y), 1);
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT |
                    GL_TEXTURE_UPDATE_BARRIER_BIT);
}
