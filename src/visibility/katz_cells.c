/* SPDX-License-Identifier: MIT
 * One point per screen cell for the live Katz mode (see katz_cells.h). */
#include "visibility/katz_cells.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/alloc.h"

// Tries at finding a cell size with at most `cap` occupied cells; each scales the side
// by the square root of occupied / cap (occupied cells fall about as the side squared).
#define CELL_TRIES 8
// Aim a little below cap so that one correction usually suffices; accept down to CELL_LOW.
#define CELL_AIM   0.95
#define CELL_LOW   0.85

// Projects every point (screen x, y in pixels from the bottom-left, depth along the view
// axis); those outside the view get depth -1. Returns how many are inside.
static size_t project(sta_katz_cells *cells, const sta_camera *camera, const double origin[3],
                      const float (*points)[3], size_t count)
{
    double f[3], r[3], u[3], eye[3];
    sta_camera_basis(camera, f, r, u);
    for (int a = 0; a < 3; a++) {
        eye[a] = camera->position[a] - origin[a];
    }
    const double w = camera->width_px, h = camera->height_px;
    const double tan_y = tan(0.5 * camera->fov_y), tan_x = tan_y * w / h;
    size_t inside = 0;
    for (size_t i = 0; i < count; i++) {
        const double d[3] = { (double)points[i][0] - eye[0], (double)points[i][1] - eye[1],
                              (double)points[i][2] - eye[2] };
        const double z = d[0] * f[0] + d[1] * f[1] + d[2] * f[2];
        float *s = cells->screen + 3 * i;
        s[2] = -1.0f;
        if (!(z >= camera->near_m)) {
            continue;
        }
        const double x = ((d[0] * r[0] + d[1] * r[1] + d[2] * r[2]) / (z * tan_x) * 0.5 + 0.5) * w;
        const double y = ((d[0] * u[0] + d[1] * u[1] + d[2] * u[2]) / (z * tan_y) * 0.5 + 0.5) * h;
        if (x >= 0.0 && x < w && y >= 0.0 && y < h) {
            s[0] = (float)x;
            s[1] = (float)y;
            s[2] = (float)z;
            inside++;
        }
    }
    return inside;
}

// Bins the projected points into cells of `side` pixels (the nearest wins); returns the
// occupied cells. `columns` receives the grid's width.
static size_t bin(sta_katz_cells *cells, const sta_camera *camera, size_t count, double side,
                  size_t *columns)
{
    const size_t cx = (size_t)ceil(camera->width_px / side);
    const size_t cy = (size_t)ceil(camera->height_px / side);
    *columns = cx;
    for (size_t c = 0; c < cx * cy; c++) {
        cells->best[c] = -1;
    }
    size_t occupied = 0;
    for (size_t i = 0; i < count; i++) {
        const float *s = cells->screen + 3 * i;
        if (s[2] < 0.0f) {
            continue;
        }
        size_t col = (size_t)((double)s[0] / side), row = (size_t)((double)s[1] / side);
        col = col < cx ? col : cx - 1;
        row = row < cy ? row : cy - 1;
        int32_t *b = &cells->best[row * cx + col];
        if (*b < 0) {
            occupied++;
            *b = (int32_t)i;
        } else if (s[2] < cells->screen[3 * (size_t)*b + 2]) {
            *b = (int32_t)i;
        }
    }
    return occupied;
}

static int compare_index(const void *a, const void *b)
{
    const int32_t x = *(const int32_t *)a, y = *(const int32_t *)b;
    return (x > y) - (x < y);
}

sta_status sta_katz_cells_select(sta_katz_cells *cells, const sta_camera *camera,
                                 const double origin[3], size_t cap, float (*points)[3],
                                 uint64_t *tags, size_t *inout_count, sta_error *err)
{
    const size_t count = *inout_count;
    *inout_count = 0;
    if (count > INT32_MAX) {
        return sta_fail(err, STA_ERR_ARG, "katz cells: %zu points, at most %d", count, INT32_MAX);
    }
    cells->in_view = 0;
    cells->cell_px = 1.0;
    if (count == 0) {
        return STA_OK;
    }
    // The finest grid used is one cell per pixel.
    const size_t most_cells = (size_t)camera->width_px * (size_t)camera->height_px;
    if (cells->screen_capacity < count) {
        sta_free(cells->screen);
        cells->screen = sta_alloc_array(count, 3 * sizeof(float));
        cells->screen_capacity = cells->screen ? count : 0;
    }
    if (cells->cell_capacity < most_cells) {
        sta_free(cells->best);
        cells->best = sta_alloc_array(most_cells ? most_cells : 1, sizeof(int32_t));
        cells->cell_capacity = cells->best ? most_cells : 0;
    }
    if (!cells->screen || !cells->best) {
        return sta_fail(err, STA_ERR_NOMEM, "katz cells: out of memory for %zu points", count);
    }
    cells->in_view = project(cells, camera, origin, (const float(*)[3])points, count);
    // Single pixels first: the occupied pixels are the area the points cover, and cells
    // of side s over it number about that area / s^2. Then correct (occupied cells go
    // about as 1 / side^2) until the count is within [CELL_LOW, 1] * cap.
    double side = 1.0;
    size_t columns = 0, occupied = bin(cells, camera, count, side, &columns);
    for (int t = 0; t < CELL_TRIES; t++) {
        const bool over = occupied > cap;
        const bool under = (double)occupied < CELL_LOW * (double)cap && side > 1.0;
        if (!over && !under) {
            break;
        }
        double next = side * sqrt((double)occupied / (CELL_AIM * (double)cap));
        next = next > 1.0 ? next : 1.0;
        const size_t next_occupied = bin(cells, camera, count, next, &columns);
        if (under && next_occupied > cap) {
            // Went over from below: take the previous, coarser side back, and stop.
            occupied = bin(cells, camera, count, side, &columns);
            break;
        }
        side = next;
        occupied = next_occupied;
    }
    // Still over (never seen): keep every step-th occupied cell.
    const double step = occupied > cap ? (double)occupied / (double)cap : 1.0;
    const size_t rows = (size_t)ceil(camera->height_px / side);
    size_t kept = 0, seen = 0;
    double next = 0.0;
    for (size_t c = 0; c < rows * columns; c++) {
        const int32_t i = cells->best[c];
        if (i < 0) {
            continue;
        }
        if ((double)seen++ < next) {
            continue;
        }
        next += step;
        cells->best[kept++] = i;
    }
    // Sorted, index k <= best[k]: compacting forward reads every point before it is
    // overwritten.
    qsort(cells->best, kept, sizeof(int32_t), compare_index);
    for (size_t k = 0; k < kept; k++) {
        const size_t i = (size_t)cells->best[k];
        memmove(points[k], points[i], sizeof(points[0]));
        tags[k] = tags[i];
    }
    cells->cell_px = side;

    *inout_count = kept;
    return STA_OK;
}

void sta_katz_cells_release(sta_katz_cells *cells)
{
    sta_free(cells->screen);
    sta_free(cells->best);
    memset(cells, 0, sizeof(*cells));
}
