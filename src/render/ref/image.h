/* SPDX-License-Identifier: MIT
 * Float images for the CPU twins of the screen-space passes (and for tests that
 * compare them with the GPU). Row 0 is the first row of the matching GL texture,
 * i.e. the bottom of the screen; pixel (x, y) has its centre at (x + 0.5, y + 0.5).
 */
#ifndef STA_RENDER_REF_IMAGE_H
#define STA_RENDER_REF_IMAGE_H

#include <stddef.h>

#include "core/status.h"

typedef struct sta_image {
    int width, height;
    int channels; /* 1..4 floats per pixel */
    float *data;  /* width * height * channels, row-major from row 0 */
} sta_image;

/* Allocates a zeroed image. */
sta_status sta_image_init(sta_image *image, int width, int height, int channels, sta_error *err);

/* Frees it; a zeroed image is a no-op. */
void sta_image_release(sta_image *image);

/* The pixel's first channel. No bounds check: callers clamp. */
static inline float *sta_image_at(const sta_image *image, int x, int y)
{
    return image->data + ((size_t)y * (size_t)image->width + (size_t)x) * (size_t)image->channels;
}

#endif
