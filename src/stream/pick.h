/* SPDX-License-Identifier: MIT
 * Picking: the drawn point under a pixel, found on the CPU in double precision.
 *
 * Design: the candidates are the nodes drawn in the last frame (the streamer's draw
 * list), so a pick finds what is on screen, whatever the GPU holds. A node whose box
 * does not project near the pixel is skipped; the others are decoded through the
 * .strata reader, each point projected with the camera in double (no float on the way,
 * so a scene 5e6 m from the origin picks as well as one at the origin), and among the
 * points within `radius_px` of the pixel the nearest to the eye wins (then the nearest
 * to the pixel). The clip, if any, filters points as the loader does. Main thread or
 * any one thread; the decoder is the caller's.
 */
#ifndef STA_STREAM_PICK_H
#define STA_STREAM_PICK_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "core/camera.h"
#include "core/point.h"
#include "format/strata_reader.h"
#include "stream/clip.h"

/* What a pick found. */
typedef struct sta_pick_result {
    bool hit;            /* false: no drawn point within the radius */
    uint32_t node;       /* node index */
    size_t index;        /* point index within the node's payload */
    sta_point point;     /* the point: original integers and attributes */
    uint32_t attributes; /* sta_attr bits of the scene (which fields of point are real) */
    double world[3];     /* its coordinates in the scene's CRS (integer * scale + offset) */
    double pixel[2];     /* where it projects, pixels */
    double depth_m;      /* distance along the view axis */
    sta_grid grid;       /* the scene's grid (its scale gives the coordinates' decimals) */
} sta_pick_result;

/* Finds the drawn point under pixel (x_px, y_px) (origin top-left). `nodes` lists
 * node_count node indices (the draw list); `clip` may be NULL. Errors name the file
 * and node (STA_ERR_FORMAT for a damaged node, STA_ERR_NOMEM). */
sta_status sta_pick(const sta_strata_reader *reader, sta_strata_decoder *decoder,
                    const uint32_t *nodes, size_t node_count, const sta_clip *clip,
                    const sta_camera *camera, double x_px, double y_px, double radius_px,
                    sta_pick_result *out, sta_error *err);

/* The LAS name of classification `c` (ASPRS standard classes 0-18 of LAS 1.4:
 * "ground", "high vegetation", ...); "reserved" or "user defined" otherwise. */
const char *sta_pick_class_name(unsigned c);

#endif
