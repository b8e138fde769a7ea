/* SPDX-License-Identifier: MIT
 * Analytic scenes: sphere, stacked planes, sphere nested in a box, PLY mesh. Their
 * geometry, exact ray casts, and uniform-by-area sampling.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "core/alloc.h"
#include "synth/synth_internal.h"

#define PI 3.14159265358979323846

static void rect_set(synth_rect *r, const double corner[3], const double a[3], const double b[3])
{
    memcpy(r->corner, corner, sizeof(r->corner));
    memcpy(r->edge_a, a, sizeof(r->edge_a));
    memcpy(r->edge_b, b, sizeof(r->edge_b));
    double n[3] = { a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                    a[0] * b[1] - a[1] * b[0] };
    double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    for (int k = 0; k < 3; k++) {
        r->normal[k] = n[k] / len;
    }
    r->area_m2 = len;
}

/* Five 10 m squares facing +z, each 2 m further along x and deeper by 1 cm, 10 cm,
 * 1 m and 10 m than the one above, so a 2 m strip of each lower plane shows from
 * straight above. */
static void init_planes(synth_analytic *an)
{
    static const double depth[5] = { 0.0, -0.01, -0.11, -1.11, -11.11 };
    for (int i = 0; i < 5; i++) {
        double corner[3] = { -5.0 + 2.0 * i, -5.0, depth[i] };
        double a[3] = { 10.0, 0.0, 0.0 }, b[3] = { 0.0, 10.0, 0.0 };
        rect_set(&an->rects[i], corner, a, b);
    }
    an->rect_count = 5;
}

/* The closed box [-5, 5]^3 with outward normals: faces -x, +x, -y, +y, -z, +z. */
static void init_box(synth_analytic *an)
{
    const double h = 5.0, e = 10.0;
    const double ex[3] = { e, 0, 0 }, ey[3] = { 0, e, 0 }, ez[3] = { 0, 0, e };
    const double lo[3] = { -h, -h, -h };
    rect_set(&an->rects[0], lo, ez, ey);                             // -x
    rect_set(&an->rects[1], (const double[3]){ h, -h, -h }, ey, ez); // +x
    rect_set(&an->rects[2], lo, ex, ez);                             // -y
    rect_set(&an->rects[3], (const double[3]){ -h, h, -h }, ez, ex); // +y
    rect_set(&an->rects[4], lo, ey, ex);                             // -z
    rect_set(&an->rects[5], (const double[3]){ -h, -h, h }, ex, ey); // +z
    an->rect_count = 6;
}

/* Splits n points over primitives by area (largest remainder, ties to the lower id). */
static void split_counts(synth_analytic *an, uint64_t n)
{
    double areas[SYNTH_MAX_RECTS + 1];
    int count = an->rect_count;
    for (int i = 0; i < count; i++) {
        areas[i] = an->rects[i].area_m2;
    }
    if (an->has_sphere) {
        areas[count++] = 4.0 * PI * an->sphere_radius_m * an->sphere_radius_m;
    }
    double total = 0.0;
    for (int i = 0; i < count; i++) {
        total += areas[i];
    }
    uint64_t given = 0;
    double rest[SYNTH_MAX_RECTS + 1];
    for (int i = 0; i < count; i++) {
        double exact = (double)n * areas[i] / total;
        an->counts[i] = (uint64_t)floor(exact);
        rest[i] = exact - floor(exact);
        given += an->counts[i];
    }
    while (given < n) {
        int pick = 0;
        for (int i = 1; i < count; i++) {
            if (rest[i] > rest[pick]) {
                pick = i;
            }
        }
        an->counts[pick]++;
        rest[pick] = -1.0;
        given++;
    }
}

// The bounding box of a mesh's vertices (empty: lo +inf, hi -inf).
static void mesh_bounds(const sta_mesh *m, double lo[3], double hi[3])
{
    for (int a = 0; a < 3; a++) {
        lo[a] = INFINITY;
        hi[a] = -INFINITY;
    }
    for (size_t i = 0; i < m->vertex_count; i++) {
        for (int a = 0; a < 3; a++) {
            lo[a] = fmin(lo[a], m->positions[3 * i + (size_t)a]);
            hi[a] = fmax(hi[a], m->positions[3 * i + (size_t)a]);
        }
    }
}

// Whether a mesh with these extents is turned from y up to z up (`requested`, or the
// model rule for STA_SYNTH_MESH_UP_AUTO); `why` as sta_synth_mesh_up_axis.
static bool mesh_y_up(sta_synth_mesh_up requested, const double lo[3], const double hi[3],
                      char *why, size_t why_size)
{
    const double extent[3] = { hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2] };
    if (requested == STA_SYNTH_MESH_UP_AUTO) {
        return sta_model_is_y_up(extent[0], extent[1], extent[2], "mesh", why, why_size);
    }
    if (why && why_size > 0) {
        snprintf(why, why_size, "mesh: %s up, as asked",
                 requested == STA_SYNTH_MESH_UP_Y ? "+Y" : "+Z");
    }
    return requested == STA_SYNTH_MESH_UP_Y;
}

static sta_status init_mesh(synth_analytic *an, const char *path, sta_synth_mesh_up mesh_up,
                            sta_error *err)
{
    sta_status status = sta_mesh_load(path, &an->mesh, err);
    if (status != STA_OK) {
        return status;
    }
    sta_mesh *m = &an->mesh;
    if (m->triangle_count == 0 || m->vertex_count == 0) {
        return sta_fail(err, STA_ERR_FORMAT, "%s: mesh has no triangles to sample", path);
    }
    double lo[3], hi[3];
    mesh_bounds(m, lo, hi);
    double extent = fmax(hi[0] - lo[0], fmax(hi[1] - lo[1], hi[2] - lo[2]));
    if (!(extent > 0.0)) {
        return sta_fail(err, STA_ERR_FORMAT, "%s: mesh has zero extent", path);
    }
    an->mesh_scale = 10.0 / extent;
    for (int a = 0; a < 3; a++) {
        an->mesh_centre[a] = 0.5 * (lo[a] + hi[a]);
    }
    an->mesh_y_up = mesh_y_up(mesh_up, lo, hi, an->mesh_up_why, sizeof(an->mesh_up_why));
    for (size_t i = 0; i < m->vertex_count; i++) {
        double *x = &m->positions[3 * i];
        for (int a = 0; a < 3; a++) {
            x[a] = (x[a] - an->mesh_centre[a]) * an->mesh_scale;
        }
        if (an->mesh_y_up) { // LAS is z up: a y-up model would lie on its side
            double y = x[1];
            x[1] = -x[2];
            x[2] = y;
        }
    }
    an->area_cdf = sta_alloc_array(m->triangle_count, sizeof(double));
    if (!an->area_cdf) {
        return sta_fail(err, STA_ERR_NOMEM, "%s: out of memory for %zu triangle areas", path,
                        m->triangle_count);
    }
    double total = 0.0;
    for (size_t t = 0; t < m->triangle_count; t++) {
        const double *p[3];
        for (int k = 0; k < 3; k++) {
            p[k] = m->positions + 3 * (size_t)m->triangles[3 * t + (size_t)k];
        }
        double e1[3], e2[3];
        for (int a = 0; a < 3; a++) {
            e1[a] = p[1][a] - p[0][a];
            e2[a] = p[2][a] - p[0][a];
        }
        double c[3] = { e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                        e1[0] * e2[1] - e1[1] * e2[0] };
        total += 0.5 * sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
        an->area_cdf[t] = total;
    }
    if (!(total > 0.0)) {
        return sta_fail(err, STA_ERR_FORMAT, "%s: mesh triangles have no area", path);
    }
    an->mesh_area_m2 = total;
    return sta_bvh_build(&an->bvh, m->positions, m->triangles, m->triangle_count, err);
}

sta_status sta_synth_analytic_init(sta_synth_scene *scene, sta_error *err)
{
    synth_analytic *an = &scene->analytic;
    switch (scene->params.kind) {
    case STA_SYNTH_SPHERE:
        an->has_sphere = true;
        an->sphere_radius_m = 10.0;
        an->sphere_id = 0;
        break;
    case STA_SYNTH_PLANES:
        init_planes(an);
        break;
    case STA_SYNTH_NESTED:
        init_box(an);
        an->has_sphere = true;
        an->sphere_radius_m = 3.0;
        an->sphere_id = 6;
        break;
    case STA_SYNTH_MESH:
        return init_mesh(an, scene->params.mesh_path, scene->params.mesh_up, err);
    case STA_SYNTH_STREET:
    case STA_SYNTH_MIRROR:
        return sta_fail(err, STA_ERR_ARG, "scene kind %d is not analytic", (int)scene->params.kind);
    }
    split_counts(an, scene->params.point_count);
    return STA_OK;
}

void sta_synth_analytic_release(synth_analytic *an)
{
    sta_bvh_release(&an->bvh);
    sta_mesh_release(&an->mesh);
    sta_free(an->area_cdf);
    memset(an, 0, sizeof(*an));
}

static double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

bool sta_synth_analytic_raycast(const synth_analytic *an, const double o[3], const double d[3],
                                double min_t, double max_t, sta_synth_hit *hit)
{
    bool found = false;
    double best = max_t;
    for (int i = 0; i < an->rect_count; i++) {
        const synth_rect *r = &an->rects[i];
        double denom = dot3(r->normal, d);
        if (denom == 0.0) {
            continue;
        }
        double rel[3] = { r->corner[0] - o[0], r->corner[1] - o[1], r->corner[2] - o[2] };
        double t = dot3(r->normal, rel) / denom;
        if (!(t > min_t && t < best)) {
            continue;
        }
        double q[3] = { o[0] + t * d[0] - r->corner[0], o[1] + t * d[1] - r->corner[1],
                        o[2] + t * d[2] - r->corner[2] };
        double a = dot3(q, r->edge_a) / dot3(r->edge_a, r->edge_a);
        double b = dot3(q, r->edge_b) / dot3(r->edge_b, r->edge_b);
        if (a < 0.0 || a > 1.0 || b < 0.0 || b > 1.0) {
            continue;
        }
        found = true;
        best = t;
        hit->t = t;
        memcpy(hit->normal, r->normal, sizeof(hit->normal));
        hit->primitive_id = (uint64_t)i;
    }
    if (an->has_sphere) {
        const double *c = an->sphere_centre;
        double oc[3] = { o[0] - c[0], o[1] - c[1], o[2] - c[2] };
        double b = dot3(oc, d);
        double disc = b * b - (dot3(oc, oc) - an->sphere_radius_m * an->sphere_radius_m);
        if (disc >= 0.0) {
            double root = sqrt(disc);
            double t = -b - root;
            if (!(t > min_t)) {
                t = -b + root;
            }
            if (t > min_t && t < best) {
                found = true;
                best = t;
                hit->t = t;
                for (int k = 0; k < 3; k++) {
                    hit->normal[k] = (o[k] + t * d[k] - c[k]) / an->sphere_radius_m;
                }
                hit->primitive_id = an->sphere_id;
            }
        }
    }
    double t;
    uint32_t tri;
    if (an->bvh.nodes && sta_bvh_raycast(&an->bvh, o, d, min_t, best, &t, &tri)) {
        found = true;
        hit->t = t;
        const uint32_t *v = an->mesh.triangles + 3 * (size_t)tri;
        const double *p0 = an->mesh.positions + 3 * (size_t)v[0];
        const double *p1 = an->mesh.positions + 3 * (size_t)v[1];
        const double *p2 = an->mesh.positions + 3 * (size_t)v[2];
        double e1[3], e2[3];
        for (int a = 0; a < 3; a++) {
            e1[a] = p1[a] - p0[a];
            e2[a] = p2[a] - p0[a];
        }
        double n[3] = { e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                        e1[0] * e2[1] - e1[1] * e2[0] };
        double len = sqrt(dot3(n, n));
        for (int a = 0; a < 3; a++) {
            hit->normal[a] = n[a] / len;
        }
        hit->primitive_id = tri;
    }
    if (found) {
        hit->material = STA_SYNTH_MAT_SURFACE;
        hit->classification = 1;
    }
    return found;
}

/* One sample: local position, unit normal, primitive id. */
typedef struct sample {
    double p[3];
    double n[3];
    uint32_t id;
} sample;

static void sample_rect(const synth_rect *r, sta_rng *rng, sample *s)
{
    double a = sta_rng_uniform(rng), b = sta_rng_uniform(rng);
    for (int k = 0; k < 3; k++) {
        s->p[k] = r->corner[k] + a * r->edge_a[k] + b * r->edge_b[k];
        s->n[k] = r->normal[k];
    }
}

static void sample_sphere(const synth_analytic *an, sta_rng *rng, sample *s)
{
    double z = 1.0 - 2.0 * sta_rng_uniform(rng);
    double phi = 2.0 * PI * sta_rng_uniform(rng);
    double xy = sqrt(fmax(0.0, 1.0 - z * z));
    s->n[0] = xy * cos(phi);
    s->n[1] = xy * sin(phi);
    s->n[2] = z;
    for (int k = 0; k < 3; k++) {
        s->p[k] = an->sphere_centre[k] + an->sphere_radius_m * s->n[k];
    }
    s->id = an->sphere_id;
}

static void sample_mesh(const synth_analytic *an, sta_rng *rng, sample *s)
{
    const sta_mesh *m = &an->mesh;
    double target = sta_rng_uniform(rng) * an->mesh_area_m2;
    size_t lo = 0, hi = m->triangle_count - 1;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        if (an->area_cdf[mid] > target) {
            hi = mid;
        } else {
            lo = mid + 1;
        }
    }
    const uint32_t *v = m->triangles + 3 * lo;
    const double *p0 = m->positions + 3 * (size_t)v[0];
    const double *p1 = m->positions + 3 * (size_t)v[1];
    const double *p2 = m->positions + 3 * (size_t)v[2];
    double r1 = sqrt(sta_rng_uniform(rng)), r2 = sta_rng_uniform(rng);
    double w0 = 1.0 - r1, w1 = r1 * (1.0 - r2), w2 = r1 * r2;
    double e1[3], e2[3];
    for (int a = 0; a < 3; a++) {
        s->p[a] = w0 * p0[a] + w1 * p1[a] + w2 * p2[a];
        e1[a] = p1[a] - p0[a];
        e2[a] = p2[a] - p0[a];
    }
    double n[3] = { e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                    e1[0] * e2[1] - e1[1] * e2[0] };
    double len = sqrt(dot3(n, n));
    for (int a = 0; a < 3; a++) {
        s->n[a] = n[a] / len;
    }
    s->id = (uint32_t)lo;
}

static void next_sample(synth_source *src, sample *s)
{
    synth_analytic *an = &src->scene->analytic;
    if (an->bvh.nodes) {
        sample_mesh(an, &src->rng, s);
        return;
    }
    while (src->primitive_left == 0) {
        src->primitive++;
        src->primitive_left = an->counts[src->primitive];
    }
    src->primitive_left--;
    if (src->primitive < an->rect_count) {
        sample_rect(&an->rects[src->primitive], &src->rng, s);
        s->id = (uint32_t)src->primitive;
    } else {
        sample_sphere(an, &src->rng, s);
    }
}

static uint16_t colour16(double unit)
{
    long v = lround(fmin(fmax(unit, 0.0), 1.0) * 255.0);
    return (uint16_t)(v * 257);
}

void sta_analytic_source_fill(synth_source *src, sta_point *out, size_t count)
{
    const double noise = src->scene->noise_m;
    for (size_t i = 0; i < count; i++) {
        sample s;
        next_sample(src, &s);
        if (noise > 0.0) {
            double e = noise * sta_rng_gauss(&src->rng);
            for (int k = 0; k < 3; k++) {
                s.p[k] += e * s.n[k];
            }
        }
        sta_point *p = &out[i];
        memset(p, 0, sizeof(*p));
        p->X = sta_synth_georef_step(src->georef, 0, s.p[0]);
        p->Y = sta_synth_georef_step(src->georef, 1, s.p[1]);
        p->Z = sta_synth_georef_step(src->georef, 2, s.p[2]);
        // Colour shows the true normal; intensity follows a light from +z.
        p->red = colour16(0.5 + 0.5 * s.n[0]);
        p->green = colour16(0.5 + 0.5 * s.n[1]);
        p->blue = colour16(0.5 + 0.5 * s.n[2]);
        p->intensity = (uint16_t)lround(1000.0 + 30000.0 * (1.0 + s.n[2]));
        p->return_number = 1;
        p->number_of_returns = 1;
        p->classification = 1;
        p->user_data = (uint8_t)(src->scene->analytic.bvh.nodes ? 0 : s.id);
        p->point_source_id = 1;
        p->gps_time = (double)src->emitted * 1e-6;
        src->emitted++;
    }
}

sta_status sta_synth_mesh_up_axis(const sta_synth_params *params, bool *out_y_up, char *why,
                                  size_t why_size, sta_error *err)
{
    *out_y_up = false;
    if (params->kind != STA_SYNTH_MESH || !params->mesh_path) {
        return sta_fail(err, STA_ERR_ARG, "the up axis is the mesh scene's (no mesh given)");
    }
    sta_mesh mesh;
    sta_status status = sta_mesh_load(params->mesh_path, &mesh, err);
    if (status != STA_OK) {
        return status;
    }
    double lo[3], hi[3];
    mesh_bounds(&mesh, lo, hi);
    sta_mesh_release(&mesh);
    *out_y_up = mesh_y_up(params->mesh_up, lo, hi, why, why_size);
    return STA_OK;
}
