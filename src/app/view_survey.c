/* SPDX-License-Identifier: MIT
 * Picking and measurement text for strata-view. */
#include "app/view_survey.h"

#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <string.h>

#include "core/json_out.h"

sta_status sta_view_pick(const sta_scene *scene, const sta_camera *camera, double x_px, double y_px,
                         sta_pick_result *out, sta_error *err)
{
    const sta_streamer *streamer = sta_scene_streamer(scene);
    size_t count = 0;
    const uint32_t *nodes = sta_streamer_last_draw(streamer, &count);
    sta_strata_decoder *decoder = NULL;
    sta_status status = sta_strata_decoder_create(&decoder, err);
    if (status == STA_OK) {
        status = sta_pick(sta_streamer_reader(streamer), decoder, nodes, count,
                          sta_streamer_clip(streamer), camera, x_px, y_px, STA_VIEW_PICK_RADIUS_PX,
                          out, err);
    }
    sta_strata_decoder_destroy(decoder);
    return status;
}

// Appends formatted text at *at (bounded by end).
static void append(char **at, const char *end, const char *text)
{
    size_t room = (size_t)(end - *at);
    size_t n = strlen(text);
    if (room == 0) {
        return;
    }
    n = n < room - 1 ? n : room - 1;
    memcpy(*at, text, n);
    *at += n;
    **at = '\0';
}

void sta_view_describe_pick(const sta_pick_result *pick, char *out, size_t size)
{
    char *at = out, *end = out + size;
    out[0] = '\0';
    if (!pick->hit) {
        append(&at, end, "no point");
        return;
    }
    char num[40], text[160];
    for (int a = 0; a < 3; a++) {
        // As many decimals as the grid step has (0.001 -> 3): the stored precision.
        int decimals = 0;
        for (double step = pick->grid.scale[a]; step < 0.999999 && decimals < 12; step *= 10) {
            decimals++;
        }
        snprintf(num, sizeof(num), "%.*f", decimals, pick->world[a]);
        append(&at, end, a == 0 ? "x " : (a == 1 ? " y " : " z "));
        append(&at, end, num);
    }
    const sta_point *p = &pick->point;
    uint32_t attr = pick->attributes;
    if (attr & STA_ATTR_CLASSIFICATION) {
        snprintf(text, sizeof(text), "  class %u (%s)", (unsigned)p->classification,
                 sta_pick_class_name(p->classification));
        append(&at, end, text);
    }
    if (attr & STA_ATTR_INTENSITY) {
        snprintf(text, sizeof(text), "  intensity %u", (unsigned)p->intensity);
        append(&at, end, text);
    }
    if (attr & STA_ATTR_RETURNS) {
        snprintf(text, sizeof(text), "  return %u of %u", (unsigned)p->return_number,
                 (unsigned)p->number_of_returns);
        append(&at, end, text);
    }
    if (attr & STA_ATTR_GPS_TIME) {
        append(&at, end, "  gps time ");
        append(&at, end, sta_format_double(p->gps_time, num, sizeof(num)));
    }
    if (attr & STA_ATTR_RGB) {
        snprintf(text, sizeof(text), "  rgb %u %u %u", (unsigned)p->red, (unsigned)p->green,
                 (unsigned)p->blue);
        append(&at, end, text);
    }
}

void sta_view_describe_measure(const sta_measure *m, char *out, size_t size)
{
    sta_measure_values v;
    if (sta_measure_compute(m->kind, (const double(*)[3])m->points, m->count, &v, NULL) != STA_OK) {
        snprintf(out, size, "%s: %s (incomplete)", m->name, sta_measure_kind_name(m->kind));
        return;
    }
    const char *name = m->name[0] ? m->name : sta_measure_kind_name(m->kind);
    switch (m->kind) {
    case STA_MEASURE_POINT:
        snprintf(out, size, "%s: %.3f %.3f %.3f", name, m->points[0][0], m->points[0][1],
                 m->points[0][2]);
        break;
    case STA_MEASURE_DISTANCE:
        snprintf(out, size, "%s: 3D %.3f m, horizontal %.3f m, vertical %+.3f m", name,
                 v.distance_3d, v.distance_xy, v.distance_z);
        break;
    case STA_MEASURE_HEIGHT:
        snprintf(out, size, "%s: height %+.3f m above ground", name, v.distance_z);
        break;
    case STA_MEASURE_POLYLINE:
        snprintf(out, size, "%s: length %.3f m (horizontal %.3f m), %zu points", name,
                 v.distance_3d, v.distance_xy, m->count);
        break;
    case STA_MEASURE_AREA:
        snprintf(out, size, "%s: area %.3f m2 plan, %.3f m2 3D, perimeter %.3f m", name, v.area_xy,
                 v.area_3d, v.distance_3d);
        break;
    }
}

// Adds one line to the readout if there is room.
static char *readout_line(sta_view_readout *out)
{
    if (out->count >= STA_VIEW_HUD_MAX_LINES) {
        return NULL;
    }
    char *line = out->lines[out->count++];
    line[0] = '\0';
    return line;
}

void sta_view_readout_fill(sta_view_readout *out, const sta_frame_stats *stats, double fps,
                           uint64_t budget_points, const char *pipeline,
                           const sta_pick_result *pick, const sta_measure_list *measures)
{
    const size_t size = sizeof(out->lines[0]);
    out->count = 0;
    char *line = readout_line(out);
    if (fps > 0) {
        snprintf(line, size, "%.0f fps  ", fps);
    }
    size_t n = strlen(line);
    snprintf(line + n, size - n, "%.2f / %.2f M points (%.0f%% of budget)  pipeline %s",
             (double)stats->points_drawn * 1e-6, (double)budget_points * 1e-6,
             budget_points ? 100.0 * (double)stats->points_drawn / (double)budget_points : 0.0,
             pipeline);
    line = readout_line(out);
    snprintf(line, size, "%u nodes resident, %zu loading  %.0f MiB GPU%s", stats->nodes_resident,
             stats->loader_backlog, (double)stats->gpu_bytes / 1048576.0,
             stats->bad_nodes ? "  (damaged nodes hidden)" : "");
    if (pick) { // coordinates on one line, attributes on the next
        line = readout_line(out);
        memcpy(line, "pick: ", 7);
        sta_view_describe_pick(pick, line + 6, size - 6);
        char *attributes = strstr(line, "  ");
        char *next = attributes ? readout_line(out) : NULL;
        if (next) {
            snprintf(next, size, "      %s", attributes + 2);
            *attributes = '\0';
        }
    }
    for (size_t i = 0; measures && i < measures->count; i++) {
        line = readout_line(out);
        if (!line) {
            break;
        }
        sta_view_describe_measure(&measures->items[i], line, size);
    }
}

void sta_view_readout_pointers(const sta_view_readout *readout, const char **out_lines)
{
    for (size_t i = 0; i < readout->count; i++) {
        out_lines[i] = readout->lines[i];
    }
}

// Appends a square of `size` px centred on (x, y).
static void add_mark(sta_hud_rect *out, size_t capacity, size_t *n, double x, double y, int size,
                     const uint8_t rgb[3])
{
    if (*n < capacity) {
        out[*n] = (sta_hud_rect){
            .x = (int)(x - size / 2.0), .y = (int)(y - size / 2.0), .w = size, .h = size
        };
        memcpy(out[*n].rgb, rgb, 3);
        (*n)++;
    }
}

// Vertices and dotted edges of one polyline (closed: back to the first vertex).
static void add_path(const sta_camera *camera, const double (*points)[3], size_t count, bool closed,
                     const uint8_t rgb[3], sta_hud_rect *out, size_t capacity, size_t *n)
{
    enum {
        DOT_STEP_PX = 5,
        MAX_DOTS = 400
    };
    size_t edges = closed && count > 2 ? count : (count > 0 ? count - 1 : 0);
    for (size_t i = 0; i < count; i++) {
        double x, y, depth;
        if (sta_camera_project(camera, points[i], &x, &y, &depth)) {
            add_mark(out, capacity, n, x, y, 5, rgb);
        }
    }
    for (size_t e = 0; e < edges; e++) {
        double a[2], b[2], depth;
        if (!sta_camera_project(camera, points[e], &a[0], &a[1], &depth) ||
            !sta_camera_project(camera, points[(e + 1) % count], &b[0], &b[1], &depth)) {
            continue; // an end behind the camera
        }
        double length = hypot(b[0] - a[0], b[1] - a[1]);
        int dots = (int)fmin(length / DOT_STEP_PX, MAX_DOTS);
        for (int d = 1; d < dots; d++) {
            double t = (double)d / dots;
            add_mark(out, capacity, n, a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t, 2, rgb);
        }
    }
}

size_t sta_view_measure_marks(const sta_camera *camera, const sta_measure_list *measures,
                              const double (*pending)[3], size_t pending_count, sta_hud_rect *out,
                              size_t capacity)
{
    static const uint8_t done_rgb[3] = { 255, 220, 0 }, pending_rgb[3] = { 0, 230, 255 };
    size_t n = 0;
    for (size_t i = 0; measures && i < measures->count; i++) {
        const sta_measure *m = &measures->items[i];
        add_path(camera, (const double(*)[3])m->points, m->count, m->kind == STA_MEASURE_AREA,
                 done_rgb, out, capacity, &n);
    }
    add_path(camera, pending, pending_count, false, pending_rgb, out, capacity, &n);
    return n;
}
