/* SPDX-License-Identifier: MIT
 * The street's layout: street-wide values, block frames and block contents, each a
 * pure function of (seed, block index). See street.h for the frame conventions.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/alloc.h"
#include "synth/street.h"
#include "synth/synth_math.h"
#include "synth/synth_rng.h"

#define PI 3.14159265358979323846

/* Stream keys, so block, side and street draws never share a stream. */
#define KEY_STREET 0x5354524545543031ull
#define KEY_BLOCK  0x424C4F434B303031ull
#define KEY_SIDE   0x5349444530303031ull

void sta_street_config_init(street_config *cfg, uint64_t seed)
{
    memset(cfg, 0, sizeof(*cfg));
    sta_rng rng;
    sta_rng_seed(&rng, sta_hash2(seed, KEY_STREET));
    cfg->seed = seed;
    cfg->heading0_rad = sta_rng_range(&rng, 0.0, 2.0 * PI);
    cfg->amplitude_rad = sta_rng_range(&rng, 6.0, 12.0) * PI / 180.0;
    cfg->lane_width_m = sta_rng_range(&rng, 3.0, 3.5);
    cfg->parking_width_m = 2.2;
    cfg->road_half_m = cfg->lane_width_m + cfg->parking_width_m;
    cfg->sidewalk_m = sta_rng_range(&rng, 3.5, 5.0);
    cfg->curb_height_m = sta_rng_range(&rng, 0.12, 0.16);
    cfg->cross_slope = 0.02;
    cfg->sidewalk_z_m = -cfg->cross_slope * cfg->road_half_m + cfg->curb_height_m;
    cfg->facade_m = cfg->road_half_m + cfg->sidewalk_m;
    cfg->centre[0][0] = 0.0;
    cfg->centre[0][1] = 0.0;
    for (int r = 0; r < STREET_PERIOD; r++) {
        double h = cfg->heading0_rad +
                   cfg->amplitude_rad * sin(2.0 * PI * (double)r / (double)STREET_PERIOD);
        cfg->heading[r] = h;
        cfg->centre[r + 1][0] = cfg->centre[r][0] + STREET_BLOCK_M * cos(h);
        cfg->centre[r + 1][1] = cfg->centre[r][1] + STREET_BLOCK_M * sin(h);
    }
}

static int64_t floor_div(int64_t a, int64_t b)
{
    int64_t q = a / b;
    return (a % b != 0 && (a < 0) != (b < 0)) ? q - 1 : q;
}

static double heading_of(const street_config *cfg, int64_t b)
{
    int64_t q = floor_div(b, STREET_PERIOD);
    return cfg->heading[b - q * STREET_PERIOD];
}

static void origin_of(const street_config *cfg, int64_t b, double out[2])
{
    int64_t q = floor_div(b, STREET_PERIOD);
    int64_t r = b - q * STREET_PERIOD;
    double shift_x = cfg->centre[STREET_PERIOD][0];
    double shift_y = cfg->centre[STREET_PERIOD][1];
    out[0] = cfg->centre[r][0] + (double)q * shift_x;
    out[1] = cfg->centre[r][1] + (double)q * shift_y;
}

/* Normal of the mitre plane at the start of block b (bisector of the two headings). */
static void mitre_of(const street_config *cfg, int64_t b, double out[2])
{
    double m = 0.5 * (heading_of(cfg, b - 1) + heading_of(cfg, b));
    out[0] = cos(m);
    out[1] = sin(m);
}

void sta_street_frame(const street_config *cfg, int64_t b, street_frame *f)
{
    double h = heading_of(cfg, b);
    f->cos_h = cos(h);
    f->sin_h = sin(h);
    origin_of(cfg, b, f->origin);
    origin_of(cfg, b + 1, f->end_origin);
    mitre_of(cfg, b, f->start_n);
    mitre_of(cfg, b + 1, f->end_n);
}

void sta_street_block_start(const street_config *cfg, int64_t b, double out_xy[2])
{
    origin_of(cfg, b, out_xy);
}

int64_t sta_street_block_of(double s_m)
{
    return sta_floor_i64(s_m / STREET_BLOCK_M);
}

/* Block coordinates (s, u) of block frame f to local xy. */
static void frame_to_local(const street_frame *f, double s, double u, double out[2])
{
    out[0] = f->origin[0] + s * f->cos_h - u * f->sin_h;
    out[1] = f->origin[1] + s * f->sin_h + u * f->cos_h;
}

static void local_to_frame(const street_frame *f, const double xy[2], double out[2])
{
    double dx = xy[0] - f->origin[0];
    double dy = xy[1] - f->origin[1];
    out[0] = dx * f->cos_h + dy * f->sin_h;
    out[1] = -dx * f->sin_h + dy * f->cos_h;
}

void sta_street_point(const street_config *cfg, double s_m, double u_m, double w_m,
                      double out_xyz[3])
{
    int64_t b = sta_street_block_of(s_m);
    street_frame f;
    sta_street_frame(cfg, b, &f);
    frame_to_local(&f, s_m - (double)b * STREET_BLOCK_M, u_m, out_xyz);
    out_xyz[2] = w_m;
}

uint8_t sta_street_class(sta_synth_material material)
{
    switch (material) {
    case STA_SYNTH_MAT_ROAD:
    case STA_SYNTH_MAT_MARKING:
        return 11;
    case STA_SYNTH_MAT_CURB:
    case STA_SYNTH_MAT_SIDEWALK:
        return 2;
    case STA_SYNTH_MAT_WALL:
    case STA_SYNTH_MAT_GLASS:
    case STA_SYNTH_MAT_DOOR:
    case STA_SYNTH_MAT_INTERIOR:
        return 6;
    case STA_SYNTH_MAT_POLE:
        return 15;
    case STA_SYNTH_MAT_WIRE:
        return 14;
    case STA_SYNTH_MAT_TRUNK:
    case STA_SYNTH_MAT_FOLIAGE:
        return 5;
    case STA_SYNTH_MAT_CAR:
    case STA_SYNTH_MAT_TYRE:
        return 64;
    case STA_SYNTH_MAT_NONE:
    case STA_SYNTH_MAT_SURFACE:
    case STA_SYNTH_MAT_COUNT:
        break;
    }
    return 1;
}

/* Block-wide draws: the poles on both sides share s, so a wire can span the road. */
typedef struct block_poles {
    double s, top, r, v;
} block_poles;

static void poles_of(const street_config *cfg, int64_t b, block_poles *out)
{
    sta_rng rng;
    sta_rng_seed(&rng, sta_hash2(cfg->seed ^ KEY_BLOCK, (uint64_t)b));
    out->s = 0.5 * STREET_BLOCK_M + sta_rng_range(&rng, -5.0, 5.0);
    out->top = cfg->sidewalk_z_m + sta_rng_range(&rng, 7.5, 8.5);
    out->r = 0.11;
    out->v = cfg->road_half_m + 0.5;
}

static void box_set(street_box *b, double s0, double s1, double v0, double v1, double w0, double w1)
{
    b->lo[0] = s0;
    b->hi[0] = s1;
    b->lo[1] = v0;
    b->hi[1] = v1;
    b->lo[2] = w0;
    b->hi[2] = w1;
}

static void box_grow(street_box *b, const street_box *add)
{
    for (int a = 0; a < 3; a++) {
        b->lo[a] = fmin(b->lo[a], add->lo[a]);
        b->hi[a] = fmax(b->hi[a], add->hi[a]);
    }
}

static void make_buildings(const street_config *cfg, sta_rng *rng, street_side *side)
{
    double s = 1.5;
    const double end = STREET_BLOCK_M - 1.5;
    side->building_count = 0;
    while (side->building_count < STREET_MAX_BUILDINGS && end - s >= 6.0) {
        double width = sta_rng_range(rng, 8.0, 20.0);
        if (s + width > end || end - (s + width) < 6.0) {
            width = end - s;
        }
        street_building *bl = &side->buildings[side->building_count];
        bl->index = (uint16_t)side->building_count;
        bl->floors = 3 + (int)sta_rng_below(rng, 4);
        bl->floor_m = sta_rng_range(rng, 3.0, 3.6);
        double v0 = cfg->facade_m + sta_rng_range(rng, 0.0, 0.6);
        double roof = cfg->sidewalk_z_m + bl->floors * bl->floor_m + sta_rng_range(rng, 0.4, 1.2);
        box_set(&bl->box, s, s + width, v0, v0 + 12.0, cfg->sidewalk_z_m, roof);
        bl->window_w = sta_rng_range(rng, 1.0, 1.5);
        bl->pitch_m = bl->window_w + sta_rng_range(rng, 0.9, 1.9);
        bl->window_h = sta_rng_range(rng, 1.3, 1.7);
        bl->sill_m = sta_rng_range(rng, 0.8, 1.0);
        bl->recess_m = sta_rng_range(rng, 0.2, 0.3);
        bl->columns = (int)floor((width - 1.2) / bl->pitch_m);
        if (bl->columns < 1) {
            bl->columns = 1;
            bl->pitch_m = width - 1.2;
        }
        bl->column_first = s + 0.5 * (width - bl->columns * bl->pitch_m);
        bl->door_column = (int)sta_rng_below(rng, (uint32_t)bl->columns);
        bl->shop = sta_rng_uniform(rng) < 0.45;
        side->building_count++;
        s += width;
        if (sta_rng_uniform(rng) < 0.5) {
            s += sta_rng_range(rng, 1.0, 3.0); // an alley
        }
    }
}

static int compare_cluster_s(const void *a, const void *b)
{
    const double *x = a, *y = b;
    if (x[0] != y[0]) {
        return x[0] < y[0] ? -1 : 1;
    }
    return (x[1] > y[1]) - (x[1] < y[1]);
}

static void make_tree(const street_config *cfg, sta_rng *rng, double s, street_tree *t)
{
    t->s = s;
    t->v = cfg->road_half_m + 1.4;
    t->trunk_r = sta_rng_range(rng, 0.12, 0.2);
    double trunk_h = sta_rng_range(rng, 2.2, 3.2);
    t->radius_h = sta_rng_range(rng, 1.8, 2.6);
    t->radius_v = sta_rng_range(rng, 2.2, 3.2);
    t->centre[0] = s;
    t->centre[1] = t->v;
    t->centre[2] = cfg->sidewalk_z_m + trunk_h + t->radius_v;
    // Lobes make the crown a noisy ellipsoid rather than a smooth one.
    double lobe_a = sta_rng_range(rng, 0.0, 2.0 * PI);
    double lobe_b = sta_rng_range(rng, 0.0, 2.0 * PI);
    t->cluster_count = 80 + (int)sta_rng_below(rng, STREET_MAX_CLUSTERS - 80 + 1);
    box_set(&t->bounds, s, s, t->v, t->v, t->centre[2], t->centre[2]);
    for (int i = 0; i < t->cluster_count; i++) {
        double z = 2.0 * sta_rng_uniform(rng) - 1.0;
        double phi = 2.0 * PI * sta_rng_uniform(rng);
        double xy = sqrt(fmax(0.0, 1.0 - z * z));
        double rho = sta_rng_uniform(rng) < 0.75 ? sta_rng_range(rng, 0.7, 1.0)
                                                 : 0.8 * cbrt(sta_rng_uniform(rng));
        rho *= 1.0 + 0.15 * sin(3.0 * phi + lobe_a) * sin(2.0 * acos(z) + lobe_b);
        double *c = t->clusters[i];
        c[0] = s + t->radius_h * rho * xy * cos(phi);
        c[1] = t->v + t->radius_h * rho * xy * sin(phi);
        c[2] = t->centre[2] + t->radius_v * rho * z;
        c[3] = sta_rng_range(rng, 0.22, 0.4);
        street_box cb;
        box_set(&cb, c[0] - c[3], c[0] + c[3], c[1] - c[3], c[1] + c[3], c[2] - c[3], c[2] + c[3]);
        box_grow(&t->bounds, &cb);
    }
    // Sorted along s, so a ray crossing the crown tests only the clusters near its s range.
    qsort(t->clusters, (size_t)t->cluster_count, sizeof(t->clusters[0]), compare_cluster_s);
    street_box trunk;
    box_set(&trunk, s - t->trunk_r, s + t->trunk_r, t->v - t->trunk_r, t->v + t->trunk_r,
            cfg->sidewalk_z_m, t->centre[2]);
    box_grow(&t->bounds, &trunk);
}

static void make_trees(const street_config *cfg, sta_rng *rng, double pole_s, street_side *side)
{
    int wanted = sta_rng_uniform(rng) < 0.5 ? 1 : 2;
    side->tree_count = 0;
    for (int attempt = 0; attempt < 8 && side->tree_count < wanted; attempt++) {
        double s = sta_rng_range(rng, 6.0, STREET_BLOCK_M - 6.0);
        bool ok = fabs(s - pole_s) >= 4.0;
        for (int i = 0; i < side->tree_count; i++) {
            ok = ok && fabs(s - side->trees[i].s) >= 9.0;
        }
        if (ok) {
            make_tree(cfg, rng, s, &side->trees[side->tree_count++]);
        }
    }
}

static void make_car(const street_config *cfg, double s0, double length, street_car *car)
{
    const double width = 1.8;
    double v0 = cfg->road_half_m - 0.25 - width;
    double base = -cfg->cross_slope * (v0 + 0.5 * width);
    box_set(&car->parts[0], s0, s0 + length, v0, v0 + width, base + 0.3, base + 1.0);
    box_set(&car->parts[1], s0 + 0.22 * length, s0 + 0.78 * length, v0 + 0.1, v0 + width - 0.1,
            base + 1.0, base + 1.45);
    const double axles[2] = { s0 + 0.8, s0 + length - 0.8 };
    for (int i = 0; i < 4; i++) {
        double sc = axles[i / 2];
        double vs = (i % 2 == 0) ? v0 : v0 + width - 0.22;
        box_set(&car->parts[2 + i], sc - 0.33, sc + 0.33, vs, vs + 0.22, base, base + 0.66);
    }
    car->bounds = car->parts[0];
    for (int i = 1; i < 6; i++) {
        box_grow(&car->bounds, &car->parts[i]);
    }
}

static void make_cars(const street_config *cfg, sta_rng *rng, street_side *side)
{
    side->car_count = 0;
    double s = sta_rng_range(rng, 1.5, 4.0);
    while (side->car_count < STREET_MAX_CARS) {
        double length = sta_rng_range(rng, 4.0, 4.9);
        if (s + length > STREET_BLOCK_M - 1.5) {
            break;
        }
        if (sta_rng_uniform(rng) < 0.65) {
            make_car(cfg, s, length, &side->cars[side->car_count++]);
            s += length + sta_rng_range(rng, 0.8, 3.0);
        } else {
            s += sta_rng_range(rng, 4.0, 8.0);
        }
    }
}

static void make_side(const street_config *cfg, int64_t b, int side_index, const block_poles *poles,
                      street_side *side)
{
    sta_rng rng;
    sta_rng_seed(&rng, sta_hash2(cfg->seed ^ KEY_SIDE, 2u * (uint64_t)b + (uint64_t)side_index));
    make_buildings(cfg, &rng, side);
    make_trees(cfg, &rng, poles->s, side);
    make_cars(cfg, &rng, side);
    side->pole_s = poles->s;
    side->pole_v = poles->v;
    side->pole_r = poles->r;
    side->pole_top = poles->top;
    side->v_min = cfg->road_half_m;
    side->v_min = fmin(side->v_min, side->pole_v - side->pole_r);
    for (int i = 0; i < side->tree_count; i++) {
        side->v_min = fmin(side->v_min, side->trees[i].bounds.lo[1]);
    }
    for (int i = 0; i < side->car_count; i++) {
        side->v_min = fmin(side->v_min, side->cars[i].bounds.lo[1]);
    }
}

/* A sagging wire between two local points, stored in frame f. */
static void make_wire(const street_frame *f, const double a[3], const double b[3], double sag,
                      double radius, uint64_t id, street_wire *w)
{
    w->radius_m = radius;
    w->id = id;
    for (int i = 0; i <= STREET_WIRE_SEGMENTS; i++) {
        double x = (double)i / STREET_WIRE_SEGMENTS;
        double p[3];
        for (int k = 0; k < 3; k++) {
            p[k] = a[k] + x * (b[k] - a[k]);
        }
        p[2] -= sag * 4.0 * x * (1.0 - x);
        double su[2];
        local_to_frame(f, p, su);
        w->points[i][0] = su[0];
        w->points[i][1] = su[1];
        w->points[i][2] = p[2];
        street_box pb;
        box_set(&pb, su[0] - radius, su[0] + radius, su[1] - radius, su[1] + radius, p[2] - radius,
                p[2] + radius);
        if (i == 0) {
            w->bounds = pb;
        } else {
            box_grow(&w->bounds, &pb);
        }
    }
}

static uint64_t wire_id(int64_t owner, unsigned index)
{
    return ((uint64_t)(uint32_t)(int32_t)owner << 32) | (6u << 24) | index;
}

/* Local position of the top of block b's pole on side sigma, minus `drop`. */
static void pole_top_local(const street_config *cfg, int64_t b, double sigma, double drop,
                           double out[3])
{
    block_poles poles;
    poles_of(cfg, b, &poles);
    street_frame f;
    sta_street_frame(cfg, b, &f);
    frame_to_local(&f, poles.s, sigma * poles.v, out);
    out[2] = poles.top - drop;
}

static void make_wires(const street_config *cfg, int64_t b, street_block *blk)
{
    const street_frame *f = &blk->frame;
    double a[3], c[3];
    pole_top_local(cfg, b, 1.0, 0.3, a);
    pole_top_local(cfg, b, -1.0, 0.3, c);
    make_wire(f, a, c, 0.25, 0.012, wire_id(b, 0), &blk->wires[0]);
    for (int side = 0; side < 2; side++) {
        double sigma = side == 0 ? 1.0 : -1.0;
        double here[3], next[3], prev[3];
        pole_top_local(cfg, b, sigma, 0.1, here);
        pole_top_local(cfg, b + 1, sigma, 0.1, next);
        pole_top_local(cfg, b - 1, sigma, 0.1, prev);
        make_wire(f, here, next, 0.45, 0.015, wire_id(b, 1u + (unsigned)side),
                  &blk->wires[1 + side]);
        make_wire(f, prev, here, 0.45, 0.015, wire_id(b - 1, 1u + (unsigned)side),
                  &blk->wires[3 + side]);
    }
    blk->wire_count = 5;
}

/* Bins [first, last] covered by s range [lo, hi] (clamped to the block). */
static void bin_range(double lo, double hi, int *first, int *last)
{
    double a = floor(lo), z = floor(hi);
    *first = a < 0.0 ? 0 : (a > STREET_BINS - 1 ? STREET_BINS - 1 : (int)a);
    *last = z < 0.0 ? 0 : (z > STREET_BINS - 1 ? STREET_BINS - 1 : (int)z);
}

static void mark_bins(uint16_t *bins, double lo, double hi, unsigned bit)
{
    int first, last;
    bin_range(lo, hi, &first, &last);
    for (int i = first; i <= last; i++) {
        bins[i] = (uint16_t)(bins[i] | (1u << bit));
    }
}

static void make_bins(street_block *blk)
{
    for (int side = 0; side < 2; side++) {
        street_side *sd = &blk->sides[side];
        memset(sd->bins, 0, sizeof(sd->bins));
        for (int i = 0; i < sd->building_count; i++) {
            const street_box *b = &sd->buildings[i].box;
            mark_bins(sd->bins, b->lo[0], b->hi[0], (unsigned)i);
        }
        for (int i = 0; i < sd->tree_count; i++) {
            const street_box *b = &sd->trees[i].bounds;
            mark_bins(sd->bins, b->lo[0], b->hi[0], 4u + (unsigned)i);
        }
        for (int i = 0; i < sd->car_count; i++) {
            const street_box *b = &sd->cars[i].bounds;
            mark_bins(sd->bins, b->lo[0], b->hi[0], 6u + (unsigned)i);
        }
        mark_bins(sd->bins, sd->pole_s - sd->pole_r, sd->pole_s + sd->pole_r, 10u);
    }
    uint16_t wires[STREET_BINS] = { 0 };
    for (int i = 0; i < blk->wire_count; i++) {
        mark_bins(wires, blk->wires[i].bounds.lo[0], blk->wires[i].bounds.hi[0], (unsigned)i);
    }
    for (int i = 0; i < STREET_BINS; i++) {
        blk->wire_bins[i] = (uint8_t)wires[i];
    }
}

static void make_block(const street_config *cfg, int64_t b, street_block *blk)
{
    blk->index = b;
    sta_street_frame(cfg, b, &blk->frame);
    block_poles poles;
    poles_of(cfg, b, &poles);
    make_side(cfg, b, 0, &poles, &blk->sides[0]);
    make_side(cfg, b, 1, &poles, &blk->sides[1]);
    make_wires(cfg, b, blk);
    double top = cfg->sidewalk_z_m;
    for (int side = 0; side < 2; side++) {
        const street_side *sd = &blk->sides[side];
        top = fmax(top, sd->pole_top);
        for (int i = 0; i < sd->building_count; i++) {
            top = fmax(top, sd->buildings[i].box.hi[2]);
        }
        for (int i = 0; i < sd->tree_count; i++) {
            top = fmax(top, sd->trees[i].bounds.hi[2]);
        }
    }
    for (int i = 0; i < blk->wire_count; i++) {
        top = fmax(top, blk->wires[i].bounds.hi[2]);
    }
    blk->top_m = top + 0.01;
    make_bins(blk);
    blk->valid = true;
}

const street_block *sta_street_block(sta_street *street, int64_t b)
{
    street_block *slot = &street->cache[(uint64_t)b % STREET_CACHE_BLOCKS];
    if (!slot->valid || slot->index != b) {
        make_block(&street->cfg, b, slot);
    }
    return slot;
}

const street_frame *sta_street_cached_frame(sta_street *street, int64_t b)
{
    street_frame_slot *slot = &street->frames[(uint64_t)b % STREET_CACHE_FRAMES];
    if (!slot->valid || slot->index != b) {
        sta_street_frame(&street->cfg, b, &slot->frame);
        slot->index = b;
        slot->valid = true;
    }
    return &slot->frame;
}

sta_status sta_street_create(uint64_t seed, double length_m, sta_street **out_street,
                             sta_error *err)
{
    *out_street = NULL;
    if (!(length_m >= 0.0) || length_m > 1e9) {
        return sta_fail(err, STA_ERR_ARG, "street length %g m out of range (0 .. 1e9)", length_m);
    }
    sta_street *street = sta_calloc(1, sizeof(*street));
    if (!street) {
        return sta_fail(err, STA_ERR_NOMEM, "out of memory for the street scene");
    }
    sta_street_config_init(&street->cfg, seed);
    street->first_block = -1;
    street->last_block = sta_street_block_of(length_m) + 1;
    *out_street = street;
    return STA_OK;
}

void sta_street_destroy(sta_street *street)
{
    sta_free(street);
}
