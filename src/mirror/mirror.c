/* SPDX-License-Identifier: MIT
 * Planar mirror geometry (mirror.h). Every computation subtracts the polygon's centre
 * first, so the differences stay small and exact enough far from the origin. */
#include "mirror/mirror.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#define MIN_AREA_M2 1e-6 /* smaller outlines have no usable normal */

static double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void cross3(const double a[3], const double b[3], double out[3])
{
    double x = a[1] * b[2] - a[2] * b[1];
    double y = a[2] * b[0] - a[0] * b[2];
    double z = a[0] * b[1] - a[1] * b[0];
    out[0] = x;
    out[1] = y;
    out[2] = z;
}

static double normalise3(double v[3])
{
    double length = sqrt(dot3(v, v));
    if (length > 0.0) {
        for (int a = 0; a < 3; a++) {
            v[a] /= length;
        }
    }
    return length;
}

sta_status sta_mirror_init(sta_mirror *out, const char *name, const double (*vertices)[3],
                           size_t count, double tolerance_m, sta_error *err)
{
    memset(out, 0, sizeof(*out));
    snprintf(out->name, sizeof(out->name), "%s", name ? name : "");
    if (count < 3) {
        return sta_fail(err, STA_ERR_FORMAT, "%zu vertices, a mirror needs at least 3", count);
    }
    if (count > STA_MIRROR_MAX_VERTICES) {
        return sta_fail(err, STA_ERR_FORMAT, "%zu vertices, at most %d are supported", count,
                        STA_MIRROR_MAX_VERTICES);
    }
    for (size_t i = 0; i < count; i++) {
        for (int a = 0; a < 3; a++) {
            if (!isfinite(vertices[i][a])) {
                return sta_fail(err, STA_ERR_FORMAT, "vertex %zu: coordinate %d is not finite",
                                i + 1, a + 1);
            }
            out->vertices[i][a] = vertices[i][a];
        }
    }
    out->vertex_count = count;
    // Centre: mean of the differences to vertex 0, then added back (exact enough).
    double mean[3] = { 0, 0, 0 };
    for (size_t i = 0; i < count; i++) {
        for (int a = 0; a < 3; a++) {
            mean[a] += vertices[i][a] - vertices[0][a];
        }
    }
    double rel[STA_MIRROR_MAX_VERTICES][3];
    for (int a = 0; a < 3; a++) {
        out->centre[a] = vertices[0][a] + mean[a] / (double)count;
    }
    for (size_t i = 0; i < count; i++) {
        for (int a = 0; a < 3; a++) {
            rel[i][a] = vertices[i][a] - out->centre[a];
        }
    }
    // Newell's normal: twice the vector area, robust for any (even concave) outline.
    double n[3] = { 0, 0, 0 };
    for (size_t i = 0; i < count; i++) {
        const double *p = rel[i], *q = rel[(i + 1) % count];
        n[0] += (p[1] - q[1]) * (p[2] + q[2]);
        n[1] += (p[2] - q[2]) * (p[0] + q[0]);
        n[2] += (p[0] - q[0]) * (p[1] + q[1]);
    }
    double area = 0.5 * normalise3(n);
    if (!(area >= MIN_AREA_M2)) {
        return sta_fail(err, STA_ERR_FORMAT, "degenerate outline (area %.3g m^2)", area);
    }
    memcpy(out->normal, n, sizeof(n));
    size_t worst = 0;
    for (size_t i = 0; i < count; i++) {
        double d = fabs(dot3(rel[i], n));
        if (d > out->max_off_plane_m) {
            out->max_off_plane_m = d;
            worst = i;
        }
    }
    if (out->max_off_plane_m > tolerance_m) {
        return sta_fail(err, STA_ERR_FORMAT,
                        "not planar: vertex %zu is %.4g m off the plane (tolerance %.4g m)",
                        worst + 1, out->max_off_plane_m, tolerance_m);
    }
    // In-plane axes: u along the world axis least aligned with the normal.
    double helper[3] = { 0, 0, 0 };
    int smallest = fabs(n[0]) <= fabs(n[1]) ? (fabs(n[0]) <= fabs(n[2]) ? 0 : 2)
                                            : (fabs(n[1]) <= fabs(n[2]) ? 1 : 2);
    helper[smallest] = 1.0;
    cross3(helper, n, out->axis_u);
    normalise3(out->axis_u);
    cross3(n, out->axis_u, out->axis_v);
    for (size_t i = 0; i < count; i++) {
        out->uv[i][0] = dot3(rel[i], out->axis_u);
        out->uv[i][1] = dot3(rel[i], out->axis_v);
    }
    return STA_OK;
}

double sta_mirror_signed_distance(const sta_mirror *m, const double p[3])
{
    double d[3] = { p[0] - m->centre[0], p[1] - m->centre[1], p[2] - m->centre[2] };
    return dot3(d, m->normal);
}

void sta_mirror_reflect_point(const sta_mirror *m, const double p[3], double out[3])
{
    double s = 2.0 * sta_mirror_signed_distance(m, p);
    for (int a = 0; a < 3; a++) {
        out[a] = p[a] - s * m->normal[a];
    }
}

void sta_mirror_reflect_direction(const sta_mirror *m, const double d[3], double out[3])
{
    double s = 2.0 * dot3(d, m->normal);
    for (int a = 0; a < 3; a++) {
        out[a] = d[a] - s * m->normal[a];
    }
}

void sta_mirror_reflection_matrix(const sta_mirror *m, double out[16])
{
    const double *n = m->normal;
    double offset = dot3(n, m->centre);
    for (int col = 0; col < 3; col++) {
        for (int row = 0; row < 3; row++) {
            out[col * 4 + row] = (row == col ? 1.0 : 0.0) - 2.0 * n[row] * n[col];
        }
        out[col * 4 + 3] = 0.0;
    }
    for (int row = 0; row < 3; row++) {
        out[12 + row] = 2.0 * offset * n[row];
    }
    out[15] = 1.0;
}

void sta_mirror_project(const sta_mirror *m, const double p[3], double out_uv[2])
{
    double d[3] = { p[0] - m->centre[0], p[1] - m->centre[1], p[2] - m->centre[2] };
    out_uv[0] = dot3(d, m->axis_u);
    out_uv[1] = dot3(d, m->axis_v);
}

bool sta_mirror_contains_uv(const sta_mirror *m, const double uv[2])
{
    bool inside = false;
    size_t n = m->vertex_count;
    for (size_t i = 0, j = n - 1; i < n; j = i++) {
        const double *a = m->uv[i], *b = m->uv[j];
        if ((a[1] > uv[1]) != (b[1] > uv[1])) {
            double x = a[0] + (uv[1] - a[1]) * (b[0] - a[0]) / (b[1] - a[1]);
            if (uv[0] < x) {
                inside = !inside;
            }
        }
    }
    return inside;
}

double sta_mirror_distance_uv(const sta_mirror *m, const double uv[2])
{
    if (sta_mirror_contains_uv(m, uv)) {
        return 0.0;
    }
    double best = INFINITY;
    size_t n = m->vertex_count;
    for (size_t i = 0, j = n - 1; i < n; j = i++) {
        const double *a = m->uv[j], *b = m->uv[i];
        double e[2] = { b[0] - a[0], b[1] - a[1] };
        double w[2] = { uv[0] - a[0], uv[1] - a[1] };
        double len2 = e[0] * e[0] + e[1] * e[1];
        double t = len2 > 0.0 ? (w[0] * e[0] + w[1] * e[1]) / len2 : 0.0;
        t = t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
        double dx = w[0] - t * e[0], dy = w[1] - t * e[1];
        double d = sqrt(dx * dx + dy * dy);
        best = d < best ? d : best;
    }
    return best;
}

bool sta_mirror_ray_hit(const sta_mirror *m, const double origin[3], const double dir[3],
                        double t_min, double t_max, double *out_t)
{
    double h = sta_mirror_signed_distance(m, origin);
    double along = dot3(dir, m->normal);
    if (h <= 0.0 || along >= 0.0) {
        return false; // behind the mirror, or moving away from its front
    }
    double t = -h / along;
    if (!(t > t_min && t < t_max)) {
        return false;
    }
    double uv[2],
        d[3] = { origin[0] - m->centre[0], origin[1] - m->centre[1], origin[2] - m->centre[2] };
    uv[0] = dot3(d, m->axis_u) + t * dot3(dir, m->axis_u);
    uv[1] = dot3(d, m->axis_v) + t * dot3(dir, m->axis_v);
    if (!sta_mirror_contains_uv(m, uv)) {
        return false;
    }
    *out_t = t;
    return true;
}

bool sta_mirror_segment_crosses(const sta_mirror *m, const double a[3], const double b[3],
                                double behind_m)
{
    double da = sta_mirror_signed_distance(m, a);
    double db = sta_mirror_signed_distance(m, b);
    if (!(da > 0.0) || !(db < -behind_m)) {
        return false;
    }
    double t = da / (da - db);
    double ua[2], ub[2];
    sta_mirror_project(m, a, ua);
    sta_mirror_project(m, b, ub);
    double uv[2] = { ua[0] + t * (ub[0] - ua[0]), ua[1] + t * (ub[1] - ua[1]) };
    return sta_mirror_contains_uv(m, uv);
}
