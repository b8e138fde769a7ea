/* SPDX-License-Identifier: MIT
 * GPU point layout. */
#include "stream/gpu_points.h"

#include <string.h>

#include "core/bytes.h"

void sta_gpu_node_frame_init(sta_gpu_node_frame *frame, const sta_strata_geometry *geometry,
                             sta_strata_key key)
{
    int64_t corner[3], size[3];
    sta_strata_node_grid_bounds(geometry, key, corner, size);
    for (int a = 0; a < 3; a++) {
        int size_log2 = geometry->root_size_log2[a] - key.level;
        frame->shift[a] = size_log2 > 16 ? size_log2 - 16 : 0;
        frame->grid_corner[a] = corner[a];
        frame->corner[a] = (double)corner[a] * geometry->grid.scale[a] + geometry->grid.offset[a];
        frame->step[a] = (double)((int64_t)1 << frame->shift[a]) * geometry->grid.scale[a];
    }
    frame->spacing = sta_strata_node_spacing(geometry, key.level);
}

void sta_gpu_points_encode(const sta_gpu_node_frame *frame, const sta_point *points, size_t count,
                           int colour_shift, uint8_t *out)
{
    const int64_t *corner = frame->grid_corner;
    for (size_t i = 0; i < count; i++) {
        const sta_point *p = &points[i];
        uint8_t *o = out + i * STA_GPU_POINT_SIZE;
        const int32_t xyz[3] = { p->X, p->Y, p->Z };
        for (int a = 0; a < 3; a++) {
            int64_t rel = ((int64_t)xyz[a] - corner[a]) >> frame->shift[a];
            rel = rel < 0 ? 0 : (rel > 65535 ? 65535 : rel);
            sta_store_u16le(o + 2 * a, (uint16_t)rel);
        }
        sta_store_u16le(o + 6, p->intensity);
        o[8] = (uint8_t)(p->red >> colour_shift);
        o[9] = (uint8_t)(p->green >> colour_shift);
        o[10] = (uint8_t)(p->blue >> colour_shift);
        o[11] = p->classification;
        o[12] = p->return_number;
        o[13] = p->number_of_returns;
        o[STA_GPU_POINT_FLAGS_BYTE] = p->mirror ? STA_GPU_FLAG_MIRROR_GHOST : 0;
        o[15] = 0;
    }
}

void sta_gpu_point_position(const sta_gpu_node_frame *frame, const uint8_t *gpu, double out[3])
{
    for (int a = 0; a < 3; a++) {
        out[a] = frame->corner[a] + (double)sta_load_u16le(gpu + 2 * a) * frame->step[a];
    }
}
