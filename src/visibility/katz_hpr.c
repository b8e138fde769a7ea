/* SPDX-License-Identifier: MIT
 * Katz et al.'s HPR operator through Qhull's reentrant library (see katz_hpr.h).
 *
 * Steps: translate so the viewpoint is the origin; set points at the origin aside
 * (visible); sort and merge equal points; optionally perturb (Braga et al.); flip
 * p' = p + 2 (R - |p|) p / |p|; find the dimension of the flipped points plus the
 * origin (3, a plane or a line through the origin); take the hull in that dimension;
 * copy each vertex flag back to every input point it stands for.
 *
 * Based on: Katz, Tal, Basri, "Direct Visibility of Point Sets", 2007, eq. 1 (spherical
 * flipping) and section 3 (visible iff on the convex hull with the viewpoint added);
 * Braga et al., section 4 (random addition of 0.01 of the radius to each coordinate).
 */
#include "visibility/katz_hpr.h"

#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <libqhull_r/libqhull_r.h>

#include "core/alloc.h"
#include "core/clock.h"

// Flipped points whose spread out of a plane (or off a line) through the viewpoint is
// below this fraction of their size are treated as flat; see docs/KATZ.md.
#define FLAT_TOLERANCE    1e-10
#define MAX_RADIUS_FACTOR 1e12
// Qhull squares coordinates of size 2 R; keep them far from overflow.
#define MAX_RADIUS        1e150
#define QHULL_MESSAGE_MAX 200

// Merged facets (Qhull's default 'C-0' premerge) are robust to round-off; vertices are
// the extreme points. 'Pp' keeps precision notes out of the error stream.
static const char OPTIONS_EXACT[] = "qhull Pp";
static const char OPTIONS_JOGGLE[] = "qhull QJ Pp";

typedef struct unique_point {
    double x[3];  // translated to the viewpoint, later perturbed
    size_t index; // first input index with these coordinates
} unique_point;

// Qhull's error stream: a memory stream so failures can be reported, not printed.
typedef struct qhull_log {
    FILE *file;
    char *text; // owned by libc (open_memstream), freed with free()
    size_t size;
} qhull_log;

static int compare_points(const void *a, const void *b)
{
    const unique_point *pa = a;
    const unique_point *pb = b;
    for (int d = 0; d < 3; d++) {
        if (pa->x[d] < pb->x[d]) {
            return -1;
        }
        if (pa->x[d] > pb->x[d]) {
            return 1;
        }
    }
    // Equal coordinates: keep input order so the representative is the first index.
    return (pa->index > pb->index) - (pa->index < pb->index);
}

// Equal as numbers (0.0 equals -0.0, as in compare_points, so equal points are adjacent
// after sorting).
static bool same_point(const double a[3], const double b[3])
{
    return a[0] == b[0] && a[1] == b[1] && a[2] == b[2];
}

static uint64_t splitmix64(uint64_t *state)
{
    uint64_t z = (*state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

// Uniform in [-1, 1).
static double uniform_signed(uint64_t *state)
{
    return (double)(splitmix64(state) >> 11) * (2.0 / 9007199254740992.0) - 1.0;
}

static double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void cross3(const double a[3], const double b[3], double out[3])
{
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

static bool is_finite3(const double p[3])
{
    return isfinite(p[0]) && isfinite(p[1]) && isfinite(p[2]);
}

// Runs Qhull on n points of dimension dim; sets is_vertex[i] for hull vertices. Returns
// Qhull's exit code (qh_ERRnone on success), or qh_ERRmem when the context cannot be
// allocated. Nothing is printed: messages go to log->file.
static int run_qhull(int dim, int n, coordT *coords, const char *options, qhull_log *log,
                     uint8_t *is_vertex, sta_katz_stats *stats)
{
    qhT *qh = sta_malloc(sizeof(*qh));
    if (!qh) {
        return qh_ERRmem;
    }
    char command[32];
    snprintf(command, sizeof(command), "%s", options);
    double start = sta_clock_ms();
    double start_cpu = sta_clock_thread_cpu_ms();
    qh_zero(qh, log->file);
    int exit_code = qh_new_qhull(qh, dim, n, coords, False, command, NULL, log->file);
    if (exit_code == qh_ERRnone) {
        memset(is_vertex, 0, (size_t)n);
        for (vertexT *v = qh->vertex_list; v && v->next; v = v->next) {
            int id = qh_pointid(qh, v->point);
            if (id >= 0 && id < n) {
                is_vertex[id] = 1;
            }
        }
    }
    qh_freeqhull(qh, !qh_ALL);
    int cur_long = 0;
    int total_long = 0;
    qh_memfreeshort(qh, &cur_long, &total_long);
    stats->hull_ms += sta_clock_ms() - start;
    stats->hull_cpu_ms += sta_clock_thread_cpu_ms() - start_cpu;
    sta_free(qh);
    return exit_code;
}

static bool is_precision_error(int exit_code)
{
    return exit_code == qh_ERRprec || exit_code == qh_ERRtopology || exit_code == qh_ERRwide ||
           exit_code == qh_ERRqhull || exit_code == qh_ERRother;
}

// Runs the exact options, then joggle after a precision error. Returns the exit code of
// the last attempt; stats->qhull_options names it.
static int hull_with_fallback(int dim, int n, coordT *coords, qhull_log *log, uint8_t *is_vertex,
                              sta_katz_stats *stats)
{
    int exit_code = run_qhull(dim, n, coords, OPTIONS_EXACT, log, is_vertex, stats);
    snprintf(stats->qhull_options, sizeof(stats->qhull_options), "%s", OPTIONS_EXACT);
    if (is_precision_error(exit_code)) {
        stats->degenerate |= STA_KATZ_JOGGLE;
        exit_code = run_qhull(dim, n, coords, OPTIONS_JOGGLE, log, is_vertex, stats);
        snprintf(stats->qhull_options, sizeof(stats->qhull_options), "%s", OPTIONS_JOGGLE);
    }
    return exit_code;
}

static sta_status qhull_failure(qhull_log *log, int exit_code, int dim, int n, const char *options,
                                sta_error *err)
{
    if (exit_code == qh_ERRmem) {
        return sta_fail(err, STA_ERR_NOMEM, "katz hpr: out of memory in Qhull (%d points, %d-d)", n,
                        dim);
    }
    fflush(log->file);
    // The last line Qhull wrote that starts with "QH" names the error.
    const char *message = "";
    if (log->text) {
        const char *found = log->text;
        for (const char *p = log->text; (p = strstr(p, "QH")) != NULL; p++) {
            found = p;
        }
        message = found;
    }
    size_t length = strcspn(message, "\n");
    if (length > QHULL_MESSAGE_MAX) {
        length = QHULL_MESSAGE_MAX;
    }
    return sta_fail(err, STA_ERR_UNSUPPORTED,
                    "katz hpr: Qhull (\"%s\") failed with exit code %d on %d %d-d points: %.*s",
                    options, exit_code, n, dim, (int)length, message);
}

// 1-d hull of flipped points on a line through the origin (direction `axis`): the
// extreme point on each side of the origin, i.e. the nearest input point on each side.
static void hull_line(const coordT *flipped, size_t count, const double axis[3], uint8_t *visible)
{
    size_t best_pos = SIZE_MAX;
    size_t best_neg = SIZE_MAX;
    double t_pos = 0.0;
    double t_neg = 0.0;
    for (size_t k = 0; k < count; k++) {
        double t = dot3(&flipped[3 * k], axis);
        if (t > t_pos) {
            t_pos = t;
            best_pos = k;
        } else if (t < t_neg) {
            t_neg = t;
            best_neg = k;
        }
    }
    if (best_pos != SIZE_MAX) {
        visible[best_pos] = 1;
    }
    if (best_neg != SIZE_MAX) {
        visible[best_neg] = 1;
    }
}

static sta_status check_params(const sta_katz_params *params, sta_katz_params *out, sta_error *err)
{
    *out = params ? *params : (sta_katz_params){ 0 };
    sta_katz_params_defaults(out);
    if (!(out->radius_factor > 1.0 && out->radius_factor <= MAX_RADIUS_FACTOR)) {
        return sta_fail(err, STA_ERR_ARG,
                        "katz hpr: radius_factor %g is outside (1, %g] (0 for the default %g)",
                        out->radius_factor, MAX_RADIUS_FACTOR, STA_KATZ_DEFAULT_RADIUS_FACTOR);
    }
    if (!(out->radius_m >= 0.0 && out->radius_m <= MAX_RADIUS)) {
        return sta_fail(err, STA_ERR_ARG, "katz hpr: radius_m %g is outside [0, %g]", out->radius_m,
                        MAX_RADIUS);
    }
    if (!(out->perturbation >= 0.0 && out->perturbation <= 1.0)) {
        return sta_fail(err, STA_ERR_ARG, "katz hpr: perturbation %g is outside [0, 1]",
                        out->perturbation);
    }
    return STA_OK;
}

void sta_katz_params_defaults(sta_katz_params *config)
{
    if (config->radius_factor == 0.0) {
        config->radius_factor = STA_KATZ_DEFAULT_RADIUS_FACTOR;
    }
    if (config->seed == 0) {
        config->seed = STA_KATZ_DEFAULT_SEED;
    }
}

// Adds the perturbation to the distinct points; a point that would land on the
// viewpoint keeps its position.
static void perturb(unique_point *pts, size_t count, const sta_katz_params *params,
                    double *out_amplitude)
{
    double lo[3] = { HUGE_VAL, HUGE_VAL, HUGE_VAL };
    double hi[3] = { -HUGE_VAL, -HUGE_VAL, -HUGE_VAL };
    for (size_t k = 0; k < count; k++) {
        for (int d = 0; d < 3; d++) {
            lo[d] = fmin(lo[d], pts[k].x[d]);
            hi[d] = fmax(hi[d], pts[k].x[d]);
        }
    }
    double extent[3] = { hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2] };
    double amplitude = params->perturbation * 0.5 * sqrt(dot3(extent, extent));
    uint64_t state = params->seed;
    for (size_t k = 0; k < count; k++) {
        double moved[3];
        for (int d = 0; d < 3; d++) {
            moved[d] = pts[k].x[d] + amplitude * uniform_signed(&state);
        }
        if (dot3(moved, moved) > 0.0) {
            memcpy(pts[k].x, moved, sizeof(moved));
        }
    }
    *out_amplitude = amplitude;
}

static double max_norm(const unique_point *pts, size_t count)
{
    double result = 0.0;
    for (size_t k = 0; k < count; k++) {
        result = fmax(result, sqrt(dot3(pts[k].x, pts[k].x)));
    }
    return result;
}

// R: the absolute radius when one is given (at least STA_KATZ_MIN_RADIUS_FACTOR times the
// farthest point, so that the sphere holds every point), else radius_factor times it.
static double resolve_radius(const sta_katz_params *params, double far_m)
{
    if (params->radius_m > 0.0) {
        return fmax(params->radius_m, STA_KATZ_MIN_RADIUS_FACTOR * far_m);
    }
    return params->radius_factor * far_m;
}

double sta_katz_view_radius(double depth_tolerance_m, double pixel_angle_rad)
{
    if (!(depth_tolerance_m > 0.0) || !(pixel_angle_rad > 0.0) || !isfinite(depth_tolerance_m)) {
        return 0.0;
    }
    return depth_tolerance_m / (pixel_angle_rad * pixel_angle_rad);
}

// Flips the distinct points into coords (count + 1 rows, the last the origin).
static void flip(const unique_point *pts, size_t count, double radius, coordT *coords,
                 double *out_radius)
{
    for (size_t k = 0; k < count; k++) {
        double norm = sqrt(dot3(pts[k].x, pts[k].x));
        double scale = 2.0 * radius / norm - 1.0; // p + 2 (R - |p|) p / |p|
        for (int d = 0; d < 3; d++) {
            coords[3 * k + (size_t)d] = pts[k].x[d] * scale;
        }
    }
    coords[3 * count] = coords[3 * count + 1] = coords[3 * count + 2] = 0.0;
    *out_radius = radius;
}

// The affine dimension of the flipped points and the origin: 3, 2 (normal in `normal`) or
// 1; `axis` is the unit direction of the farthest flipped point.
static int flat_dimension(const coordT *flipped, size_t count, double axis[3], double normal[3])
{
    size_t far = 0;
    double far_norm = 0.0;
    for (size_t k = 0; k < count; k++) {
        double norm = sqrt(dot3(&flipped[3 * k], &flipped[3 * k]));
        if (norm > far_norm) {
            far_norm = norm;
            far = k;
        }
    }
    for (int d = 0; d < 3; d++) {
        axis[d] = flipped[3 * far + (size_t)d] / far_norm;
    }
    double best = 0.0;
    for (size_t k = 0; k < count; k++) {
        double c[3];
        cross3(axis, &flipped[3 * k], c);
        double length = sqrt(dot3(c, c));
        if (length > best) {
            best = length;
            memcpy(normal, c, sizeof(c));
        }
    }
    if (best <= FLAT_TOLERANCE * far_norm) {
        return 1;
    }
    for (int d = 0; d < 3; d++) {
        normal[d] /= best;
    }
    for (size_t k = 0; k < count; k++) {
        if (fabs(dot3(normal, &flipped[3 * k])) > FLAT_TOLERANCE * far_norm) {
            return 3;
        }
    }
    return 2;
}

// Projects the flipped points (and the origin) into the plane spanned by axis and
// normal x axis, in place: row k becomes 2 coordinates.
static void project_plane(coordT *coords, size_t rows, const double axis[3], const double normal[3])
{
    double second[3];
    cross3(normal, axis, second);
    for (size_t k = 0; k < rows; k++) {
        double p[3] = { coords[3 * k], coords[3 * k + 1], coords[3 * k + 2] };
        coords[2 * k] = dot3(p, axis);
        coords[2 * k + 1] = dot3(p, second);
    }
}

// Takes the hull of the `unique` flipped points plus the origin in coords, in the
// lowest dimension that holds them, and sets visible[k] for the distinct points.
static sta_status hull_visible(coordT *coords, size_t unique, uint8_t *visible,
                               sta_katz_stats *stats, sta_error *err)
{
    sta_status status = STA_OK;
    int rows = (int)unique + 1;
    uint8_t *is_vertex = sta_calloc((size_t)rows, 1);
    qhull_log log = { 0 };
    if (!is_vertex) {
        status = sta_fail(err, STA_ERR_NOMEM, "katz hpr: out of memory for %d hull flags", rows);
        goto out;
    }
    log.file = open_memstream(&log.text, &log.size);
    if (!log.file) {
        status = sta_fail(err, STA_ERR_NOMEM, "katz hpr: cannot open Qhull's message stream");
        goto out;
    }
    double axis[3] = { 0.0, 0.0, 0.0 };
    double normal[3] = { 0.0, 0.0, 0.0 };
    int dim = flat_dimension(coords, unique, axis, normal);
    int exit_code = qh_ERRnone;
    if (dim == 3) {
        exit_code = hull_with_fallback(3, rows, coords, &log, is_vertex, stats);
        if (exit_code == qh_ERRsingular) {
            dim = 2; // flat to Qhull's tolerance, not to ours
        }
    }
    if (dim == 2) {
        stats->degenerate |= STA_KATZ_PLANE;
        project_plane(coords, (size_t)rows, axis, normal);
        exit_code = hull_with_fallback(2, rows, coords, &log, is_vertex, stats);
        if (exit_code == qh_ERRsingular) {
            // Collinear to Qhull's tolerance: the line runs along `axis`, so the first 2-d
            // coordinate is the position on it; lay rows out as 3-d for hull_line.
            for (int k = rows - 1; k >= 0; k--) {
                coords[3 * k] = coords[2 * k];
                coords[3 * k + 1] = 0.0;
                coords[3 * k + 2] = 0.0;
            }
            double unit_x[3] = { 1.0, 0.0, 0.0 };
            memcpy(axis, unit_x, sizeof(unit_x));
            dim = 1;
        }
    }
    if (dim == 1) {
        stats->degenerate |= STA_KATZ_LINE;
        stats->qhull_options[0] = '\0';
        memset(is_vertex, 0, (size_t)rows);
        hull_line(coords, unique, axis, is_vertex);
        exit_code = qh_ERRnone;
    }
    if (exit_code != qh_ERRnone) {
        status = qhull_failure(&log, exit_code, dim, rows, stats->qhull_options, err);
        goto out;
    }
    stats->hull_dim = dim;
    for (size_t k = 0; k < unique; k++) {
        visible[k] = is_vertex[k];
        stats->hull_vertex_count += is_vertex[k];
    }
out:
    if (log.file) {
        fclose(log.file);
    }
    free(log.text); // allocated by open_memstream
    sta_free(is_vertex);
    return status;
}

static sta_status compute(const double (*points)[3], size_t count, const double viewpoint[3],
                          const sta_katz_params *params, uint8_t *out_visible,
                          sta_katz_stats *stats, sta_error *err)
{
    sta_status status = STA_OK;
    unique_point *pts = sta_alloc_array(count, sizeof(*pts));
    size_t *slot = sta_alloc_array(count, sizeof(*slot)); // distinct index, SIZE_MAX: at C
    uint8_t *visible = NULL;
    coordT *coords = NULL;
    if (!pts || !slot) {
        status = sta_fail(err, STA_ERR_NOMEM, "katz hpr: out of memory for %zu points", count);
        goto out;
    }
    size_t kept = 0;
    for (size_t i = 0; i < count; i++) {
        if (!is_finite3(points[i])) {
            status = sta_fail(err, STA_ERR_ARG, "katz hpr: point %zu is (%g, %g, %g), not finite",
                              i, points[i][0], points[i][1], points[i][2]);
            goto out;
        }
        double q[3] = { points[i][0] - viewpoint[0], points[i][1] - viewpoint[1],
                        points[i][2] - viewpoint[2] };
        if (!is_finite3(q) || !isfinite(dot3(q, q))) {
            status = sta_fail(err, STA_ERR_ARG,
                              "katz hpr: point %zu (%g, %g, %g) is too far from the viewpoint "
                              "(%g, %g, %g) for double precision",
                              i, points[i][0], points[i][1], points[i][2], viewpoint[0],
                              viewpoint[1], viewpoint[2]);
            goto out;
        }
        if (dot3(q, q) == 0.0) {
            slot[i] = SIZE_MAX; // at the viewpoint (or its square underflows)
            stats->at_viewpoint_count++;
            continue;
        }
        memcpy(pts[kept].x, q, sizeof(q));
        pts[kept].index = i;
        kept++;
    }
    if (stats->at_viewpoint_count > 0) {
        stats->degenerate |= STA_KATZ_AT_VIEWPOINT;
    }
    qsort(pts, kept, sizeof(*pts), compare_points);
    size_t unique = 0;
    for (size_t k = 0; k < kept; k++) {
        if (unique > 0 && same_point(pts[k].x, pts[unique - 1].x)) {
            slot[pts[k].index] = unique - 1;
            stats->duplicate_count++;
            continue;
        }
        pts[unique] = pts[k];
        slot[pts[unique].index] = unique;
        unique++;
    }
    if (stats->duplicate_count > 0) {
        stats->degenerate |= STA_KATZ_DUPLICATES;
    }
    if (unique > (size_t)INT_MAX - 1) {
        status =
            sta_fail(err, STA_ERR_ARG, "katz hpr: %zu distinct points exceed Qhull's limit of %d",
                     unique, INT_MAX - 1);
        goto out;
    }
    stats->hull_input_count = unique;
    visible = sta_calloc(unique ? unique : 1, 1);
    if (!visible) {
        status = sta_fail(err, STA_ERR_NOMEM, "katz hpr: out of memory for %zu flags", unique);
        goto out;
    }
    if (unique < 4) {
        stats->degenerate |= unique > 0 ? STA_KATZ_FEW_POINTS : 0u;
        memset(visible, 1, unique);
        stats->hull_vertex_count = unique;
    } else {
        coords = sta_alloc_array((unique + 1) * 3, sizeof(*coords));
        if (!coords) {
            status = sta_fail(err, STA_ERR_NOMEM, "katz hpr: out of memory for %zu flipped points",
                              unique);
            goto out;
        }
        double radius = resolve_radius(params, max_norm(pts, unique));
        if (radius > MAX_RADIUS) {
            status = sta_fail(err, STA_ERR_ARG,
                              "katz hpr: sphere radius %g (radius_m %g, radius_factor %g times the "
                              "largest distance to the viewpoint) exceeds %g",
                              radius, params->radius_m, params->radius_factor, MAX_RADIUS);
            goto out;
        }
        if (params->perturbation > 0.0) {
            perturb(pts, unique, params, &stats->perturbation_abs);
            // The sphere must still hold every (moved) point.
            radius = fmax(radius, STA_KATZ_MIN_RADIUS_FACTOR * max_norm(pts, unique));
        }
        flip(pts, unique, radius, coords, &stats->radius);
        status = hull_visible(coords, unique, visible, stats, err);
        if (status != STA_OK) {
            goto out;
        }
    }
    for (size_t i = 0; i < count; i++) {
        out_visible[i] = slot[i] == SIZE_MAX ? 1 : visible[slot[i]];
        stats->visible_count += out_visible[i];
    }
out:
    sta_free(coords);
    sta_free(visible);
    sta_free(slot);
    sta_free(pts);
    return status;
}

sta_status sta_katz_visible(const double (*points)[3], size_t count, const double viewpoint[3],
                            const sta_katz_params *params, uint8_t *out_visible,
                            sta_katz_stats *out_stats, sta_error *err)
{
    double start = sta_clock_ms();
    sta_katz_stats stats = { 0 };
    sta_katz_params resolved;
    if (!viewpoint || (count > 0 && (!points || !out_visible))) {
        return sta_fail(err, STA_ERR_ARG, "katz hpr: %s is NULL",
                        !viewpoint ? "viewpoint" : (!points ? "points" : "out_visible"));
    }
    if (!is_finite3(viewpoint)) {
        return sta_fail(err, STA_ERR_ARG, "katz hpr: viewpoint (%g, %g, %g) is not finite",
                        viewpoint[0], viewpoint[1], viewpoint[2]);
    }
    sta_status status = check_params(params, &resolved, err);
    if (status != STA_OK) {
        return status;
    }
    if (count > 0) {
        status = compute(points, count, viewpoint, &resolved, out_visible, &stats, err);
    }
    stats.total_ms = sta_clock_ms() - start;
    if (status == STA_OK && out_stats) {
        *out_stats = stats;
    }
    return status;
}
