/* SPDX-License-Identifier: MIT
 * PNG and OpenEXR output. */
#include "render/image_io.h"

#include <errno.h>
#include <openexr.h>
#include <png.h>
#include <stdbool.h>
#include <stdio.h>
#include <string.h>

#include "core/alloc.h"

sta_status sta_png_write_rgba(const char *path, const uint8_t *rgba, int width_px, int height_px,
                              sta_error *err)
{
    png_image image;
    memset(&image, 0, sizeof(image));
    image.version = PNG_IMAGE_VERSION;
    image.width = (png_uint_32)width_px;
    image.height = (png_uint_32)height_px;
    image.format = PNG_FORMAT_RGBA;
    if (!png_image_write_to_file(&image, path, 0, rgba, 0, NULL)) {
        return sta_fail(err, STA_ERR_IO, "%s: cannot write PNG: %s", path, image.message);
    }
    return STA_OK;
}

sta_status sta_png_read_rgba(const char *path, uint8_t **out_rgba, int *out_width, int *out_height,
                             sta_error *err)
{
    png_image image;
    memset(&image, 0, sizeof(image));
    image.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_file(&image, path)) {
        return sta_fail(err, STA_ERR_IO, "%s: cannot read PNG: %s", path, image.message);
    }
    image.format = PNG_FORMAT_RGBA;
    uint8_t *rgba = sta_alloc_array(PNG_IMAGE_SIZE(image), 1);
    if (!rgba) {
        png_image_free(&image);
        return sta_fail(err, STA_ERR_NOMEM, "%s: out of memory", path);
    }
    if (!png_image_finish_read(&image, NULL, rgba, 0, NULL)) {
        sta_free(rgba);
        return sta_fail(err, STA_ERR_IO, "%s: cannot decode PNG: %s", path, image.message);
    }
    *out_rgba = rgba;
    *out_width = (int)image.width;
    *out_height = (int)image.height;
    return STA_OK;
}

sta_status sta_exr_write(const char *path, const sta_exr_channel *channels, int channel_count,
                         int width_px, int height_px, sta_error *err)
{
    exr_context_t ctx = NULL;
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    exr_result_t r = exr_start_write(&ctx, path, EXR_WRITE_FILE_DIRECTLY, &init);
    if (r != EXR_ERR_SUCCESS) {
        return sta_fail(err, STA_ERR_IO, "%s: cannot create EXR: %s", path,
                        exr_get_default_error_message(r));
    }
    int part = 0;
    r = exr_add_part(ctx, "buffers", EXR_STORAGE_SCANLINE, &part);
    if (r == EXR_ERR_SUCCESS) {
        r = exr_initialize_required_attr_simple(ctx, part, width_px, height_px,
                                                EXR_COMPRESSION_ZIP);
    }
    for (int c = 0; c < channel_count && r == EXR_ERR_SUCCESS; c++) {
        r = exr_add_channel(ctx, part, channels[c].name, EXR_PIXEL_FLOAT,
                            EXR_PERCEPTUALLY_LOGARITHMIC, 1, 1);
    }
    if (r == EXR_ERR_SUCCESS) {
        r = exr_write_header(ctx);
    }
    int32_t lines_per_chunk = 1;
    if (r == EXR_ERR_SUCCESS) {
        r = exr_get_scanlines_per_chunk(ctx, part, &lines_per_chunk);
    }
    exr_encode_pipeline_t encoder;
    memset(&encoder, 0, sizeof(encoder));
    bool encoder_ready = false;
    for (int y = 0; y < height_px && r == EXR_ERR_SUCCESS; y += lines_per_chunk) {
        exr_chunk_info_t chunk;
        r = exr_write_scanline_chunk_info(ctx, part, y, &chunk);
        if (r != EXR_ERR_SUCCESS) {
            break;
        }
        r = encoder_ready ? exr_encoding_update(ctx, part, &chunk, &encoder)
                          : exr_encoding_initialize(ctx, part, &chunk, &encoder);
        if (r != EXR_ERR_SUCCESS) {
            break;
        }
        encoder_ready = true;
        // Channels are stored in alphabetical order; match each by name.
        for (int16_t c = 0; c < encoder.channel_count; c++) {
            exr_coding_channel_info_t *info = &encoder.channels[c];
            const float *source = NULL;
            for (int k = 0; k < channel_count; k++) {
                if (strcmp(channels[k].name, info->channel_name) == 0) {
                    source = channels[k].pixels;
                }
            }
            info->encode_from_ptr = (const uint8_t *)(source + (size_t)y * (size_t)width_px);
            info->user_pixel_stride = (int32_t)sizeof(float);
            info->user_line_stride = (int32_t)(sizeof(float) * (size_t)width_px);
            info->user_bytes_per_element = (int16_t)sizeof(float);
            info->user_data_type = EXR_PIXEL_FLOAT;
        }
        r = exr_encoding_choose_default_routines(ctx, part, &encoder);
        if (r == EXR_ERR_SUCCESS) {
            r = exr_encoding_run(ctx, part, &encoder);
        }
    }
    if (encoder_ready) {
        exr_encoding_destroy(ctx, &encoder);
    }
    exr_result_t finish = exr_finish(&ctx);
    if (r != EXR_ERR_SUCCESS || finish != EXR_ERR_SUCCESS) {
        return sta_fail(err, STA_ERR_IO, "%s: cannot write EXR: %s", path,
                        exr_get_default_error_message(r != EXR_ERR_SUCCESS ? r : finish));
    }
    return STA_OK;
}
