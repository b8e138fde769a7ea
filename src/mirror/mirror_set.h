/* SPDX-License-Identifier: MIT
 * The mirrors of a scene as one set: the mirror file (JSON, docs/MIRRORS.md) read and
 * written, and the ghost test of a point against every mirror (first match wins, so
 * a label k means "seen through mirror k-1 of the file", as the MIRROR attribute).
 */
#ifndef STA_MIRROR_MIRROR_SET_H
#define STA_MIRROR_MIRROR_SET_H

#include <stdint.h>

#include "core/json_out.h"
#include "core/status.h"
#include "mirror/mirror.h"

#define STA_MIRROR_FILE_FORMAT               "strata-mirrors"
#define STA_MIRROR_FILE_VERSION              1
#define STA_MIRROR_DEFAULT_TOLERANCE_M       0.05 /* vertex distance to the plane */
#define STA_MIRROR_DEFAULT_BEHIND_M          0.05 /* ghosts lie at least this far behind */
#define STA_MIRROR_DEFAULT_MAX_INCIDENCE_DEG 80.0 /* view rays of the volume model */

/* A scanner station of a terrestrial scan: the points whose LAS point source ID is
 * `point_source_id` were measured from `position` (world coordinates). */
typedef struct sta_mirror_station {
    uint16_t point_source_id;
    double position[3];
} sta_mirror_station;

#define STA_MIRROR_MAX_STATIONS 4096

/* Zero fields mean default (sta_mirror_set_defaults). */
typedef struct sta_mirror_set {
    sta_mirror *mirrors; /* count mirrors (sta_alloc) */
    size_t count;
    double tolerance_m;           /* planarity tolerance for the outlines */
    double behind_m;              /* a ghost lies more than this behind the plane */
    double max_incidence_deg;     /* volume model: largest angle of a view ray to the normal */
    sta_mirror_station *stations; /* station_count (sta_alloc); none: the volume model only */
    size_t station_count;
} sta_mirror_set;

void sta_mirror_set_defaults(sta_mirror_set *set);

/* Appends a mirror built by sta_mirror_init with the set's tolerance. Errors name
 * the mirror ("mirror 2 'hall': ..."). */
sta_status sta_mirror_set_add(sta_mirror_set *set, const char *name, const double (*vertices)[3],
                              size_t count, sta_error *err);

/* `out` = `set` moved by `offset` (e.g. scene-local to world coordinates). */
sta_status sta_mirror_set_translated(const sta_mirror_set *set, const double offset[3],
                                     sta_mirror_set *out, sta_error *err);

/* Appends a station; a point source ID given twice is an error naming both. */
sta_status sta_mirror_set_add_station(sta_mirror_set *set, uint16_t point_source_id,
                                      const double position[3], sta_error *err);

/* Frees the mirrors and stations; the set is empty afterwards (settings kept). */
void sta_mirror_set_release(sta_mirror_set *set);

/* Reads a mirror file. Every error names the file and, where one is at fault, the
 * mirror: "<path>: mirror 2 'hall': not planar: ...". Unknown keys are errors.
 * On failure the set is empty. */
sta_status sta_mirror_set_load(const char *path, sta_mirror_set *out, sta_error *err);

/* As sta_mirror_set_load for `size` bytes of JSON text; `path` only names it. */
sta_status sta_mirror_set_parse(const char *text, size_t size, const char *path,
                                sta_mirror_set *out, sta_error *err);

/* Writes the file's top-level object at the writer's position (for sidecars). */
void sta_mirror_set_write_json(sta_json_out *json, const sta_mirror_set *set);

/* Writes the mirror file under a temporary name and renames it. */
sta_status sta_mirror_set_save(const char *path, const sta_mirror_set *set, sta_error *err);

/* Scanner model: k + 1 for the first mirror k that the segment scanner -> p crosses
 * from the front to more than behind_m behind it; 0 for a real point. */
uint8_t sta_mirror_ghost_from_scanner(const sta_mirror_set *set, const double scanner[3],
                                      const double p[3]);

/* Volume model (no scanner known): k + 1 for the first mirror k that p lies more
 * than behind_m behind, at a depth h where its projection on the plane is within
 * h * tan(max_incidence) of the outline; 0 otherwise. docs/MIRRORS.md. */
uint8_t sta_mirror_ghost_in_volume(const sta_mirror_set *set, const double p[3]);

/* The label of a point measured under `point_source_id`: the scanner model from the
 * station of that ID when the set has one, otherwise the volume model. */
uint8_t sta_mirror_ghost_of(const sta_mirror_set *set, uint16_t point_source_id, const double p[3]);

#endif
