/* SPDX-License-Identifier: MIT
 * CPU twins of the shading passes. */
#include "render/ref/shade_ref.h"

#include <math.h>

void sta_shade_params_defaults(sta_shade_params *config)
{
    config->ambient = config->ambient > 0 ? config->ambient : STA_SHADE_DEFAULT_AMBIENT;
    config->diffuse = config->diffuse > 0 ? config->diffuse : STA_SHADE_DEFAULT_DIFFUSE;
    config->specular = config->specular > 0 ? config->specular : STA_SHADE_DEFAULT_SPECULAR;
    config->shininess = config->shininess > 0 ? config->shininess : STA_SHADE_DEFAULT_SHININESS;
}

void sta_edl_params_defaults(sta_edl_params *config)
{
    config->radius_px = config->radius_px > 0 ? config->radius_px : STA_EDL_DEFAULT_RADIUS_PX;
    config->strength = config->strength > 0 ? config->strength : STA_EDL_DEFAULT_STRENGTH;
}

static float clamp01(float v)
{
    return v < 0.0f ? 0.0f : (v > 1.0f ? 1.0f : v);
}

void sta_shade_ref(const sta_shade_params *params, const sta_image *position,
                   const sta_image *colour, const sta_image *normal, sta_image *out)
{
    for (int y = 0; y < position->height; y++) {
        for (int x = 0; x < position->width; x++) {
            const float *p = sta_image_at(position, x, y);
            const float *n = sta_image_at(normal, x, y);
            const float *c = sta_image_at(colour, x, y);
            float *o = sta_image_at(out, x, y);
            float result[3] = { params->background[0], params->background[1],
                                params->background[2] };
            if (p[3] > 0.0f) {
                float len = sqrtf(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
                float eye[3] = { 0.0f, 0.0f, 1.0f };
                if (len > 0.0f) {
                    eye[0] = -p[0] / len;
                    eye[1] = -p[1] / len;
                    eye[2] = -p[2] / len;
                }
                for (int k = 0; k < 3; k++) {
                    result[k] = c[k] * (params->ambient + params->diffuse);
                }
                if (n[3] > 0.0f) {
                    float lambert = fmaxf(n[0] * eye[0] + n[1] * eye[1] + n[2] * eye[2], 0.0f);
                    float specular = powf(lambert, params->shininess);
                    for (int k = 0; k < 3; k++) {
                        result[k] = c[k] * (params->ambient + params->diffuse * lambert) +
                                    params->specular * specular;
                    }
                }
            }
            if (colour->channels == 4 && c[3] > 0.5f) {
                for (int k = 0; k < 3; k++) { // the overlay's marked point, unlit
                    result[k] = c[k];
                }
            }
            o[0] = clamp01(result[0]);
            o[1] = clamp01(result[1]);
            o[2] = clamp01(result[2]);
            o[3] = 1.0f;
        }
    }
}

void sta_edl_ref(const sta_edl_params *params, const sta_image *position, const sta_image *colour,
                 sta_image *out)
{
    const int w = position->width, h = position->height;
    for (int y = 0; y < h; y++) {
        for (int x = 0; x < w; x++) {
            const float *p = sta_image_at(position, x, y);
            float *o = sta_image_at(out, x, y);
            if (p[3] <= 0.0f) {
                o[0] = params->background[0];
                o[1] = params->background[1];
                o[2] = params->background[2];
                o[3] = 1.0f;
                continue;
            }
            float log_depth = log2f(-p[2]);
            float response = 0.0f;
            for (int i = 0; i < 8; i++) {
                float angle = (float)i * 0.78539816339f;
                int qx = x + (int)roundf(cosf(angle) * params->radius_px);
                int qy = y + (int)roundf(sinf(angle) * params->radius_px);
                qx = qx < 0 ? 0 : (qx >= w ? w - 1 : qx);
                qy = qy < 0 ? 0 : (qy >= h ? h - 1 : qy);
                const float *q = sta_image_at(position, qx, qy);
                float other = q[3] > 0.0f ? log2f(-q[2]) : log_depth + 10.0f;
                response += fmaxf(0.0f, log_depth - other);
            }
            float shade = expf(-params->strength * response / 8.0f);
            const float *c = sta_image_at(colour, x, y);
            o[0] = clamp01(c[0] * shade);
            o[1] = clamp01(c[1] * shade);
            o[2] = clamp01(c[2] * shade);
            o[3] = 1.0f;
        }
    }
}
