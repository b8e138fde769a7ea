/* SPDX-License-Identifier: MIT
 * The mirror room's terrestrial scanner: from each station, pulses in a Fibonacci
 * spiral over the sphere; a pulse that meets a mirror's front is reflected and its
 * return recorded along the first direction at the whole path length (a ghost,
 * user_data = 1 + the first mirror's index). Every pulse gives one return (the room
 * is closed), unless it bounces more than ROOM_MAX_BOUNCES times.
 */
#include <math.h>
#include <string.h>

#include "synth/mirror_room.h"
#include "synth/synth_internal.h"

#define GOLDEN_ANGLE 2.39996322972865332 /* pi (3 - sqrt 5) */
#define MIN_RANGE_M  0.5
#define MAX_RANGE_M  200.0
#define GHOST_DIM    0.85 /* a mirror keeps this share of the light */

/* Colour (8-bit) and LAS class per surface of mirror_room.c. */
static const struct {
    double rgb[3];
    uint8_t classification;
    double reflectance;
} surfaces[] = {
    { { 150, 120, 90 }, 2, 0.4 },  /* floor */
    { { 220, 215, 200 }, 6, 0.6 }, /* walls, ceiling */
    { { 60, 90, 160 }, 1, 0.3 },   /* couch */
    { { 200, 200, 200 }, 1, 0.5 }, /* column */
    { { 140, 90, 50 }, 1, 0.35 },  /* table */
    { { 235, 235, 230 }, 1, 0.6 }, /* cupboard */
    { { 200, 60, 50 }, 1, 0.45 },  /* sphere */
    { { 80, 80, 80 }, 1, 0.2 },    /* mirror backs */
};
#define SURFACE_COUNT ((int)(sizeof(surfaces) / sizeof(surfaces[0])))

static uint16_t channel16(double value)
{
    double v = value < 0.0 ? 0.0 : (value > 255.0 ? 255.0 : value);
    return (uint16_t)((unsigned)(v + 0.5) * 257u);
}

/* Follows one pulse through up to ROOM_MAX_BOUNCES mirrors. */
static bool trace_pulse(const synth_room *room, const double origin[3], const double dir[3],
                        double *out_path, double out_normal[3], double *out_cos, int *out_surface,
                        uint8_t *out_label)
{
    double o[3] = { origin[0], origin[1], origin[2] }, d[3] = { dir[0], dir[1], dir[2] };
    double path = 0.0, t_lo = MIN_RANGE_M;
    *out_label = 0;
    for (int bounce = 0; bounce <= ROOM_MAX_BOUNCES; bounce++) {
        double t = 0.0;
        if (!sta_room_raycast(room, o, d, t_lo, MAX_RANGE_M, &t, out_normal, out_surface)) {
            return false;
        }
        double t_mirror = t;
        size_t which = room->mirrors.count;
        for (size_t k = 0; k < room->mirrors.count; k++) {
            double tk;
            if (sta_mirror_ray_hit(&room->mirrors.mirrors[k], o, d, t_lo, t_mirror, &tk)) {
                t_mirror = tk;
                which = k;
            }
        }
        if (which == room->mirrors.count) {
            *out_path = path + t;
            *out_cos = fabs(d[0] * out_normal[0] + d[1] * out_normal[1] + d[2] * out_normal[2]);
            return true;
        }
        if (*out_label == 0) {
            *out_label = (uint8_t)(which + 1);
        }
        path += t_mirror;
        for (int a = 0; a < 3; a++) {
            o[a] += t_mirror * d[a];
        }
        sta_mirror_reflect_direction(&room->mirrors.mirrors[which], d, d);
        t_lo = 1e-9; // leave the mirror's surface
    }
    return false;
}

void sta_room_source_fill(synth_source *src, sta_point *out, size_t count)
{
    synth_room *room = src->scene->room;
    const uint64_t m = room->rays_per_station;
    size_t done = 0;
    while (done < count) {
        uint64_t i = src->room_ray++;
        int station = sta_room_station_of(room, i);
        uint64_t j = i % m, pass = i / (m * ROOM_STATIONS);
        double z = 1.0 - 2.0 * ((double)j + 0.5) / (double)m;
        double r = sqrt(fmax(0.0, 1.0 - z * z));
        double phi = (double)j * GOLDEN_ANGLE + 1.0 * station + 0.5 * (double)pass;
        double d[3] = { r * cos(phi), r * sin(phi), z };
        double path, normal[3], cos_i;
        int surface;
        uint8_t label;
        if (!trace_pulse(room, room->stations[station], d, &path, normal, &cos_i, &surface,
                         &label)) {
            continue;
        }
        surface = surface < SURFACE_COUNT ? surface : SURFACE_COUNT - 1;
        double range = path + src->scene->noise_m * sta_rng_gauss(&src->rng);
        double dim = label ? GHOST_DIM : 1.0;
        double level = surfaces[surface].reflectance * (0.2 + 0.8 * cos_i) * dim;
        const double *s = room->stations[station];
        sta_point *p = &out[done++];
        *p = (sta_point){
            .X = sta_synth_georef_step(src->georef, 0, s[0] + range * d[0]),
            .Y = sta_synth_georef_step(src->georef, 1, s[1] + range * d[1]),
            .Z = sta_synth_georef_step(src->georef, 2, s[2] + range * d[2]),
            .intensity = (uint16_t)(level * 65000.0 + 1.5),
            .return_number = 1,
            .number_of_returns = 1,
            .classification = surfaces[surface].classification,
            .user_data = label,
            .point_source_id = (uint16_t)(station + 1),
            .gps_time = ROOM_GPS_START + (double)i * ROOM_RAY_PERIOD_S,
        };
        p->red = channel16(surfaces[surface].rgb[0] * dim);
        p->green = channel16(surfaces[surface].rgb[1] * dim);
        p->blue = channel16(surfaces[surface].rgb[2] * dim);
        room->ghost_counts[label]++;
    }
    src->emitted += count;
}
