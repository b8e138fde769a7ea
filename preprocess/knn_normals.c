/* SPDX-License-Identifier: MIT
 * Per-chunk normals from kNN neighbourhoods (knn_grid.h): covariance, eigenvector,
 * orientation, radius, packed into the records' SPLAT bytes. */
#include "knn_normals.h"

#include <math.h>
#include <string.h>

#include "core/alloc.h"
#include "core/eigen3.h"
#include "core/octahedral.h"
#include "knn_grid.h"

/* l1 <= COLLINEAR * l2: the neighbours lie on a line, no plane to fit. */
#define COLLINEAR    1e-6
/* l1 < LINEAR * l2 (spread across the strip under a tenth of the spread along it): the
 * neighbours are nearly one line (a dense scan line), and noise across it would decide
 * the plane: the neighbourhood is widened. */
#define LINEAR       0.01
/* l0 > THICK * l1: across the fitted plane the neighbours spread more than 0.22 of their
 * narrower spread within it (standard deviations): two surfaces close together (a square
 * 1 cm under another) or range noise of the order of the spacing. The wider fit's
 * in-plane spread outgrows the layer's thickness: widened. On strata-synth planes the
 * p95 error falls from 16.7 to 2.3 degrees; 0.1 still left 7.7. */
#define THICK        0.05
/* Offsets from the query point summed exactly in int64 (fit_normal) stay below 2^FIT_BITS. */
#define FIT_BITS     28
/* |n . v| below this, v the unit direction to the scanner (the trajectory): the fitted
 * plane holds the line of sight (within 10 degrees). No surface is scanned edge-on: this
 * is one profile whose range noise (along the rays) spans the plane; widened. */
#define EDGE_ON      0.17
/* A widened neighbourhood holds this many times K (at most STA_KNN_MAX). On the 20 M
 * street's road (1.5 cm range noise, profiles 5 cm apart) 4 K gave 5.2 degrees median,
 * 6 K 3.8 (4 M street): the wider fit averages the noise over more profiles. */
#define WIDEN_MAX    6
/* |n . up| below this: a vertical surface (a wall), oriented by the trajectory or the
 * scene's up-axis line. */
#define VERTICAL_DOT 0.2

int sta_normals_widest_k(int k)
{
    return WIDEN_MAX * k < STA_NORMALS_MAX_K ? WIDEN_MAX * k : STA_NORMALS_MAX_K;
}

size_t sta_normals_memory_bytes(size_t points)
{
    // + the positions, as floats and integers
    return sta_knn_memory_bytes(points) + points * 3 * (sizeof(float) + sizeof(int32_t));
}

// The rule of docs/CONVERTER.md: up for surfaces that face up or down; a wall faces the
// scanner's position when the trajectory knows it, else away from the scene's up-axis
// line (an object scanned from around it).
static void orient(const sta_normals_chunk *chunk, const double p[3], const double *gps_time,
                   double n[3])
{
    int up = chunk->up_axis == 1 ? 1 : 2;
    double sign = n[up];
    if (fabs(n[up]) < VERTICAL_DOT) {
        double target[3];
        bool seen = chunk->trajectory && gps_time &&
                    sta_trajectory_at(chunk->trajectory, *gps_time, target);
        sign = 0.0;
        for (int a = 0; a < 3; a++) {
            if (seen) {
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

// The plane normal of a neighbourhood around grid point q and the covariance's
// eigenvalues, ascending (zero when none); false when it is degenerate. The sums are of
// integers (offsets from q), exact: the same bits whatever order the set comes in.
static bool fit_normal(const sta_normals_chunk *chunk, const int32_t q[3], const sta_knn *nb,
                       double n[3], double w[3])
{
    int32_t lo[3], hi[3]; // the box of the neighbourhood (loops the compiler vectorises)
    for (int a = 0; a < 3; a++) {
        lo[a] = hi[a] = q[a];
        for (int i = 0; i < nb->size; i++) {
            lo[a] = nb->grid[i][a] < lo[a] ? nb->grid[i][a] : lo[a];
            hi[a] = nb->grid[i][a] > hi[a] ? nb->grid[i][a] : hi[a];
        }
    }
    int64_t span = 0;
    for (int a = 0; a < 3; a++) {
        int64_t below = (int64_t)q[a] - lo[a], above = (int64_t)hi[a] - q[a];
        span = below > span ? below : span;
        span = above > span ? above : span;
    }
    // Offsets under 2^FIT_BITS keep 65 squares inside int64; a wider neighbourhood (a
    // few far outliers) is fitted at a coarser step.
    int shift = 0;
    while ((span >> shift) >= ((int64_t)1 << FIT_BITS)) {
        shift++;
    }
    int64_t s1[3] = { 0, 0, 0 }, s2[6] = { 0, 0, 0, 0, 0, 0 };
    for (int i = 0; i < nb->size; i++) {
        int64_t d[3];
        for (int a = 0; a < 3; a++) {
            d[a] = (int64_t)nb->grid[i][a] - q[a];
            if (shift > 0) { // (rare: a division, not a shift, rounds negatives alike)
                d[a] /= (int64_t)1 << shift;
            }
            s1[a] += d[a];
        }
        s2[0] += d[0] * d[0], s2[1] += d[0] * d[1], s2[2] += d[0] * d[2];
        s2[3] += d[1] * d[1], s2[4] += d[1] * d[2], s2[5] += d[2] * d[2];
    }
    double step[3], cov[9] = { 0 };
    for (int a = 0; a < 3; a++) {
        step[a] = chunk->scale[a] * (double)((int64_t)1 << shift);
    }
    for (int r = 0, t = 0; r < 3; r++) {
        for (int c = r; c < 3; c++, t++) {
            double centred = (double)s2[t] - (double)s1[r] * (double)s1[c] / nb->size;
            cov[3 * r + c] = centred * step[r] * step[c];
        }
    }
    double v[3][3];
    sta_eigen3_path path = sta_eigen3_sym_d(cov, w, v);
    if (path == STA_EIGEN3_ZERO || path == STA_EIGEN3_INVALID || !(w[2] > 0.0) ||
        w[1] <= COLLINEAR * w[2]) {
        return false; // duplicates, one point, a line
    }
    memcpy(n, v[0], sizeof(v[0]));
    return isfinite(n[0]) && isfinite(n[1]) && isfinite(n[2]);
}

// Distance in metres from grid point p to the outside of the halo (the box grown by the
// margin, clipped to the scene bounds beyond which no point lies).
static double halo_reach(const sta_normals_chunk *chunk, const int32_t p[3])
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

// Normal, orientation and radius of record i from its neighbourhood, into its SPLAT bytes.
typedef struct normals_visit {
    const sta_normals_chunk *chunk;
    const sta_record_layout *layout;
    uint8_t *records;
    sta_normals_stats *stats;
} normals_visit;

// Whether a neighbourhood with this fit should be widened (docs/CONVERTER.md "Adaptive
// neighbourhoods"): nearly linear, thick across its plane, or a plane that holds the line
// of sight.
static bool too_narrow(const sta_normals_chunk *chunk, const double p[3], const double *gps_time,
                       bool ok, const double n[3], const double w[3])
{
    if (!ok || w[1] < LINEAR * w[2] || w[0] > THICK * w[1]) {
        return true;
    }
    double target[3];
    if (!chunk->trajectory || !gps_time ||
        !sta_trajectory_at(chunk->trajectory, *gps_time, target)) {
        return false;
    }
    double dot = 0.0, len2 = 0.0;
    for (int a = 0; a < 3; a++) {
        double v = (target[a] - p[a]) * chunk->scale[a];
        dot += n[a] * v;
        len2 += v * v;
    }
    return fabs(dot) < EDGE_ON * sqrt(len2);
}

static int finish_point(void *user, size_t i, const sta_knn *nb)
{
    const normals_visit *v = user;
    const sta_normals_chunk *chunk = v->chunk;
    const sta_record_layout *layout = v->layout;
    uint8_t *records = v->records;
    sta_normals_stats *stats = v->stats;
    double normal[3] = { 0, 0, 0 }, w[3] = { 0, 0, 0 };
    normal[chunk->up_axis == 1 ? 1 : 2] = 1.0; // the fallback: up
    int32_t p[3];
    sta_record_position(records + i * layout->size, p);
    bool ok = nb->size >= 3 && fit_normal(chunk, p, nb, normal, w);
    double pd[3] = { p[0], p[1], p[2] };
    double gps_time;
    bool timed = (layout->attributes & STA_ATTR_GPS_TIME) != 0;
    if (timed) {
        memcpy(&gps_time, records + i * layout->size + layout->gps_offset, sizeof(gps_time));
    }
    int k = nb->capacity - 1;
    int widest =
        WIDEN_MAX * chunk->k < STA_NORMALS_MAX_K ? WIDEN_MAX * chunk->k : STA_NORMALS_MAX_K;
    if (k < widest && nb->size == nb->capacity &&
        too_narrow(chunk, pd, timed ? &gps_time : NULL, ok, normal, w)) {
        return widest;
    }
    if (k > chunk->k) {
        stats->widened++;
    }
    if (ok) {
        orient(chunk, pd, timed ? &gps_time : NULL, normal);
    } else {
        stats->degenerate++;
    }
    // Radius: the mean distance to the nearest STA_NORMALS_RADIUS_K (or K) neighbours,
    // whatever K the normal used, summed nearest first (the same bits in any set order);
    // the nearest is q itself (distance 0).
    float nearest[STA_NORMALS_RADIUS_K + 1];
    int m = 0;
    float farthest = 0.0f;
    for (int j = 0; j < nb->size; j++) { // the STA_NORMALS_RADIUS_K + 1 smallest, sorted
        float d2 = nb->d2[j];
        farthest = fmaxf(farthest, d2);
        if (m == STA_NORMALS_RADIUS_K + 1 && !(d2 < nearest[m - 1])) {
            continue;
        }
        int at = m < STA_NORMALS_RADIUS_K + 1 ? m++ : m - 1;
        while (at > 0 && d2 < nearest[at - 1]) {
            nearest[at] = nearest[at - 1];
            at--;
        }
        nearest[at] = d2;
    }
    double sum = 0.0;
    for (int j = 1; j < m; j++) {
        sum += sqrt((double)nearest[j]);
    }
    double radius = m > 1 ? sum / (m - 1) : 0.0;
    if (nb->size > 0 && sqrt((double)farthest) > halo_reach(chunk, p)) {
        stats->beyond_halo++;
    }
    const float nf[3] = { (float)normal[0], (float)normal[1], (float)normal[2] };
    uint16_t packed[3];
    sta_splat_pack(nf, (float)radius, packed);
    memcpy(records + i * layout->size + layout->splat_offset, packed, sizeof(packed));
    return 0;
}

sta_status sta_normals_compute(const sta_normals_chunk *chunk, const sta_record_layout *layout,
                               uint8_t *records, size_t count, const int32_t *halo,
                               size_t halo_count, sta_normals_stats *stats, sta_error *err)
{
    if (!(layout->attributes & STA_ATTR_SPLAT) || chunk->k < 3 || chunk->k > STA_NORMALS_MAX_K) {
        return sta_fail(err, STA_ERR_ARG, "normals: no SPLAT attribute or K outside 3..%d",
                        STA_NORMALS_MAX_K);
    }
    size_t n = count + halo_count;
    if (count == 0) {
        return STA_OK;
    }
    float(*xyz)[3] = sta_alloc_array(n, sizeof(*xyz));
    int32_t(*grid)[3] = sta_alloc_array(n, sizeof(*grid));
    if (!xyz || !grid) {
        sta_free(xyz);
        sta_free(grid);
        return sta_fail(err, STA_ERR_NOMEM, "normals: out of memory for %zu points", n);
    }
    for (size_t i = 0; i < n; i++) {
        if (i < count) {
            sta_record_position(records + i * layout->size, grid[i]);
        } else {
            memcpy(grid[i], halo + 3 * (i - count), sizeof(grid[i]));
        }
        for (int a = 0; a < 3; a++) {
            // From the scene's corner, not the chunk's: the same floats in every chunking.
            xyz[i][a] = (float)((double)(grid[i][a] - chunk->scene_min[a]) * chunk->scale[a]);
        }
    }
    normals_visit ctx = { chunk, layout, records, stats };
    sta_status status = sta_knn_each((const float(*)[3])xyz, (const int32_t(*)[3])grid, n, count,
                                     chunk->k, finish_point, &ctx, err);
    if (status == STA_OK) {
        stats->points += count;
    }
    sta_free(xyz);
    sta_free(grid);
    return status;
}
