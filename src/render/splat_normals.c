/* SPDX-License-Identifier: MIT
 * Splat normals per pixel, from the ids and the splat arena. */
#include "render/splat_normals.h"

#include <math.h>
#include <string.h>

#include "core/alloc.h"
#include "render/gl.h"
#include "stream/gpu_splats.h"

sta_status sta_splat_normal_image(const sta_gpu_cache *cache, const sta_render_target *target,
                                  const sta_camera *camera, sta_image *out, sta_error *err)
{
    const int w = target->width_px, h = target->height_px;
    sta_status s = sta_image_init(out, w, h, 4, err);
    if (s != STA_OK) {
        return s;
    }
    if (!cache->has_splats || !cache->splat_buffer || cache->end == 0) {
        return STA_OK;
    }
    const size_t pixels = (size_t)w * (size_t)h;
    uint32_t *ids = sta_alloc_array(pixels, 2 * sizeof(uint32_t));
    uint8_t *records = sta_alloc_array(cache->end, STA_GPU_SPLAT_SIZE);
    if (!ids || !records) {
        sta_free(ids);
        sta_free(records);
        return sta_fail(err, STA_ERR_NOMEM, "out of memory reading back %u splats", cache->end);
    }
    sta_render_target_read_ids(target, ids);
    glGetNamedBufferSubData(cache->splat_buffer, 0,
                            (GLsizeiptr)((size_t)cache->end * STA_GPU_SPLAT_SIZE), records);
    float view[16], projection[16];
    sta_camera_view_rotation(camera, view);
    sta_camera_projection(camera, projection);
    for (int y = 0; y < h; y++) {
        for (int x = 0; x < w; x++) {
            const uint32_t *id = ids + 2 * ((size_t)(h - 1 - y) * (size_t)w + (size_t)x);
            if (id[0] >= cache->node_count || !cache->entries[id[0]].is_resident ||
                id[1] >= cache->entries[id[0]].count) {
                continue; // nothing drawn (or not a point of a resident node)
            }
            float world[3], n[3], radius;
            size_t slot = (size_t)cache->entries[id[0]].offset + id[1];
            sta_gpu_splat_decode(records + slot * STA_GPU_SPLAT_SIZE, world, &radius);
            for (int i = 0; i < 3; i++) {
                n[i] = view[i] * world[0] + view[4 + i] * world[1] + view[8 + i] * world[2];
            }
            // The eye ray through the pixel centre; the normal faces against it.
            float ray[3] = { (((float)x + 0.5f) * 2.0f / (float)w - 1.0f) / projection[0],
                             (((float)y + 0.5f) * 2.0f / (float)h - 1.0f) / projection[5], -1.0f };
            float sign = n[0] * ray[0] + n[1] * ray[1] + n[2] * ray[2] > 0.0f ? -1.0f : 1.0f;
            float *o = out->data + 4 * ((size_t)y * (size_t)w + (size_t)x);
            o[0] = sign * n[0];
            o[1] = sign * n[1];
            o[2] = sign * n[2];
            o[3] = 1.0f;
        }
    }
    sta_free(ids);
    sta_free(records);
    return sta_gl_check("reading back splat normals", err);
}
