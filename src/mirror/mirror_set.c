/* SPDX-License-Identifier: MIT
 * A growable set of mirrors with the settings of its file. */
#include "mirror/mirror_set.h"

#include <math.h>
#include <string.h>

#include "core/alloc.h"

void sta_mirror_set_defaults(sta_mirror_set *set)
{
    if (set->tolerance_m == 0.0) {
        set->tolerance_m = STA_MIRROR_DEFAULT_TOLERANCE_M;
    }
    if (set->behind_m == 0.0) {
        set->behind_m = STA_MIRROR_DEFAULT_BEHIND_M;
    }
    if (set->max_incidence_deg == 0.0) {
        set->max_incidence_deg = STA_MIRROR_DEFAULT_MAX_INCIDENCE_DEG;
    }
}

sta_status sta_mirror_set_add(sta_mirror_set *set, const char *name, const double (*vertices)[3],
                              size_t count, sta_error *err)
{
    sta_mirror_set_defaults(set);
    size_t k = set->count + 1;
    if (set->count >= STA_MIRROR_MAX_COUNT) {
        return sta_fail(err, STA_ERR_FORMAT, "mirror %zu: at most %d mirrors are supported", k,
                        STA_MIRROR_MAX_COUNT);
    }
    sta_mirror *grown = sta_realloc_array(set->mirrors, k, sizeof(sta_mirror));
    if (!grown) {
        return sta_fail(err, STA_ERR_NOMEM, "out of memory for %zu mirrors", k);
    }
    set->mirrors = grown;
    sta_error inner = { 0 };
    if (sta_mirror_init(&set->mirrors[set->count], name, vertices, count, set->tolerance_m,
                        &inner) != STA_OK) {
        return sta_fail(err, inner.code, "mirror %zu '%s': %s", k, name ? name : "", inner.message);
    }
    set->count = k;
    return STA_OK;
}

sta_status sta_mirror_set_add_station(sta_mirror_set *set, uint16_t point_source_id,
                                      const double position[3], sta_error *err)
{
    size_t k = set->station_count + 1;
    if (set->station_count >= STA_MIRROR_MAX_STATIONS) {
        return sta_fail(err, STA_ERR_FORMAT, "station %zu: at most %d stations are supported", k,
                        STA_MIRROR_MAX_STATIONS);
    }
    for (size_t i = 0; i < set->station_count; i++) {
        if (set->stations[i].point_source_id == point_source_id) {
            return sta_fail(err, STA_ERR_FORMAT,
                            "station %zu: point source ID %u is already station %zu", k,
                            (unsigned)point_source_id, i + 1);
        }
    }
    for (int a = 0; a < 3; a++) {
        if (!isfinite(position[a])) {
            return sta_fail(err, STA_ERR_FORMAT, "station %zu: position is not finite", k);
        }
    }
    sta_mirror_station *grown = sta_realloc_array(set->stations, k, sizeof(*grown));
    if (!grown) {
        return sta_fail(err, STA_ERR_NOMEM, "out of memory for %zu stations", k);
    }
    set->stations = grown;
    set->stations[k - 1].point_source_id = point_source_id;
    memcpy(set->stations[k - 1].position, position, sizeof(double[3]));
    set->station_count = k;
    return STA_OK;
}

void sta_mirror_set_release(sta_mirror_set *set)
{
    sta_free(set->mirrors);
    set->mirrors = NULL;
    set->count = 0;
    sta_free(set->stations);
    set->stations = NULL;
    set->station_count = 0;
}

sta_status sta_mirror_set_translated(const sta_mirror_set *set, const double offset[3],
                                     sta_mirror_set *out, sta_error *err)
{
    *out = (sta_mirror_set){ .tolerance_m = set->tolerance_m,
                             .behind_m = set->behind_m,
                             .max_incidence_deg = set->max_incidence_deg };
    for (size_t k = 0; k < set->count; k++) {
        const sta_mirror *m = &set->mirrors[k];
        double v[STA_MIRROR_MAX_VERTICES][3];
        for (size_t i = 0; i < m->vertex_count; i++) {
            for (int a = 0; a < 3; a++) {
                v[i][a] = m->vertices[i][a] + offset[a];
            }
        }
        sta_status s =
            sta_mirror_set_add(out, m->name, (const double(*)[3])v, m->vertex_count, err);
        if (s != STA_OK) {
            sta_mirror_set_release(out);
            return s;
        }
    }
    for (size_t i = 0; i < set->station_count; i++) {
        double p[3];
        for (int a = 0; a < 3; a++) {
            p[a] = set->stations[i].position[a] + offset[a];
        }
        sta_status s = sta_mirror_set_add_station(out, set->stations[i].point_source_id, p, err);
        if (s != STA_OK) {
            sta_mirror_set_release(out);
            return s;
        }
    }
    return STA_OK;
}
