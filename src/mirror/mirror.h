/* SPDX-License-Identifier: MIT
 * Planar mirrors of polygonal outline: the plane from the vertices (with a planarity
 * tolerance), reflection of points, directions and cameras, point-in-polygon, and
 * ray and segment crossings. Everything in double precision relative to the
 * polygon's centre, so that mirrors millions of metres from the origin keep
 * sub-millimetre accuracy. No GL, no files (mirror_file.h reads and writes them).
 *
 * Orientation: the normal follows the vertex order by the right-hand rule (Newell's
 * method), so the vertices run counter-clockwise seen from the front, the reflecting
 * side. Ghost points lie behind (signed distance < 0). See docs/MIRRORS.md.
 */
#ifndef STA_MIRROR_MIRROR_H
#define STA_MIRROR_MIRROR_H

#include <stdbool.h>
#include <stddef.h>

#include "core/status.h"

#define STA_MIRROR_MAX_VERTICES 64  /* vertices of one outline */
#define STA_MIRROR_MAX_COUNT    255 /* mirrors of one file (the MIRROR attribute is a u8) */
#define STA_MIRROR_NAME_MAX     64  /* bytes of a name, with its NUL */

typedef struct sta_mirror {
    char name[STA_MIRROR_NAME_MAX];
    size_t vertex_count;                         /* 3 .. STA_MIRROR_MAX_VERTICES */
    double vertices[STA_MIRROR_MAX_VERTICES][3]; /* world coordinates, as given */
    double centre[3];                            /* mean of the vertices */
    double normal[3];                            /* unit, towards the front */
    double axis_u[3], axis_v[3];                 /* in-plane unit axes, u x v = normal */
    double uv[STA_MIRROR_MAX_VERTICES][2];       /* vertices in (u, v) about the centre */
    double max_off_plane_m;                      /* largest vertex distance to the plane */
} sta_mirror;

/* Builds `out` from `count` vertices (world coordinates). Fails with STA_ERR_FORMAT
 * for fewer than 3 or more than STA_MIRROR_MAX_VERTICES vertices, a non-finite
 * coordinate, a degenerate outline (area below 1e-6 m^2), or a vertex farther than
 * `tolerance_m` from the best plane; the message names the vertex and the distance.
 * `name` may be NULL. */
sta_status sta_mirror_init(sta_mirror *out, const char *name, const double (*vertices)[3],
                           size_t count, double tolerance_m, sta_error *err);

/* Signed distance of `p` to the plane: > 0 in front, < 0 behind. */
double sta_mirror_signed_distance(const sta_mirror *m, const double p[3]);

/* The mirror image of point `p`; `out` may alias `p`. */
void sta_mirror_reflect_point(const sta_mirror *m, const double p[3], double out[3]);

/* The mirror image of direction `d` (not translated); `out` may alias `d`. */
void sta_mirror_reflect_direction(const sta_mirror *m, const double d[3], double out[3]);

/* The reflection as a 4x4 column-major matrix (x' = M x): I - 2nn^T and 2(n.c)n. */
void sta_mirror_reflection_matrix(const sta_mirror *m, double out[16]);

/* (u, v) of the orthogonal projection of `p` on the plane, about the centre. */
void sta_mirror_project(const sta_mirror *m, const double p[3], double out_uv[2]);

/* Whether plane coordinates `uv` lie inside the outline (even-odd rule). */
bool sta_mirror_contains_uv(const sta_mirror *m, const double uv[2]);

/* Distance in the plane from `uv` to the outline; 0 inside. */
double sta_mirror_distance_uv(const sta_mirror *m, const double uv[2]);

/* The ray origin + t dir (any length of dir) hits the polygon's front face for
 * t_min < t < t_max: true and *out_t. Rays arriving from behind do not hit. */
bool sta_mirror_ray_hit(const sta_mirror *m, const double origin[3], const double dir[3],
                        double t_min, double t_max, double *out_t);

/* Whether the segment a -> b goes from the front (distance > 0) through the polygon
 * to at least `behind_m` behind it. */
bool sta_mirror_segment_crosses(const sta_mirror *m, const double a[3], const double b[3],
                                double behind_m);

#endif
