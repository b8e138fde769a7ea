/* SPDX-License-Identifier: MIT
 * The window's measuring tools, without GLFW: the current tool, the vertices picked
 * so far, the finished measurements and the last pick. The window feeds it picks and
 * keys; tests drive it directly.
 *
 * Tools (T cycles): point, distance, height (ground first), polyline, area. A click
 * adds the picked point; point, distance and height finish by themselves, polyline
 * and area on finish (Enter). Undo (Backspace) drops the last vertex, or the last
 * measurement when none is pending.
 */
#ifndef STA_APP_VIEW_TOOLS_H
#define STA_APP_VIEW_TOOLS_H

#include <stdbool.h>

#include "core/measure.h"
#include "stream/pick.h"

#define STA_VIEW_TOOLS_MAX_PENDING 256 /* vertices of a polyline or area being drawn */

typedef struct sta_view_tools {
    sta_measure_kind tool; /* the current tool */
    double pending[STA_VIEW_TOOLS_MAX_PENDING][3];
    size_t pending_count;
    sta_measure_list list; /* finished measurements */
    sta_pick_result last_pick;
    bool has_pick;
    unsigned next_number; /* names "distance 1", "area 2", ... */
} sta_view_tools;

/* Starts with the point tool and an empty list; release with _release. */
void sta_view_tools_init(sta_view_tools *tools);
void sta_view_tools_release(sta_view_tools *tools);

/* Switches to the next tool (dropping pending vertices). */
void sta_view_tools_next(sta_view_tools *tools);

/* Records a pick; a hit adds a vertex, and completes point, distance and height.
 * Returns true when a measurement was finished. Errors: STA_ERR_NOMEM. */
sta_status sta_view_tools_click(sta_view_tools *tools, const sta_pick_result *pick,
                                bool *out_finished, sta_error *err);

/* Finishes a polyline or area with its pending vertices; false when there are too
 * few (nothing changes then). */
bool sta_view_tools_finish(sta_view_tools *tools);

/* Drops the last pending vertex, or else the last measurement. */
void sta_view_tools_undo(sta_view_tools *tools);

/* "tool: distance (1 of 2 points)" for the readout. */
void sta_view_tools_status(const sta_view_tools *tools, char *out, size_t size);

#endif
