/* SPDX-License-Identifier: MIT
 * Splat twin: ray-disk intersection per pixel centre. */
#include "render/ref/splat_ref.h"

#include <string.h>

// Camera-space direction of world vector v (the view matrix is a rotation).
static void rotate(const float m[16], const float v[3], float out[3])
{
    for (int i = 0; i < 3; i++) {
        out[i] = m[i] * v[0] + m[4 + i] * v[1] + m[8 + i] * v[2];
    }
}

static float dot3(const float a[3], const float b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

float sta_splat_ref_radius(const sta_splat_ref_params *p, float stored_radius, float depth_m)
{
    float pixel_angle = 2.0f / (p->projection[5] * (float)p->height_px);
    float r = (stored_radius > 0.0f ? stored_radius : p->default_radius_m) * p->scale;
    float smallest = p->min_radius_px * pixel_angle * (depth_m > 0.0f ? depth_m : 0.0f);
    return r > smallest ? r : smallest;
}

static void shade(const sta_splat_ref_params *p, const sta_splat_ref_point *s, const float n[3],
                  const float hit[3], float out[3])
{
    if (!p->lit) {
        memcpy(out, s->colour, 3 * sizeof(float));
        return;
    }
    float len = sqrtf(dot3(hit, hit));
    float to_eye[3] = { -hit[0] / len, -hit[1] / len, -hit[2] / len };
    float lambert = fabsf(dot3(n, to_eye));
    float specular = p->light[2] * powf(lambert, p->light[3]);
    for (int c = 0; c < 3; c++) {
        float v = s->colour[c] * (p->light[0] + p->light[1] * lambert) + specular;
        out[c] = v < 0.0f ? 0.0f : v > 1.0f ? 1.0f : v;
    }
}

static void draw_one(const sta_splat_ref_params *p, const sta_splat_ref_point *s, float *depth,
                     uint32_t *ids, float *rgb)
{
    float centre[3], n[3];
    rotate(p->view, s->relative, centre);
    rotate(p->view, s->normal, n);
    float nl = sqrtf(dot3(n, n));
    if (!(nl > 0.0f) || !(centre[2] < 0.0f)) {
        return; // behind the eye: the GPU clips it (its near side is beyond any near plane)
    }
    for (int a = 0; a < 3; a++) {
        n[a] /= nl;
    }
    float r = sta_splat_ref_radius(p, s->radius, -centre[2]);
    float plane = dot3(centre, n);
    for (int y = 0; y < p->height_px; y++) {
        for (int x = 0; x < p->width_px; x++) {
            // The eye ray through the pixel centre, camera space (z = -1).
            float ndc_x = ((float)x + 0.5f) * 2.0f / (float)p->width_px - 1.0f;
            float ndc_y = ((float)y + 0.5f) * 2.0f / (float)p->height_px - 1.0f;
            float d[3] = { ndc_x / p->projection[0], ndc_y / p->projection[5], -1.0f };
            float along = dot3(d, n);
            if (along == 0.0f) {
                continue; // edge-on: the square has no area
            }
            float t = plane / along;
            float hit[3] = { t * d[0], t * d[1], t * d[2] };
            float off[3] = { hit[0] - centre[0], hit[1] - centre[1], hit[2] - centre[2] };
            if (!(t > 0.0f) || dot3(off, off) > r * r) {
                continue;
            }
            // Reverse-Z infinite: depth = near / -z; in front of the near plane only.
            float z = p->projection[14] / -hit[2];
            size_t i = (size_t)y * (size_t)p->width_px + (size_t)x;
            if (z > 1.0f || !(z > depth[i])) {
                continue;
            }
            depth[i] = z;
            ids[2 * i] = s->id[0];
            ids[2 * i + 1] = s->id[1];
            if (rgb) {
                shade(p, s, n, hit, rgb + 3 * i);
            }
        }
    }
}

void sta_splat_ref_draw(const sta_splat_ref_params *p, const sta_splat_ref_point *points,
                        size_t count, float *depth, uint32_t *ids, float *rgb)
{
    size_t pixels = (size_t)p->width_px * (size_t)p->height_px;
    memset(depth, 0, pixels * sizeof(float));
    memset(ids, 0xFF, pixels * 2 * sizeof(uint32_t));
    if (rgb) {
        memset(rgb, 0, pixels * 3 * sizeof(float));
    }
    for (size_t k = 0; k < count; k++) {
        draw_one(p, &points[k], depth, ids, rgb);
    }
}
