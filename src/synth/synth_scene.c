/* SPDX-License-Identifier: MIT
 * Scenes: parameters, creation and the public ray cast (the georeference is in
 * synth_georef.c).
 */
#include <math.h>
#include <string.h>

#include "core/alloc.h"
#include "synth/synth_internal.h"

static const char *const kind_names[] = { "?",      "street", "sphere", "planes",
                                          "nested", "mesh",   "mirror" };

bool sta_synth_kind_from_name(const char *name, sta_synth_kind *out_kind)
{
    for (int k = STA_SYNTH_STREET; k <= STA_SYNTH_MIRROR; k++) {
        if (strcmp(name, kind_names[k]) == 0) {
            *out_kind = (sta_synth_kind)k;
            return true;
        }
    }
    return false;
}

const char *sta_synth_kind_name(sta_synth_kind kind)
{
    if (kind < STA_SYNTH_STREET || kind > STA_SYNTH_MIRROR) {
        return kind_names[0];
    }
    return kind_names[kind];
}

static sta_status check_params(const sta_synth_params *p, sta_error *err)
{
    if (p->kind < STA_SYNTH_STREET || p->kind > STA_SYNTH_MIRROR) {
        return sta_fail(err, STA_ERR_ARG, "unknown scene kind %d", (int)p->kind);
    }
    if (p->point_count == 0) {
        return sta_fail(err, STA_ERR_ARG, "point count must be positive");
    }
    if (p->point_format != 0 && p->point_format != 3 && p->point_format != 7) {
        return sta_fail(err, STA_ERR_ARG, "point format %d: use 3 (LAS 1.2) or 7 (LAS 1.4)",
                        p->point_format);
    }
    if (p->point_format == 3 && p->point_count > UINT32_MAX) {
        return sta_fail(err, STA_ERR_ARG,
                        "%llu points do not fit LAS 1.2 (at most 4294967295): use format 7",
                        (unsigned long long)p->point_count);
    }
    if (p->origin < STA_SYNTH_ORIGIN_UTM || p->origin > STA_SYNTH_ORIGIN_ECEF) {
        return sta_fail(err, STA_ERR_ARG, "unknown origin %d", (int)p->origin);
    }
    if (p->kind == STA_SYNTH_MESH && (!p->mesh_path || !p->mesh_path[0])) {
        return sta_fail(err, STA_ERR_ARG, "the mesh scene needs a PLY or OBJ file (--mesh FILE)");
    }
    if (p->mesh_up < STA_SYNTH_MESH_UP_AUTO || p->mesh_up > STA_SYNTH_MESH_UP_Y) {
        return sta_fail(err, STA_ERR_ARG, "unknown mesh up axis %d", (int)p->mesh_up);
    }
    if (p->has_noise && !(p->noise_m >= 0.0 && p->noise_m <= 10.0)) {
        return sta_fail(err, STA_ERR_ARG, "noise %g m out of range (0 .. 10)", p->noise_m);
    }
    if (!(p->street_length_m >= 0.0 && p->street_length_m <= 1e9)) {
        return sta_fail(err, STA_ERR_ARG, "street length %g m out of range (0 .. 1e9)",
                        p->street_length_m);
    }
    return STA_OK;
}

sta_status sta_synth_scene_create(const sta_synth_params *params, sta_synth_scene **out_scene,
                                  sta_error *err)
{
    *out_scene = NULL;
    sta_status status = check_params(params, err);
    if (status != STA_OK) {
        return status;
    }
    sta_synth_scene *scene = sta_calloc(1, sizeof(*scene));
    if (!scene) {
        return sta_fail(err, STA_ERR_NOMEM, "out of memory for a scene");
    }
    scene->params = *params;
    scene->params.mesh_path = NULL;
    if (scene->params.point_format == 0) {
        scene->params.point_format = 7;
    }
    if (params->kind == STA_SYNTH_MESH) {
        scene->mesh_path_copy = sta_strdup(params->mesh_path);
        if (!scene->mesh_path_copy) {
            status = sta_fail(err, STA_ERR_NOMEM, "out of memory for a scene");
            goto out_destroy;
        }
        scene->params.mesh_path = scene->mesh_path_copy;
    }
    bool street = params->kind == STA_SYNTH_STREET;
    bool room = params->kind == STA_SYNTH_MIRROR;
    scene->noise_m = params->has_noise ? params->noise_m
                     : street          ? 0.015
                     : room            ? ROOM_DEFAULT_NOISE_M
                                       : 0.0;
    scene->params.has_noise = true;
    scene->params.noise_m = scene->noise_m;
    if (street) {
        street_config cfg;
        sta_street_config_init(&cfg, params->seed);
        sta_street_scan_config_init(&scene->scan, &cfg, params->point_count);
        double length = params->street_length_m > 0.0 ? params->street_length_m
                                                      : 1.5 * scene->scan.nominal_length_m;
        scene->params.street_length_m = length;
        status =
            sta_street_create(params->seed, scene->scan.start_s_m + length, &scene->street, err);
    } else if (room) {
        scene->room = sta_calloc(1, sizeof(*scene->room));
        status = scene->room ? sta_room_init(scene->room, params->point_count, err)
                             : sta_fail(err, STA_ERR_NOMEM, "out of memory for a scene");
    } else {
        status = sta_synth_analytic_init(scene, err);
    }
    if (status != STA_OK) {
        goto out_destroy;
    }
    *out_scene = scene;
    return STA_OK;
out_destroy:
    sta_synth_scene_destroy(scene);
    return status;
}

void sta_synth_scene_destroy(sta_synth_scene *scene)
{
    if (!scene) {
        return;
    }
    sta_street_destroy(scene->street);
    if (scene->room) {
        sta_room_release(scene->room);
        sta_free(scene->room);
    }
    sta_synth_analytic_release(&scene->analytic);
    sta_free(scene->mesh_path_copy);
    sta_free(scene);
}

const sta_synth_params *sta_synth_scene_params(const sta_synth_scene *scene)
{
    return &scene->params;
}

bool sta_synth_scene_raycast_ex(sta_synth_scene *scene, const double origin[3], const double dir[3],
                                double min_t, double max_t, unsigned flags, sta_synth_hit *out_hit)
{
    if (scene->street) {
        sta_street *st = scene->street;
        return sta_street_trace(st, st->first_block, st->last_block, origin, dir, min_t, max_t,
                                flags, out_hit);
    }
    if (scene->room) {
        sta_synth_hit h = { .material = STA_SYNTH_MAT_SURFACE, .classification = 1 };
        int surface = 0;
        if (!sta_room_raycast(scene->room, origin, dir, min_t, max_t, &h.t, h.normal, &surface)) {
            return false;
        }
        h.primitive_id = (uint64_t)surface;
        *out_hit = h;
        return true;
    }
    return sta_synth_analytic_raycast(&scene->analytic, origin, dir, min_t, max_t, out_hit);
}

bool sta_synth_scene_raycast(sta_synth_scene *scene, const double origin[3], const double dir[3],
                             double max_t, sta_synth_hit *out_hit)
{
    return sta_synth_scene_raycast_ex(scene, origin, dir, 0.0, max_t, 0, out_hit);
}

sta_status sta_synth_scene_scanner_position(const sta_synth_scene *scene, double gps_time,
                                            double out_position[3], sta_error *err)
{
    if (scene->room) {
        double ray = floor((gps_time - ROOM_GPS_START) / ROOM_RAY_PERIOD_S + 0.5);
        if (!(ray >= 0.0 && ray < 1e18)) {
            return sta_fail(err, STA_ERR_ARG, "GPS time %.17g is not one of the scan's", gps_time);
        }
        int station = sta_room_station_of(scene->room, (uint64_t)ray);
        memcpy(out_position, scene->room->stations[station], 3 * sizeof(double));
        return STA_OK;
    }
    if (!scene->street) {
        return sta_fail(err, STA_ERR_ARG, "%s scene has no scanner",
                        sta_synth_kind_name(scene->params.kind));
    }
    const street_scan_config *scan = &scene->scan;
    const street_config *cfg = &scene->street->cfg;
    double s = scan->start_s_m + scan->speed_mps * (gps_time - scan->gps_time_start);
    double w = -cfg->cross_slope * fabs(scan->lane_u_m) + scan->height_m;
    sta_street_point(cfg, s, scan->lane_u_m, w, out_position);
    return STA_OK;
}

const sta_mirror_set *sta_synth_scene_mirrors(const sta_synth_scene *scene)
{
    return scene->room ? &scene->room->mirrors : NULL;
}
