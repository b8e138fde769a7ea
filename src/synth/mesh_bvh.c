/* SPDX-License-Identifier: MIT
 * Triangle BVH: build by median split, stack traversal, Moller-Trumbore triangles.
 *
 * Based on: T. Moller and B. Trumbore, "Fast, minimum storage ray-triangle
 * intersection", 1997.
 */
#include "synth/mesh_bvh.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/alloc.h"

#define LEAF_SIZE  4
#define STACK_SIZE 64

typedef struct keyed keyed;

typedef struct build_ctx {
    sta_bvh *bvh;
    double *centroids; /* 3 per triangle */
    keyed *scratch;    /* one per triangle */
} build_ctx;

static void triangle_bounds(const sta_bvh *bvh, uint32_t tri, double lo[3], double hi[3])
{
    for (int k = 0; k < 3; k++) {
        const double *p = bvh->positions + 3 * (size_t)bvh->triangles[3 * (size_t)tri + k];
        for (int a = 0; a < 3; a++) {
            if (k == 0 || p[a] < lo[a]) {
                lo[a] = p[a];
            }
            if (k == 0 || p[a] > hi[a]) {
                hi[a] = p[a];
            }
        }
    }
}

typedef struct keyed {
    double key;     /* centroid coordinate on the split axis */
    uint32_t index; /* triangle */
} keyed;

static int compare_keyed(const void *a, const void *b)
{
    const keyed *x = a, *y = b;
    if (x->key != y->key) {
        return x->key < y->key ? -1 : 1;
    }
    return x->index < y->index ? -1 : (x->index > y->index ? 1 : 0);
}

/* Sorts order[first .. first + count) by centroid on `axis` (ties by index, so the
 * tree does not depend on the sort's stability). */
static void sort_range(build_ctx *ctx, size_t first, size_t count, int axis)
{
    uint32_t *order = ctx->bvh->order;
    for (size_t i = 0; i < count; i++) {
        ctx->scratch[i].key = ctx->centroids[3 * (size_t)order[first + i] + (size_t)axis];
        ctx->scratch[i].index = order[first + i];
    }
    qsort(ctx->scratch, count, sizeof(*ctx->scratch), compare_keyed);
    for (size_t i = 0; i < count; i++) {
        order[first + i] = ctx->scratch[i].index;
    }
}

static void build_node(build_ctx *ctx, size_t node_index, size_t first, size_t count)
{
    sta_bvh *bvh = ctx->bvh;
    sta_bvh_node *node = &bvh->nodes[node_index];
    double clo[3] = { HUGE_VAL, HUGE_VAL, HUGE_VAL }, chi[3] = { -HUGE_VAL, -HUGE_VAL, -HUGE_VAL };
    for (size_t i = first; i < first + count; i++) {
        double lo[3], hi[3];
        triangle_bounds(bvh, bvh->order[i], lo, hi);
        const double *c = ctx->centroids + 3 * (size_t)bvh->order[i];
        for (int a = 0; a < 3; a++) {
            node->lo[a] = i == first ? lo[a] : fmin(node->lo[a], lo[a]);
            node->hi[a] = i == first ? hi[a] : fmax(node->hi[a], hi[a]);
            clo[a] = fmin(clo[a], c[a]);
            chi[a] = fmax(chi[a], c[a]);
        }
    }
    if (count <= LEAF_SIZE) {
        node->first = (uint32_t)first;
        node->count = (uint32_t)count;
        return;
    }
    int axis = 0;
    for (int a = 1; a < 3; a++) {
        if (chi[a] - clo[a] > chi[axis] - clo[axis]) {
            axis = a;
        }
    }
    size_t half = count / 2;
    sort_range(ctx, first, count, axis);
    size_t left = bvh->node_count;
    bvh->node_count += 2;
    node->first = (uint32_t)left;
    node->count = 0;
    build_node(ctx, left, first, half);
    build_node(ctx, left + 1, first + half, count - half);
}

sta_status sta_bvh_build(sta_bvh *bvh, const double *positions, const uint32_t *triangles,
                         size_t triangle_count, sta_error *err)
{
    if (triangle_count == 0 || triangle_count > UINT32_MAX / 2) {
        return sta_fail(err, STA_ERR_ARG, "BVH: %zu triangles (1 .. 2^31)", triangle_count);
    }
    sta_status status = STA_OK;
    build_ctx ctx = { .bvh = bvh };
    bvh->positions = positions;
    bvh->triangles = triangles;
    bvh->order = sta_alloc_array(triangle_count, sizeof(*bvh->order));
    bvh->nodes = sta_alloc_array(2 * triangle_count, sizeof(*bvh->nodes));
    ctx.centroids = sta_alloc_array(triangle_count, 3 * sizeof(double));
    ctx.scratch = sta_alloc_array(triangle_count, sizeof(*ctx.scratch));
    if (!bvh->order || !bvh->nodes || !ctx.centroids || !ctx.scratch) {
        status =
            sta_fail(err, STA_ERR_NOMEM, "BVH: out of memory for %zu triangles", triangle_count);
        sta_bvh_release(bvh);
        goto out_free;
    }
    for (size_t i = 0; i < triangle_count; i++) {
        bvh->order[i] = (uint32_t)i;
        double lo[3], hi[3];
        triangle_bounds(bvh, (uint32_t)i, lo, hi);
        for (int a = 0; a < 3; a++) {
            ctx.centroids[3 * i + (size_t)a] = 0.5 * (lo[a] + hi[a]);
        }
    }
    bvh->node_count = 1;
    build_node(&ctx, 0, 0, triangle_count);
out_free:
    sta_free(ctx.centroids);
    sta_free(ctx.scratch);
    return status;
}

void sta_bvh_release(sta_bvh *bvh)
{
    sta_free(bvh->order);
    sta_free(bvh->nodes);
    memset(bvh, 0, sizeof(*bvh));
}

static bool node_hit(const sta_bvh_node *n, const double o[3], const double inv[3], double t_lo,
                     double t_hi)
{
    for (int a = 0; a < 3; a++) {
        double t0 = (n->lo[a] - o[a]) * inv[a];
        double t1 = (n->hi[a] - o[a]) * inv[a];
        if (t0 > t1) {
            double t = t0;
            t0 = t1;
            t1 = t;
        }
        // NaN (0 * inf on a face) compares false and leaves the bounds alone.
        if (t0 > t_lo) {
            t_lo = t0;
        }
        if (t1 < t_hi) {
            t_hi = t1;
        }
    }
    return t_lo <= t_hi;
}

static double triangle_hit(const sta_bvh *bvh, uint32_t tri, const double o[3], const double d[3])
{
    const uint32_t *v = bvh->triangles + 3 * (size_t)tri;
    const double *p0 = bvh->positions + 3 * (size_t)v[0];
    const double *p1 = bvh->positions + 3 * (size_t)v[1];
    const double *p2 = bvh->positions + 3 * (size_t)v[2];
    double e1[3], e2[3], s[3];
    for (int a = 0; a < 3; a++) {
        e1[a] = p1[a] - p0[a];
        e2[a] = p2[a] - p0[a];
        s[a] = o[a] - p0[a];
    }
    double p[3] = { d[1] * e2[2] - d[2] * e2[1], d[2] * e2[0] - d[0] * e2[2],
                    d[0] * e2[1] - d[1] * e2[0] };
    double det = e1[0] * p[0] + e1[1] * p[1] + e1[2] * p[2];
    if (det == 0.0) {
        return HUGE_VAL;
    }
    double inv = 1.0 / det;
    double u = (s[0] * p[0] + s[1] * p[1] + s[2] * p[2]) * inv;
    if (u < 0.0 || u > 1.0) {
        return HUGE_VAL;
    }
    double q[3] = { s[1] * e1[2] - s[2] * e1[1], s[2] * e1[0] - s[0] * e1[2],
                    s[0] * e1[1] - s[1] * e1[0] };
    double v2 = (d[0] * q[0] + d[1] * q[1] + d[2] * q[2]) * inv;
    if (v2 < 0.0 || u + v2 > 1.0) {
        return HUGE_VAL;
    }
    return (e2[0] * q[0] + e2[1] * q[1] + e2[2] * q[2]) * inv;
}

bool sta_bvh_raycast(const sta_bvh *bvh, const double origin[3], const double dir[3], double min_t,
                     double max_t, double *out_t, uint32_t *out_triangle)
{
    if (!bvh->nodes) {
        return false;
    }
    double inv[3];
    for (int a = 0; a < 3; a++) {
        inv[a] = 1.0 / dir[a];
    }
    uint32_t stack[STACK_SIZE];
    int top = 0;
    stack[top++] = 0;
    bool found = false;
    double best = max_t;
    while (top > 0) {
        const sta_bvh_node *n = &bvh->nodes[stack[--top]];
        if (!node_hit(n, origin, inv, min_t, best)) {
            continue;
        }
        if (n->count > 0) {
            for (uint32_t i = n->first; i < n->first + n->count; i++) {
                double t = triangle_hit(bvh, bvh->order[i], origin, dir);
                if (t > min_t && t < best) {
                    best = t;
                    found = true;
                    *out_triangle = bvh->order[i];
                }
            }
        } else {
            // Depth is at most log2(2^31) + 1, so two more entries always fit.
            stack[top++] = n->first;
            stack[top++] = n->first + 1;
        }
    }
    if (found) {
        *out_t = best;
    }
    return found;
}
