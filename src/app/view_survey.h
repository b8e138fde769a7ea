/* SPDX-License-Identifier: MIT
 * strata-view's surveyor tools, shared by the window and headless runs: picking the
 * point under a pixel and describing it, and listing measurements as text.
 */
#ifndef STA_APP_VIEW_SURVEY_H
#define STA_APP_VIEW_SURVEY_H

#include <stdio.h>

#include "core/measure.h"
#include "render/scene.h"
#include "stream/pick.h"

/* Pixels around the cursor searched for a point. */
#define STA_VIEW_PICK_RADIUS_PX 4.0

/* Picks the drawn point under (x_px, y_px) of the last rendered frame. */
sta_status sta_view_pick(const sta_scene *scene, const sta_camera *camera, double x_px, double y_px,
                         sta_pick_result *out, sta_error *err);

/* One line describing a pick: coordinates in the scene's CRS at full precision
 * (shortest exact decimals), then the attributes the scene has: class with its LAS
 * name, intensity, return n of m, GPS time, RGB. Writes "no point" for a miss. */
void sta_view_describe_pick(const sta_pick_result *pick, char *out, size_t size);

/* One line per measurement: name, kind and its values (metres, square metres). */
void sta_view_describe_measure(const sta_measure *m, char *out, size_t size);

#endif
