/* SPDX-License-Identifier: MIT
 * Synthetic scenes with known truth: a mobile-mapping street scan and analytic
 * surfaces (sphere, stacked planes, sphere nested in a box, a PLY mesh), written as
 * LAS with a JSON truth sidecar, and a ray caster over the same geometry.
 *
 * Design: a scene (sta_synth_scene) is built from parameters alone; the same
 * parameters always give the same geometry and, through sta_synth_generate, the
 * same bytes. The street is procedural: each 40 m block is generated from (seed,
 * block index) when a ray first needs it and kept in a small cache, so memory does
 * not grow with the run length. The street's scanner itself casts its rays through
 * sta_synth_scene_raycast_ex, so generated points and ray-cast truth come from one
 * implementation.
 *
 * Coordinates: scene-local metres, x east, y north, z up (for the ECEF origin the
 * axes stay parallel to ECEF axes; see docs/SYNTH.md). Real-world coordinates are
 * local + georef origin; the integer LAS coordinate of local value x on axis a is
 * llround(x / scale) + origin_steps[a], so the local geometry is the same integer
 * geometry whichever origin is chosen.
 */
#ifndef STA_SYNTH_SYNTH_H
#define STA_SYNTH_SYNTH_H

#include <stdbool.h>
#include <stdint.h>

#include "core/point.h"
#include "core/status.h"
#include "mirror/mirror_set.h"

#define STA_SYNTH_STREET_VERSION 1 /* bump when the street generator's output changes */

typedef enum sta_synth_kind {
    STA_SYNTH_STREET = 1, /* mobile-mapping run along a procedural street */
    STA_SYNTH_SPHERE,     /* uniform points on a sphere of radius 10 m */
    STA_SYNTH_PLANES,     /* 5 stacked, staggered 10 m squares at depth gaps 1 cm .. 10 m */
    STA_SYNTH_NESTED,     /* a sphere inside a closed box (hidden from outside) */
    STA_SYNTH_MESH,       /* uniform-by-area samples of a PLY triangle mesh */
    STA_SYNTH_MIRROR,     /* a room with mirrors: ghost points behind them (truth labelled) */
} sta_synth_kind;

typedef enum sta_synth_origin {
    STA_SYNTH_ORIGIN_UTM = 0, /* default: near (650000, 5400000, 100), EPSG:32632 */
    STA_SYNTH_ORIGIN_ZERO,    /* local coordinates as they are */
    STA_SYNTH_ORIGIN_ECEF,    /* near (4.2e6, 0.17e6, 4.78e6), EPSG:4978 */
} sta_synth_origin;

/* Surface materials reported by the ray caster (and written as user_data). */
typedef enum sta_synth_material {
    STA_SYNTH_MAT_NONE = 0,
    STA_SYNTH_MAT_ROAD,     /* asphalt */
    STA_SYNTH_MAT_MARKING,  /* road paint */
    STA_SYNTH_MAT_CURB,     /* curb face */
    STA_SYNTH_MAT_SIDEWALK, /* sidewalk and the ground beyond it */
    STA_SYNTH_MAT_WALL,     /* facade, window reveals, side walls, roof */
    STA_SYNTH_MAT_GLASS,    /* window glass (only with STA_SYNTH_RAY_GLASS) */
    STA_SYNTH_MAT_DOOR,     /* door panel */
    STA_SYNTH_MAT_INTERIOR, /* room surfaces seen through windows */
    STA_SYNTH_MAT_POLE,     /* utility pole */
    STA_SYNTH_MAT_WIRE,     /* overhead wire */
    STA_SYNTH_MAT_TRUNK,    /* tree trunk */
    STA_SYNTH_MAT_FOLIAGE,  /* leaf clusters of a crown */
    STA_SYNTH_MAT_CAR,      /* parked car body */
    STA_SYNTH_MAT_TYRE,     /* parked car wheel */
    STA_SYNTH_MAT_SURFACE,  /* analytic scene surface */
    STA_SYNTH_MAT_COUNT
} sta_synth_material;

/* Ray cast flags. */
enum {
    STA_SYNTH_RAY_GLASS = 1u << 0, /* report window glass (otherwise rays pass through) */
};

/* Which way is up in the mesh scene's model (the LAS it writes is z up). */
typedef enum sta_synth_mesh_up {
    STA_SYNTH_MESH_UP_AUTO = 0, /* from its extents, the converter's rule (io/model_up.h) */
    STA_SYNTH_MESH_UP_Z,        /* z up: its axes kept */
    STA_SYNTH_MESH_UP_Y,        /* y up: turned so that +Y becomes +Z, (x, y, z) -> (x, -z, y) */
} sta_synth_mesh_up;

/* Generation parameters. Zero means default for each field. */
typedef struct sta_synth_params {
    sta_synth_kind kind;
    uint64_t seed;             /* any value */
    uint64_t point_count;      /* points to write, > 0 (the LAS holds exactly this many) */
    int point_format;          /* 3 (LAS 1.2) or 7 (LAS 1.4); 0 means 7 */
    sta_synth_origin origin;   /* see sta_synth_origin */
    const char *mesh_path;     /* PLY or OBJ for STA_SYNTH_MESH (borrowed, copied by create) */
    sta_synth_mesh_up mesh_up; /* STA_SYNTH_MESH: which way the model's up is */
    bool has_noise;            /* noise_m given; otherwise street 0.015 m, others 0 */
    double noise_m;            /* Gaussian sigma: range noise (street), along the normal */
    double street_length_m;    /* street: run length the ray caster covers; 0 means the
                                  nominal length for point_count (see docs/SYNTH.md) */
} sta_synth_params;

/* Where the scene sits in the world and on which integer grid. */
typedef struct sta_synth_georef {
    double origin[3];        /* real-world coordinate of local (0, 0, 0) */
    sta_grid grid;           /* scale 0.001 m, offsets round numbers near the origin */
    int64_t origin_steps[3]; /* (origin - offset) / scale, exact integers */
    const char *crs;         /* "EPSG:32632", "EPSG:4978" or "local" (static) */
    const char *wkt;         /* OGC WKT (static) or NULL for "local" */
} sta_synth_georef;

/* A ray hit, in scene-local coordinates. */
typedef struct sta_synth_hit {
    double t;               /* metres along the unit direction, min_t <= t < max_t */
    double normal[3];       /* unit normal of the surface as defined (outward for
                               closed solids, +z for planes, triangle winding for
                               meshes); not flipped towards the ray */
    uint64_t primitive_id;  /* scene-specific id, see docs/SYNTH.md */
    uint8_t material;       /* sta_synth_material */
    uint8_t classification; /* LAS 1.4 class of the surface */
} sta_synth_hit;

typedef struct sta_synth_scene sta_synth_scene;

/* Mirror scene only: its mirrors in scene-local coordinates (else NULL). Valid until
 * destroy. Add the georef origin for world coordinates. */
const sta_mirror_set *sta_synth_scene_mirrors(const sta_synth_scene *scene);

/* The mirror file's path of a LAS path: "x.las" -> "x.mirrors.json" (as
 * sta_synth_truth_path). The mirror scene writes it beside its sidecar, in world
 * coordinates. *out_path is owned by the caller (sta_free). */
sta_status sta_synth_mirrors_path(const char *las_path, char **out_path, sta_error *err);

/* The scene kind for a name ("street", "sphere", "planes", "nested", "mesh", "mirror"). */
bool sta_synth_kind_from_name(const char *name, sta_synth_kind *out_kind);

/* The name of a kind ("?" when unknown). Never NULL. */
const char *sta_synth_kind_name(sta_synth_kind kind);

/* The georeference of an origin choice. */
void sta_synth_georef_init(sta_synth_origin origin, sta_synth_georef *out_georef);

/* Integer LAS coordinate of local value `local_m` on `axis` under `georef`. */
int32_t sta_synth_georef_step(const sta_synth_georef *georef, int axis, double local_m);

/* Builds a scene from `params` (borrowed). The mesh scene loads its PLY here.
 * Errors: STA_ERR_ARG for bad parameters, the PLY loader's errors for meshes.
 * On success *out_scene is owned by the caller (sta_synth_scene_destroy). */
sta_status sta_synth_scene_create(const sta_synth_params *params, sta_synth_scene **out_scene,
                                  sta_error *err);

/* Frees a scene; NULL is a no-op. */
void sta_synth_scene_destroy(sta_synth_scene *scene);

/* The parameters the scene was built with, defaults resolved. Valid until destroy. */
const sta_synth_params *sta_synth_scene_params(const sta_synth_scene *scene);

/* The nearest surface hit along origin + t * dir for 0 < t < max_t (glass is passed
 * through). `dir` must be a unit vector. Returns false (and leaves *out_hit alone)
 * when nothing is hit. Not thread-safe for the street scene (it caches blocks): use
 * one scene per thread. */
bool sta_synth_scene_raycast(sta_synth_scene *scene, const double origin[3], const double dir[3],
                             double max_t, sta_synth_hit *out_hit);

/* As sta_synth_scene_raycast for min_t < t < max_t, with STA_SYNTH_RAY_* flags. */
bool sta_synth_scene_raycast_ex(sta_synth_scene *scene, const double origin[3], const double dir[3],
                                double min_t, double max_t, unsigned flags, sta_synth_hit *out_hit);

/* Street and mirror scenes: the scanner's position (local metres) at GPS time
 * `gps_time`. STA_ERR_ARG for other scenes. */
sta_status sta_synth_scene_scanner_position(const sta_synth_scene *scene, double gps_time,
                                            double out_position[3], sta_error *err);

/* Mesh scene: whether `params->mesh_path`'s model is turned from y up to z up
 * (*out_y_up) and in `why` (may be NULL) one line saying how that was decided, as
 * sta_synth_scene_create decides it (the mesh is loaded for its extents). */
sta_status sta_synth_mesh_up_axis(const sta_synth_params *params, bool *out_y_up, char *why,
                                  size_t why_size, sta_error *err);

/* Called between batches with the points written so far; return false to stop
 * (sta_synth_generate then fails with STA_ERR_CANCELLED). */
typedef bool (*sta_synth_progress_fn)(void *user, uint64_t done, uint64_t total);

/* Generates `params->point_count` points into `las_path` (LAS 1.2 format 3 or LAS 1.4
 * format 7) and writes the truth sidecar beside it (sta_synth_truth_path). Both are
 * written under temporary names and renamed when complete. Memory is bounded
 * (batches of 64 Ki points). `progress` may be NULL. */
sta_status sta_synth_generate(const sta_synth_params *params, const char *las_path,
                              sta_synth_progress_fn progress, void *user, sta_error *err);

/* What sta_synth_generate_reported decided on the way. */
typedef struct sta_synth_report {
    bool mesh_y_up;        /* mesh scene: the model was turned from y up to z up */
    char mesh_up_why[256]; /* mesh scene: how that was decided, one line; "" otherwise */
} sta_synth_report;

/* sta_synth_generate, and in *out_report (may be NULL) what it decided (filled once the
 * scene is made, even when writing fails later). */
sta_status sta_synth_generate_reported(const sta_synth_params *params, const char *las_path,
                                       sta_synth_progress_fn progress, void *user,
                                       sta_synth_report *out_report, sta_error *err);

/* The sidecar path of a LAS path: "x.las" -> "x.truth.json" (".las" in any case is
 * replaced; other names get ".truth.json" appended). *out_path is owned by the
 * caller (sta_free). */
sta_status sta_synth_truth_path(const char *las_path, char **out_path, sta_error *err);

#endif
