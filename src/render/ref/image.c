/* SPDX-License-Identifier: MIT
 * Float images. */
#include "render/ref/image.h"

#include <string.h>

#include "core/alloc.h"

sta_status sta_image_init(sta_image *image, int width, int height, int channels, sta_error *err)
{
    memset(image, 0, sizeof(*image));
    if (width <= 0 || height <= 0 || channels < 1 || channels > 4) {
        return sta_fail(err, STA_ERR_ARG, "image %dx%dx%d is invalid", width, height, channels);
    }
    image->data = sta_calloc((size_t)width * (size_t)height * (size_t)channels, sizeof(float));
    if (!image->data) {
        return sta_fail(err, STA_ERR_NOMEM, "out of memory for a %dx%d image", width, height);
    }
    image->width = width;
    image->height = height;
    image->channels = channels;
    return STA_OK;
}

void sta_image_release(sta_image *image)
{
    sta_free(image->data);
    memset(image, 0, sizeof(*image));
}
