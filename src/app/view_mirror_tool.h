/* SPDX-License-Identifier: MIT
 * The window's mirror-marking tool, without GLFW (docs/MIRRORS.md): picked points
 * become the vertices of a mirror's outline; closing it (3 or more vertices) adds the
 * mirror, its front turned towards the camera, and writes the mirror file. The window
 * feeds it picks and keys (O toggles the tool; Ctrl+click adds a vertex, Enter
 * closes, Backspace drops the last vertex or else the last mirror); tests drive it
 * directly.
 */
#ifndef STA_APP_VIEW_MIRROR_TOOL_H
#define STA_APP_VIEW_MIRROR_TOOL_H

#include <stdbool.h>
#include <stddef.h>

#include "mirror/mirror_set.h"
#include "stream/pick.h"

#define STA_VIEW_MIRROR_DEFAULT_FILE "mirrors.json" /* without --mirrors */

typedef struct sta_view_mirror_tool {
    bool active; /* clicks and keys go to the tool */
    double pending[STA_MIRROR_MAX_VERTICES][3];
    size_t pending_count;
    sta_mirror_set set; /* the file's mirrors and those marked since */
    const char *path;   /* borrowed: where the set is saved */
    unsigned next_number;
} sta_view_mirror_tool;

/* Starts inactive with the mirrors of `path` when it exists (errors: those of
 * sta_mirror_set_load), else none. */
sta_status sta_view_mirror_tool_init(sta_view_mirror_tool *tool, const char *path, sta_error *err);

void sta_view_mirror_tool_release(sta_view_mirror_tool *tool);

/* A hit adds a vertex (a miss changes nothing). STA_ERR_ARG when the outline already
 * has STA_MIRROR_MAX_VERTICES vertices. */
sta_status sta_view_mirror_tool_click(sta_view_mirror_tool *tool, const sta_pick_result *pick,
                                      sta_error *err);

/* Closes the outline into a mirror named "mirror N" whose front faces `eye` (the
 * vertex order is reversed when needed), then saves the file. Fewer than 3 vertices,
 * a non-planar or degenerate outline: an error naming the mirror, the vertices kept
 * (undo them). */
sta_status sta_view_mirror_tool_close(sta_view_mirror_tool *tool, const double eye[3],
                                      sta_error *err);

/* Drops the last vertex or, when none is pending, the last mirror (then saves). */
sta_status sta_view_mirror_tool_undo(sta_view_mirror_tool *tool, sta_error *err);

/* "mirrors: 2 of 3+ vertices, 1 mirror in mirrors.json" for the readout. */
void sta_view_mirror_tool_status(const sta_view_mirror_tool *tool, char *out, size_t size);

#endif
