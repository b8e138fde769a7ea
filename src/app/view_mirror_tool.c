/* SPDX-License-Identifier: MIT
 * The mirror-marking tool's state (view_mirror_tool.h). */
#include "app/view_mirror_tool.h"

#include <stdio.h>
#include <string.h>
#include <unistd.h>

sta_status sta_view_mirror_tool_init(sta_view_mirror_tool *tool, const char *path, sta_error *err)
{
    memset(tool, 0, sizeof(*tool));
    tool->path = path ? path : STA_VIEW_MIRROR_DEFAULT_FILE;
    tool->next_number = 1;
    if (access(tool->path, F_OK) == 0) {
        sta_status s = sta_mirror_set_load(tool->path, &tool->set, err);
        if (s != STA_OK) {
            return s;
        }
        tool->next_number = (unsigned)tool->set.count + 1;
    }
    sta_mirror_set_defaults(&tool->set);
    return STA_OK;
}

void sta_view_mirror_tool_release(sta_view_mirror_tool *tool)
{
    sta_mirror_set_release(&tool->set);
}

sta_status sta_view_mirror_tool_click(sta_view_mirror_tool *tool, const sta_pick_result *pick,
                                      sta_error *err)
{
    if (!pick->hit) {
        return STA_OK;
    }
    if (tool->pending_count >= STA_MIRROR_MAX_VERTICES) {
        return sta_fail(err, STA_ERR_ARG, "a mirror has at most %d vertices: close it (Enter)",
                        STA_MIRROR_MAX_VERTICES);
    }
    memcpy(tool->pending[tool->pending_count++], pick->world, sizeof(pick->world));
    return STA_OK;
}

sta_status sta_view_mirror_tool_close(sta_view_mirror_tool *tool, const double eye[3],
                                      sta_error *err)
{
    char name[STA_MIRROR_NAME_MAX];
    snprintf(name, sizeof(name), "mirror %u", tool->next_number);
    size_t n = tool->pending_count;
    sta_status s = sta_mirror_set_add(&tool->set, name, (const double(*)[3])tool->pending, n, err);
    if (s != STA_OK) {
        return s;
    }
    if (sta_mirror_signed_distance(&tool->set.mirrors[tool->set.count - 1], eye) < 0.0) {
        // Picked clockwise as seen from the camera: the same outline, the other way.
        double reversed[STA_MIRROR_MAX_VERTICES][3];
        for (size_t i = 0; i < n; i++) {
            memcpy(reversed[i], tool->pending[n - 1 - i], sizeof(reversed[i]));
        }
        tool->set.count--;
        s = sta_mirror_set_add(&tool->set, name, (const double(*)[3])reversed, n, err);
        if (s != STA_OK) {
            return s;
        }
    }
    tool->pending_count = 0;
    tool->next_number++;
    return sta_mirror_set_save(tool->path, &tool->set, err);
}

sta_status sta_view_mirror_tool_undo(sta_view_mirror_tool *tool, sta_error *err)
{
    if (tool->pending_count > 0) {
        tool->pending_count--;
        return STA_OK;
    }
    if (tool->set.count == 0) {
        return STA_OK;
    }
    tool->set.count--;
    return sta_mirror_set_save(tool->path, &tool->set, err);
}

void sta_view_mirror_tool_status(const sta_view_mirror_tool *tool, char *out, size_t size)
{
    snprintf(out, size, "mirrors: %zu of 3+ vertices, %zu mirror%s in %s", tool->pending_count,
             tool->set.count, tool->set.count == 1 ? "" : "s", tool->path);
}
