/* SPDX-License-Identifier: MIT
 * Ray casting through the street: blocks are visited where the ray lies between their
 * mitre planes, and each block's primitives are intersected in its own frame.
 *
 * Surfaces are one-sided where a solid is entered (boxes, cylinders, spheres, wires
 * report only the entering intersection); a ray that starts inside a leaf cluster or
 * a wire therefore passes on, which is how the scanner produces later returns.
 */
#include <math.h>

#include "synth/street.h"
#include "synth/synth_math.h"

/* Primitive id kinds (bits 24..31 of the id; see docs/SYNTH.md). */
enum {
    KIND_ROAD = 1,
    KIND_CURB = 2,
    KIND_SIDEWALK = 3,
    KIND_BUILDING = 4,
    KIND_POLE = 5,
    KIND_WIRE = 6,
    KIND_TRUNK = 7,
    KIND_FOLIAGE = 8,
    KIND_CAR = 9,
    KIND_INTERIOR = 10,
};

typedef struct ray {
    double o[3];
    double d[3];
    double inv[3];    /* 1 / d (infinite for a zero component) */
    street_box reach; /* bounds of the ray segment that can still give a hit */
} ray;

static double min2(double a, double b)
{
    return a < b ? a : b;
}

static double max2(double a, double b)
{
    return a > b ? a : b;
}

/* Sets r->reach to the bounds of o + t d for t in [t0, t1]. */
static void set_reach(ray *r, double t0, double t1)
{
    for (int a = 0; a < 3; a++) {
        double p0 = r->o[a] + t0 * r->d[a], p1 = r->o[a] + t1 * r->d[a];
        r->reach.lo[a] = min2(p0, p1);
        r->reach.hi[a] = max2(p0, p1);
    }
}

/* Cheap rejection: box b cannot be hit when it misses the segment's bounds. */
static bool may_reach(const ray *r, const street_box *b)
{
    return b->lo[0] <= r->reach.hi[0] && b->hi[0] >= r->reach.lo[0] && b->lo[1] <= r->reach.hi[1] &&
           b->hi[1] >= r->reach.lo[1] && b->lo[2] <= r->reach.hi[2] && b->hi[2] >= r->reach.lo[2];
}

/* The best hit so far inside one block, normal in block coordinates (s, u, w). */
typedef struct candidate {
    double t;    /* best t so far (upper bound for further tests) */
    double t_lo; /* lower bound */
    bool found;
    double n[3];
    uint8_t material;
    uint64_t id;
} candidate;

static uint64_t make_id(int64_t block, unsigned kind, unsigned side, unsigned index)
{
    return ((uint64_t)(uint32_t)(int32_t)block << 32) | ((uint64_t)kind << 24) |
           ((uint64_t)(side & 15u) << 20) | (index & 0xFFFFFu);
}

static void take(candidate *c, double t, double ns, double nu, double nw, sta_synth_material m,
                 uint64_t id)
{
    c->t = t;
    c->found = true;
    c->n[0] = ns;
    c->n[1] = nu;
    c->n[2] = nw;
    c->material = (uint8_t)m;
    c->id = id;
}

static bool usable(const candidate *c, double t)
{
    return t > c->t_lo && t < c->t;
}

/* Slab test. On success t_enter and t_exit bound the ray inside the box; axis and
 * from_low tell the entering face (axis -1 when the origin is inside every slab). */
static bool slab(const street_box *b, const ray *r, double *t_enter, double *t_exit, int *axis,
                 bool *from_low)
{
    double t0 = -HUGE_VAL, t1 = HUGE_VAL;
    *axis = -1;
    *from_low = false;
    for (int a = 0; a < 3; a++) {
        if (r->d[a] == 0.0) {
            if (r->o[a] < b->lo[a] || r->o[a] > b->hi[a]) {
                return false;
            }
            continue;
        }
        double inv = r->inv[a];
        double near = ((r->d[a] > 0.0 ? b->lo[a] : b->hi[a]) - r->o[a]) * inv;
        double far = ((r->d[a] > 0.0 ? b->hi[a] : b->lo[a]) - r->o[a]) * inv;
        if (near > t0) {
            t0 = near;
            *axis = a;
            *from_low = r->d[a] > 0.0;
        }
        if (far < t1) {
            t1 = far;
        }
    }
    *t_enter = t0;
    *t_exit = t1;
    return t0 <= t1;
}

/* True when the ray's segment inside the candidate's range may touch box b. */
static bool box_touched(const street_box *b, const ray *r, const candidate *c)
{
    if (!may_reach(r, b)) {
        return false;
    }
    double t0, t1;
    int axis;
    bool low;
    return slab(b, r, &t0, &t1, &axis, &low) && t1 > c->t_lo && t0 < c->t;
}

/* Exit of a ray from inside box b: t and the face (outward axis/direction). */
static double exit_face(const street_box *b, const ray *r, int *axis)
{
    double t1 = HUGE_VAL;
    *axis = 0;
    for (int a = 0; a < 3; a++) {
        if (r->d[a] == 0.0) {
            continue;
        }
        double t = ((r->d[a] > 0.0 ? b->hi[a] : b->lo[a]) - r->o[a]) / r->d[a];
        if (t < t1) {
            t1 = t;
            *axis = a;
        }
    }
    return t1;
}

/* Entering intersection with a vertical cylinder (axis at s, v), w in [w0, w1]. */
static double vertical_cylinder(const ray *r, double s, double v, double radius, double w0,
                                double w1)
{
    double ds = r->o[0] - s, dv = r->o[1] - v;
    double a = r->d[0] * r->d[0] + r->d[1] * r->d[1];
    if (a <= 0.0) {
        return HUGE_VAL;
    }
    double b = ds * r->d[0] + dv * r->d[1];
    double c = ds * ds + dv * dv - radius * radius;
    double disc = b * b - a * c;
    if (disc < 0.0 || c < 0.0) {
        return HUGE_VAL; // miss, or the origin is inside
    }
    double t = (-b - sqrt(disc)) / a;
    double w = r->o[2] + t * r->d[2];
    return (w >= w0 && w <= w1) ? t : HUGE_VAL;
}

/* Entering intersection with a sphere; unit direction. */
static double sphere_enter(const ray *r, const double centre[3], double radius)
{
    double oc[3] = { r->o[0] - centre[0], r->o[1] - centre[1], r->o[2] - centre[2] };
    double b = oc[0] * r->d[0] + oc[1] * r->d[1] + oc[2] * r->d[2];
    double c = oc[0] * oc[0] + oc[1] * oc[1] + oc[2] * oc[2] - radius * radius;
    if (c < 0.0 || b > 0.0) {
        return HUGE_VAL; // inside, or moving away
    }
    double disc = b * b - c;
    return disc < 0.0 ? HUGE_VAL : -b - sqrt(disc);
}

/* Entering intersection with the finite cylinder around segment a-b. */
static double segment_cylinder(const ray *r, const double a[3], const double b[3], double radius,
                               double out_n[3])
{
    double ba[3] = { b[0] - a[0], b[1] - a[1], b[2] - a[2] };
    double oc[3] = { r->o[0] - a[0], r->o[1] - a[1], r->o[2] - a[2] };
    double baba = ba[0] * ba[0] + ba[1] * ba[1] + ba[2] * ba[2];
    double bard = ba[0] * r->d[0] + ba[1] * r->d[1] + ba[2] * r->d[2];
    double baoc = ba[0] * oc[0] + ba[1] * oc[1] + ba[2] * oc[2];
    double ocd = oc[0] * r->d[0] + oc[1] * r->d[1] + oc[2] * r->d[2];
    double ococ = oc[0] * oc[0] + oc[1] * oc[1] + oc[2] * oc[2];
    double k2 = baba - bard * bard;
    double k1 = baba * ocd - baoc * bard;
    double k0 = baba * ococ - baoc * baoc - radius * radius * baba;
    if (k2 <= 0.0 || k0 < 0.0) {
        return HUGE_VAL; // parallel, or the origin is inside the tube
    }
    double h = k1 * k1 - k2 * k0;
    if (h < 0.0) {
        return HUGE_VAL;
    }
    double t = (-k1 - sqrt(h)) / k2;
    double y = baoc + t * bard;
    if (y < 0.0 || y > baba) {
        return HUGE_VAL;
    }
    for (int i = 0; i < 3; i++) {
        out_n[i] = (oc[i] + t * r->d[i] - ba[i] * y / baba) / radius;
    }
    return t;
}

static bool in_range(double x, double lo, double hi)
{
    return x >= lo && x < hi;
}

/* Road (crowned tent), markings, curb faces and sidewalks of one block. */
static void trace_ground(const street_config *cfg, int64_t block, const ray *r, candidate *c)
{
    const double g = cfg->cross_slope, half = cfg->road_half_m;
    const double norm = 1.0 / sqrt(1.0 + g * g);
    // Sidewalk and the ground beyond, w = sidewalk_z for half <= |u| < ground limit.
    if (r->d[2] < 0.0) {
        double t = (cfg->sidewalk_z_m - r->o[2]) * r->inv[2];
        double v = fabs(r->o[1] + t * r->d[1]);
        if (usable(c, t) && in_range(v, half, STREET_GROUND_M)) {
            unsigned side = r->o[1] + t * r->d[1] >= 0.0 ? 0u : 1u;
            take(c, t, 0.0, 0.0, 1.0, STA_SYNTH_MAT_SIDEWALK,
                 make_id(block, KIND_SIDEWALK, side, 0));
        }
    }
    // Curb faces at |u| = half, facing the road: only the one the ray moves towards.
    if (r->d[1] != 0.0) {
        double sigma = r->d[1] > 0.0 ? 1.0 : -1.0;
        double t = (sigma * half - r->o[1]) * r->inv[1];
        double w = r->o[2] + t * r->d[2];
        if (usable(c, t) && in_range(w, -g * half, cfg->sidewalk_z_m) && sigma * r->o[1] < half) {
            take(c, t, 0.0, -sigma, 0.0, STA_SYNTH_MAT_CURB,
                 make_id(block, KIND_CURB, sigma > 0.0 ? 0u : 1u, 0));
        }
    }
    for (int side = 0; side < 2; side++) {
        double sigma = side == 0 ? 1.0 : -1.0;
        double v_o = sigma * r->o[1], v_d = sigma * r->d[1];
        // Road half: w = -g v for 0 <= v <= half; seen from above only.
        double denom = r->d[2] + g * v_d;
        if (denom < 0.0) {
            double t = -(r->o[2] + g * v_o) / denom;
            double v = v_o + t * v_d;
            if (usable(c, t) && in_range(v, 0.0, half)) {
                double s = r->o[0] + t * r->d[0];
                double dash = s - 6.0 * (double)sta_floor_i64(s / 6.0);
                bool centre_line = v < 0.06 && dash < 3.0;
                bool edge_line = fabs(v - cfg->lane_width_m) < 0.06;
                sta_synth_material m =
                    (centre_line || edge_line) ? STA_SYNTH_MAT_MARKING : STA_SYNTH_MAT_ROAD;
                take(c, t, 0.0, sigma * g * norm, norm, m, make_id(block, KIND_ROAD, side, 0));
            }
        }
    }
}

typedef struct opening {
    double s0, s1, w0, w1; /* the hole in the facade */
    double floor_w;        /* floor level of its storey */
    bool door;
} opening;

static bool find_opening(const street_building *bl, double s, double w, opening *out)
{
    double z = w - bl->box.lo[2];
    int64_t storey = sta_floor_i64(z / bl->floor_m);
    int64_t column = sta_floor_i64((s - bl->column_first) / bl->pitch_m);
    if (storey < 0 || storey >= bl->floors || column < 0 || column >= bl->columns) {
        return false;
    }
    double cs = bl->column_first + (double)column * bl->pitch_m;
    double zb = bl->box.lo[2] + (double)storey * bl->floor_m;
    out->floor_w = zb;
    out->door = false;
    if (storey == 0 && column == bl->door_column) {
        out->s0 = cs + 0.5 * (bl->pitch_m - 1.1);
        out->s1 = out->s0 + 1.1;
        out->w0 = zb;
        out->w1 = zb + 2.3;
        out->door = true;
    } else if (storey == 0 && bl->shop) {
        out->s0 = cs + 0.25;
        out->s1 = cs + bl->pitch_m - 0.25;
        out->w0 = zb + 0.5;
        out->w1 = zb + 2.7;
    } else {
        out->s0 = cs + 0.5 * (bl->pitch_m - bl->window_w);
        out->s1 = out->s0 + bl->window_w;
        out->w0 = zb + bl->sill_m;
        out->w1 = out->w0 + bl->window_h;
    }
    return in_range(s, out->s0, out->s1) && in_range(w, out->w0, out->w1);
}

/* Normal in canonical (s, v, w) of the face a ray leaves a box through (inward). */
static void inward_normal(const ray *r, int axis, double n[3])
{
    n[0] = n[1] = n[2] = 0.0;
    n[axis] = r->d[axis] > 0.0 ? -1.0 : 1.0;
}

/* Takes a hit given in canonical side coordinates. */
static void take_side(candidate *c, double sigma, double t, const double n[3], sta_synth_material m,
                      uint64_t id)
{
    take(c, t, n[0], sigma * n[1], n[2], m, id);
}

static void trace_building(const street_building *bl, int64_t block, int side, double sigma,
                           const ray *r, unsigned flags, candidate *c)
{
    double t0, t1;
    int axis;
    bool from_low;
    if (!may_reach(r, &bl->box) || !slab(&bl->box, r, &t0, &t1, &axis, &from_low) || axis < 0 ||
        !usable(c, t0)) {
        return;
    }
    uint64_t id = make_id(block, KIND_BUILDING, (unsigned)side, bl->index);
    double n[3] = { 0.0, 0.0, 0.0 };
    opening hole;
    bool front = axis == 1 && from_low;
    if (!front || !find_opening(bl, r->o[0] + t0 * r->d[0], r->o[2] + t0 * r->d[2], &hole)) {
        n[axis] = from_low ? -1.0 : 1.0;
        take_side(c, sigma, t0, n, STA_SYNTH_MAT_WALL, id);
        return;
    }
    // Inside the opening's recess: the ray leaves through a reveal or the back.
    const double v0 = bl->box.lo[1];
    street_box recess = { { hole.s0, v0, hole.w0 }, { hole.s1, v0 + bl->recess_m, hole.w1 } };
    int exit_axis;
    double tx = exit_face(&recess, r, &exit_axis);
    if (!usable(c, tx)) {
        return;
    }
    if (exit_axis != 1) {
        inward_normal(r, exit_axis, n);
        take_side(c, sigma, tx, n, STA_SYNTH_MAT_WALL, id);
        return;
    }
    n[1] = -1.0;
    if (hole.door) {
        take_side(c, sigma, tx, n, STA_SYNTH_MAT_DOOR, id);
        return;
    }
    if (flags & STA_SYNTH_RAY_GLASS) {
        take_side(c, sigma, tx, n, STA_SYNTH_MAT_GLASS, id);
        return;
    }
    // Through the glass into the room of that storey.
    street_box room = { { bl->box.lo[0] + 0.25, v0 + bl->recess_m, hole.floor_w },
                        { bl->box.hi[0] - 0.25, v0 + bl->recess_m + 4.5,
                          hole.floor_w + bl->floor_m - 0.3 } };
    double tr = exit_face(&room, r, &exit_axis);
    if (usable(c, tr)) {
        inward_normal(r, exit_axis, n);
        take_side(c, sigma, tr, n, STA_SYNTH_MAT_INTERIOR,
                  make_id(block, KIND_INTERIOR, (unsigned)side, bl->index));
    }
}

static void trace_tree(const street_tree *tree, const street_config *cfg, int64_t block, int side,
                       unsigned index, double sigma, const ray *r, candidate *c)
{
    if (!may_reach(r, &tree->bounds)) {
        return; // bounds hold trunk and crown
    }
    double t =
        vertical_cylinder(r, tree->s, tree->v, tree->trunk_r, cfg->sidewalk_z_m, tree->centre[2]);
    if (usable(c, t)) {
        double n[3] = { (r->o[0] + t * r->d[0] - tree->s) / tree->trunk_r,
                        (r->o[1] + t * r->d[1] - tree->v) / tree->trunk_r, 0.0 };
        take_side(c, sigma, t, n, STA_SYNTH_MAT_TRUNK,
                  make_id(block, KIND_TRUNK, (unsigned)side, index));
    }
    double t0, t1;
    int axis;
    bool low;
    if (!slab(&tree->bounds, r, &t0, &t1, &axis, &low) || t1 <= c->t_lo || t0 >= c->t) {
        return;
    }
    // Only clusters whose s lies near the ray's s range inside the crown can be hit.
    t0 = max2(t0, c->t_lo);
    t1 = min2(t1, c->t);
    double s_a = r->o[0] + t0 * r->d[0], s_b = r->o[0] + t1 * r->d[0];
    double s_lo = min2(s_a, s_b) - STREET_CLUSTER_MAX_R,
           s_hi = max2(s_a, s_b) + STREET_CLUSTER_MAX_R;
    int lo = 0, hi = tree->cluster_count;
    while (lo < hi) {
        int mid = (lo + hi) / 2;
        if (tree->clusters[mid][0] < s_lo) {
            lo = mid + 1;
        } else {
            hi = mid;
        }
    }
    for (int i = lo; i < tree->cluster_count && tree->clusters[i][0] <= s_hi; i++) {
        const double *cl = tree->clusters[i];
        t = sphere_enter(r, cl, cl[3]);
        if (usable(c, t)) {
            double n[3];
            for (int k = 0; k < 3; k++) {
                n[k] = (r->o[k] + t * r->d[k] - cl[k]) / cl[3];
            }
            take_side(c, sigma, t, n, STA_SYNTH_MAT_FOLIAGE,
                      make_id(block, KIND_FOLIAGE, (unsigned)side, index * 256u + (unsigned)i));
        }
    }
}

static void trace_car(const street_car *car, int64_t block, int side, unsigned index, double sigma,
                      const ray *r, candidate *c)
{
    if (!box_touched(&car->bounds, r, c)) {
        return;
    }
    for (unsigned p = 0; p < 6; p++) {
        double t0, t1;
        int axis;
        bool from_low;
        if (slab(&car->parts[p], r, &t0, &t1, &axis, &from_low) && axis >= 0 && usable(c, t0)) {
            double n[3] = { 0.0, 0.0, 0.0 };
            n[axis] = from_low ? -1.0 : 1.0;
            take_side(c, sigma, t0, n, p < 2 ? STA_SYNTH_MAT_CAR : STA_SYNTH_MAT_TYRE,
                      make_id(block, KIND_CAR, (unsigned)side, index * 8u + p));
        }
    }
}

/* OR of the bins the ray's reach covers along s. */
static unsigned reach_mask(const ray *r, const uint16_t *bins16, const uint8_t *bins8)
{
    int64_t first = sta_floor_i64(r->reach.lo[0]), last = sta_floor_i64(r->reach.hi[0]);
    first = first < 0 ? 0 : (first > STREET_BINS - 1 ? STREET_BINS - 1 : first);
    last = last < 0 ? 0 : (last > STREET_BINS - 1 ? STREET_BINS - 1 : last);
    unsigned mask = 0;
    for (int64_t i = first; i <= last; i++) {
        mask |= bins16 ? bins16[i] : bins8[i];
    }
    return mask;
}

static void trace_side(const street_config *cfg, const street_block *blk, int side,
                       const ray *block_ray, unsigned flags, candidate *c)
{
    const street_side *sd = &blk->sides[side];
    double sigma = side == 0 ? 1.0 : -1.0;
    // Nothing of this side lies below v_min: skip it when the ray segment stays there.
    double reach_v = side == 0 ? block_ray->reach.hi[1] : -block_ray->reach.lo[1];
    if (reach_v < sd->v_min) {
        return;
    }
    // Only objects in the 1 m bins the ray's reach crosses along s.
    unsigned mask = reach_mask(block_ray, sd->bins, NULL);
    if (mask == 0) {
        return;
    }
    ray r = *block_ray;
    r.o[1] *= sigma;
    r.d[1] *= sigma;
    r.inv[1] *= sigma;
    if (sigma < 0.0) {
        double lo = r.reach.lo[1];
        r.reach.lo[1] = -r.reach.hi[1];
        r.reach.hi[1] = -lo;
    }
    for (int i = 0; i < sd->building_count; i++) {
        if (mask & (1u << i)) {
            trace_building(&sd->buildings[i], blk->index, side, sigma, &r, flags, c);
        }
    }
    if (mask & (1u << 10)) {
        street_box pole = { { sd->pole_s - sd->pole_r, sd->pole_v - sd->pole_r, cfg->sidewalk_z_m },
                            { sd->pole_s + sd->pole_r, sd->pole_v + sd->pole_r, sd->pole_top } };
        double t = may_reach(&r, &pole) ? vertical_cylinder(&r, sd->pole_s, sd->pole_v, sd->pole_r,
                                                            cfg->sidewalk_z_m, sd->pole_top)
                                        : HUGE_VAL;
        if (usable(c, t)) {
            double n[3] = { (r.o[0] + t * r.d[0] - sd->pole_s) / sd->pole_r,
                            (r.o[1] + t * r.d[1] - sd->pole_v) / sd->pole_r, 0.0 };
            take_side(c, sigma, t, n, STA_SYNTH_MAT_POLE,
                      make_id(blk->index, KIND_POLE, (unsigned)side, 0));
        }
    }
    for (int i = 0; i < sd->tree_count; i++) {
        if (mask & (1u << (4 + i))) {
            trace_tree(&sd->trees[i], cfg, blk->index, side, (unsigned)i, sigma, &r, c);
        }
    }
    for (int i = 0; i < sd->car_count; i++) {
        if (mask & (1u << (6 + i))) {
            trace_car(&sd->cars[i], blk->index, side, (unsigned)i, sigma, &r, c);
        }
    }
}

static void trace_wires(const street_block *blk, const ray *r, candidate *c)
{
    unsigned mask = reach_mask(r, NULL, blk->wire_bins);
    for (int i = 0; i < blk->wire_count; i++) {
        const street_wire *w = &blk->wires[i];
        if (!(mask & (1u << i)) || !box_touched(&w->bounds, r, c)) {
            continue;
        }
        for (int k = 0; k < STREET_WIRE_SEGMENTS; k++) {
            // Segments outside the ray's reach along s cannot be hit.
            double s0 = w->points[k][0], s1 = w->points[k + 1][0];
            if (min2(s0, s1) - w->radius_m > r->reach.hi[0] ||
                max2(s0, s1) + w->radius_m < r->reach.lo[0]) {
                continue;
            }
            double n[3] = { 0.0, 0.0, 0.0 };
            double t = segment_cylinder(r, w->points[k], w->points[k + 1], w->radius_m, n);
            if (usable(c, t)) {
                take(c, t, n[0], n[1], n[2], STA_SYNTH_MAT_WIRE, w->id);
            }
        }
    }
}

/* The part [lo, hi] of the ray between the block's mitre planes. *exit tells where
 * the ray leaves at hi: +1 through the end plane, -1 through the start plane, 0 when
 * hi is the caller's bound. */
static bool block_interval(const street_frame *f, const double o[3], const double d[3], double *lo,
                           double *hi, int *exit)
{
    const double *normals[2] = { f->start_n, f->end_n };
    const double *points[2] = { f->origin, f->end_origin };
    *exit = 0;
    for (int i = 0; i < 2; i++) {
        // Inside: start plane n.(p - q) >= 0, end plane n.(p - q) < 0.
        double sign = i == 0 ? 1.0 : -1.0;
        double a =
            sign * (normals[i][0] * (o[0] - points[i][0]) + normals[i][1] * (o[1] - points[i][1]));
        double k = sign * (normals[i][0] * d[0] + normals[i][1] * d[1]);
        if (k > 0.0) {
            *lo = max2(*lo, -a / k);
        } else if (k < 0.0) {
            double t = -a / k;
            if (t < *hi) {
                *hi = t;
                *exit = i == 0 ? -1 : 1;
            }
        } else if (a < 0.0) {
            return false;
        }
    }
    return *lo < *hi;
}

/* Conservative test: can the ray segment come near block b at all? */
static bool near_block(const street_config *cfg, int64_t b, const double o[3], const double d[3],
                       double t_lo, double t_hi)
{
    double a[2], e[2];
    sta_street_block_start(cfg, b, a);
    sta_street_block_start(cfg, b + 1, e);
    double centre[3] = { 0.5 * (a[0] + e[0]), 0.5 * (a[1] + e[1]), 10.0 };
    const double radius = 0.5 * STREET_BLOCK_M + STREET_GROUND_M + 30.0;
    double oc[3] = { centre[0] - o[0], centre[1] - o[1], centre[2] - o[2] };
    double t = oc[0] * d[0] + oc[1] * d[1] + oc[2] * d[2];
    t = min2(max2(t, t_lo), t_hi);
    double q[3] = { oc[0] - t * d[0], oc[1] - t * d[1], oc[2] - t * d[2] };
    return q[0] * q[0] + q[1] * q[1] + q[2] * q[2] <= radius * radius;
}

/* Nearest hit inside block b for lo < t < hi; false when none. */
static bool trace_one_block(sta_street *street, int64_t b, const double origin[3],
                            const double dir[3], double lo, double hi, unsigned flags,
                            sta_synth_hit *hit)
{
    const street_block *blk = sta_street_block(street, b);
    const street_frame *f = &blk->frame;
    // Above the block's top and below its lowest ground there is nothing to hit.
    if (dir[2] > 0.0) {
        hi = min2(hi, (blk->top_m - origin[2]) / dir[2]);
    } else if (dir[2] < 0.0) {
        lo = max2(lo, (blk->top_m - origin[2]) / dir[2]);
        double bottom = -street->cfg.cross_slope * street->cfg.road_half_m - 0.01;
        hi = min2(hi, (bottom - origin[2]) / dir[2]);
    } else if (origin[2] > blk->top_m) {
        return false;
    }
    if (!(lo < hi)) {
        return false;
    }
    double dx = origin[0] - f->origin[0], dy = origin[1] - f->origin[1];
    ray r = { .o = { dx * f->cos_h + dy * f->sin_h, -dx * f->sin_h + dy * f->cos_h, origin[2] },
              .d = { dir[0] * f->cos_h + dir[1] * f->sin_h, -dir[0] * f->sin_h + dir[1] * f->cos_h,
                     dir[2] } };
    for (int a = 0; a < 3; a++) {
        r.inv[a] = 1.0 / r.d[a];
    }
    // Hits are accepted in [lo, hi): the half-open mitre interval of this block.
    // (a hit exactly on a mitre plane is lost; t is continuous, so this never matters)
    candidate c = { .t = hi, .t_lo = lo };
    trace_ground(&street->cfg, b, &r, &c);
    // The ground bounds most rays; objects are culled against what is left.
    set_reach(&r, max2(c.t_lo, 0.0), min2(c.t, 1e6));
    trace_wires(blk, &r, &c);
    trace_side(&street->cfg, blk, 0, &r, flags, &c);
    trace_side(&street->cfg, blk, 1, &r, flags, &c);
    if (!c.found) {
        return false;
    }
    hit->t = c.t;
    hit->normal[0] = c.n[0] * f->cos_h - c.n[1] * f->sin_h;
    hit->normal[1] = c.n[0] * f->sin_h + c.n[1] * f->cos_h;
    hit->normal[2] = c.n[2];
    hit->material = c.material;
    hit->classification = sta_street_class((sta_synth_material)c.material);
    hit->primitive_id = c.id;
    return true;
}

bool sta_street_trace(sta_street *street, int64_t b_lo, int64_t b_hi, const double origin[3],
                      const double dir[3], double t_lo, double t_hi, unsigned flags,
                      sta_synth_hit *hit)
{
    bool found = false;
    double best = t_hi;
    for (int64_t b = b_lo; b <= b_hi; b++) {
        if (!near_block(&street->cfg, b, origin, dir, t_lo, best)) {
            continue;
        }
        double lo = t_lo, hi = best;
        int exit;
        if (block_interval(sta_street_cached_frame(street, b), origin, dir, &lo, &hi, &exit) &&
            trace_one_block(street, b, origin, dir, lo, hi, flags, hit)) {
            found = true;
            best = hit->t;
        }
    }
    return found;
}

/* Mitre side of point p relative to block b: -1 before it, +1 after it, 0 inside. */
static int block_side(const street_frame *f, const double p[3])
{
    if (f->start_n[0] * (p[0] - f->origin[0]) + f->start_n[1] * (p[1] - f->origin[1]) < 0.0) {
        return -1;
    }
    if (f->end_n[0] * (p[0] - f->end_origin[0]) + f->end_n[1] * (p[1] - f->end_origin[1]) >= 0.0) {
        return 1;
    }
    return 0;
}

bool sta_street_trace_walk(sta_street *street, int64_t b_hint, const double origin[3],
                           const double dir[3], double t_lo, double t_hi, unsigned flags,
                           sta_synth_hit *hit)
{
    // Find the block holding the ray's start, then follow the ray from block to block:
    // the mitre planes partition the street, so the first block with a hit holds the
    // nearest one.
    const double p[3] = { origin[0] + t_lo * dir[0], origin[1] + t_lo * dir[1],
                          origin[2] + t_lo * dir[2] };
    int64_t b = b_hint;
    for (int step = 0; step < 8; step++) {
        int side = block_side(sta_street_cached_frame(street, b), p);
        if (side == 0) {
            break;
        }
        b += side;
    }
    for (int step = 0; step < 8; step++) {
        double lo = t_lo, hi = t_hi;
        int exit;
        bool inside =
            block_interval(sta_street_cached_frame(street, b), origin, dir, &lo, &hi, &exit);
        if (inside && trace_one_block(street, b, origin, dir, lo, hi, flags, hit)) {
            return true;
        }
        if (exit == 0) {
            return false;
        }
        b += exit;
    }
    return false;
}
