/* SPDX-License-Identifier: MIT
 * Internal: the scene object shared by the synth sources, and the point sources the
 * generator drives (street scanner, analytic samplers).
 */
#ifndef STA_SYNTH_INTERNAL_H
#define STA_SYNTH_INTERNAL_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "io/model_up.h"
#include "io/obj.h"
#include "io/ply.h"
#include "synth/mesh_bvh.h"
#include "synth/mirror_room.h"
#include "synth/street.h"
#include "synth/synth.h"
#include "synth/synth_rng.h"

#define SYNTH_MAX_RECTS 6

/* A parallelogram: corner + a * edge_a + b * edge_b for a, b in [0, 1]. */
typedef struct synth_rect {
    double corner[3];
    double edge_a[3];
    double edge_b[3];
    double normal[3]; /* unit, as defined (not flipped) */
    double area_m2;
} synth_rect;

/* The analytic scenes' geometry. Primitive ids: rects 0..rect_count-1, then the
 * sphere (nested: 6; sphere scene: 0); mesh: the triangle index. */
typedef struct synth_analytic {
    synth_rect rects[SYNTH_MAX_RECTS];
    int rect_count;
    bool has_sphere;
    double sphere_centre[3];
    double sphere_radius_m;
    uint32_t sphere_id;
    uint64_t counts[SYNTH_MAX_RECTS + 1]; /* points per primitive (rects, then sphere) */
    sta_mesh mesh;                        /* positions already transformed to scene-local */
    sta_bvh bvh;                          /* over mesh */
    double *area_cdf;                     /* cumulative triangle areas (mesh) */
    double mesh_area_m2;                  /* total */
    double mesh_scale;                    /* local = R (mesh - mesh_centre) * mesh_scale */
    double mesh_centre[3];                /* bounding-box centre of the mesh's vertices */
    bool mesh_y_up;                       /* R turns +Y to +Z: (x, y, z) -> (x, -z, y) */
    char mesh_up_why[256];                /* how mesh_y_up was decided, one line */
} synth_analytic;

/* Scanner settings of a street run (functions of point_count; see docs/SYNTH.md). */
typedef struct street_scan_config {
    double speed_mps;      /* vehicle speed */
    double profile_hz;     /* mirror revolutions per second */
    int rays_per_profile;  /* pulses per revolution */
    double tilt_rad;       /* profile plane leans forward by this much */
    double height_m;       /* scanner above the road surface */
    double lane_u_m;       /* lateral position (negative: right of the crown) */
    double start_s_m;      /* run position at the first pulse */
    double gps_time_start; /* adjusted standard GPS time of the first pulse */
    double min_range_m, max_range_m;
    double nominal_length_m; /* run length the settings aim at */
} street_scan_config;

struct sta_synth_scene {
    sta_synth_params params; /* defaults resolved; mesh_path points at mesh_path_copy */
    char *mesh_path_copy;    /* owned */
    double noise_m;          /* resolved noise sigma */
    sta_street *street;      /* street scene, else NULL */
    street_scan_config scan; /* street scene */
    synth_analytic analytic; /* other scenes */
    synth_room *room;        /* mirror scene, else NULL */
};

/* Scanner settings for `point_count` points. */
void sta_street_scan_config_init(street_scan_config *scan, const street_config *cfg,
                                 uint64_t point_count);

/* Sets up the analytic geometry of `scene` (kind, mesh already chosen). */
sta_status sta_synth_analytic_init(sta_synth_scene *scene, sta_error *err);

void sta_synth_analytic_release(synth_analytic *analytic);

/* Ray cast over the analytic geometry. */
bool sta_synth_analytic_raycast(const synth_analytic *analytic, const double origin[3],
                                const double dir[3], double min_t, double max_t,
                                sta_synth_hit *hit);

/* One scanner pulse. */
typedef struct street_pulse {
    double o[3]; /* scanner position, local */
    double d[3]; /* unit direction, local */
    double gps_time;
    int16_t scan_angle; /* 0.006 degree units from nadir */
    int64_t block;      /* block of the scanner position */
} street_pulse;

/* One return of a pulse before it becomes a point. */
typedef struct street_return {
    sta_synth_hit hit;
    double energy; /* share of the pulse left when it got here (0..1] */
} street_return;

/* A stream of points for the generator. */
typedef struct synth_source {
    sta_synth_scene *scene;         /* borrowed */
    const sta_synth_georef *georef; /* borrowed */
    bool legacy_classes;            /* LAS 1.2: map classes above 12 to 1 */
    sta_rng rng;
    uint64_t emitted; /* points handed out so far */
    // Street scanner state.
    double *ray_cos, *ray_sin;       /* per ray of a profile at phase 0 (owned) */
    uint64_t profile;                /* current profile */
    int ray;                         /* next ray within it */
    double phase;                    /* profile's start, in angular steps (0..1) */
    double phase_cos, phase_sin;     /* rotation by that fraction of a step */
    double tilt_cos, tilt_sin;       /* of the profile plane's lean */
    double inv_rays, inv_profile_hz; /* 1 / rays_per_profile, 1 / profile_hz */
    street_frame frame;              /* frame of frame_block, when has_frame */
    int64_t frame_block;
    bool has_frame;
    street_pulse pulse;            /* the last pulse */
    street_return returns[8];      /* its returns */
    int return_count, return_next; /* returns found, returns handed out */
    uint64_t pulse_count;          /* pulses cast */
    double last_s_m;               /* run position of the last pulse */
    double last_gps_time;          /* of the last pulse */
    uint64_t room_ray;             /* mirror scene: next pulse */
    // Analytic sampler state.
    int primitive;           /* current rect/sphere index */
    uint64_t primitive_left; /* points left on it */
} synth_source;

sta_status sta_synth_source_init(synth_source *src, sta_synth_scene *scene,
                                 const sta_synth_georef *georef, bool legacy_classes,
                                 sta_error *err);

void sta_synth_source_release(synth_source *src);

/* Writes exactly `count` next points into `out`. */
void sta_synth_source_fill(synth_source *src, sta_point *out, size_t count);

/* Street / analytic halves of sta_synth_source_fill. */
sta_status sta_street_source_init(synth_source *src, sta_error *err);
void sta_street_source_fill(synth_source *src, sta_point *out, size_t count);
void sta_analytic_source_fill(synth_source *src, sta_point *out, size_t count);
void sta_room_source_fill(synth_source *src, sta_point *out, size_t count);

/* Writes the truth sidecar for a finished run to `path` (temporary + rename). */
sta_status sta_synth_truth_write(const char *path, const synth_source *src, sta_error *err);

#endif
