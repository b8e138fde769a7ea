/* SPDX-License-Identifier: MIT
 * CPU twin of the splat pass (render/pass_splats.h): oriented round disks, the nearest
 * per pixel by an exact ray-disk intersection through each pixel centre, its depth, id
 * and shaded colour. The GPU draws the disk's square in its own plane and discards
 * outside the unit circle; the twin intersects the eye ray with the plane and keeps hits
 * within the radius: the same set of pixels up to rounding at the rims. No GL.
 *
 * The splat's rules, shared with shaders/splat_common.glsl: radius = (stored radius, or
 * the default where 0) x scale, at least min_radius_px pixels at the centre's depth
 * (metres per pixel at 1 m: sta_splat_pixel_angle); lit with the headlight Blinn-Phong
 * of the screen-space shading, two-sided.
 */
#ifndef STA_RENDER_REF_SPLAT_REF_H
#define STA_RENDER_REF_SPLAT_REF_H

#include <math.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "core/camera.h"

/* The runtime factor on the stored radius when none is given (--splat-scale). */
#define STA_SPLAT_DEFAULT_SCALE         1.0f
/* Smallest splat radius on screen, pixels: far splats stay at least a point (above
 * sqrt(1/2), so a disk anywhere covers at least one pixel centre). */
#define STA_SPLAT_DEFAULT_MIN_RADIUS_PX 0.75f

/* Metres per pixel at 1 m in front of the camera: 2 tan(fov_y / 2) / height. */
static inline float sta_splat_pixel_angle(const sta_camera *camera)
{
    return (float)(2.0 * tan(camera->fov_y * 0.5) /
                   (double)(camera->height_px > 0 ? camera->height_px : 1));
}

typedef struct sta_splat_ref_point {
    float relative[3]; /* centre minus camera position, world axes, metres */
    float normal[3];   /* unit normal, world axes */
    float radius;      /* metres; 0: the default */
    float colour[3];   /* albedo 0..1 */
    uint32_t id[2];    /* node slot, point index */
} sta_splat_ref_point;

typedef struct sta_splat_ref_params {
    float view[16];       /* column-major, world directions -> camera space */
    float projection[16]; /* column-major, reverse-Z infinite (core/camera.h) */
    int width_px, height_px;
    float scale;            /* radius factor */
    float default_radius_m; /* for points stored without a radius */
    float min_radius_px;
    float light[4]; /* ambient, diffuse, specular, shininess */
    bool lit;
} sta_splat_ref_params;

/* World radius of a splat whose camera-space centre is at depth `depth_m` (> 0). */
float sta_splat_ref_radius(const sta_splat_ref_params *params, float stored_radius, float depth_m);

/* Draws the points in order; the largest reverse-Z depth wins, the first at equal depth.
 * Outputs per pixel, rows from the bottom (GL order): `depth` (0 where empty), `ids`
 * (2 per pixel; 0xFFFFFFFF both where empty) and `rgb` (3 floats per pixel; 0 where
 * empty; may be NULL). */
void sta_splat_ref_draw(const sta_splat_ref_params *params, const sta_splat_ref_point *points,
                        size_t count, float *depth, uint32_t *ids, float *rgb);

#endif
