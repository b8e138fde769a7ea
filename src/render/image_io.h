/* SPDX-License-Identifier: MIT
 * Writing rendered buffers: PNG (libpng) for pictures, OpenEXR (its C API) for float
 * buffers such as depth and normals.
 */
#ifndef STA_RENDER_IMAGE_IO_H
#define STA_RENDER_IMAGE_IO_H

#include <stdint.h>

#include "core/status.h"

/* Writes an 8-bit RGBA image (top row first) as PNG. */
sta_status sta_png_write_rgba(const char *path, const uint8_t *rgba, int width_px, int height_px,
                              sta_error *err);

/* Reads a PNG into a new RGBA8 buffer (owner: caller, sta_free). For tests. */
sta_status sta_png_read_rgba(const char *path, uint8_t **out_rgba, int *out_width, int *out_height,
                             sta_error *err);

/* One float channel of an EXR file. */
typedef struct sta_exr_channel {
    const char *name;    /* e.g. "R", "Z", "N.X" */
    const float *pixels; /* width * height, top row first */
} sta_exr_channel;

/* Writes float channels as a scanline OpenEXR file (FLOAT pixels, ZIP compression). */
sta_status sta_exr_write(const char *path, const sta_exr_channel *channels, int channel_count,
                         int width_px, int height_px, sta_error *err);

#endif
