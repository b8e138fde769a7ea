/* SPDX-License-Identifier: MIT
 * CPU twin of the unproject pass. */
#include "render/ref/unproject_ref.h"

void sta_unproject_ref(const sta_view_params *view, const sta_image *depth, sta_image *out)
{
    float tan_y = tanf(0.5f * view->fov_y);
    float tan_x = tan_y * (float)view->width_px / (float)view->height_px;
    for (int y = 0; y < depth->height; y++) {
        for (int x = 0; x < depth->width; x++) {
            float d = *sta_image_at(depth, x, y);
            float *o = sta_image_at(out, x, y);
            if (d > 0.0f) {
                float distance = view->near_m / d;
                float ndc_x = ((float)x + 0.5f) / (float)depth->width * 2.0f - 1.0f;
                float ndc_y = ((float)y + 0.5f) / (float)depth->height * 2.0f - 1.0f;
                o[0] = ndc_x * tan_x * distance;
                o[1] = ndc_y * tan_y * distance;
                o[2] = -distance;
                o[3] = 1.0f;
            } else {
                o[0] = o[1] = o[2] = o[3] = 0.0f;
            }
        }
    }
}
