/* SPDX-License-Identifier: MIT
 * Picking the drawn point under a pixel (see pick.h). */
#include "stream/pick.h"

#include <math.h>
#include <string.h>

const char *sta_pick_class_name(unsigned c)
{
    // LAS 1.4 R15, Table 17 (ASPRS standard point classes).
    static const char *const names[] = { "created, never classified",
                                         "unclassified",
                                         "ground",
                                         "low vegetation",
                                         "medium vegetation",
                                         "high vegetation",
                                         "building",
                                         "low point (noise)",
                                         "model key-point",
                                         "water",
                                         "rail",
                                         "road surface",
                                         "overlap",
                                         "wire - guard (shield)",
                                         "wire - conductor (phase)",
                                         "transmission tower",
                                         "wire-structure connector",
                                         "bridge deck",
                                         "high noise" };
    if (c < sizeof(names) / sizeof(names[0])) {
        return names[c];
    }
    return c < 64 ? "reserved" : "user defined";
}

// Whether the node's box can project within `radius` of the pixel: the bounding
// rectangle of its projected corners, or true when a corner is behind the near plane.
static bool box_near_pixel(const sta_camera *camera, const double min[3], const double max[3],
                           double x, double y, double radius)
{
    double lo[2] = { INFINITY, INFINITY }, hi[2] = { -INFINITY, -INFINITY };
    for (int c = 0; c < 8; c++) {
        const double corner[3] = { c & 1 ? max[0] : min[0], c & 2 ? max[1] : min[1],
                                   c & 4 ? max[2] : min[2] };
        double px, py, depth;
        if (!sta_camera_project(camera, corner, &px, &py, &depth)) {
            return true;
        }
        lo[0] = fmin(lo[0], px);
        lo[1] = fmin(lo[1], py);
        hi[0] = fmax(hi[0], px);
        hi[1] = fmax(hi[1], py);
    }
    return x >= lo[0] - radius && x <= hi[0] + radius && y >= lo[1] - radius && y <= hi[1] + radius;
}

sta_status sta_pick(const sta_strata_reader *reader, sta_strata_decoder *decoder,
                    const uint32_t *nodes, size_t node_count, const sta_clip *clip,
                    const sta_camera *camera, double x_px, double y_px, double radius_px,
                    sta_pick_result *out, sta_error *err)
{
    memset(out, 0, sizeof(*out));
    const sta_strata_info *info = sta_strata_reader_info(reader);
    const sta_grid *grid = &info->geometry.grid;
    const uint32_t attributes = sta_strata_attributes_to_sta_attr(info->layout.attributes);
    out->attributes = attributes;
    out->grid = *grid;
    const bool filter = clip && sta_clip_filters_points(clip);
    double best_depth = INFINITY, best_d2 = INFINITY;
    for (size_t k = 0; k < node_count; k++) {
        const sta_strata_node *node = sta_strata_reader_node(reader, nodes[k]);
        if (!node || node->point_count == 0) {
            continue;
        }
        double min[3], max[3];
        sta_strata_node_real_bounds(&info->geometry, node->key, min, max);
        if (!box_near_pixel(camera, min, max, x_px, y_px, radius_px)) {
            continue;
        }
        sta_strata_points points;
        sta_status status = sta_strata_decode_node(reader, nodes[k], decoder, &points, err);
        if (status != STA_OK) {
            return status;
        }
        for (size_t i = 0; i < points.count; i++) {
            const sta_point *p = &points.points[i];
            if (filter && !sta_clip_keeps_point(clip, grid, attributes, p)) {
                continue;
            }
            const double world[3] = { sta_grid_apply(grid, 0, p->X), sta_grid_apply(grid, 1, p->Y),
                                      sta_grid_apply(grid, 2, p->Z) };
            double px, py, depth;
            if (!sta_camera_project(camera, world, &px, &py, &depth)) {
                continue;
            }
            double d2 = (px - x_px) * (px - x_px) + (py - y_px) * (py - y_px);
            if (d2 > radius_px * radius_px) {
                continue;
            }
            if (depth < best_depth || (depth == best_depth && d2 < best_d2)) {
                best_depth = depth;
                best_d2 = d2;
                out->hit = true;
                out->node = nodes[k];
                out->index = i;
                out->point = *p;
                memcpy(out->world, world, sizeof(world));
                out->pixel[0] = px;
                out->pixel[1] = py;
                out->depth_m = depth;
            }
        }
    }
    return STA_OK;
}
