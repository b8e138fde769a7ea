/* SPDX-License-Identifier: MIT
 * strata-view's surveyor tools, shared by the window and headless runs: picking the
 * point under a pixel and describing it, and listing measurements as text.
 */
#ifndef STA_APP_VIEW_SURVEY_H
#define STA_APP_VIEW_SURVEY_H

#include <stdio.h>

#include "core/measure.h"
#include "render/hud_text.h"
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

/* The readout's lines (fps, budget use, nodes, pipeline, picked point, measurements). */
#define STA_VIEW_HUD_MAX_LINES 24
typedef struct sta_view_readout {
    char lines[STA_VIEW_HUD_MAX_LINES][320];
    size_t count;
    sta_hud_rect *marks; /* measurement markers (owner: whoever filled them), or NULL */
    size_t mark_count;
} sta_view_readout;

/* Rectangles of markers drawn at most per frame. */
#define STA_VIEW_MAX_MARKS 8192

/* Fills `out` with the frame's figures: `fps` (0: not shown, e.g. headless), points
 * drawn of the budget, nodes resident and loading, GPU memory, the pipeline's name,
 * then the pick (when `pick` is not NULL) and up to the lines left of measurements. */
void sta_view_readout_fill(sta_view_readout *out, const sta_frame_stats *stats, double fps,
                           uint64_t budget_points, const char *pipeline,
                           const sta_pick_result *pick, const sta_measure_list *measures);

/* The readout's lines as an array of pointers (for sta_hud_draw_lines). */
void sta_view_readout_pointers(const sta_view_readout *readout, const char **out_lines);

/* Markers of the measurements (vertices 5 px squares, edges dotted; areas closed) and
 * of `pending_count` vertices being picked, projected with `camera`; at most
 * `capacity` rectangles into `out`. Returns how many. Parts behind the camera are left
 * out. */
size_t sta_view_measure_marks(const sta_camera *camera, const sta_measure_list *measures,
                              const double (*pending)[3], size_t pending_count, sta_hud_rect *out,
                              size_t capacity);

/* One line per measurement: name, kind and its values (metres, square metres). */
void sta_view_describe_measure(const sta_measure *m, char *out, size_t size);

#endif
