/* SPDX-License-Identifier: MIT
 * The parts of a normal that both ways of strata-convert --normals share (the kNN
 * neighbourhoods of knn_normals.c, the cell moments of moment_normals.c): the plane fit
 * of a set of points from its moments (Kopp's hybrid solver, core/eigen3.h), the tests
 * of a fit that cannot decide a plane, the orientation rule of docs/CONVERTER.md, the
 * halo's reach, and the packing into a record's SPLAT bytes.
 */
#ifndef STA_PREPROCESS_NORMAL_FIT_H
#define STA_PREPROCESS_NORMAL_FIT_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "knn_normals.h"
#include "record.h"

/* l1 <= STA_NORMALS_COLLINEAR * l2: the neighbours lie on a line, no plane to fit. */
#define STA_NORMALS_COLLINEAR    1e-6
/* l1 < STA_NORMALS_LINEAR * l2 (spread across the strip under a tenth of the spread along it): the
 * neighbours are nearly one line (a dense scan line), and noise across it would decide
 * the plane: the neighbourhood is widened. */
#define STA_NORMALS_LINEAR       0.01
/* l0 > STA_NORMALS_THICK * l1: across the fitted plane the neighbours spread more than 0.22 of
 * their narrower spread within it (standard deviations): two surfaces close together (a square 1 cm
 * under another) or range noise of the order of the spacing. The wider fit's in-plane spread
 * outgrows the layer's thickness: widened. On strata-synth planes the p95 error falls from 16.7
 * to 2.3 degrees; 0.1 still left 7.7. */
#define STA_NORMALS_THICK        0.05
/* |n . v| below this, v the unit direction to the scanner (the trajectory): the fitted
 * plane holds the line of sight (within 10 degrees). No surface is scanned edge-on: this
 * is one profile whose range noise (along the rays) spans the plane; widened. */
#define STA_NORMALS_EDGE_ON      0.17
/* |n . up| below this: a vertical surface (a wall), oriented by the trajectory or the
 * scene's up-axis line. */
#define STA_NORMALS_VERTICAL_DOT 0.2

/* The plane normal of a set of points from its moments (count, sum of offsets from some
 * corner, sum of their products, in grid units x 2^shift; weighted sums are welcome) and
 * the covariance's eigenvalues, ascending, in m^2 times the count (zero when none);
 * false when it is degenerate (duplicates, one point, a line). */
bool sta_normal_fit_moments(const sta_normals_chunk *chunk, double count, const double s1[3],
                            const double s2[6], int shift, double n[3], double w[3]);

/* Whether a fit cannot decide the plane (docs/CONVERTER.md "Adaptive neighbourhoods"):
 * no fit, nearly linear, thick across its plane (when `thick`), or a plane that holds the
 * line of sight to the scanner path (p in grid units; gps_time NULL when unknown). */
bool sta_normal_too_narrow(const sta_normals_chunk *chunk, const double p[3],
                           const double *gps_time, bool ok, const double n[3], const double w[3],
                           bool thick);

/* sta_normal_too_narrow with the scanner's position (grid units) already looked up:
 * `target`, NULL when unknown. */
bool sta_normal_too_narrow_at(const sta_normals_chunk *chunk, const double p[3],
                              const double *target, bool ok, const double n[3], const double w[3],
                              bool thick);

/* Orients n (a plane normal) by the rule of docs/CONVERTER.md ("Orientation"). */
void sta_normal_orient(const sta_normals_chunk *chunk, const double p[3], const double *gps_time,
                       double n[3]);

/* sta_normal_orient with the scanner's position (grid units) already looked up: `target`,
 * NULL when unknown. */
void sta_normal_orient_at(const sta_normals_chunk *chunk, const double p[3], const double *target,
                          double n[3]);

/* Copies the `count` records' positions then the `halo_count` halo positions (3 x int32
 * each) into `grid` and widens [lo, hi] (start at INT32_MAX / INT32_MIN) to them. */
void sta_normal_gather_positions(const sta_record_layout *layout, const uint8_t *records,
                                 size_t count, const int32_t *halo, size_t halo_count,
                                 int32_t (*grid)[3], int32_t lo[3], int32_t hi[3]);

/* Distance in metres from grid point p to the outside of the halo (the chunk's box grown
 * by the margin, clipped to the scene bounds beyond which no point lies). */
double sta_normal_halo_reach(const sta_normals_chunk *chunk, const int32_t p[3]);

/* Orients `normal` (when ok; else the up fallback, counted as degenerate), packs it with
 * the radius into the SPLAT bytes of `record`. */
void sta_normal_store(const sta_normals_chunk *chunk, const sta_record_layout *layout,
                      uint8_t *record, bool ok, double normal[3], double radius,
                      sta_normals_stats *stats);

/* sta_normal_store for the record of grid point p with the scanner's position already
 * looked up (`target`, NULL when unknown). */
void sta_normal_store_at(const sta_normals_chunk *chunk, const sta_record_layout *layout,
                         uint8_t *record, const double p[3], const double *target, bool ok,
                         double normal[3], double radius, sta_normals_stats *stats);
/* The last normal encoded and its octahedral map: the points of one flat box share their
 * normal up to its sign (zero: empty). */
typedef struct sta_normal_memo {
    bool valid;
    float normal[3];
    uint16_t packed[2];
} sta_normal_memo;

/* The same with the radius already a half float (sta_half_from_float): the moments method
 * converts a box's radius once for all its points; and the octahedral map taken from memo
 * (NULL: none) when the normal is the last one's, bit for bit. */
void sta_normal_store_half_at(const sta_normals_chunk *chunk, const sta_record_layout *layout,
                              uint8_t *record, const double p[3], const double *target, bool ok,
                              double normal[3], uint16_t radius_half, sta_normal_memo *memo,
                              sta_normals_stats *stats);

#endif
