/* SPDX-License-Identifier: MIT
 * Per-chunk normals from cell moments: level by level, each waiting point takes the box of
 * its nearest grid vertex (one fit shared by the box's points), oriented, its radius from
 * the box's density. */
#include "moment_normals.h"

#include <math.h>
#include <string.h>

#include "box_plane.h"
#include "cell_blocks.h"
#include "cell_moments.h"
#include "cell_order.h"
#include "core/alloc.h"
#include "core/octahedral.h"
#include "cylinder_fit.h"
#include "key_slots.h"
#include "normal_fit.h"
#include "quadric_fit.h"
#include "sphere_fit.h"

/* Vertex boxes a level's table starts with (it grows), a power of two. */
#define FIRST_VERTICES         4096
#define AXIS_MASK              (((uint64_t)1 << STA_MOMENTS_AXIS_BITS) - 1)
/* Per point: done, waiting for its level, or growing (takes the next level whatever it
 * holds: its box was nearly linear, edge-on or degenerate). */
#define STATE_WAIT             0
#define STATE_GROW             1
#define STATE_DONE             2
#define STATE_CANDIDATE        3 /* + the levels it moved up for a flatter box */
/* A base-level candidate that skipped its base box and whose second step up is decided
 * too (skips_base): it takes the box two levels up without deciding one level up. */
#define STATE_JUMP             (STATE_CANDIDATE + STEPS + 1)
#define STATE_MASK             0x7f
/* Flag in a state byte: the point is the first of its base cell's run (the own points are
 * in the Morton order of their base cells: a cell's points come together). */
#define RUN_START              0x80
/* A byte's value times this: it in each of a word's 8 bytes (the passes' skip of 8 points). */
#define STATE_BYTES            0x0101010101010101ull
/* A candidate moves up at most this many levels for a flatter box. */
#define STEPS                  2
/* The base cells are 1/2 to 1 times this many mean spacings wide (the spacing of the
 * scene's points spread over its two widest extents; STA_NORMALS_MOMENTS_FINE: half). On
 * the 20 M street (spacing 62 mm: cells of 128 mm, fine 64 mm) fine took 1.6x the CPU
 * and 1.8x the memory for curbs' and cars' p95 of 24 and 34 degrees against 48 and 53
 * (the 12-16 cm curb face inside the boxes); 1 spacing (cells of 32 mm there) gave worse
 * roads (boxes of 10 points on one scan line). The default's adaptive fine level now
 * takes half-size cells only around rough points (ROUGH_VARIATION). */
#define BASE_CELL_SPACINGS     4.0
/* A candidate moves to the next level's box only when its normal is within this (cosine:
 * 10 degrees) of this level's: the same surface, flatter (on a curb face the wider box is
 * flatter, but the road's). 4 M street (docs/BENCHMARKS.md, twelfth round): 0.94 -> 0.985
 * took poles' median from 17 to 14 degrees and trees', cars' and curbs' p95 down 0.4-0.9;
 * trees' median 3.10 -> 3.24. */
#define AGREE                  0.985
/* The blend leaves out the vertex boxes whose normal is more than this (cosine: 30
 * degrees) from the point's nearest box's: another surface, an edge is not smoothed. Where
 * the nearest box is flat (surface variation at most SPHERE_VARIATION) BLEND_AGREE_FLAT
 * (8 degrees): a flat box's normal is already right, and the blend only pulled in the
 * tilted boxes across an edge (4 M street: cars' median 1.96 -> 0.69 degrees, buildings'
 * 0.46 -> 0.33, roads' p95 2.0 -> 1.06). (A looser 0.7 above a variation of 0.1 took
 * cars' p95 from 33.4 to 32.9 but turned more road points at curbs down: dropped.) */
#define BLEND_AGREE            0.87
#define BLEND_AGREE_FLAT       0.99
/* Scanned surfaces are sampled more evenly than uniform random points (profiles, a
 * lattice): their mean distance to the 10 nearest is larger than the uniform expectation
 * at the same density. On the 4 M street the exact kNN radius is 1.18-1.22x the uniform
 * estimate (roads, walls, cars, trees), on a square lattice 1.11x, on strata-synth's
 * uniform sphere 1.03x; this factor sits between (without it the splats left gaps between
 * the profiles of sparse walls). */
#define EVENNESS               1.15
/* The base cells' table starts with room for one cell this many points (it grows when
 * more): the 4 M street's chunks had one cell for 4 to 15 points, autzen's 1 for 11. */
#define POINTS_PER_BASE_CELL   16
/* Records asked for this many points ahead of the pass (their GPS time, their SPLAT). */
#define PREFETCH               8
/* Positions asked for this many points ahead when they are read in cell order. */
#define POSITIONS_AHEAD        16
/* Newton steps for the smallest eigenvalue (surface_variation). */
#define VARIATION_STEPS        6
/* The mean distance to the nearest j of points on a line `spacing` apart: for j = 10, the
 * nearest two at each of 1..5 spacings. */
#define LINE_RADIUS_SPACINGS   3.0
/* A box whose surface variation exceeds SPHERE_VARIATION is not flat: its points take the
 * normal of its algebraic sphere (sphere_fit.h) at them where the sphere fits better than
 * SPHERE_BETTER times the plane (a leaf cluster, a pole's side; not an edge, which neither
 * fits well), and above SPHERE_SCALE_VARIATION the scale's flatness test compares its
 * sphere's residual (a leaf cluster's box is not left for a wider one that only looks
 * flatter). 4 M street (docs/BENCHMARKS.md, tenth round): trees 5.6 / 42 degrees -> 3.1 /
 * 37 with the adaptive level below; SPHERE_BETTER 1 lost the buildings' p95 (8.3 -> 9.3).
 * Above ROUGH_VARIATION the sphere must fit better (SPHERE_BETTER_ROUGH): twelfth round,
 * curbs' p95 22.8 -> 21.9 degrees, cars' 34.0 -> 33.4, trees' median unchanged (0.4
 * everywhere took trees' median from 3.24 to 3.58; 0.3 above ROUGH_VARIATION lost cars). */
#define SPHERE_VARIATION       0.005
#define SPHERE_SCALE_VARIATION 0.02
#define SPHERE_BETTER          0.5
#define SPHERE_BETTER_ROUGH    0.4
/* A slightly rough box (surface variation above SPHERE_SCALE_VARIATION, at most
 * ROUGH_VARIATION) at the base level or above takes its sphere wherever the sphere fits
 * better than the plane (SPHERE_BETTER_SLIGHT); SPHERE_BETTER kept half the leaf clusters'
 * and poles' such boxes in the planes' blend, which fits a plane across a pole.
 * Thirteenth round, second part (4 M street): poles' p95 44.5 -> 33.8 degrees, trees'
 * 24.7 -> 23.9; buildings' p95 6.7 -> 7.3, cars' 31.9 -> 32.9 (docs/BENCHMARKS.md). The
 * adaptive fine level's boxes keep SPHERE_BETTER: there 1.2 lost trees' p95. */
#define SPHERE_BETTER_SLIGHT   1.0
/* Above the base level a rough box (variation above ROUGH_VARIATION) takes its sphere where
 * it fits better than the plane too (SPHERE_BETTER_ABOVE; at the base level the quadric
 * and SPHERE_BETTER_ROUGH decide): sparse leaf points that reach such boxes had the
 * planes' blend, 80-99 % of them more than 20 degrees off (4 M street). With the start
 * below and the no-growing rule of finish_level (before FLAT_ENOUGH), 20 M street: trees'
 * p95 20.62 -> 20.57 degrees, cars' 31.42 -> 31.77, curbs' 20.64 -> 21.05. */
#define SPHERE_BETTER_ABOVE    1.0
/* The default method's adaptive fine level: a base cell holding an own point whose nearest
 * base box's surface variation exceeds this is rough (a curb's step, a car's edge,
 * foliage); its points first try the boxes of half-size cells, as moments-fine does
 * everywhere. 4 M street: curbs' p95 47 -> 24 degrees, cars' 50 -> 35; 0.08 lost cars and
 * poles, 0.03 took more CPU for the same. */
#define ROUGH_VARIATION        0.05
/* A rough point's base box (surface variation above ROUGH_VARIATION) takes its quadric's
 * gradient at the point (quadric_fit.h; the box's moment tensors are summed in fine_pass,
 * around the rough points only) where the quadric's residual is under QUADRIC_BETTER
 * times the plane's surface variation and the sphere's residual, and the gradient there
 * is at least QUADRIC_GRADIENT times its root mean square over the box (not near an
 * edge's line, where it vanishes). A quadric holds a box's two faces across an edge and a
 * pole's or trunk's cylinder. Thirteenth round of docs/BENCHMARKS.md (20 M street): cars'
 * p95 34.5 -> 33.8 degrees, trees' 33.3 -> 31.2, curbs' 23.4 -> 20.8; the quadric at the
 * adaptive fine level too (guided or not) lost cars and poles: its boxes hold too few
 * points for 9 unknowns against 15 mm of range noise. */
#define QUADRIC_BETTER         0.5
#define QUADRIC_GRADIENT       0.3
/* A candidate does not move up to a box whose spread along its widest axis exceeds
 * ELONGATED times that along its second (a pole's, a strip's) when this level's box is
 * not elongated: the surface variation of a long box over a pole is small however badly
 * its plane fits across the pole (thirteenth round: poles' p95 50.7 -> 47.1 degrees on
 * the 20 M street, trees' 31.2 -> 30.9). */
#define ELONGATED              3.0
/* A candidate of the default method does not move up to a box whose surface variation
 * exceeds FLAT_ENOUGH: a wider box that is not flat either straddles leaf clusters (its
 * sphere's residual can still be smaller than this level's). Thirteenth round, second
 * part (20 M street, with the start below, SPHERE_BETTER_ABOVE and degenerate boxes grown
 * until they fit): trees' p95 20.57 -> 20.35 degrees, buildings' 7.96 -> 7.11; 0.01 took
 * the analytic planes' p95 to 5.9 degrees (a box at two planes' edge cannot move up),
 * 0.0125 gives 1.46, 0.02 trees 20.39 (docs/BENCHMARKS.md). */
#define FLAT_ENOUGH            0.0125
/* The default method's candidates need a next-level cell of this share of K (--knn)
 * points, at least NEED_LEAST (K = 10: 1, every point starts at its first level): sparse
 * leaf clusters (a crown's far sides) otherwise wait for 0.5-1 m boxes across several
 * clusters. Thirteenth round (20 M street, K 10 -> 4): trees' p95 30.9 -> 24.0 degrees,
 * poles' 47.1 -> 44.2, cars' 33.7 -> 32.9, buildings' 7.4 -> 7.0; its second part, with
 * the other rules of that part: 4 -> 1 took trees' p95 from 22.04 to 20.62, buildings'
 * from 7.54 to 7.95 (docs/BENCHMARKS.md). */
#define NEED_SHARE             0.1
#define NEED_LEAST             1
/* A point whose box is not flat (surface variation above SPHERE_VARIATION) takes the
 * normal of the cylinder (cylinder_fit.h) of its box CYLINDER_LEVELS_UP levels above the
 * base where that box is elongated (its spread along its widest axis over that along its
 * second above ELONGATED: a pole, a trunk), its cylinder fits it (root mean square
 * distance under CYLINDER_RMS times its radius, the radius under CYLINDER_RADIUS times
 * the box's cell edge) and passes near the point (within CYLINDER_NEAR times its radius:
 * not the ground at a pole's foot); the normal where the point's ray from the scanner
 * enters the cylinder (or radial where the scanner is not known). Before any other model:
 * on a pole of 0.22 m the base boxes (0.256 m on the street) neither follow the cylinder
 * with a sphere nor with a plane. Fifteenth round of docs/BENCHMARKS.md (20 M street):
 * poles 11.10 / 32.52 degrees -> 2.20 / 14.25, trees 2.940 / 20.35 -> 2.913 / 20.09;
 * CYLINDER_RMS 0.2 or a radius up to a cell edge lost cars' p95 (31.3 -> 31.7, 33.7 on
 * the 4 M street); 0.1 left most pole boxes out. */
#define CYLINDER_LEVELS_UP     1
#define CYLINDER_RMS           0.15
#define CYLINDER_RADIUS        0.5
#define CYLINDER_NEAR          0.5
/* The default method's widest boxes: cells this many levels above the base. A candidate
 * moves up at most STEPS levels; one more (STA_MOMENTS_LEVELS_ABOVE_BASE, moments-fine's)
 * served only the points grown once more from there (edge-on, nearly linear or degenerate
 * boxes two levels up: 2 % of the 4 M street's points) and took a halo twice as wide.
 * Seventeenth round of docs/BENCHMARKS.md (20 M street, with skips_base): the halo's
 * points and the temporary file's halos halved, no class worse (curbs' p95 21.05 -> 20.71
 * degrees, buildings' 7.30 -> 7.06); 374 instead of 4 points take the fallback (a box of
 * fewer than 3 points, or no plane, at the widest level: strays). */
#define LEVELS_ABOVE           2

/* The adaptive fine level's marks reserved for each base cell holding rough points (its 27
 * neighbours, less those marked for the cell before it: 6 to 24 a cell in the 4 M street's
 * chunks, 9 over all; the set grows past it). */
#define MARKS_PER_RUN 10

/* A cell coordinate no cell has (fine_pass's "none marked yet"). */
#define NO_CELL (INT64_MIN / 4)

/* Cylinder fits kept by their box's vertex: a pass meets a base cell's 8 octants' vertices
 * in turn (a power of two, at least 64). */
#define CYLINDER_SLOTS 1024

/* A cylinder fitted to the box of vertex v (cylinder_normal). */
typedef struct cylinder_slot {
    int64_t v[3];
    int state; /* 0: empty, 1: fitted, 2: none */
    sta_cylinder fit;
} cylinder_slot;

/* The moments of the 2 x 2 x 2 cells around a grid vertex, centred. */
typedef struct vertex_box {
    double n;
    double m2[6];     /* sum of (d - mean)(d - mean)^T over the points, grid units^2 */
    double variation; /* surface variation, < 0 until computed */
    int fit;          /* 0: not fitted yet, 1: a plane, 2: none (degenerate) */
    int32_t radius;   /* box_radius as packed (a half float), < 0 until computed: once a box */
    double normal[3], w[3];
    double mean[3];  /* the points' mean, grid units from the box's corner */
    int sphere_fit;  /* 0: not fitted yet, 1: a sphere, 2: none */
    float sphere[6]; /* fitted: the sphere's u[3], u4, residual, spread */
    int32_t quadric; /* 0: not fitted yet, -1: none, else 1 + its place in box_quadrics */
} vertex_box;

/* The quadrics of the base level's boxes around the rough points (quadric_normal;
 * fine_pass), each from its box's moment tensors, summed from its points (box_tensors). */
typedef struct box_quadrics {
    int level;       /* the boxes' */
    size_t own_hint; /* where the last search in the own points ended */
    sta_quadric *fits;
    size_t used, capacity;
} box_quadrics;

/* One level's vertex boxes, computed when first wanted: open addressing over the keys,
 * the boxes themselves in the order they were made (the points come in cell order, so a
 * point's boxes lie near each other in memory, not in random slots). */
typedef struct vertex_table {
    size_t capacity, used, box_capacity; /* slots (a power of two), boxes, room for boxes */
    uint64_t *keys;                      /* 0: empty, else packed vertex coordinates + 1 */
    uint32_t *index;                     /* per slot: its box */
    vertex_box *boxes;
} vertex_table;

static bool table_init(vertex_table *t, size_t capacity, size_t box_capacity)
{
    t->capacity = capacity;
    t->used = 0;
    t->box_capacity = box_capacity;
    t->keys = sta_calloc(capacity, sizeof(*t->keys));
    t->index = sta_alloc_array(capacity, sizeof(*t->index));
    t->boxes = sta_alloc_array(box_capacity, sizeof(*t->boxes));
    return t->keys && t->index && t->boxes;
}

static void table_release(vertex_table *t)
{
    sta_free(t->keys);
    sta_free(t->index);
    sta_free(t->boxes);
    memset(t, 0, sizeof(*t));
}

// Twice the slots (the boxes stay where they are).
static bool table_grow(vertex_table *t)
{
    void *const values[] = { t->index };
    const size_t sizes[] = { sizeof(*t->index) };
    void *grown[1];
    if (!sta_key_slots_double(&t->keys, &t->capacity, values, sizes, grown, 1)) {
        return false;
    }
    t->index = grown[0];
    return true;
}

// The moments of the 8 cells around vertex v (cell coordinates from the scene corner),
// centred: from their exact integer sums, so the box is the same bits whatever the
// chunking. (Offsets from the block's corner stay under 2^17 units: the cancellation in
// s2 - s1 s1^T / n loses ~2^-53 n 2^34, far below a grid unit squared times n.) Not the
// sphere's higher sums: few boxes need them (box_sphere probes the cells again then).
static void vertex_moments(const sta_cell_blocks *cells, const int64_t v[3], vertex_box *box)
{
    sta_moment_sums sum;
    sta_cell_blocks_vertex_lower(cells, v, &sum);
    int64_t n = sum.n;
    const int64_t *s1 = sum.s1, *s2 = sum.s2;
    memset(box, 0, sizeof(*box));
    box->variation = -1.0;
    box->radius = -1;
    if (n == 0) {
        return;
    }
    double nd = (double)n;
    box->n = nd;
    for (int r = 0, t = 0; r < 3; r++) {
        for (int q = r; q < 3; q++, t++) {
            box->m2[t] = (double)s2[t] - (double)s1[r] * (double)s1[q] / nd;
        }
    }
    for (int a = 0; a < 3; a++) {
        box->mean[a] = (double)s1[a] / nd;
    }
}

// Vertex v's box, computed when first asked for; NULL when out of memory.
static vertex_box *vertex_at(vertex_table *t, const sta_cell_blocks *cells, const int64_t v[3])
{
    uint64_t key = 1;
    for (int a = 0; a < 3; a++) {
        // Vertices of the points' cells lie inside the set's addressable range (its base is
        // at least one cell below the lowest, cell_blocks.h).
        key += (uint64_t)(v[a] - cells->base[a]) << (a * STA_MOMENTS_AXIS_BITS);
    }
    size_t s = sta_key_slot(t->keys, t->capacity, key);
    if (t->keys[s] == 0) {
        if (2 * (t->used + 1) > t->capacity) {
            if (!table_grow(t)) {
                return NULL;
            }
            s = sta_key_slot(t->keys, t->capacity, key);
        }
        if (t->used == t->box_capacity) { // (moves the boxes: callers copy what they keep)
            if (t->used >= UINT32_MAX / 2) {
                return NULL;
            }
            vertex_box *boxes = sta_realloc_array(t->boxes, 2 * t->box_capacity, sizeof(*boxes));
            if (!boxes) {
                return NULL;
            }
            t->boxes = boxes;
            t->box_capacity *= 2;
        }
        t->keys[s] = key;
        t->index[s] = (uint32_t)t->used;
        vertex_moments(cells, v, &t->boxes[t->used++]);
    }
    return &t->boxes[t->index[s]];
}

// Mean distance to the nearest STA_NORMALS_RADIUS_K of uniform points at unit density on a
// plane, times sqrt(pi): sum of Gamma(j + 1/2) / Gamma(j), j = 1..K, over K.
static double plane_radius_factor(void)
{
    double sum = 0.0;
    for (int j = 1; j <= STA_NORMALS_RADIUS_K; j++) {
        sum += exp(lgamma(j + 0.5) - lgamma(j));
    }
    return sum / STA_NORMALS_RADIUS_K;
}

// The radius from a box's fit: the expected mean distance to the nearest
// STA_NORMALS_RADIUS_K at the density of its points on the fitted plane (its area from the
// spread within the plane: a uniform rectangle's variances are a^2/12 and b^2/12), or on
// its line when that is larger (a wire, a single scan line).
static double box_radius(double count, const double w[3], double factor)
{
    if (!(count >= 2.0) || !(w[2] > 0.0)) {
        return 0.0;
    }
    double var1 = fmax(w[1], 0.0) / count, var2 = w[2] / count;
    double area = 12.0 * sqrt(var1 * var2);
    double plane =
        area > 0.0 ? EVENNESS * factor / sqrt(3.14159265358979323846 * count / area) : 0.0;
    double line = LINE_RADIUS_SPACINGS * sqrt(12.0 * var2) / count;
    return plane > line ? plane : line;
}

// How far in metres the boxes of the 8 vertices of its cell at `level` (the cells from
// one below to one above its own) reach from grid point u (from the scene corner) along
// any axis.
static double box_reach(const sta_normals_chunk *chunk, const int64_t u[3], int level)
{
    double reach = 0.0;
    for (int a = 0; a < 3; a++) {
        int64_t c = u[a] >> level, cell = (int64_t)1 << level;
        int64_t lo = (c - 1) * cell, hi = (c + 2) * cell; // (c - 1 may be -1: no shift)
        double d = (double)(u[a] - lo > hi - u[a] ? u[a] - lo : hi - u[a]) * chunk->scale[a];
        reach = d > reach ? d : reach;
    }
    return reach;
}

// One level's cells and the vertex boxes computed from them so far.
typedef struct level_boxes {
    const sta_cell_blocks *cells;
    vertex_table table;
    int64_t last[3];      /* the vertex last asked for by nearest_box, */
    vertex_box *last_box; /* its box (NULL: none) */
    size_t last_capacity; /* and the table's room for boxes then (more moves them) */
    bool corners_valid;   /* the normals of the 8 vertex boxes of cell `corner_cell` */
    int64_t corner_cell[3];
    bool corner_ok[8];
    double corner_normal[8][3];
} level_boxes;

static bool level_init(level_boxes *l, const sta_cell_blocks *cells)
{
    size_t expect = (size_t)FIRST_VERTICES;
    while (expect < cells->used && expect < ((size_t)1 << 40)) {
        expect *= 2;
    }
    l->cells = cells;
    l->last_box = NULL;
    l->corners_valid = false;
    size_t boxes = cells->used > FIRST_VERTICES ? cells->used : FIRST_VERTICES;
    if (!table_init(&l->table, expect, boxes)) {
        table_release(&l->table);
        return false;
    }
    return true;
}

// The surface variation of a box (Pauly et al.): its smallest eigenvalue over the sum,
// the smallest root of the characteristic polynomial by Newton's method from 0 (below
// the root the polynomial is convex and falling: it converges from below, without the
// eigenvectors' cost).
static double surface_variation(const sta_normals_chunk *chunk, const double m2[6])
{
    const double *s = chunk->scale;
    double a = m2[0] * s[0] * s[0], b = m2[1] * s[0] * s[1], c = m2[2] * s[0] * s[2];
    double d = m2[3] * s[1] * s[1], e = m2[4] * s[1] * s[2], f = m2[5] * s[2] * s[2];
    double c2 = a + d + f, c1 = a * d + a * f + d * f - b * b - c * c - e * e;
    double c0 = a * (d * f - e * e) - b * (b * f - c * e) + c * (b * e - c * d);
    if (!(c2 > 0.0)) {
        return 1.0;
    }
    double x = 0.0;
    for (int i = 0; i < VARIATION_STEPS && c0 > 0.0; i++) {
        double p = ((-x + c2) * x - c1) * x + c0, dp = (-3.0 * x + 2.0 * c2) * x - c1;
        if (!(dp < 0.0)) {
            break;
        }
        x -= p / dp;
    }
    return x / c2;
}

// The grid vertex nearest to u (grid units from the scene corner) at `level`.
static void nearest_vertex(const int64_t u[3], int level, int64_t v[3])
{
    for (int a = 0; a < 3; a++) {
        v[a] = (2 * u[a] + ((int64_t)1 << level)) >> (level + 1);
    }
}

// nearest_box's look-up where its vertex v is not the last one asked for.
static vertex_box *nearest_box_new(const sta_normals_chunk *chunk, level_boxes *l,
                                   const int64_t v[3])
{
    vertex_box *b = vertex_at(&l->table, l->cells, v);
    if (b && b->variation < 0.0) {
        b->variation = surface_variation(chunk, b->m2);
    }
    memcpy(l->last, v, sizeof(l->last));
    l->last_box = b;
    l->last_capacity = l->table.box_capacity;
    return b;
}

// The box of the grid vertex nearest to u (grid units from the scene corner) at this level,
// with its surface variation; NULL when out of memory. (Inline: most calls are the last
// vertex's again, a few instructions.)
static inline vertex_box *nearest_box(const sta_normals_chunk *chunk, level_boxes *l,
                                      const int64_t u[3])
{
    int64_t v[3];
    nearest_vertex(u, l->cells->level, v);
    if (l->last_box && l->last_capacity == l->table.box_capacity && v[0] == l->last[0] &&
        v[1] == l->last[1] && v[2] == l->last[2]) {
        return l->last_box;
    }
    return nearest_box_new(chunk, l, v);
}

// Whether box b has a plane, fitted when first asked (one solve for all its points): by
// Newton's method and a cross product where its two smallest eigenvalues are apart (most
// boxes: box_plane.h), else by Kopp's solver.
static bool box_fit(const sta_normals_chunk *chunk, vertex_box *b)
{
    if (b->fit == 0) {
        const double zero[3] = { 0, 0, 0 };
        bool fitted =
            b->n > 2.0 && (sta_box_plane(chunk->scale, b->m2, b->normal, b->w) ||
                           sta_normal_fit_moments(chunk, b->n, zero, b->m2, 0, b->normal, b->w));
        b->fit = fitted ? 1 : 2;
    }
    return b->fit == 1;
}

// Whether box b of l, u's nearest (grid units from the scene corner), is not flat and has
// an algebraic sphere (fitted when first asked, from the box's higher sums, summed from
// its cells only then); only in the default method.
static bool box_sphere(const sta_normals_chunk *chunk, const level_boxes *l, vertex_box *b,
                       const int64_t u[3])
{
    int level = l->cells->level;
    if (b->sphere_fit != 0) { // (fitted or refused before: the tests below passed then)
        return b->sphere_fit == 1;
    }
    if (chunk->method != STA_NORMALS_MOMENTS || !(b->variation > SPHERE_VARIATION) ||
        !sta_sphere_isotropic(chunk->scale)) {
        return false; // (moments-fine stays as it was: the sphere cost it edges, 20 M street)
    }
    if (b->sphere_fit == 0) {
        sta_sphere_moments m;
        sta_sphere fitted;
        sta_moment_sums higher;
        int64_t v[3];
        nearest_vertex(u, level, v);
        sta_cell_blocks_vertex_higher(l->cells, v, &higher);
        bool fits = sta_sphere_moments_higher(&higher, (double)((int64_t)2 << level), b->n, b->mean,
                                              b->m2, &m) &&
                    sta_sphere_fit(&m, &fitted);
        b->sphere_fit = fits ? 1 : 2;
        if (fits) {
            const double f[6] = { fitted.u[0], fitted.u[1],     fitted.u[2],
                                  fitted.u4,   fitted.residual, fitted.spread };
            for (int i = 0; i < 6; i++) {
                b->sphere[i] = (float)f[i];
            }
        }
    }
    return b->sphere_fit == 1;
}

// How far box b's points lie from its best model, over their spread squared: the surface
// variation, or where b is not flat its sphere's residual (the scale's flatness test: a
// leaf cluster's sphere fits its box better than a wider box's plane or sphere).
static double box_error(const sta_normals_chunk *chunk, const level_boxes *l, vertex_box *b,
                        const int64_t u[3])
{
    if (!(b->variation > SPHERE_SCALE_VARIATION)) {
        return b->variation;
    }
    return box_sphere(chunk, l, b, u) ? (double)b->sphere[4] : b->variation;
}

// Whether box b of l (u's nearest) is not flat and its sphere fits it clearly better than
// its plane (by the bound for b's surface variation and l's level against the pass's base
// level): where its points take the sphere's normal.
static bool sphere_taken(const sta_normals_chunk *chunk, const level_boxes *l, vertex_box *b,
                         const int64_t u[3], int base_level)
{
    double better = b->variation > ROUGH_VARIATION ? SPHERE_BETTER_ROUGH : SPHERE_BETTER;
    if (chunk->method == STA_NORMALS_MOMENTS && b->variation > SPHERE_SCALE_VARIATION &&
        b->variation <= ROUGH_VARIATION && l->cells->level >= base_level) {
        better = SPHERE_BETTER_SLIGHT;
    }
    if (b->variation > ROUGH_VARIATION && l->cells->level > base_level) {
        better = SPHERE_BETTER_ABOVE; // (moments-fine: box_sphere refuses)
    }
    return box_sphere(chunk, l, b, u) && (double)b->sphere[4] < better * b->variation;
}

// The normal at u of the algebraic sphere of its nearest box b, where sphere_taken; false
// when the planes' blend decides.
static bool sphere_normal(const sta_normals_chunk *chunk, const level_boxes *l, vertex_box *b,
                          const int64_t u[3], int base_level, double normal[3])
{
    int level = l->cells->level;
    // (a flat box has no sphere: box_sphere's first test, before sphere_taken's bounds)
    if (!(b->variation > SPHERE_VARIATION) || !sphere_taken(chunk, l, b, u, base_level)) {
        return false;
    }
    const float *f = b->sphere;
    sta_sphere s = { .u = { f[0], f[1], f[2] }, .u4 = f[3], .residual = f[4], .spread = f[5] };
    double p[3];
    for (int a = 0; a < 3; a++) { // u from the box's corner, one cell below its vertex
        int64_t v = (2 * u[a] + ((int64_t)1 << level)) >> (level + 1);
        p[a] = (double)(u[a] - (v - 1) * ((int64_t)1 << level)); // (v - 1 may be -1)
        s.mean[a] = b->mean[a];
    }
    return sta_sphere_normal(&s, p, normal);
}

// The normals of the boxes of the 8 grid vertices of u's cell, blended by the point's place
// in the cell (trilinear weights), each turned to agree with `normal` (its nearest box's,
// of surface variation `variation`; replaced by the blend): the normal field between the
// boxes' centres. On a curved surface
// the nearest box's centre lies up to a quarter of its edge from the point (a 0.3 m leaf
// sphere, a 15 cm box: 3.7 cm, 7 degrees); on a plane the boxes agree. False when out of
// memory.
static bool blend_normals(const sta_normals_chunk *chunk, level_boxes *l, const int64_t u[3],
                          double normal[3], double variation)
{
    // The default method's flat boxes (surface variation at most SPHERE_VARIATION) keep their
    // plane's normal: the blend moved it by little (BLEND_AGREE_FLAT) and cost the fits of
    // the vertices' boxes no point is nearest to. Fifteenth round, third part (20 M street,
    // median / p95 degrees): buildings 0.361 / 7.13 -> 0.222 / 7.17, cars' median 0.673 ->
    // 0.601, curbs' 0.098 -> 0.090, roads 0.049 / 1.03 -> 0.062 / 0.955; 7 % fewer
    // instructions on the 4 M street (docs/BENCHMARKS.md). (moments-fine stays as it was.)
    if (chunk->method == STA_NORMALS_MOMENTS && !(variation > SPHERE_VARIATION)) {
        return true;
    }
    double agree = variation > SPHERE_VARIATION ? BLEND_AGREE : BLEND_AGREE_FLAT;
    int level = l->cells->level;
    int64_t c[3];
    double f[3];
    for (int a = 0; a < 3; a++) {
        c[a] = u[a] >> level;
        f[a] = (double)(u[a] - (c[a] << level)) / (double)((int64_t)1 << level);
    }
    if (!l->corners_valid || memcmp(c, l->corner_cell, sizeof(c)) != 0) {
        for (int k = 0; k < 8; k++) {
            const int64_t v[3] = { c[0] + (k & 1), c[1] + (k >> 1 & 1), c[2] + (k >> 2) };
            vertex_box *b = vertex_at(&l->table, l->cells, v);
            if (!b) {
                l->corners_valid = false;
                return false;
            }
            l->corner_ok[k] = box_fit(chunk, b);
            memcpy(l->corner_normal[k], b->normal, sizeof(b->normal));
        }
        memcpy(l->corner_cell, c, sizeof(c));
        l->corners_valid = true;
    }
    double sum[3] = { 0, 0, 0 };
    for (int k = 0; k < 8; k++) {
        if (!l->corner_ok[k]) {
            continue;
        }
        const double *nk = l->corner_normal[k];
        double w = ((k & 1) ? f[0] : 1.0 - f[0]) * ((k >> 1 & 1) ? f[1] : 1.0 - f[1]) *
                   ((k >> 2) ? f[2] : 1.0 - f[2]);
        double dot = nk[0] * normal[0] + nk[1] * normal[1] + nk[2] * normal[2];
        if (fabs(dot) < agree) {
            continue; // another surface (an edge, a curb): not blended across
        }
        w = dot < 0.0 ? -w : w;
        for (int a = 0; a < 3; a++) {
            sum[a] += w * nk[a];
        }
    }
    double len = sqrt(sum[0] * sum[0] + sum[1] * sum[1] + sum[2] * sum[2]);
    if (len > 1e-6) {
        for (int a = 0; a < 3; a++) {
            normal[a] = sum[a] / len;
        }
    }
    return true;
}

// What one level's pass over the waiting points shares.
typedef struct moment_pass {
    const sta_normals_chunk *chunk;
    const sta_record_layout *layout;
    uint8_t *records;
    sta_normals_stats *stats;
    uint8_t *state;           /* per own point, in cell order, | RUN_START */
    const uint32_t *order;    /* the own points' records in cell order (cell_order.h) */
    const int32_t (*grid)[3]; /* their positions, in that order */
    const int32_t (*own)[3];  /* all own points' positions (box_tensors): `grid`, or the
                                 set `grid` picks from (`places`) */
    size_t own_count;
    const uint32_t *places;   /* per point of `grid` its place in `own` (NULL: the same) */
    size_t count;             /* own points */
    int base_level;           /* the runs' cells (the first pass's level) */
    uint32_t *finish;         /* scratch: the points a pass finishes, count of them */
    uint8_t *rough;           /* per own point (cell order): the adaptive fine level's */
    bool defer;               /* the base level's first pass: a new candidate whose box is
                                 rough is marked in `rough` and left waiting */
    bool only_rough;          /* only the points marked in `rough` take part */
    box_quadrics *quadrics;   /* the rough points' base pass (else NULL) */
    double need;              /* points a box must hold */
    const int32_t (*halo)[3]; /* the halo's positions in cell order (cylinder_normal) */
    size_t halo_count;
    const int32_t *corner;    /* the cell order's corner */
    size_t *halo_hint;        /* where the last search in the halo ended */
    cylinder_slot *cylinders; /* CYLINDER_SLOTS fits, NULL: no cylinders (not the default
                                 method, or no adaptive base level) */
    level_boxes *axis;        /* the boxes CYLINDER_LEVELS_UP above the base, NULL when
                                 released (the passes above them) */
    double factor;            /* plane_radius_factor() */
    level_boxes *above;       /* the boxes two levels above the base, in the base level's
                                 first pass of the default method only (else NULL):
                                 skips_base */
} moment_pass;

// Point j's grid coordinates from the scene corner.
static void point_offset(const moment_pass *m, size_t j, int64_t u[3])
{
    for (int a = 0; a < 3; a++) {
        u[a] = (int64_t)m->grid[j][a] - m->chunk->scene_min[a];
    }
}

static void box_tensors(const moment_pass *m, int level, const int64_t v[3], size_t *own_hint,
                        sta_tensor_sums *out);

// The normal at u of the quadric of its nearest box b, at m->quadrics' level (the rough
// points' base pass), where b is rough and the quadric fits it clearly
// better than its plane and sphere, and its gradient at u is not near zero (an edge's
// line). 1: `normal` set, 0: the other rules decide, -1: out of memory.
static int quadric_normal(const moment_pass *m, const level_boxes *l, vertex_box *b,
                          const int64_t u[3], double normal[3])
{
    box_quadrics *q = m->quadrics;
    int level = l->cells->level;
    if (!q || q->level != level || !(b->variation > ROUGH_VARIATION) ||
        !sta_sphere_isotropic(m->chunk->scale)) {
        return 0;
    }
    int64_t v[3];
    nearest_vertex(u, level, v);
    if (b->quadric == 0) {
        sta_tensor_sums sums;
        sta_quadric fit;
        box_tensors(m, level, v, &q->own_hint, &sums);
        b->quadric = -1;
        if (sta_quadric_fit(&sums, (double)((int64_t)2 << level), &fit)) {
            if (q->used == q->capacity) {
                size_t capacity = q->capacity ? 2 * q->capacity : FIRST_VERTICES;
                sta_quadric *fits = sta_realloc_array(q->fits, capacity, sizeof(*fits));
                if (!fits) {
                    return -1;
                }
                q->fits = fits;
                q->capacity = capacity;
            }
            q->fits[q->used++] = fit;
            b->quadric = (int32_t)q->used;
        }
    }
    if (b->quadric < 0) {
        return 0;
    }
    const sta_quadric *fit = &q->fits[b->quadric - 1];
    double best = b->variation;
    if (box_sphere(m->chunk, l, b, u) && (double)b->sphere[4] < best) {
        best = (double)b->sphere[4];
    }
    double p[3], length, n[3];
    for (int a = 0; a < 3; a++) { // u from the box's corner, one cell below its vertex
        p[a] = (double)(u[a] - (v[a] - 1) * ((int64_t)1 << level));
    }
    if (!(fit->residual < QUADRIC_BETTER * best) || !sta_quadric_normal(fit, p, n, &length) ||
        !(length > QUADRIC_GRADIENT)) {
        return 0;
    }
    memcpy(normal, n, sizeof(n));
    return 1;
}

// The key of u's part of its base cell in decide_level: `bits` bits an axis from bit
// `low` (at the base level, one bit: which half of the cell, so its nearest vertex).
static unsigned run_key(const int64_t u[3], int low, int bits)
{
    unsigned k = 0;
    for (int a = 0; a < 3; a++) {
        k |= (unsigned)(u[a] >> low & ((1 << bits) - 1)) << (a * bits);
    }
    return k;
}

// Whether a candidate at u moves up: the next level's box is flatter (less surface
// variation, or sphere residual where not flat: box_error) and its normal agrees with this
// level's; or, at the default method's adaptive fine level (below `base_level`), its box
// is not flat and would take its sphere: then it waits for the base level (quadric,
// sphere or blend there). The fine boxes are too small to tell a leaf cluster's or a
// car's curve from the range noise: 84 % of the tree points and 73 % of the car points
// that took a rough fine box's sphere were more than 20 degrees off (4 M street);
// thirteenth round, second part, for the rough fine boxes alone: cars' p95 31.9 -> 30.9
// degrees, trees' 24.7 -> 24.1, curbs' 19.4 -> 19.1, nothing worse; the slightly rough
// ones too: trees' 23.3 -> 23.1. 1 or 0; -1 when out of memory.
static int moves_up(const sta_normals_chunk *chunk, level_boxes *fine, level_boxes *coarse,
                    const int64_t u[3], int base_level)
{
    vertex_box *b = nearest_box(chunk, fine, u), *c = b ? nearest_box(chunk, coarse, u) : NULL;
    if (!c) {
        return -1;
    }
    if (chunk->method == STA_NORMALS_MOMENTS && fine->cells->level < base_level &&
        b->variation > SPHERE_SCALE_VARIATION && sphere_taken(chunk, fine, b, u, base_level)) {
        return 1;
    }
    if (chunk->method == STA_NORMALS_MOMENTS && c->variation > FLAT_ENOUGH) {
        return 0;
    }
    return box_error(chunk, coarse, c, u) < box_error(chunk, fine, b, u) && box_fit(chunk, b) &&
           box_fit(chunk, c) &&
           fabs(b->normal[0] * c->normal[0] + b->normal[1] * c->normal[1] +
                b->normal[2] * c->normal[2]) > AGREE &&
           (chunk->method != STA_NORMALS_MOMENTS || !(c->w[2] > ELONGATED * c->w[1]) ||
            b->w[2] > ELONGATED * b->w[1]); // (moments-fine stays as it was)
}

// Whether a base-level candidate at u skips its base box (default method): its box one
// level up (`one`) is nearly flat (surface variation at most FLAT_ENOUGH), has a plane, is
// not elongated, and the plane of its box two levels up (`two`) agrees with it (AGREE).
// Then it goes on from the level above as if it had moved up (moves_up's first step, a
// flatter box of the same surface, is taken for granted): on a road or a wall the base
// box is rougher than the wider one (the range noise over a smaller spread) and is never
// taken, but made and fitted for the decision. The second step is moves_up's own
// decision one level up, which these tests make too unless the upper box is elongated:
// 2 when it is made here (the point takes the box two levels up), 1 when the level above
// decides, 0 when the base box is made; -1 when out of memory.
static int skips_base(const sta_normals_chunk *chunk, level_boxes *one, level_boxes *two,
                      const int64_t u[3])
{
    vertex_box *b = nearest_box(chunk, one, u), *c = b ? nearest_box(chunk, two, u) : NULL;
    if (!c) {
        return -1;
    }
    if (!(b->variation <= FLAT_ENOUGH && c->variation < b->variation && box_fit(chunk, b) &&
          !(b->w[2] > ELONGATED * b->w[1]) && box_fit(chunk, c) &&
          fabs(b->normal[0] * c->normal[0] + b->normal[1] * c->normal[1] +
               b->normal[2] * c->normal[2]) > AGREE)) {
        return 0;
    }
    return c->w[2] > ELONGATED * c->w[1] ? 1 : 2;
}

// The decisions of one level for the points still waiting at `fine`'s level: those whose
// cell of the next level (`coarse`, NULL at the last level; the same edge as the box)
// holds enough points become candidates; a candidate whose box at the next level is
// flatter (less surface variation) and agrees waits for it, at most STEPS levels; the
// others are listed in m->finish (in order) to take this level. Above the base level a
// base cell lies inside one half of its cell of the level along each axis, so all its
// points share their nearest vertex of this level and the next, and the parent cell:
// one decision a run of a base cell's points (and a half cell at the base level), not
// one a point (the passes' visits are mostly points that only move up). Returns how many
// wait for the next level, or SIZE_MAX when out of memory; *finishing: how many listed.
static size_t decide_level(const moment_pass *m, level_boxes *fine, level_boxes *coarse,
                           size_t *finishing)
{
    int level = fine->cells->level;
    // At and below the base a base cell's points share their cell of the next level (up to
    // one level below the base), but not their nearest vertices of this level and the
    // next: these follow the bits of u from this level's half cell (level - 1; bit 0 at
    // level 0) to the base's, `bits` an axis (1 at the base, 2 at the adaptive fine level
    // below it): one decision a run and part of a base cell, keyed by those bits.
    int low = level > 0 ? level - 1 : 0, bits = level <= m->base_level ? m->base_level - low : 0;
    bool each_point = m->chunk->decide_each_point || level + 1 < m->base_level || bits > 2;
    bool keyed = bits > 0;
    size_t left = 0, listed = 0;
    int enough = -1;    // the run's next-level cell holds enough points (-1: not known yet)
    signed char up[64]; // by key (-1: not known)
    signed char rough[8] = { -1, -1, -1, -1, -1, -1, -1, -1 }; // m->defer's, by octant
    int skip = -1; // m->above's, the run's (a base cell lies in one cell of each level above)
    memset(up, -1, sizeof(up));
    for (size_t j = 0; j < m->count; j++) {
        // Eight points at once where none takes part (all done, or none rough in the rough
        // points' passes): most of the passes above the base and the rough ones.
        if ((j & 7) == 0 && j + 8 <= m->count) {
            uint64_t states, marks = 1;
            memcpy(&states, m->state + j, sizeof(states));
            if (m->only_rough) {
                memcpy(&marks, m->rough + j, sizeof(marks));
            }
            if ((states & STATE_BYTES * STATE_MASK) == STATE_BYTES * STATE_DONE || marks == 0) {
                if ((states & STATE_BYTES * RUN_START) || each_point) {
                    enough = -1; // (as below: the next point taking part starts afresh)
                    memset(up, -1, sizeof(up));
                    memset(rough, -1, sizeof(rough));
                    skip = -1;
                }
                j += 7;
                continue;
            }
        }
        uint8_t flags = m->state[j], state = flags & STATE_MASK;
        if ((flags & RUN_START) || each_point) { // a new base cell: nothing known
            enough = -1;
            memset(up, -1, sizeof(up));
            memset(rough, -1, sizeof(rough));
            skip = -1;
        }
        if (state == STATE_DONE || (m->only_rough && !m->rough[j])) {
            continue;
        }
        int64_t u[3];
        bool have_u = false;
        if (state == STATE_WAIT && coarse) {
            if (enough < 0 && m->need <= 1.0) {
                enough = 1; // (the point's own cell holds it: no look-up; the default K)
            } else if (enough < 0) {
                point_offset(m, j, u);
                have_u = true;
                int l = coarse->cells->level;
                int64_t parent[3] = { u[0] >> l, u[1] >> l, u[2] >> l };
                enough = (double)sta_cell_blocks_count(coarse->cells, parent) >= m->need;
            }
            if (!enough) {
                left++;
                continue;
            }
            state = STATE_CANDIDATE;
        }
        if (state == STATE_JUMP) { // (one level above the base: on to the next)
            m->state[j] = (uint8_t)((flags & RUN_START) | (STATE_CANDIDATE + STEPS));
            left++;
            continue;
        }
        if (m->above && coarse && state == STATE_CANDIDATE && !m->chunk->keep_base_boxes) {
            if (skip < 0) {
                if (!have_u) {
                    point_offset(m, j, u);
                    have_u = true;
                }
                skip = skips_base(m->chunk, coarse, m->above, u);
                if (skip < 0) {
                    return SIZE_MAX;
                }
            }
            if (skip) {
                uint8_t next = skip == 2 ? STATE_JUMP : STATE_CANDIDATE + 1;
                m->state[j] = (uint8_t)((flags & RUN_START) | next);
                m->stats->skipped_base++;
                left++;
                continue;
            }
        }
        if (m->defer && state == STATE_CANDIDATE) { // (at the base level: by octant)
            if (!have_u) {
                point_offset(m, j, u);
                have_u = true;
            }
            unsigned k = run_key(u, low, bits); // (bits is 1 here: an octant)
            if (rough[k] < 0) {
                vertex_box *b = nearest_box(m->chunk, fine, u);
                if (!b) {
                    return SIZE_MAX;
                }
                rough[k] = b->variation > ROUGH_VARIATION;
            }
            if (rough[k]) {
                m->rough[j] = 1; // (still waiting: the fine level first)
                left++;
                continue;
            }
        }
        if (state != STATE_GROW && coarse && state >= STATE_CANDIDATE &&
            state < STATE_CANDIDATE + STEPS) {
            unsigned k = 0;
            if (keyed || up[0] < 0) { // (above the base every point has key 0's)
                if (!have_u) {
                    point_offset(m, j, u);
                }
                k = keyed ? run_key(u, low, bits) : 0;
                if (up[k] < 0) {
                    int moved = moves_up(m->chunk, fine, coarse, u, m->base_level);
                    if (moved < 0) {
                        return SIZE_MAX;
                    }
                    up[k] = (signed char)moved;
                }
            }
            if (up[k]) {
                m->state[j] = (uint8_t)((flags & RUN_START) | (state + 1)); // flatter, same surface
                left++;
                continue;
            }
        }
        m->finish[listed++] = (uint32_t)j;
    }
    *finishing = listed;
    return left;
}

// The exact tensor sums of the own and halo points in the 2 x 2 x 2 cells of `level` (at
// or above the base) around vertex v, as offsets from the box's corner: each cell's points
// are one run of the cell order, its start found by a galloping search from *own_hint (the
// asking point's place, or where the last box's search ended; set to where this one
// ended) and, in the halo, from where the last one ended. The same sums in any chunking
// (the halo covers the boxes up to sta_moment_normals_levels_above), and the same as the
// cells' tensors moved to the box's corner (exact integer sums either way).
static void box_tensors(const moment_pass *m, int level, const int64_t v[3], size_t *own_hint,
                        sta_tensor_sums *out)
{
    const sta_normals_chunk *chunk = m->chunk;
    int base = m->base_level;
    int64_t edge = (int64_t)1 << level;
    const int32_t(*sets[2])[3] = { m->own, m->halo };
    const size_t counts[2] = { m->own_count, m->halo_count };
    size_t hints[2] = { *own_hint, *m->halo_hint };
    memset(out, 0, sizeof(*out));
    // The 8 cells in key order: each search goes on from where the last ended, a few steps.
    int64_t cells[8][3];
    uint64_t keys[8];
    int found = 0;
    for (int q = 0; q < 8; q++) {
        int64_t cell[3], first[3]; // the cell, and its first base cell from the order's corner
        bool inside = true;
        for (int a = 0; a < 3; a++) {
            cell[a] = v[a] - 1 + (q >> a & 1); // (may be -1: no shift of it)
            // (the order's corner is aligned 8 levels above the base: a cell lies wholly
            // above it, or below where no point is)
            first[a] = (cell[a] * edge + chunk->scene_min[a] - m->corner[a]) >> base;
            inside = inside && first[a] >= 0 && first[a] < ((int64_t)1 << STA_CELL_ORDER_AXIS_BITS);
        }
        if (!inside) {
            continue;
        }
        uint64_t key = sta_cell_order_key(first);
        int at = found++;
        for (; at > 0 && keys[at - 1] > key; at--) {
            keys[at] = keys[at - 1];
            memcpy(cells[at], cells[at - 1], sizeof(cells[0]));
        }
        keys[at] = key;
        memcpy(cells[at], cell, sizeof(cell));
    }
    for (int c = 0; c < found; c++) {
        const int64_t *cell = cells[c];
        for (int s = 0; s < 2; s++) {
            // The cell's run: from its first key on, while the points lie in the cell.
            size_t i =
                sta_cell_order_lower_near(sets[s], counts[s], m->corner, base, keys[c], hints[s]);
            for (; i < counts[s]; i++) {
                uint64_t d[3];
                bool in = true;
                for (int a = 0; a < 3; a++) {
                    int64_t from_corner = (int64_t)sets[s][i][a] - chunk->scene_min[a];
                    in = in && from_corner >> level == cell[a];
                    d[a] = (uint64_t)(from_corner - (v[a] - 1) * edge);
                }
                if (!in) {
                    break;
                }
                sta_tensor_sums_add(out, d);
            }
            hints[s] = i;
        }
    }
    *own_hint = hints[0];
    *m->halo_hint = hints[1];
}

// The normal at u of the cylinder of its box CYLINDER_LEVELS_UP levels above the base,
// where that box is elongated, its cylinder fits and passes near u (the constants'
// comment); at the ray's entry from the scanner `target` (grid units; NULL: unknown). j: u's
// point in the cell order (where the searches for its box's cells start).
static int cylinder_normal(const moment_pass *m, size_t j, const int64_t u[3], const double *target,
                           double normal[3])
{
    if (!m->cylinders || !m->axis || !sta_sphere_isotropic(m->chunk->scale)) {
        return 0;
    }
    // Elongated: from the level's vertex box (its lower sums are the same points'), before
    // the points are gathered for the tensors.
    vertex_box *box = nearest_box(m->chunk, m->axis, u);
    if (!box) {
        return -1;
    }
    int level = m->base_level + CYLINDER_LEVELS_UP;
    // (and narrow: points within a radius r of an axis spread at most r^2 across it)
    double reach = CYLINDER_RADIUS * (double)((int64_t)1 << level) * m->chunk->scale[0];
    if (!box_fit(m->chunk, box) || !(box->w[2] > ELONGATED * box->w[1]) ||
        !(box->w[1] < reach * reach * box->n)) {
        return 0;
    }
    int64_t v[3];
    nearest_vertex(u, level, v);
    uint64_t h = ((uint64_t)v[0] * 0x9E3779B97F4A7C15ull) ^
                 ((uint64_t)v[1] * 0xC2B2AE3D27D4EB4Full) ^
                 ((uint64_t)v[2] * 0x165667B19E3779F9ull);
    cylinder_slot *slot = &m->cylinders[(h >> 40) & (CYLINDER_SLOTS - 1)];
    if (slot->state == 0 || memcmp(slot->v, v, sizeof(v)) != 0) {
        sta_tensor_sums sums;
        size_t hint = m->places ? m->places[j] : j;
        box_tensors(m, level, v, &hint, &sums);
        memcpy(slot->v, v, sizeof(v));
        slot->state = sta_cylinder_fit(&sums, (double)((int64_t)2 << level), &slot->fit) ? 1 : 2;
    }
    const sta_cylinder *c = &slot->fit;
    double cell = (double)((int64_t)1 << level);
    if (slot->state != 1 || !(sqrt(c->residual) < CYLINDER_RMS * c->radius) ||
        !(c->radius * c->spread < CYLINDER_RADIUS * cell)) {
        return 0;
    }
    double p[3], from[3], n[3], off;
    for (int a = 0; a < 3; a++) { // u from the box's corner, one cell below its vertex
        double corner = (double)((v[a] - 1) * ((int64_t)1 << level));
        p[a] = (double)u[a] - corner;
        from[a] = target ? target[a] - (double)m->chunk->scene_min[a] - corner : 0.0;
    }
    bool fits =
        target ? sta_cylinder_normal_seen(c, p, from, n, &off) : sta_cylinder_normal(c, p, n, &off);
    if (!fits || !(off < CYLINDER_NEAR)) {
        return 0;
    }
    memcpy(normal, n, sizeof(n));
    return 1;
}

// The points decide_level listed take `fine`'s level: the nearest box's plane, unless it
// is nearly linear, edge-on or degenerate (then they take the next level once, when there
// is one), blended with the boxes of their cell's vertices, oriented, packed with the
// radius. Returns how many grew, or SIZE_MAX when out of memory.
static size_t finish_level(const moment_pass *m, level_boxes *fine, bool last, size_t listed)
{
    const sta_normals_chunk *chunk = m->chunk;
    const sta_record_layout *layout = m->layout;
    size_t grew = 0;
    bool timed = (layout->attributes & STA_ATTR_GPS_TIME) != 0;
    sta_trajectory_memo memo = { 0 };
    sta_normal_memo packed = { 0 };
    // Whether a point's boxes can reach past the margin at this level (box_reach is at most
    // 2 cells along any axis): below the top, never; the test is then not made a point.
    int level = fine->cells->level;
    double widest = 0.0;
    for (int a = 0; a < 3; a++) {
        double d = 2.0 * (double)((int64_t)1 << level) * chunk->scale[a];
        widest = d > widest ? d : widest;
    }
    bool may_pass_margin = widest > chunk->margin;
    for (size_t i = 0; i < listed; i++) {
        size_t j = m->finish[i];
        uint8_t flags = m->state[j];
        uint8_t *record = m->records + (size_t)m->order[j] * layout->size;
        const int32_t *p = m->grid[j];
        if (i + PREFETCH < listed) { // (records lie in input order: a miss each)
            __builtin_prefetch(m->records +
                               (size_t)m->order[m->finish[i + PREFETCH]] * layout->size);
        }
        int64_t u[3];
        point_offset(m, j, u);
        bool grow = (flags & STATE_MASK) == STATE_GROW;
        vertex_box *b = nearest_box(chunk, fine, u);
        if (!b) {
            return SIZE_MAX;
        }
        box_fit(chunk, b);
        if (b->radius < 0) {
            b->radius = sta_half_from_float((float)box_radius(b->n, b->w, m->factor));
        }
        // (b may move: blend_normals can grow the table)
        uint16_t radius = (uint16_t)b->radius;
        double variation = b->variation, normal[3], w[3];
        bool ok = b->fit == 1;
        memcpy(normal, b->normal, sizeof(normal));
        memcpy(w, b->w, sizeof(w));
        // The scanner's position, looked up once for the edge-on test and the orientation.
        double pd[3] = { p[0], p[1], p[2] }, at[3];
        const double *target = NULL;
        if (timed && chunk->trajectory) {
            double gps_time;
            memcpy(&gps_time, record + layout->gps_offset, sizeof(gps_time));
            target = sta_trajectory_at_memo(chunk->trajectory, &memo, gps_time, at) ? at : NULL;
        }
        // A box that takes its sphere, or is rough, is not grown for being edge-on or nearly
        // linear (default method): a leaf cluster's silhouette is edge-on to the scanner, and
        // 78-93 % of the points grown from such boxes were more than 20 degrees off (4 M
        // street; thirteenth round, second part: trees' p95 22.23 -> 22.04 on the 20 M).
        bool keep = chunk->method == STA_NORMALS_MOMENTS && ok &&
                    variation > SPHERE_SCALE_VARIATION &&
                    (variation > ROUGH_VARIATION || sphere_taken(chunk, fine, b, u, m->base_level));
        // A degenerate box (fewer than 3 points, a line) grows until it fits, not once
        // (default method: its start at 1 point leaves sparse points in such boxes).
        bool regrow = chunk->method == STA_NORMALS_MOMENTS && !ok;
        if ((!grow || regrow) && !last && !keep) {
            if (sta_normal_too_narrow_at(chunk, pd, target, ok, normal, w, false)) {
                // nearly linear, edge-on or no plane: once wider
                m->state[j] = (uint8_t)((flags & RUN_START) | STATE_GROW);
                m->stats->widened++;
                grew++;
                continue;
            }
        }
        // A flat box of the default method keeps its plane's normal: no cylinder, quadric,
        // sphere (all need a variation above SPHERE_VARIATION) nor blend (blend_normals).
        bool flat = chunk->method == STA_NORMALS_MOMENTS && !(variation > SPHERE_VARIATION);
        int cylinder = ok && !flat && variation > SPHERE_VARIATION
                           ? cylinder_normal(m, j, u, target, normal)
                           : 0;
        int quadric = ok && !flat && cylinder == 0 ? quadric_normal(m, fine, b, u, normal) : 0;
        if (quadric < 0 || cylinder < 0 ||
            (ok && !flat && cylinder == 0 && quadric == 0 &&
             !sphere_normal(chunk, fine, b, u, m->base_level, normal) &&
             !blend_normals(chunk, fine, u, normal, variation))) {
            return SIZE_MAX;
        }
        // (the halo reaches at least its margin from an own point: most boxes need no more)
        double reach = may_pass_margin ? box_reach(chunk, u, level) : 0.0;
        if (reach > chunk->margin && reach > sta_normal_halo_reach(chunk, p)) {
            m->stats->beyond_halo++;
        }
        sta_normal_store_half_at(chunk, layout, record, pd, target, ok, normal, radius, &packed,
                                 m->stats);
        m->state[j] = (uint8_t)((flags & RUN_START) | STATE_DONE);
    }
    return grew;
}

// One level's pass (decide_level, then finish_level). Returns how many points are left for
// the next level, or SIZE_MAX when out of memory.
static size_t fit_level(const moment_pass *m, level_boxes *fine, level_boxes *coarse)
{
    size_t listed = 0, left = decide_level(m, fine, coarse, &listed);
    if (left == SIZE_MAX) {
        return SIZE_MAX;
    }
    size_t grew = finish_level(m, fine, coarse == NULL, listed);
    return grew == SIZE_MAX ? SIZE_MAX : left + grew;
}

// Whether cell d lies in the block from `from` to `to` cells around cell c along each axis
// (the cells marked for the previous one: marking them again changes nothing).
static bool within(const int64_t d[3], const int64_t c[3], int from, int to)
{
    for (int a = 0; a < 3; a++) {
        if (d[a] < c[a] + from || d[a] > c[a] + to) {
            return false;
        }
    }
    return true;
}

// The adaptive fine level of the default method, after the base level's first pass marked
// the rough points in m->rough (a point's mark depends on its nearest base box only, never
// on which chunk owns it): boxes of half-size cells from the points, own and halo, of the
// rough points' base cells and their 26 neighbours (the fine boxes and blends of a point
// reach one fine cell beyond its base cell); the rough points' pass at the fine level,
// then at the base level again (`base`, `coarse` the next, NULL at the top), where their
// base boxes also have quadrics (quadric_normal; the moment tensors of the 8 base cells of
// each rough point's box, from the same points). Returns false when out of memory.
static sta_status fine_pass(moment_pass *m, level_boxes *base, level_boxes *coarse,
                            const int32_t (*halo)[3], size_t halo_count, const int32_t corner[3],
                            const int32_t lo[3], const int32_t hi[3], sta_error *err)
{
    const sta_normals_chunk *chunk = m->chunk;
    int level = base->cells->level;
    sta_cell_moments wanted = { 0 };
    sta_cell_blocks fine_cells = { 0 };
    level_boxes fine_boxes = { 0 };
    box_quadrics quadrics = { .level = level };
    // The rough points alone (5 % of a street's), in their order: the passes below visit
    // them only. A base cell's run starts at its first rough point (decide_level's per-run
    // decisions are reset there, as at the run's first point in the whole set).
    size_t rough = 0;
    for (size_t j = 0; j < m->count; j++) {
        rough += m->rough[j] != 0;
    }
    moment_pass sub = *m;
    int32_t(*grid)[3] = sta_alloc_array(rough + 1, sizeof(*grid));
    uint32_t *order = sta_alloc_array(rough + 1, sizeof(*order));
    uint32_t *places = sta_alloc_array(rough + 1, sizeof(*places));
    uint8_t *state = sta_alloc_array(rough + 1, sizeof(*state));
    sta_status status =
        grid && order && places && state
            ? STA_OK
            : sta_fail(err, STA_ERR_NOMEM, "normals: out of memory for %zu points", rough);
    bool start = false;
    size_t runs = 0; // (base cells holding rough points)
    for (size_t j = 0, i = 0; status == STA_OK && j < m->count; j++) {
        start = start || (m->state[j] & RUN_START);
        if (m->rough[j]) {
            memcpy(grid[i], m->grid[j], sizeof(grid[0]));
            order[i] = m->order[j];
            places[i] = (uint32_t)j;
            state[i++] = (uint8_t)((m->state[j] & STATE_MASK) | (start ? RUN_START : 0));
            runs += start;
            start = false;
        }
    }
    sub.grid = (const int32_t(*)[3])grid;
    sub.order = order;
    sub.places = places;
    sub.state = state;
    sub.count = rough;
    sub.only_rough = false; // (all of them are)
    sub.rough = NULL;
    if (status == STA_OK) {
        status = sta_cell_moments_init_marks(&wanted, level, chunk->scene_min, lo, hi, err);
    }
    if (status == STA_OK && !sta_cell_moments_reserve(&wanted, MARKS_PER_RUN * runs)) {
        status = sta_fail(err, STA_ERR_NOMEM, "normals: out of memory for cells");
    }
    // The base cell marked last with its neighbours (none yet: far from any cell).
    int64_t last[3] = { NO_CELL, NO_CELL, NO_CELL };
    for (size_t j = 0; j < rough && status == STA_OK; j++) {
        int64_t c[3], u[3];
        point_offset(&sub, j, u);
        for (int a = 0; a < 3; a++) {
            c[a] = u[a] >> level;
        }
        if (memcmp(c, last, sizeof(c)) == 0) {
            continue;
        }
        bool marked = true;
        for (int q = 0; q < 27 && marked; q++) {
            const int64_t d[3] = { c[0] + q % 3 - 1, c[1] + q / 3 % 3 - 1, c[2] + q / 9 - 1 };
            marked = within(d, last, -1, 1) || sta_cell_moments_mark(&wanted, d);
        }
        memcpy(last, c, sizeof(c));
        if (!marked) {
            status = sta_fail(err, STA_ERR_NOMEM, "normals: out of memory for cells");
        }
    }
    // The own points and the halo's, both in the Morton order of their base cells: the
    // wanted cells' children in order, with the sphere's sums (the default method's).
    if (status == STA_OK) {
        status = sta_cell_blocks_init(&fine_cells, level - 1, true, chunk->scene_min, lo, hi, err);
    }
    if (status == STA_OK) {
        status = sta_cell_blocks_add_children(&fine_cells, m->grid, m->count, halo, halo_count,
                                              corner, &wanted, err);
    }
    if (status == STA_OK && !level_init(&fine_boxes, &fine_cells)) {
        status = sta_fail(err, STA_ERR_NOMEM, "normals: out of memory for vertex boxes");
    }
    if (status == STA_OK && fit_level(&sub, &fine_boxes, base) == SIZE_MAX) {
        status = sta_fail(err, STA_ERR_NOMEM, "normals: out of memory for vertex boxes");
    }
    if (status == STA_OK) {
        sub.quadrics = &quadrics;
        if (fit_level(&sub, base, coarse) == SIZE_MAX) {
            status = sta_fail(err, STA_ERR_NOMEM, "normals: out of memory for vertex boxes");
        }
    }
    for (size_t i = 0; status == STA_OK && i < rough; i++) { // (their runs' starts stay)
        uint8_t *to = &m->state[places[i]];
        *to = (uint8_t)((*to & RUN_START) | (state[i] & STATE_MASK));
    }
    table_release(&fine_boxes.table);
    sta_cell_blocks_release(&fine_cells);
    sta_free(quadrics.fits);
    sta_cell_moments_release(&wanted);
    sta_free(grid);
    sta_free(order);
    sta_free(places);
    sta_free(state);
    return status;
}

int sta_moment_normals_base_level(sta_normals_method method, uint64_t points,
                                  const double extent[3], double unit)
{
    double spacings =
        method == STA_NORMALS_MOMENTS_FINE ? BASE_CELL_SPACINGS / 2.0 : BASE_CELL_SPACINGS;
    double e[3] = { extent[0], extent[1], extent[2] };
    for (int i = 0; i < 2; i++) { // the two widest first
        for (int j = i + 1; j < 3; j++) {
            if (e[j] > e[i]) {
                double t = e[i];
                e[i] = e[j];
                e[j] = t;
            }
        }
    }
    if (points == 0 || !(unit > 0.0) || !(e[0] * e[1] > 0.0)) {
        return 0;
    }
    double spacing = sqrt(e[0] * e[1] / (double)points) / unit;
    int level = 0;
    while (level < STA_MOMENTS_MAX_LEVEL && (double)((int64_t)2 << level) <= spacings * spacing) {
        level++;
    }
    return level;
}

int sta_moment_normals_need(sta_normals_method method, int k)
{
    if (method != STA_NORMALS_MOMENTS) {
        return k; // (moments-fine stays as it was)
    }
    int need = (int)ceil(NEED_SHARE * (double)k - 1e-9); // (10 -> 1 whatever the rounding)
    return need > NEED_LEAST ? need : NEED_LEAST;
}

int sta_moment_normals_levels_above(sta_normals_method method)
{
    return method == STA_NORMALS_MOMENTS ? LEVELS_ABOVE : STA_MOMENTS_LEVELS_ABOVE_BASE;
}

double sta_moment_normals_reach(sta_normals_method method, int base_level, double unit)
{
    // A point blends the boxes of its cell's 8 vertices: they reach 2 cells from it.
    int top = base_level + sta_moment_normals_levels_above(method);
    return 2.0 *
           (double)((int64_t)1 << (top < STA_MOMENTS_MAX_LEVEL ? top : STA_MOMENTS_MAX_LEVEL)) *
           unit;
}

/* Bytes a point of one level's cells and vertex boxes takes at most (measured, see
 * docs/CONVERTER.md "Memory"), besides its position and state: 96 before the sphere's sums
 * and the adaptive fine level, which took the 20 M street's peak from 531 to 832 MB (two
 * workers of about 3.75 M points with their halos: 40 bytes a point more). */
#define MOMENT_BYTES_PER_POINT 136

size_t sta_normals_memory_bytes(sta_normals_method method, size_t points)
{
    size_t knn = sta_knn_normals_memory_bytes(points);
    // (+ a state byte and a place in the finish list a point)
    size_t moments = points * (MOMENT_BYTES_PER_POINT + 3 * sizeof(int32_t) + 1 + sizeof(uint32_t));
    // (a set the cells cannot address takes the kNN method: rare, not planned for)
    return method == STA_NORMALS_KNN ? knn : moments;
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
    if (chunk->method == STA_NORMALS_KNN || n > STA_MOMENTS_MAX_POINTS) {
        return sta_knn_normals_compute(chunk, layout, records, count, halo, halo_count, stats, err);
    }
    if (count == 0) {
        return STA_OK;
    }
    int32_t(*grid)[3] = sta_alloc_array(n, sizeof(*grid));
    uint8_t *state = sta_calloc(count, 1);
    uint32_t *order = sta_alloc_array(n, sizeof(*order));
    uint32_t *finish = sta_alloc_array(count, sizeof(*finish));
    if (!grid || !state || !order || !finish) {
        sta_free(grid);
        sta_free(state);
        sta_free(order);
        sta_free(finish);
        return sta_fail(err, STA_ERR_NOMEM, "normals: out of memory for %zu points", n);
    }
    int32_t lo[3] = { INT32_MAX, INT32_MAX, INT32_MAX },
            hi[3] = { INT32_MIN, INT32_MIN, INT32_MIN };
    sta_normal_gather_positions(layout, records, count, halo, halo_count, grid, lo, hi);
    // Levels: from the scene's base (or the finest whose cells stay addressable) to
    // sta_moment_normals_levels_above it (the halo's reach): the same in every chunk.
    // (10 cells of margin: the first block starts up to 4 below the lowest, 3 above stay)
    int level = chunk->base_level > 0 ? chunk->base_level : 0;
    for (int a = 0; a < 3; a++) {
        int64_t span = (int64_t)hi[a] - lo[a];
        while (level < STA_MOMENTS_MAX_LEVEL &&
               (span >> level) + 10 >= ((int64_t)1 << STA_MOMENTS_AXIS_BITS)) {
            level++;
        }
    }
    int top = chunk->base_level + sta_moment_normals_levels_above(chunk->method);
    top = top < STA_MOMENTS_MAX_LEVEL ? top : STA_MOMENTS_MAX_LEVEL;
    top = top > level ? top : level;
    if (level >= STA_MOMENTS_MAX_LEVEL) { // (a set wider than the cells address)
        sta_free(grid);
        sta_free(state);
        sta_free(order);
        sta_free(finish);
        return sta_knn_normals_compute(chunk, layout, records, count, halo, halo_count, stats, err);
    }
    moment_pass pass = { .chunk = chunk,
                         .layout = layout,
                         .records = records,
                         .stats = stats,
                         .state = state,
                         .order = order,
                         .count = count,
                         .base_level = level,
                         .finish = finish,
                         .need = (double)sta_moment_normals_need(chunk->method, chunk->k),
                         .factor = plane_radius_factor() };
    // Two levels at a time: the one fitted and the next (the scale's counts and the
    // candidates' flatness); the next becomes the fitted one with its vertex boxes.
    sta_cell_blocks cells[2] = { { 0 } };
    level_boxes boxes[2] = { { 0 } };
    int at = 0; // cells[at] is `level`
    // The sphere's sums: the default method's only (sphere_fit.h).
    bool higher = chunk->method == STA_NORMALS_MOMENTS;
    sta_status status =
        sta_cell_blocks_init(&cells[0], level, higher, chunk->scene_min, lo, hi, err);
    int32_t corner[3]; // the cell order's (aligned 8 levels up: nested to there)
    if (status == STA_OK) {
        // Morton order of the base cells.
        int align = level + 8;
        for (int a = 0; a < 3; a++) {
            int64_t from = (int64_t)lo[a] - chunk->scene_min[a];
            corner[a] = (int32_t)(chunk->scene_min[a] + ((from >> align) << align));
        }
        status = sta_cell_order((const int32_t(*)[3])grid, n, corner, level, order, err);
    }
    if (status == STA_OK && !sta_cell_blocks_reserve(&cells[0], n / POINTS_PER_BASE_CELL)) {
        status = sta_fail(err, STA_ERR_NOMEM, "normals: out of memory for cells");
    }
    if (status == STA_OK) {
        status = sta_cell_blocks_add(&cells[0], (const int32_t(*)[3])grid, n, order, err);
    }
    uint8_t *rough = NULL; // the adaptive fine level's marks (fine_pass)
    bool adaptive = chunk->method == STA_NORMALS_MOMENTS && level == chunk->base_level && level > 0;
    if (status == STA_OK && !level_init(&boxes[0], &cells[0])) {
        status = sta_fail(err, STA_ERR_NOMEM, "normals: out of memory for vertex boxes");
    }
    if (status == STA_OK && adaptive && !(rough = sta_calloc(count, 1))) {
        status = sta_fail(err, STA_ERR_NOMEM, "normals: out of memory for %zu points", count);
    }
    // The own points in cell order with their positions: the passes read them in order (and
    // the adaptive fine level's cells are summed from them and the halo's in that order).
    int32_t(*own)[3] = status == STA_OK ? sta_alloc_array(count, sizeof(*own)) : NULL;
    int32_t(*halo_sorted)[3] =
        status == STA_OK && adaptive ? sta_alloc_array(halo_count + 1, sizeof(*halo_sorted)) : NULL;
    if (status == STA_OK && (!own || (adaptive && !halo_sorted))) {
        status = sta_fail(err, STA_ERR_NOMEM, "normals: out of memory for %zu points", n);
    }
    for (size_t j = 0, k = 0, h = 0; status == STA_OK && j < n; j++) {
        if (j + POSITIONS_AHEAD < n) { // (a random read each)
            __builtin_prefetch(grid[order[j + POSITIONS_AHEAD]]);
        }
        if (order[j] < count) {
            order[k] = order[j];
            memcpy(own[k], grid[order[j]], sizeof(own[0]));
            // The runs of one base cell's points (the order keeps a cell's points together).
            bool same = k > 0;
            for (int a = 0; a < 3 && same; a++) {
                same = ((int64_t)own[k][a] - chunk->scene_min[a]) >> level ==
                       ((int64_t)own[k - 1][a] - chunk->scene_min[a]) >> level;
            }
            state[k++] = same ? 0 : RUN_START;
        } else if (halo_sorted) {
            memcpy(halo_sorted[h++], grid[order[j]], sizeof(halo_sorted[0]));
        }
    }
    pass.grid = (const int32_t(*)[3])own;
    pass.own = pass.grid;
    pass.own_count = count;
    sta_free(grid);
    // The cylinders' and quadrics' boxes' points (box_tensors: the default method's, from
    // the sorted halo) and the cylinders' fits (cylinder_normal).
    cylinder_slot *cylinders = NULL;
    size_t halo_hint = 0;
    if (status == STA_OK && adaptive) {
        pass.halo = (const int32_t(*)[3])halo_sorted;
        pass.halo_count = halo_count;
        pass.corner = corner;
        pass.halo_hint = &halo_hint;
    }
    if (status == STA_OK && adaptive && level + CYLINDER_LEVELS_UP <= top) {
        cylinders = sta_calloc(CYLINDER_SLOTS, sizeof(*cylinders));
        if (!cylinders) {
            status = sta_fail(err, STA_ERR_NOMEM, "normals: out of memory for cylinders");
        }
        pass.cylinders = cylinders;
    }
    // The level two above the base, made in the base level's first pass for skips_base (the
    // default method's), then handed on as the next level one level up.
    sta_cell_blocks above_cells = { 0 };
    level_boxes above_boxes = { 0 };
    bool have_above = false;
    while (status == STA_OK) {
        int next = 1 - at;
        if (level < top && have_above) {
            cells[next] = above_cells;
            boxes[next] = above_boxes;
            boxes[next].cells = &cells[next];
            memset(&above_cells, 0, sizeof(above_cells));
            memset(&above_boxes, 0, sizeof(above_boxes));
            have_above = false;
        } else if (level < top) {
            status = sta_cell_blocks_init(&cells[next], level + 1, higher, chunk->scene_min, lo, hi,
                                          err);
            if (status == STA_OK) {
                status = sta_cell_blocks_coarsen(&cells[at], &cells[next], err);
            }
            if (status == STA_OK && !level_init(&boxes[next], &cells[next])) {
                status = sta_fail(err, STA_ERR_NOMEM, "normals: out of memory for vertex boxes");
            }
            if (status != STA_OK) {
                break;
            }
        }
        if (adaptive && level == chunk->base_level && level + 2 <= top) {
            have_above = true;
            status = sta_cell_blocks_init(&above_cells, level + 2, higher, chunk->scene_min, lo, hi,
                                          err);
            if (status == STA_OK) {
                status = sta_cell_blocks_coarsen(&cells[next], &above_cells, err);
            }
            if (status == STA_OK && !level_init(&above_boxes, &above_cells)) {
                status = sta_fail(err, STA_ERR_NOMEM, "normals: out of memory for vertex boxes");
            }
            if (status != STA_OK) {
                break;
            }
        }
        pass.rough = rough;
        pass.defer = adaptive && level == chunk->base_level;
        int axis_level = level - chunk->base_level; // (the cylinders' boxes' level: fine or next)
        pass.axis = axis_level == CYLINDER_LEVELS_UP                      ? &boxes[at]
                    : axis_level == CYLINDER_LEVELS_UP - 1 && level < top ? &boxes[next]
                                                                          : NULL;
        pass.above = have_above && level == chunk->base_level ? &above_boxes : NULL;
        size_t left = fit_level(&pass, &boxes[at], level < top ? &boxes[next] : NULL);
        pass.defer = false;
        pass.above = NULL;
        if (left == SIZE_MAX) {
            status = sta_fail(err, STA_ERR_NOMEM, "normals: out of memory for vertex boxes");
        } else if (adaptive && level == chunk->base_level) {
            status = fine_pass(&pass, &boxes[at], level < top ? &boxes[next] : NULL,
                               (const int32_t(*)[3])halo_sorted, halo_count, corner, lo, hi, err);
            left = 0; // (the rough points' passes left some waiting: count them)
            for (size_t j = 0; j < count; j++) {
                left += (state[j] & STATE_MASK) != STATE_DONE;
            }
            left = status == STA_OK ? left : SIZE_MAX;
        }
        if (left == 0 || left == SIZE_MAX || level == top) {
            break;
        }
        table_release(&boxes[at].table);
        sta_cell_blocks_release(&cells[at]);
        at = next;
        level++;
    }
    for (int j = 0; j < 2; j++) {
        table_release(&boxes[j].table);
        sta_cell_blocks_release(&cells[j]);
    }
    table_release(&above_boxes.table);
    sta_cell_blocks_release(&above_cells);
    if (status == STA_OK) {
        stats->points += count;
    }
    sta_free(own);
    sta_free(cylinders);
    sta_free(halo_sorted);
    sta_free(rough);
    sta_free(state);
    sta_free(order);
    sta_free(finish);
    return status;
}
