/* SPDX-License-Identifier: MIT
 * Default views from a sample of the scene's points. */
#include "core/camera_frame.h"

#include <math.h>
#include <stdlib.h>

#include "core/alloc.h"

double sta_camera_points_long_yaw(const sta_camera *c, const double *p, size_t n,
                                  double *out_elongation)
{
    if (out_elongation) {
        *out_elongation = 1.0;
    }
    if (n < 2) {
        return 0.0;
    }
    // 2x2 covariance of the horizontal (frame x, y) coordinates.
    double mean[2] = { 0.0, 0.0 };
    for (size_t i = 0; i < n; i++) {
        double f[3];
        sta_camera_to_frame(c, p + 3 * i, f);
        mean[0] += f[0];
        mean[1] += f[1];
    }
    mean[0] /= (double)n;
    mean[1] /= (double)n;
    double sxx = 0.0, syy = 0.0, sxy = 0.0;
    for (size_t i = 0; i < n; i++) {
        double f[3];
        sta_camera_to_frame(c, p + 3 * i, f);
        double x = f[0] - mean[0], y = f[1] - mean[1];
        sxx += x * x;
        syy += y * y;
        sxy += x * y;
    }
    // Eigenvalues of [[sxx, sxy], [sxy, syy]]; the major axis is at
    // 0.5 atan2(2 sxy, sxx - syy).
    double half_trace = 0.5 * (sxx + syy);
    double root = sqrt(0.25 * (sxx - syy) * (sxx - syy) + sxy * sxy);
    double major = half_trace + root, minor = half_trace - root;
    if (out_elongation && major > 0.0) {
        *out_elongation = minor > major * 1e-12 ? fmin(sqrt(major / minor), 1e6) : 1e6;
    }
    return 0.5 * atan2(2.0 * sxy, sxx - syy);
}

static int compare_doubles(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

// The distance from `centre` along -f at which, for each edge of the view, the k-th
// smallest requirement (a `k` of n points inside it) is met, and then every requirement
// beyond it up to the first jump of more than `stray_gap` times the k-th distance; cut[side]: how
// many points the edge leaves out (sides +r, -r, +u, -u); need: 4 n doubles scratch.
static double fit_distance(const double *p, size_t n, size_t k, const double centre[3],
                           const double f[3], const double r[3], const double u[3], double tan_x,
                           double tan_y, double stray_gap, double *need, size_t cut[4])
{
    // Point i is inside the right edge of the view from distance D along -f when
    // x <= tan_x (D + z), i.e. D >= x / tan_x - z; likewise the other three edges.
    double base = 0.0;
    for (int side = 0; side < 4; side++) {
        const double *axis = side < 2 ? r : u;
        double sign = side % 2 ? -1.0 : 1.0, t = side < 2 ? tan_x : tan_y;
        double *side_need = need + (size_t)side * n;
        for (size_t i = 0; i < n; i++) {
            const double *q = p + 3 * i;
            double d[3] = { q[0] - centre[0], q[1] - centre[1], q[2] - centre[2] };
            double s = sign * (d[0] * axis[0] + d[1] * axis[1] + d[2] * axis[2]);
            double z = d[0] * f[0] + d[1] * f[1] + d[2] * f[2];
            side_need[i] = s / t - z;
        }
        qsort(side_need, n, sizeof(double), compare_doubles);
        base = fmax(base, side_need[k - 1]);
    }
    double gap = stray_gap * base, distance = base;
    for (int side = 0; side < 4; side++) {
        const double *side_need = need + (size_t)side * n;
        size_t last = k - 1;
        while (gap > 0.0 && last + 1 < n && side_need[last + 1] - side_need[last] <= gap) {
            last++;
        }
        cut[side] = n - 1 - last;
        distance = fmax(distance, side_need[last]);
    }
    return distance;
}

// Moves `centre` across the view so that the points' screen extent seen from `distance`,
// less the points each edge cuts (cut[side], sides as fit_distance's), is centred.
static void centre_extent(const double *p, size_t n, const size_t cut[4], double centre[3],
                          double distance, const double f[3], const double r[3], const double u[3],
                          double tan_x, double tan_y, double *need)
{
    double shift[2];
    for (int axis_index = 0; axis_index < 2; axis_index++) {
        const double *axis = axis_index == 0 ? r : u;
        double t = axis_index == 0 ? tan_x : tan_y;
        size_t m = 0;
        for (size_t i = 0; i < n; i++) {
            const double *q = p + 3 * i;
            double d[3] = { q[0] - centre[0], q[1] - centre[1], q[2] - centre[2] };
            double s = d[0] * axis[0] + d[1] * axis[1] + d[2] * axis[2];
            double depth = distance + d[0] * f[0] + d[1] * f[1] + d[2] * f[2];
            if (depth > 0.0) {
                need[m++] = s / (depth * t);
            }
        }
        if (m == 0) {
            return;
        }
        qsort(need, m, sizeof(double), compare_doubles);
        // The low end is the -r (-u) edge's, the high end the +r (+u) edge's.
        size_t cut_low = cut[2 * axis_index + 1], cut_high = cut[2 * axis_index];
        cut_low = cut_low < m ? cut_low : m - 1;
        cut_high = cut_high < m ? cut_high : m - 1;
        shift[axis_index] = 0.5 * (need[cut_low] + need[m - 1 - cut_high]) * distance * t;
    }
    for (int a = 0; a < 3; a++) {
        centre[a] += r[a] * shift[0] + u[a] * shift[1];
    }
}

void sta_camera_frame_points(sta_camera *c, const double centre_in[3], const double *p, size_t n,
                             const sta_camera_frame_rule *rule)
{
    double f[3], r[3], u[3];
    sta_camera_basis(c, f, r, u);
    int width = c->width_px > 0 ? c->width_px : 1, height = c->height_px > 0 ? c->height_px : 1;
    double tan_y = tan(c->fov_y * 0.5), tan_x = tan_y * (double)width / (double)height;
    double centre[3] = { centre_in[0], centre_in[1], centre_in[2] };
    double distance = 1.0;
    double *need = n ? sta_alloc_array(n, 4 * sizeof(double)) : NULL;
    if (need) {
        // Each edge is placed so that a `keep` share of the points lies on its inner
        // side (the outliers cut are those beyond that edge); then the view is moved
        // across to centre what it frames, and fitted again.
        double share = rule->keep > 0.0 && rule->keep <= 1.0 ? rule->keep : 1.0;
        size_t k = (size_t)ceil(share * (double)n);
        k = k > 0 ? k : 1;
        size_t cut[4];
        for (int round = 0; round < STA_CAMERA_FRAME_ROUNDS; round++) {
            distance =
                fit_distance(p, n, k, centre, f, r, u, tan_x, tan_y, rule->stray_gap, need, cut);
            if (round + 1 < STA_CAMERA_FRAME_ROUNDS) {
                centre_extent(p, n, cut, centre, distance, f, r, u, tan_x, tan_y, need);
            }
        }
        distance *= 1.05; // a small margin
        if (rule->margin_px > 0.0) {
            // The same fit in a view narrowed by the margin on every side, if that stands
            // farther back; at most a quarter of the view per side (a thumbnail smaller
            // than the band would show a speck).
            double keep_x = fmax(0.5, 1.0 - 2.0 * rule->margin_px / (double)width);
            double keep_y = fmax(0.5, 1.0 - 2.0 * rule->margin_px / (double)height);
            distance = fmax(distance, fit_distance(p, n, k, centre, f, r, u, tan_x * keep_x,
                                                   tan_y * keep_y, rule->stray_gap, need, cut));
        }
        sta_free(need);
    }
    if (!(distance > 1e-3) || !isfinite(distance)) {
        distance = 1e-3;
    }
    for (int a = 0; a < 3; a++) {
        c->position[a] = centre[a] - f[a] * distance;
    }
    c->near_m = fmax(1e-3, distance * 1e-3);
}
