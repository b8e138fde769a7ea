/* SPDX-License-Identifier: MIT
 * The mirror room's geometry and its ray cast: the room (inside of a box), solid
 * boxes and a sphere for furniture, and the mirrors' backs (opaque). Mirror fronts
 * are handled by the scanner (mirror_scan.c), which reflects the pulse there. */
#include "synth/mirror_room.h"

#include <math.h>
#include <string.h>

#define ROOM_X 12.0
#define ROOM_Y 8.0
#define ROOM_Z 3.0

/* Surfaces: 0 floor, 1 walls and ceiling, 2.. furniture, then mirror backs. */
enum {
    SURFACE_FLOOR = 0,
    SURFACE_WALL = 1,
    SURFACE_FIRST_OBJECT = 2
};

typedef struct room_box {
    double lo[3], hi[3];
} room_box;

static const room_box furniture[] = {
    { { 7.0, 1.0, 0.0 }, { 9.2, 2.0, 0.8 } },   /* couch */
    { { 9.5, 5.0, 0.0 }, { 10.0, 5.5, 3.0 } },  /* column */
    { { 2.0, 6.0, 0.0 }, { 3.0, 7.0, 0.75 } },  /* table */
    { { 10.6, 6.8, 0.0 }, { 11.6, 7.6, 1.9 } }, /* cupboard */
};
#define FURNITURE_COUNT ((int)(sizeof(furniture) / sizeof(furniture[0])))
static const double sphere_centre[3] = { 4.0, 5.0, 0.7 };
static const double sphere_radius = 0.7;

static const double station_positions[ROOM_STATIONS][3] = {
    { 3.0, 3.0, 1.6 },
    { 8.5, 5.8, 1.4 },
    { 10.4, 2.6, 1.7 },
};

/* Adds the outline, flipped if needed so that its front faces `inside`. */
static sta_status add_mirror(synth_room *room, const char *name, double (*v)[3], size_t n,
                             const double inside[3], sta_error *err)
{
    sta_status s = sta_mirror_set_add(&room->mirrors, name, (const double(*)[3])v, n, err);
    if (s != STA_OK) {
        return s;
    }
    sta_mirror *m = &room->mirrors.mirrors[room->mirrors.count - 1];
    if (sta_mirror_signed_distance(m, inside) > 0.0) {
        return STA_OK;
    }
    double flipped[STA_MIRROR_MAX_VERTICES][3];
    for (size_t i = 0; i < n; i++) {
        memcpy(flipped[i], v[n - 1 - i], sizeof(flipped[i]));
    }
    room->mirrors.count--;
    return sta_mirror_set_add(&room->mirrors, name, (const double(*)[3])flipped, n, err);
}

sta_status sta_room_init(synth_room *room, uint64_t point_count, sta_error *err)
{
    memset(room, 0, sizeof(*room));
    sta_mirror_set_defaults(&room->mirrors);
    memcpy(room->stations, station_positions, sizeof(station_positions));
    room->rays_per_station = (point_count + ROOM_STATIONS - 1) / ROOM_STATIONS;
    const double inside[3] = { 6.0, 4.0, 1.5 };
    // A rectangle on the east wall, 2 cm proud of it.
    double east[4][3] = {
        { 11.98, 2.5, 0.6 }, { 11.98, 4.5, 0.6 }, { 11.98, 4.5, 2.4 }, { 11.98, 2.5, 2.4 }
    };
    // A hexagon on the north wall.
    double north[6][3];
    for (int i = 0; i < 6; i++) {
        double a = 2.0 * 3.14159265358979323846 * i / 6.0;
        north[i][0] = 6.5 + 0.8 * cos(a);
        north[i][1] = 7.98;
        north[i][2] = 1.6 + 0.8 * sin(a);
    }
    // A floor mirror with a pointed top leaning against the south wall: foot 0.45 m
    // out, top touching the wall 1.85 m up (its plane is tilted by 13.4 degrees).
    double lean[5][3];
    const double xs[5] = { 5.0, 6.2, 6.2, 5.6, 5.0 }, ss[5] = { 0.0, 0.0, 0.85, 1.0, 0.85 };
    for (int i = 0; i < 5; i++) {
        lean[i][0] = xs[i];
        lean[i][1] = 0.47 - 0.45 * ss[i];
        lean[i][2] = 0.05 + 1.8 * ss[i];
    }
    sta_status s = add_mirror(room, "east wall", east, 4, inside, err);
    s = s == STA_OK ? add_mirror(room, "north wall hexagon", north, 6, inside, err) : s;
    s = s == STA_OK ? add_mirror(room, "leaning floor mirror", lean, 5, inside, err) : s;
    // The stations go into the mirror file too (the point source ID of their points is
    // station + 1, mirror_scan.c), so that --mirrors can use the scanner model.
    for (int k = 0; k < ROOM_STATIONS && s == STA_OK; k++) {
        s = sta_mirror_set_add_station(&room->mirrors, (uint16_t)(k + 1), room->stations[k], err);
    }
    if (s != STA_OK) {
        sta_room_release(room);
    }
    return s;
}

void sta_room_release(synth_room *room)
{
    sta_mirror_set_release(&room->mirrors);
}

int sta_room_station_of(const synth_room *room, uint64_t ray)
{
    return (int)((ray / room->rays_per_station) % ROOM_STATIONS);
}

/* Slab test: entry and exit distances of the ray through the box, with the axes. */
static bool slabs(const double lo[3], const double hi[3], const double o[3], const double d[3],
                  double *t0, double *t1, int *axis0, int *axis1)
{
    double a = -INFINITY, b = INFINITY;
    for (int k = 0; k < 3; k++) {
        if (d[k] == 0.0) {
            if (o[k] < lo[k] || o[k] > hi[k]) {
                return false;
            }
            continue;
        }
        double inv = 1.0 / d[k];
        double ta = (lo[k] - o[k]) * inv, tb = (hi[k] - o[k]) * inv;
        if (ta > tb) {
            double t = ta;
            ta = tb;
            tb = t;
        }
        if (ta > a) {
            a = ta;
            *axis0 = k;
        }
        if (tb < b) {
            b = tb;
            *axis1 = k;
        }
    }
    *t0 = a;
    *t1 = b;
    return a <= b;
}

static void take(double t, const double n[3], int surface, double *best, double out_n[3],
                 int *out_surface)
{
    *best = t;
    memcpy(out_n, n, 3 * sizeof(double));
    *out_surface = surface;
}

bool sta_room_raycast(const synth_room *room, const double o[3], const double d[3], double min_t,
                      double max_t, double *out_t, double out_normal[3], int *out_surface)
{
    double best = max_t;
    bool hit = false;
    // The room from inside: its exit distance.
    const double lo[3] = { 0, 0, 0 }, hi[3] = { ROOM_X, ROOM_Y, ROOM_Z };
    double t0, t1;
    int a0 = 0, a1 = 0;
    if (slabs(lo, hi, o, d, &t0, &t1, &a0, &a1) && t1 > min_t && t1 < best) {
        double n[3] = { 0, 0, 0 };
        n[a1] = d[a1] > 0.0 ? -1.0 : 1.0; // facing into the room
        take(t1, n, a1 == 2 && d[2] < 0.0 ? SURFACE_FLOOR : SURFACE_WALL, &best, out_normal,
             out_surface);
        hit = true;
    }
    for (int i = 0; i < FURNITURE_COUNT; i++) {
        if (slabs(furniture[i].lo, furniture[i].hi, o, d, &t0, &t1, &a0, &a1) && t0 > min_t &&
            t0 < best) {
            double n[3] = { 0, 0, 0 };
            n[a0] = d[a0] > 0.0 ? -1.0 : 1.0;
            take(t0, n, SURFACE_FIRST_OBJECT + i, &best, out_normal, out_surface);
            hit = true;
        }
    }
    double oc[3] = { o[0] - sphere_centre[0], o[1] - sphere_centre[1], o[2] - sphere_centre[2] };
    double bq = oc[0] * d[0] + oc[1] * d[1] + oc[2] * d[2];
    double cq = oc[0] * oc[0] + oc[1] * oc[1] + oc[2] * oc[2] - sphere_radius * sphere_radius;
    double disc = bq * bq - cq;
    if (disc >= 0.0) {
        double t = -bq - sqrt(disc);
        if (t > min_t && t < best) {
            double n[3];
            for (int k = 0; k < 3; k++) {
                n[k] = (oc[k] + t * d[k]) / sphere_radius;
            }
            take(t, n, SURFACE_FIRST_OBJECT + FURNITURE_COUNT, &best, out_normal, out_surface);
            hit = true;
        }
    }
    // Mirror backs: opaque (the front is the scanner's business).
    for (size_t k = 0; k < room->mirrors.count; k++) {
        const sta_mirror *m = &room->mirrors.mirrors[k];
        double back_n[3] = { -m->normal[0], -m->normal[1], -m->normal[2] };
        sta_mirror flipped = *m;
        memcpy(flipped.normal, back_n, sizeof(back_n));
        flipped.axis_v[0] = -m->axis_v[0]; // keep u x v = n; outline mirrored in v
        flipped.axis_v[1] = -m->axis_v[1];
        flipped.axis_v[2] = -m->axis_v[2];
        for (size_t i = 0; i < m->vertex_count; i++) {
            flipped.uv[i][1] = -m->uv[i][1];
        }
        double t;
        if (sta_mirror_ray_hit(&flipped, o, d, min_t, best, &t)) {
            take(t, back_n, SURFACE_FIRST_OBJECT + FURNITURE_COUNT + 1, &best, out_normal,
                 out_surface);
            hit = true;
        }
    }
    if (hit) {
        *out_t = best;
    }
    return hit;
}
