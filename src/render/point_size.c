/* SPDX-License-Identifier: MIT
 * Point size: options, and the per-frame footprint both rasterisers draw. */
#include "render/point_size.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void sta_point_size_defaults(sta_point_size *size)
{
    memset(size, 0, sizeof(*size));
    size->mode = STA_POINT_SIZE_FIXED;
    size->size_px = STA_POINT_SIZE_DEFAULT_PX;
    size->min_px = STA_POINT_SIZE_DEFAULT_MIN_PX;
    size->max_px = STA_POINT_SIZE_DEFAULT_MAX_PX;
}

static double clamp_px(double px, double fallback)
{
    px = px > 0 ? px : fallback;
    return px < 1.0 ? 1.0 : (px > STA_POINT_SIZE_LIMIT_PX ? STA_POINT_SIZE_LIMIT_PX : px);
}

void sta_point_size_resolve(const sta_point_size *size, sta_point_size *out)
{
    out->mode =
        size->mode == STA_POINT_SIZE_ADAPTIVE ? STA_POINT_SIZE_ADAPTIVE : STA_POINT_SIZE_FIXED;
    out->size_px = clamp_px(size->size_px, STA_POINT_SIZE_DEFAULT_PX);
    out->min_px = clamp_px(size->min_px, STA_POINT_SIZE_DEFAULT_MIN_PX);
    out->max_px = clamp_px(size->max_px, STA_POINT_SIZE_DEFAULT_MAX_PX);
    if (out->max_px < out->min_px) {
        out->max_px = out->min_px;
    }
}

bool sta_point_size_is_one_pixel(const sta_point_size *size)
{
    sta_point_size r;
    sta_point_size_resolve(size, &r);
    return r.mode == STA_POINT_SIZE_FIXED && r.size_px <= 1.0;
}

void sta_point_size_footprint(const sta_point_size *size, const sta_camera *camera,
                              sta_raster_ref_footprint *out)
{
    memset(out, 0, sizeof(*out));
    sta_point_size r;
    sta_point_size_resolve(size, &r);
    if (sta_point_size_is_one_pixel(&r)) {
        return;
    }
    // A length L at eye distance w spans L * (height / 2) * P11 / w pixels, P11 =
    // 1 / tan(fov / 2) as in sta_camera_projection; the rasterisers multiply by 1 / w.
    double height = camera->height_px > 0 ? camera->height_px : 1;
    double pixels_per_metre_at_1m = 0.5 * height / tan(0.5 * camera->fov_y);
    out->wide = 1;
    out->adaptive = r.mode == STA_POINT_SIZE_ADAPTIVE;
    out->radius_px = (float)(0.5 * r.size_px);
    // Diameter = the spacing on screen: radius = spacing / 2 in pixels.
    out->spacing_to_px = (float)(0.5 * pixels_per_metre_at_1m);
    out->min_radius_px = (float)(0.5 * r.min_px);
    out->max_radius_px = (float)(0.5 * r.max_px);
    // The radius in metres at distance w is R / pixels_per_metre_at_1m * w: relative to
    // w, R * depth_per_px.
    out->depth_per_px = (float)(1.0 / pixels_per_metre_at_1m);
}

sta_status sta_point_size_parse(const char *text, sta_point_size *out, sta_error *err)
{
    if (strcmp(text, "adaptive") == 0) {
        out->mode = STA_POINT_SIZE_ADAPTIVE;
        return STA_OK;
    }
    char *end = NULL;
    double px = strtod(text, &end);
    if (end == text || *end != '\0' || !isfinite(px) || px < 1.0 || px > STA_POINT_SIZE_LIMIT_PX) {
        return sta_fail(err, STA_ERR_ARG,
                        "point size '%s': expected 'adaptive' or a diameter in pixels from 1 "
                        "to %g",
                        text, STA_POINT_SIZE_LIMIT_PX);
    }
    out->mode = STA_POINT_SIZE_FIXED;
    out->size_px = px;
    return STA_OK;
}

void sta_point_size_describe(const sta_point_size *size, char *out_text, size_t text_size)
{
    sta_point_size r;
    sta_point_size_resolve(size, &r);
    if (r.mode == STA_POINT_SIZE_ADAPTIVE) {
        snprintf(out_text, text_size, "adaptive %g-%g px", r.min_px, r.max_px);
    } else {
        snprintf(out_text, text_size, "%g px", r.size_px);
    }
}

void sta_point_size_step(sta_point_size *size, int direction)
{
    // Up to 16 px: the cost grows with the disk's area (on llvmpipe 16 px took 4 s a
    // frame for 1.3 M points at 960x540, docs/VIEWER.md), so a key press should not go
    // further; --point-size reaches 64.
    static const double steps[] = { 1, 2, 3, 4, 5, 6, 8, 10, 12, 16 };
    const int count = (int)(sizeof(steps) / sizeof(steps[0]));
    sta_point_size r;
    sta_point_size_resolve(size, &r);
    double current = r.mode == STA_POINT_SIZE_ADAPTIVE ? r.max_px : r.size_px;
    double next = current;
    if (direction > 0) { // the smallest step above, or no change past the last one
        for (int i = count - 1; i >= 0 && steps[i] > current; i--) {
            next = steps[i];
        }
    } else if (direction < 0) { // the largest step below, at least the first one
        next = steps[0];
        for (int i = 0; i < count && steps[i] < current; i++) {
            next = steps[i];
        }
    }
    size->mode = STA_POINT_SIZE_FIXED;
    size->size_px = next;
}
