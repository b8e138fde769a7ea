/* SPDX-License-Identifier: MIT
 * Measurement maths in double, relative to the first vertex (see measure.h). */
#include "core/measure.h"

#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <string.h>

#include "core/alloc.h"
#include "core/array.h"

static const char *const kind_names[STA_MEASURE_KIND_COUNT] = { "point", "distance", "height",
                                                                "polyline", "area" };

const char *sta_measure_kind_name(sta_measure_kind kind)
{
    return (unsigned)kind < STA_MEASURE_KIND_COUNT ? kind_names[kind] : NULL;
}

int sta_measure_kind_from_name(const char *name)
{
    for (int k = 0; k < STA_MEASURE_KIND_COUNT; k++) {
        if (strcmp(name, kind_names[k]) == 0) {
            return k;
        }
    }
    return -1;
}

size_t sta_measure_min_points(sta_measure_kind kind)
{
    static const size_t min[STA_MEASURE_KIND_COUNT] = { 1, 2, 2, 2, 3 };
    return (unsigned)kind < STA_MEASURE_KIND_COUNT ? min[kind] : 0;
}

size_t sta_measure_max_points(sta_measure_kind kind)
{
    static const size_t max[STA_MEASURE_KIND_COUNT] = { 1, 2, 2, STA_MEASURE_MAX_POINTS,
                                                        STA_MEASURE_MAX_POINTS };
    return (unsigned)kind < STA_MEASURE_KIND_COUNT ? max[kind] : 0;
}

// Vertex i relative to vertex 0.
static void relative(const double (*points)[3], size_t i, double out[3])
{
    for (int a = 0; a < 3; a++) {
        out[a] = points[i][a] - points[0][a];
    }
}

// Length of the path through the vertices (closed: back to the first).
static void path_length(const double (*points)[3], size_t count, bool closed,
                        sta_measure_values *out)
{
    size_t edges = closed ? count : count - 1;
    for (size_t e = 0; e < edges; e++) {
        double a[3], b[3];
        relative(points, e, a);
        relative(points, (e + 1) % count, b);
        double dx = b[0] - a[0], dy = b[1] - a[1], dz = b[2] - a[2];
        out->distance_xy += hypot(dx, dy);
        out->distance_3d += sqrt(dx * dx + dy * dy + dz * dz);
    }
}

// Plan area (shoelace) and 3D area (half the norm of Newell's normal).
static void polygon_area(const double (*points)[3], size_t count, sta_measure_values *out)
{
    double n[3] = { 0, 0, 0 };
    for (size_t i = 0; i < count; i++) {
        double a[3], b[3];
        relative(points, i, a);
        relative(points, (i + 1) % count, b);
        n[0] += (a[1] - b[1]) * (a[2] + b[2]);
        n[1] += (a[2] - b[2]) * (a[0] + b[0]);
        n[2] += (a[0] - b[0]) * (a[1] + b[1]);
    }
    out->area_xy = fabs(n[2]) / 2.0;
    out->area_3d = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]) / 2.0;
}

sta_status sta_measure_compute(sta_measure_kind kind, const double (*points)[3], size_t count,
                               sta_measure_values *out, sta_error *err)
{
    memset(out, 0, sizeof(*out));
    const char *name = sta_measure_kind_name(kind);
    if (!name) {
        return sta_fail(err, STA_ERR_ARG, "unknown measurement kind %d", (int)kind);
    }
    if (count < sta_measure_min_points(kind) || count > sta_measure_max_points(kind)) {
        return sta_fail(err, STA_ERR_ARG, "a %s measurement has %zu..%zu points, not %zu", name,
                        sta_measure_min_points(kind), sta_measure_max_points(kind), count);
    }
    for (size_t i = 0; i < count; i++) {
        if (!isfinite(points[i][0]) || !isfinite(points[i][1]) || !isfinite(points[i][2])) {
            return sta_fail(err, STA_ERR_ARG, "%s measurement: point %zu is not finite", name, i);
        }
    }
    switch (kind) {
    case STA_MEASURE_POINT:
        break;
    case STA_MEASURE_DISTANCE:
        path_length(points, count, false, out);
        out->distance_z = points[1][2] - points[0][2];
        break;
    case STA_MEASURE_HEIGHT:
        out->distance_z = points[1][2] - points[0][2];
        break;
    case STA_MEASURE_POLYLINE:
        path_length(points, count, false, out);
        break;
    case STA_MEASURE_AREA:
        path_length(points, count, true, out);
        polygon_area(points, count, out);
        break;
    }
    return STA_OK;
}

sta_status sta_measure_list_add(sta_measure_list *list, sta_measure_kind kind, const char *name,
                                const double (*points)[3], size_t count, sta_error *err)
{
    sta_measure_values values;
    sta_status status = sta_measure_compute(kind, points, count, &values, err);
    if (status != STA_OK) {
        return status;
    }
    if (sta_array_reserve((void **)&list->items, &list->capacity, list->count + 1,
                          sizeof(*list->items), 8, err) != STA_OK) {
        return sta_fail(err, STA_ERR_NOMEM, "out of memory for a measurement");
    }
    double(*copy)[3] = sta_alloc_array(count, sizeof(*copy));
    if (!copy) {
        return sta_fail(err, STA_ERR_NOMEM, "out of memory for a measurement");
    }
    memcpy(copy, points, count * sizeof(*copy));
    sta_measure *m = &list->items[list->count++];
    memset(m, 0, sizeof(*m));
    m->kind = kind;
    snprintf(m->name, sizeof(m->name), "%s", name ? name : "");
    m->points = copy;
    m->count = count;
    return STA_OK;
}

void sta_measure_list_pop(sta_measure_list *list)
{
    if (list->count > 0) {
        sta_free(list->items[--list->count].points);
    }
}

void sta_measure_list_release(sta_measure_list *list)
{
    while (list->count > 0) {
        sta_measure_list_pop(list);
    }
    sta_free(list->items);
    memset(list, 0, sizeof(*list));
}
