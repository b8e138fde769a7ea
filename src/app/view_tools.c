/* SPDX-License-Identifier: MIT
 * Measuring tools state (see view_tools.h). */
#include "app/view_tools.h"

#include <stdio.h>
#include <string.h>

void sta_view_tools_init(sta_view_tools *tools)
{
    memset(tools, 0, sizeof(*tools));
    tools->tool = STA_MEASURE_POINT;
    tools->next_number = 1;
}

void sta_view_tools_release(sta_view_tools *tools)
{
    sta_measure_list_release(&tools->list);
}

void sta_view_tools_next(sta_view_tools *tools)
{
    tools->tool = (sta_measure_kind)((tools->tool + 1) % STA_MEASURE_KIND_COUNT);
    tools->pending_count = 0;
}

static sta_status finish(sta_view_tools *tools, sta_error *err)
{
    char name[64];
    snprintf(name, sizeof(name), "%s %u", sta_measure_kind_name(tools->tool), tools->next_number);
    sta_status status =
        sta_measure_list_add(&tools->list, tools->tool, name, (const double(*)[3])tools->pending,
                             tools->pending_count, err);
    if (status == STA_OK) {
        tools->next_number++;
        tools->pending_count = 0;
    }
    return status;
}

sta_status sta_view_tools_click(sta_view_tools *tools, const sta_pick_result *pick,
                                bool *out_finished, sta_error *err)
{
    *out_finished = false;
    tools->last_pick = *pick;
    tools->has_pick = true;
    if (!pick->hit) {
        return STA_OK;
    }
    size_t room = sta_measure_max_points(tools->tool);
    room = room < STA_VIEW_TOOLS_MAX_PENDING ? room : STA_VIEW_TOOLS_MAX_PENDING;
    if (tools->pending_count >= room) {
        return STA_OK; // a full polyline waits for finish
    }
    memcpy(tools->pending[tools->pending_count++], pick->world, sizeof(pick->world));
    if (tools->tool <= STA_MEASURE_HEIGHT &&
        tools->pending_count == sta_measure_max_points(tools->tool)) {
        sta_status status = finish(tools, err);
        *out_finished = status == STA_OK;
        return status;
    }
    return STA_OK;
}

bool sta_view_tools_finish(sta_view_tools *tools)
{
    if (tools->tool < STA_MEASURE_POLYLINE ||
        tools->pending_count < sta_measure_min_points(tools->tool)) {
        return false;
    }
    return finish(tools, NULL) == STA_OK;
}

void sta_view_tools_undo(sta_view_tools *tools)
{
    if (tools->pending_count > 0) {
        tools->pending_count--;
    } else {
        sta_measure_list_pop(&tools->list);
    }
}

void sta_view_tools_status(const sta_view_tools *tools, char *out, size_t size)
{
    static const char *const hints[STA_MEASURE_KIND_COUNT] = {
        "Ctrl+click a point", "Ctrl+click two points", "Ctrl+click the ground, then a point",
        "Ctrl+click points, Enter ends", "Ctrl+click corners, Enter closes"
    };
    snprintf(out, size, "tool %s: %s (%zu picked)  T tool, Backspace undo, J save, C csv",
             sta_measure_kind_name(tools->tool), hints[tools->tool], tools->pending_count);
}
