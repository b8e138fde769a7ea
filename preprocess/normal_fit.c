/* SPDX-License-Identifier: MIT
 * Plane fit from moments, fit tests, orientation and packing shared by both normals
 * methods. */
#include "normal_fit.h"

#include <math.h>
#include <string.h>

#include "core/eigen3.h"
#include "core/octahedral.h"

// The rule of docs/CONVERTER.md: up for surfaces that face up or down; a wall faces the
// scanner's position when the trajectory knows it, else away from the scene's up-axis
// line (an object scanned from around it).
void sta_normal_orient_at(const sta_normals_chunk *chunk, const double p[3], const double *target,
                          double n[3])
{
    int up = chunk->up_axis == 1 ? 1 : 2;
    double sign = n[up];
    if (fabs(n[up]) < STA_NORMALS_VERTICAL_DOT) {
        sign = 0.0;
        for (int a = 0; a < 3; a++) {
            if (target) {
                sign += n[a] * (target[a] - p[a]) * chunk->scale[a];
            } else if (a != up) {
                sign += n[a] * (p[a] - chunk->scene_centre[a]) * chunk->scale[a];
            }
        }
    }
    if (sign < 0.0) {
        for (int a = 0; a < 3; a++) {
            n[a] = -n[a];
        }
    }
}

void sta_normal_orient(const sta_normals_chunk *chunk, const double p[3], const double *gps_time,
                       double n[3])
{
    int up = chunk->up_axis == 1 ? 1 : 2;
    double target[3];
    bool seen = fabs(n[up]) < STA_NORMALS_VERTICAL_DOT && chunk->trajectory && gps_time &&
                sta_trajectory_at(chunk->trajectory, *gps_time, target);
    sta_normal_orient_at(chunk, p, seen ? target : NULL, n);
}

// The plane normal of a set of points from its moments (n, sum of offsets from some
// corner, sum of their products, in grid units x 2^shift; weighted sums are welcome) and
// the covariance's eigenvalues, ascending (zero when none); false when it is degenerate
// (duplicates, one point, a line).
bool sta_normal_fit_moments(const sta_normals_chunk *chunk, double count, const double s1[3],
                            const double s2[6], int shift, double n[3], double w[3])
{
    double step[3], cov[9] = { 0 };
    for (int a = 0; a < 3; a++) {
        step[a] = chunk->scale[a] * (double)((int64_t)1 << shift);
    }
    for (int r = 0, t = 0; r < 3; r++) {
        for (int c = r; c < 3; c++, t++) {
            double centred = s2[t] - s1[r] * s1[c] / count;
            cov[3 * r + c] = centred * step[r] * step[c];
        }
    }
    double v[3][3];
    sta_eigen3_path path = sta_eigen3_sym_d(cov, w, v);
    if (path == STA_EIGEN3_ZERO || path == STA_EIGEN3_INVALID || !(w[2] > 0.0) ||
        w[1] <= STA_NORMALS_COLLINEAR * w[2]) {
        return false;
    }
    memcpy(n, v[0], sizeof(v[0]));
    return isfinite(n[0]) && isfinite(n[1]) && isfinite(n[2]);
}

// Distance in metres from grid point p to the outside of the halo (the box grown by the
// margin, clipped to the scene bounds beyond which no point lies).
double sta_normal_halo_reach(const sta_normals_chunk *chunk, const int32_t p[3])
{
    double reach = INFINITY;
    for (int a = 0; a < 3; a++) {
        double lo = (double)(p[a] - chunk->box_min[a]) * chunk->scale[a] + chunk->margin;
        double hi = (double)(chunk->box_max[a] - p[a]) * chunk->scale[a] + chunk->margin;
        if (chunk->box_min[a] > chunk->scene_min[a]) {
            reach = fmin(reach, lo);
        }
        if (chunk->box_max[a] <= chunk->scene_max[a]) {
            reach = fmin(reach, hi);
        }
    }
    return reach;
}

// Whether a neighbourhood with this fit should be widened (docs/CONVERTER.md "Adaptive
// neighbourhoods"): nearly linear, thick across its plane, or a plane that holds the line
// of sight. `thick`: whether thickness counts (not for the blocks' escalation: a wider
// block would reach the next layer sooner than average the noise).
bool sta_normal_too_narrow_at(const sta_normals_chunk *chunk, const double p[3],
                              const double *target, bool ok, const double n[3], const double w[3],
                              bool thick)
{
    if (!ok || w[1] < STA_NORMALS_LINEAR * w[2] || (thick && w[0] > STA_NORMALS_THICK * w[1])) {
        return true;
    }
    if (!target) {
        return false;
    }
    double dot = 0.0, len2 = 0.0;
    for (int a = 0; a < 3; a++) {
        double v = (target[a] - p[a]) * chunk->scale[a];
        dot += n[a] * v;
        len2 += v * v;
    }
    return fabs(dot) < STA_NORMALS_EDGE_ON * sqrt(len2);
}

bool sta_normal_too_narrow(const sta_normals_chunk *chunk, const double p[3],
                           const double *gps_time, bool ok, const double n[3], const double w[3],
                           bool thick)
{
    double target[3];
    bool seen =
        chunk->trajectory && gps_time && sta_trajectory_at(chunk->trajectory, *gps_time, target);
    return sta_normal_too_narrow_at(chunk, p, seen ? target : NULL, ok, n, w, thick);
}

// Packs the (oriented) normal, or the up fallback, with the radius as a half float
// (sta_half_from_float) into the SPLAT bytes: sta_splat_pack's bytes.
static void pack_splat_half(const sta_normals_chunk *chunk, const sta_record_layout *layout,
                            uint8_t *record, bool ok, double normal[3], uint16_t radius_half,
                            sta_normal_memo *memo, sta_normals_stats *stats)
{
    if (!ok) {
        stats->degenerate++;
        normal[0] = normal[1] = normal[2] = 0.0;
        normal[chunk->up_axis == 1 ? 1 : 2] = 1.0; // the fallback: up
    }
    const float nf[3] = { (float)normal[0], (float)normal[1], (float)normal[2] };
    uint16_t packed[3];
    if (memo && memo->valid && memcmp(nf, memo->normal, sizeof(nf)) == 0) {
        memcpy(packed, memo->packed, sizeof(memo->packed));
    } else {
        sta_octahedral_encode(nf, packed);
        if (memo) {
            memcpy(memo->normal, nf, sizeof(nf));
            memcpy(memo->packed, packed, sizeof(memo->packed));
            memo->valid = true;
        }
    }
    packed[2] = radius_half;
    memcpy(record + layout->splat_offset, packed, sizeof(packed));
}

static void pack_splat(const sta_normals_chunk *chunk, const sta_record_layout *layout,
                       uint8_t *record, bool ok, double normal[3], double radius,
                       sta_normals_stats *stats)
{
    pack_splat_half(chunk, layout, record, ok, normal, sta_half_from_float((float)radius), NULL,
                    stats);
}

void sta_normal_store(const sta_normals_chunk *chunk, const sta_record_layout *layout,
                      uint8_t *record, bool ok, double normal[3], double radius,
                      sta_normals_stats *stats)
{
    if (ok) {
        int32_t p[3];
        sta_record_position(record, p);
        double pd[3] = { p[0], p[1], p[2] };
        double gps_time;
        bool timed = (layout->attributes & STA_ATTR_GPS_TIME) != 0;
        if (timed) {
            memcpy(&gps_time, record + layout->gps_offset, sizeof(gps_time));
        }
        sta_normal_orient(chunk, pd, timed ? &gps_time : NULL, normal);
    }
    pack_splat(chunk, layout, record, ok, normal, radius, stats);
}

void sta_normal_store_at(const sta_normals_chunk *chunk, const sta_record_layout *layout,
                         uint8_t *record, const double p[3], const double *target, bool ok,
                         double normal[3], double radius, sta_normals_stats *stats)
{
    if (ok) {
        sta_normal_orient_at(chunk, p, target, normal);
    }
    pack_splat(chunk, layout, record, ok, normal, radius, stats);
}

void sta_normal_store_half_at(const sta_normals_chunk *chunk, const sta_record_layout *layout,
                              uint8_t *record, const double p[3], const double *target, bool ok,
                              double normal[3], uint16_t radius_half, sta_normal_memo *memo,
                              sta_normals_stats *stats)
{
    if (ok) {
        sta_normal_orient_at(chunk, p, target, normal);
    }
    pack_splat_half(chunk, layout, record, ok, normal, radius_half, memo, stats);
}

void sta_normal_gather_positions(const sta_record_layout *layout, const uint8_t *records,
                                 size_t count, const int32_t *halo, size_t halo_count,
                                 int32_t (*grid)[3], int32_t lo[3], int32_t hi[3])
{
    for (size_t i = 0; i < count + halo_count; i++) {
        if (i < count) {
            sta_record_position(records + i * layout->size, grid[i]);
        } else {
            memcpy(grid[i], halo + 3 * (i - count), sizeof(grid[i]));
        }
        for (int a = 0; a < 3; a++) {
            lo[a] = grid[i][a] < lo[a] ? grid[i][a] : lo[a];
            hi[a] = grid[i][a] > hi[a] ? grid[i][a] : hi[a];
        }
    }
}
