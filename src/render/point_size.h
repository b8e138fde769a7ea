/* SPDX-License-Identifier: MIT
 * Point size of the geometry pass: one pixel (the default), a fixed diameter in pixels,
 * or adaptive: the node's spacing projected to pixels, clamped to [min, max]. Points
 * wider than a pixel are round, with a depth per fragment (a paraboloid towards the
 * camera, as Potree's "paraboloid" points), so that where disks overlap the nearer
 * surface wins per pixel instead of the whole of whichever point is nearer; both
 * rasterisers and their C twin draw the same footprint (render/ref/raster_ref.h).
 * No GL.
 */
#ifndef STA_RENDER_POINT_SIZE_H
#define STA_RENDER_POINT_SIZE_H

#include <stdbool.h>
#include <stddef.h>

#include "core/camera.h"
#include "core/status.h"
#include "render/ref/raster_ref.h"

typedef enum sta_point_size_mode {
    STA_POINT_SIZE_FIXED = 0, /* size_px for every point */
    STA_POINT_SIZE_ADAPTIVE,  /* the node's spacing on screen, in [min_px, max_px] */
} sta_point_size_mode;

#define STA_POINT_SIZE_DEFAULT_PX     1.0 /* one pixel: the golden renders */
#define STA_POINT_SIZE_DEFAULT_MIN_PX 1.0 /* adaptive: smallest diameter */
#define STA_POINT_SIZE_DEFAULT_MAX_PX 8.0 /* adaptive: largest diameter */
/* Largest diameter accepted, pixels: keeps the footprint's integer arithmetic (squared
 * distances in 1/256 pixel) in 32 bits and GL_POINTS' sprite within llvmpipe's 255. */
#define STA_POINT_SIZE_LIMIT_PX       64.0

typedef struct sta_point_size {
    int mode;       /* sta_point_size_mode */
    double size_px; /* fixed diameter, pixels; 0: STA_POINT_SIZE_DEFAULT_PX */
    double min_px;  /* adaptive; 0: STA_POINT_SIZE_DEFAULT_MIN_PX */
    double max_px;  /* adaptive; 0: STA_POINT_SIZE_DEFAULT_MAX_PX */
} sta_point_size;

void sta_point_size_defaults(sta_point_size *size);

/* Fills zero fields with their defaults and clamps every diameter to
 * [1, STA_POINT_SIZE_LIMIT_PX] (max no smaller than min). */
void sta_point_size_resolve(const sta_point_size *size, sta_point_size *out);

/* Whether points are drawn as single pixels (the fast, exact one-pixel rule). */
bool sta_point_size_is_one_pixel(const sta_point_size *size);

/* The footprint the rasterisers draw this frame for `camera` (its viewport height and
 * field of view give the projection of a spacing and the depth of the paraboloid). */
void sta_point_size_footprint(const sta_point_size *size, const sta_camera *camera,
                              sta_raster_ref_footprint *out);

/* Reads "adaptive" or a diameter in pixels ("3", "2.5") in [1, STA_POINT_SIZE_LIMIT_PX]
 * into out->mode and out->size_px; fails with STA_ERR_ARG naming the text. */
sta_status sta_point_size_parse(const char *text, sta_point_size *out, sta_error *err);

/* "1 px", "3 px", "adaptive 1-8 px": for the title bar and logs. */
void sta_point_size_describe(const sta_point_size *size, char *out_text, size_t text_size);

/* The next fixed size up (+1) or down (-1) from the current one (the window's keys):
 * 1, 2, 3, 4, 5, 6, 8, 10, 12, 16 pixels (a size above 16, from --point-size, stays
 * until stepped down); leaves adaptive mode. */
void sta_point_size_step(sta_point_size *size, int direction);

#endif
