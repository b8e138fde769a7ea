/* SPDX-License-Identifier: MIT
 * Surveyor's measurements in the scene's CRS, in double precision: distances (3D,
 * horizontal, vertical), height above a ground point, polyline length, polygon area,
 * and a list of named measurements as the viewer keeps them.
 *
 * Design: coordinates far from the origin (UTM: 6e5 m east, 5e6 m north) are first
 * made relative to the measurement's first vertex, so differences and products stay
 * exact to the data's precision (millimetres on a 1 mm grid) instead of losing
 * digits in sums of large products (a shoelace over absolute UTM coordinates would
 * cancel ~10 of its 16 digits).
 */
#ifndef STA_CORE_MEASURE_H
#define STA_CORE_MEASURE_H

#include <stddef.h>

#include "core/status.h"

/* What a measurement measures. */
typedef enum sta_measure_kind {
    STA_MEASURE_POINT = 0,    /* one picked point (its coordinates) */
    STA_MEASURE_DISTANCE = 1, /* two points: 3D, horizontal and vertical distance */
    STA_MEASURE_HEIGHT = 2,   /* ground point then a point: height above the ground */
    STA_MEASURE_POLYLINE = 3, /* two or more points: length (3D and horizontal) */
    STA_MEASURE_AREA = 4,     /* three or more points, closed: area (plan and 3D) */
} sta_measure_kind;

#define STA_MEASURE_KIND_COUNT 5
#define STA_MEASURE_MAX_POINTS 4096 /* vertices per measurement */

/* The values of one measurement (metres, square metres in the CRS's unit). */
typedef struct sta_measure_values {
    double distance_3d; /* DISTANCE: |b - a|; POLYLINE and AREA: 3D length of the path
                           (AREA: including the closing edge) */
    double distance_xy; /* horizontal: the same in the XY plane */
    double distance_z;  /* DISTANCE: b.z - a.z (signed); HEIGHT: point z - ground z */
    double area_xy;     /* AREA: plan area (shoelace, unsigned) */
    double area_3d;     /* AREA: area of the polygon in 3D (Newell's vector, unsigned) */
} sta_measure_values;

/* One measurement: a kind and its vertices (x, y, z in the scene's CRS). */
typedef struct sta_measure {
    sta_measure_kind kind;
    char name[64];       /* NUL-terminated label */
    double (*points)[3]; /* count vertices (owned by the list) */
    size_t count;
} sta_measure;

/* The measurements on screen, in order. Zero-initialise; release with _release. */
typedef struct sta_measure_list {
    sta_measure *items;
    size_t count;
    size_t capacity;
} sta_measure_list;

/* The kind's name ("point", "distance", "height", "polyline", "area"); NULL if unknown. */
const char *sta_measure_kind_name(sta_measure_kind kind);

/* The kind named `name`, or -1. */
int sta_measure_kind_from_name(const char *name);

/* Fewest vertices a complete measurement of `kind` has (1, 2, 2, 2, 3). */
size_t sta_measure_min_points(sta_measure_kind kind);

/* Most vertices (1, 2, 2, STA_MEASURE_MAX_POINTS, STA_MEASURE_MAX_POINTS). */
size_t sta_measure_max_points(sta_measure_kind kind);

/* Computes the values of `count` vertices measured as `kind` (zeros for fields the
 * kind does not have). Errors: STA_ERR_ARG when count is outside the kind's range or
 * a coordinate is not finite. */
sta_status sta_measure_compute(sta_measure_kind kind, const double (*points)[3], size_t count,
                               sta_measure_values *out, sta_error *err);

/* Appends a measurement (points copied). Errors: as sta_measure_compute, STA_ERR_NOMEM. */
sta_status sta_measure_list_add(sta_measure_list *list, sta_measure_kind kind, const char *name,
                                const double (*points)[3], size_t count, sta_error *err);

/* Removes the last measurement (no-op on an empty list). */
void sta_measure_list_pop(sta_measure_list *list);

/* Frees everything; a zeroed list is a no-op. */
void sta_measure_list_release(sta_measure_list *list);

#endif
