/* SPDX-License-Identifier: MIT
 * Per-chunk normals from kNN neighbourhoods (knn_grid.h) and, for widened ones, boxes
 * of cell moments (cell_moments.h): covariance, eigenvector, orientation, radius, packed
 * into the records' SPLAT bytes. Three passes: the K search of every point, the box fits
 * level by level, the exact widest search of the points whose box stayed thick. */
#include "knn_normals.h"

#include <math.h>
#include <string.h>

#include "cell_moments.h"
#include "core/alloc.h"
#include "knn_grid.h"
#include "normal_fit.h"

/* Offsets from the query point summed exactly in int64 (fit_normal) stay below 2^FIT_BITS. */
#define FIT_BITS    28
/* A widened neighbourhood holds this many times K (at most STA_KNN_MAX). On the 20 M
 * street's road (1.5 cm range noise, profiles 5 cm apart) 4 K gave 5.2 degrees median,
 * 6 K 3.8 (4 M street): the wider fit averages the noise over more profiles. */
#define WIDEN_MAX   6
/* The wide fit's block of cells (cell_moments.h) has an edge of about this many times the
 * K-th neighbour's distance r_K: on a surface where K points lie within r_K (density
 * K / (pi r_K^2)) a square of edge sqrt(6 pi) r_K holds WIDEN_MAX K = 6 K points. */
#define WIDE_EXTENT 4.34
/* A block with at most K points (a point far from its block's other points), or whose fit
 * is still linear or edge-on (rules 1 and 2 of too_narrow: the block was sized for even
 * sampling, and scan lines 15 spacings apart need a wider one) moves to the next wider
 * block, at most this many times. */
#define ESCALATE    2
/* A box fit thicker than this (smallest eigenvalue over the middle one) is a volume or
 * curved layers (foliage: spheres of 0.2-0.4 m) rather than range noise on a plane: the
 * exact 6 K nearest fit it better (4 M street, trees 4.26 degrees median against 6.54
 * with the box; 0.05: 3.98, but 1.32 M exact searches instead of 0.99 M; 0.1: 4.96). */
#define BOX_THICK   0.07

int sta_normals_widest_k(int k)
{
    return WIDEN_MAX * k < STA_NORMALS_MAX_K ? WIDEN_MAX * k : STA_NORMALS_MAX_K;
}

/* Bytes a point of the widened fits' cells (cell_moments.h) take at most, measured: on the
 * 4 M street (chunks of 0.3-1.2 M points) one level's table held up to 0.41 slots a point
 * (88 bytes a slot), and 1.5 times that while it grows. */
#define CELL_BYTES_PER_POINT 56

size_t sta_knn_normals_memory_bytes(size_t points)
{
    // The search and the cells are not held at once; + the positions, as floats and
    // integers, and the radius and box code of each point.
    size_t search = sta_knn_memory_bytes(points), cells = points * CELL_BYTES_PER_POINT;
    return (search > cells ? search : cells) +
           points * (3 * (sizeof(float) + sizeof(int32_t)) + sizeof(float) + 1);
}

// The plane normal of a neighbourhood around grid point q (fit_moments). The sums are of
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
    double s1d[3], s2d[6];
    for (int t = 0; t < 6; t++) {
        s2d[t] = (double)s2[t];
        s1d[t % 3] = (double)s1[t % 3];
    }
    return sta_normal_fit_moments(chunk, (double)nb->size, s1d, s2d, shift, n, w);
}

// The edge, in grid units, of the boxes of code c: b = 2 + (c & 1) cells of level c / 2.
static int64_t block_extent(int code)
{
    return (int64_t)(2 + (code & 1)) << (code >> 1);
}

// The box of `code` centred on a point at u (grid units from the scene corner) overlaps
// b + 1 cells an axis from `anchor`; each is weighted by the share of it inside the box
// (the points taken as spread evenly in a cell): the first 1 - f, the last f, the others
// 1. Coordinates doubled so that half a cell stays an integer.
static void block_anchor(int code, const int64_t u[3], int64_t anchor[3], double first[3])
{
    int64_t cell2 = (int64_t)2 << (code >> 1);
    for (int a = 0; a < 3; a++) {
        int64_t lower2 = 2 * u[a] - block_extent(code);
        anchor[a] = lower2 >= 0 ? lower2 / cell2 : -((cell2 - 1 - lower2) / cell2);
        first[a] = (double)(lower2 - anchor[a] * cell2) / (double)cell2;
    }
}

// What sta_knn_normals_compute shares with the visits of its two passes.
typedef struct normals_visit {
    const sta_normals_chunk *chunk;
    const sta_record_layout *layout;
    uint8_t *records;
    sta_normals_stats *stats;
    int min_code;         /* the block codes usable for this set (cell_moments.h's limits), */
    int max_code;         /* max_code -1: none, the exact search only */
    double unit_m;        /* metres per grid unit (the coarsest axis) */
    float *radius;        /* per record, of the points left for a block fit */
    uint8_t *code;        /* per record: CODE_DONE, or a block code | escalations << CODE_BITS */
    int32_t lo[3], hi[3]; /* the box of the chunk's and halo's points, grid units */
} normals_visit;

#define CODE_BITS  6
#define CODE_MASK  ((1 << CODE_BITS) - 1)
#define CODE_DONE  0xFF
#define CODE_EXACT 0xFE

// The block code whose extent is nearest (geometrically) to WIDE_EXTENT times the K-th
// neighbour's distance, or -1 past the widest usable one.
static int block_code(const normals_visit *v, float kth_d2)
{
    double target = WIDE_EXTENT * sqrt((double)kth_d2) / v->unit_m;
    for (int c = 0; c <= v->max_code; c++) {
        double e0 = (double)block_extent(c), e1 = (double)block_extent(c + 1);
        if (target * target < e0 * e1) {
            return c >= v->min_code ? c : -1;
        }
    }
    return -1;
}

// Orients `normal` (when ok), packs it with the radius into record i's SPLAT bytes.
static void store(const normals_visit *v, size_t i, bool ok, double normal[3], double radius)
{
    sta_normal_store(v->chunk, v->layout, v->records + i * v->layout->size, ok, normal, radius,
                     v->stats);
}

static int finish_point(void *user, size_t i, const sta_knn *nb)
{
    normals_visit *v = user;
    const sta_normals_chunk *chunk = v->chunk;
    const sta_record_layout *layout = v->layout;
    sta_normals_stats *stats = v->stats;
    double normal[3] = { 0, 0, 0 }, w[3] = { 0, 0, 0 };
    int32_t p[3];
    sta_record_position(v->records + i * layout->size, p);
    bool ok = nb->size >= 3 && fit_normal(chunk, p, nb, normal, w);
    // Radius: the mean distance to the nearest STA_NORMALS_RADIUS_K (or K) neighbours,
    // whatever K the normal used, summed nearest first (the same bits in any set order);
    // the nearest is q itself (distance 0).
    float nearest[STA_NORMALS_RADIUS_K + 1];
    int m = 0;
    float farthest = 0.0f;
    for (int j = 0; j < nb->size; j++) { // the STA_NORMALS_RADIUS_K + 1 smallest, sorted
        float d2 = nb->d2[j];
        farthest = d2 > farthest ? d2 : farthest; // no NaN: not libm's fmaxf call
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
    int k = nb->capacity - 1;
    double pd[3] = { p[0], p[1], p[2] };
    double gps_time;
    bool timed = (layout->attributes & STA_ATTR_GPS_TIME) != 0;
    if (timed) {
        memcpy(&gps_time, v->records + i * layout->size + layout->gps_offset, sizeof(gps_time));
    }
    int widest = sta_normals_widest_k(chunk->k);
    if (k < widest && nb->size == nb->capacity &&
        sta_normal_too_narrow(chunk, pd, timed ? &gps_time : NULL, ok, normal, w, true)) {
        // The wide fit: from the moments of a block of cells sized for 6 K points (second
        // pass), else (a block too wide for the grid) the exact 6 K nearest.
        int code = block_code(v, farthest);
        if (code >= 0) {
            v->code[i] = (uint8_t)code;
            v->radius[i] = (float)radius;
            return 0;
        }
        return widest;
    }
    if (k > chunk->k) { // the exact widest K nearest (no usable box)
        stats->widened++;
        stats->widened_exact++;
    }
    if (nb->size > 0 && sqrt((double)farthest) > sta_normal_halo_reach(chunk, p)) {
        stats->beyond_halo++;
    }
    store(v, i, ok, normal, radius);
    return 0;
}

// The moments of the cells a box overlaps (as doubles, from the cells' first corner),
// remembered for the next points whose boxes start in the same cell.
#define BOX_CELLS 64 /* 4 x 4 x 4: the most cells a box overlaps */
typedef struct block_cells {
    int code; /* -1: empty */
    int64_t anchor[3];
    double n[BOX_CELLS], s1[BOX_CELLS][3], s2[BOX_CELLS][6];
} block_cells;

#define BLOCK_CACHE 256 /* boxes remembered (direct-mapped), a power of two */

// A box's fit: the normal, the eigenvalues and the (weighted) count.
typedef struct block_fit {
    bool ok;
    double n, normal[3], w[3];
} block_fit;

static void fit_block(const normals_visit *v, const sta_cell_moments *cells, int code,
                      const int64_t anchor[3], const double first[3], block_cells *cache,
                      sta_moment_sums *scratch, block_fit *f)
{
    uint64_t h = ((uint64_t)anchor[0] * 0x9E3779B97F4A7C15ull) ^
                 ((uint64_t)anchor[1] * 0xC2B2AE3D27D4EB4Full) ^
                 ((uint64_t)anchor[2] * 0x165667B19E3779F9ull) ^ (uint64_t)code;
    block_cells *c = &cache[(h >> 40) & (BLOCK_CACHE - 1)];
    int m = 3 + (code & 1);
    if (c->code != code || c->anchor[0] != anchor[0] || c->anchor[1] != anchor[1] ||
        c->anchor[2] != anchor[2]) {
        c->code = code;
        memcpy(c->anchor, anchor, sizeof(c->anchor));
        sta_cell_moments_block(cells, anchor, m, scratch);
        for (int i = 0; i < m * m * m; i++) {
            c->n[i] = (double)scratch[i].n;
            for (int a = 0; a < 3; a++) {
                c->s1[i][a] = (double)scratch[i].s1[a];
            }
            for (int t = 0; t < 6; t++) {
                c->s2[i][t] = (double)scratch[i].s2[t];
            }
        }
    }
    double wt[3][4];
    for (int a = 0; a < 3; a++) {
        for (int j = 0; j < m; j++) {
            wt[a][j] = j == 0 ? 1.0 - first[a] : j == m - 1 ? first[a] : 1.0;
        }
    }
    double n = 0.0, s1[3] = { 0, 0, 0 }, s2[6] = { 0, 0, 0, 0, 0, 0 };
    for (int z = 0, i = 0; z < m; z++) {
        for (int y = 0; y < m; y++) {
            for (int x = 0; x < m; x++, i++) {
                if (c->n[i] == 0.0) {
                    continue;
                }
                double w = wt[0][x] * wt[1][y] * wt[2][z];
                n += w * c->n[i];
                for (int a = 0; a < 3; a++) {
                    s1[a] += w * c->s1[i][a];
                }
                for (int t = 0; t < 6; t++) {
                    s2[t] += w * c->s2[i][t];
                }
            }
        }
    }
    f->n = n;
    f->ok = n > 2.0 && sta_normal_fit_moments(v->chunk, n, s1, s2, 0, f->normal, f->w);
}

// Whether point i's block fit is still linear or edge-on (too_narrow without thickness).
static bool still_narrow(const normals_visit *v, size_t i, const int32_t p[3], const block_fit *f)
{
    const sta_record_layout *layout = v->layout;
    double pd[3] = { p[0], p[1], p[2] };
    double gps_time;
    bool timed = (layout->attributes & STA_ATTR_GPS_TIME) != 0;
    if (timed) {
        memcpy(&gps_time, v->records + i * layout->size + layout->gps_offset, sizeof(gps_time));
    }
    return sta_normal_too_narrow(v->chunk, pd, timed ? &gps_time : NULL, f->ok, f->normal, f->w,
                                 false);
}

// Distance in metres from grid point p to the farthest corner of the cells a box overlaps.
static double block_reach(const normals_visit *v, const int32_t p[3], int code,
                          const int64_t anchor[3])
{
    double d2 = 0.0;
    for (int a = 0; a < 3; a++) {
        double lo = (double)(v->chunk->scene_min[a] + anchor[a] * ((int64_t)1 << (code >> 1)));
        double hi = lo + (double)((int64_t)(3 + (code & 1)) << (code >> 1));
        double d = fmax(fabs(p[a] - lo), fabs(hi - p[a])) * v->chunk->scale[a];
        d2 += d * d;
    }
    return sqrt(d2);
}

// The cells of `level` that the boxes of the points waiting at that level overlap: first
// the set of cells 4 times wider that hold them (a box reaches at most 2 cells from its
// point), then the points of those. The cells hold all their points: the same sums as
// if every point had been added.
static sta_status level_cells(const normals_visit *v, const int32_t (*grid)[3], size_t n,
                              size_t count, int level, sta_cell_moments *cells, sta_error *err)
{
    const int64_t *origin = v->chunk->scene_min;
    int coarse = level + 2 < STA_MOMENTS_MAX_LEVEL ? level + 2 : STA_MOMENTS_MAX_LEVEL;
    sta_cell_moments wanted;
    sta_status status = sta_cell_moments_init_marks(&wanted, coarse, origin, v->lo, v->hi, err);
    if (status != STA_OK) {
        return status;
    }
    int64_t last[2][3] = { { -1, -1, -1 }, { -1, -1, -1 } }, reach = (int64_t)2 << level;
    for (size_t i = 0; i < count; i++) {
        if (v->code[i] >= CODE_EXACT || (v->code[i] & CODE_MASK) >> 1 != level) {
            continue;
        }
        int64_t range[2][3];
        for (int a = 0; a < 3; a++) {
            int64_t u = (int64_t)grid[i][a] - origin[a];
            range[0][a] = (u - reach) >> coarse;
            range[1][a] = (u + reach) >> coarse;
        }
        if (memcmp(range, last, sizeof(range)) == 0) {
            continue; // (the previous point marked the same cells)
        }
        memcpy(last, range, sizeof(last));
        for (int64_t z = range[0][2]; z <= range[1][2]; z++) {
            for (int64_t y = range[0][1]; y <= range[1][1]; y++) {
                for (int64_t x = range[0][0]; x <= range[1][0]; x++) {
                    if (!sta_cell_moments_mark(&wanted, (const int64_t[3]){ x, y, z })) {
                        sta_cell_moments_release(&wanted);
                        return sta_fail(err, STA_ERR_NOMEM, "normals: out of memory for cells");
                    }
                }
            }
        }
    }
    status = sta_cell_moments_init(cells, level, origin, v->lo, v->hi, err);
    if (status == STA_OK) {
        status = sta_cell_moments_add(cells, grid, n, NULL, &wanted, err);
        if (status != STA_OK) {
            sta_cell_moments_release(cells);
        }
    }
    sta_cell_moments_release(&wanted);
    return status;
}

// The second pass: the points left with a block code get the fit of their block, level by
// level (one level's cells at a time). A block with fewer than K + 1 points or no plane
// moves to the next wider block, at most ESCALATE times.
static sta_status fit_blocks(normals_visit *v, const int32_t (*grid)[3], size_t n, size_t count,
                             sta_error *err)
{
    int lo = CODE_MASK, hi = -1;
    for (size_t i = 0; i < count; i++) {
        if (v->code[i] < CODE_EXACT) {
            int c = v->code[i] & CODE_MASK;
            lo = c < lo ? c : lo;
            hi = c > hi ? c : hi;
        }
    }
    if (hi < 0) {
        return STA_OK;
    }
    block_cells *cache = sta_alloc_array(BLOCK_CACHE, sizeof(*cache));
    sta_moment_sums *scratch = sta_alloc_array(BOX_CELLS, sizeof(*scratch));
    if (!cache || !scratch) {
        sta_free(cache);
        sta_free(scratch);
        return sta_fail(err, STA_ERR_NOMEM, "normals: out of memory for block fits");
    }
    for (size_t s = 0; s < BLOCK_CACHE; s++) {
        cache[s].code = -1;
    }
    const sta_normals_chunk *chunk = v->chunk;
    sta_status status = STA_OK;
    for (int level = lo >> 1; level <= (hi >> 1) && status == STA_OK; level++) {
        sta_cell_moments cells;
        status = level_cells(v, grid, n, count, level, &cells, err);
        if (status != STA_OK) {
            break;
        }
        for (size_t i = 0; i < count; i++) {
            while (v->code[i] < CODE_EXACT && (v->code[i] & CODE_MASK) >> 1 == level) {
                int code = v->code[i] & CODE_MASK, steps = v->code[i] >> CODE_BITS;
                int64_t u[3], anchor[3];
                double first[3];
                for (int a = 0; a < 3; a++) {
                    u[a] = (int64_t)grid[i][a] - chunk->scene_min[a];
                }
                block_anchor(code, u, anchor, first);
                block_fit fit, *f = &fit;
                fit_block(v, &cells, code, anchor, first, cache, scratch, f);
                if (steps < ESCALATE && code < v->max_code &&
                    (f->n <= chunk->k || still_narrow(v, i, grid[i], f))) {
                    v->code[i] = (uint8_t)((code + 1) | (steps + 1) << CODE_BITS);
                    hi = code + 1 > hi ? code + 1 : hi;
                    continue;
                }
                if (!f->ok || f->w[0] > BOX_THICK * f->w[1]) {
                    v->code[i] = CODE_EXACT; // a volume, or layers: the exact 6 K nearest
                    continue;
                }
                v->stats->widened++;
                if (block_reach(v, grid[i], code, anchor) > sta_normal_halo_reach(chunk, grid[i])) {
                    v->stats->beyond_halo++;
                }
                double normal[3] = { f->normal[0], f->normal[1], f->normal[2] };
                store(v, i, f->ok, normal, v->radius[i]);
                v->code[i] = CODE_DONE;
            }
        }
        sta_cell_moments_release(&cells);
    }
    sta_free(cache);
    sta_free(scratch);
    return status;
}

// The third pass: the points whose box fit is a volume or layers (CODE_EXACT) get the
// plane of their exact widest-K nearest instead. They are moved to the front of the
// arrays (the search queries the first points; candidates are all of them, in any order).
typedef struct exact_visit {
    normals_visit *v;
    const size_t *index; /* record of each query */
} exact_visit;

static int finish_exact(void *user, size_t j, const sta_knn *nb)
{
    const exact_visit *e = user;
    normals_visit *v = e->v;
    size_t i = e->index[j];
    int32_t p[3];
    sta_record_position(v->records + i * v->layout->size, p);
    double normal[3] = { 0, 0, 0 }, w[3];
    bool ok = nb->size >= 3 && fit_normal(v->chunk, p, nb, normal, w);
    float farthest = 0.0f;
    for (int k = 0; k < nb->size; k++) {
        farthest = nb->d2[k] > farthest ? nb->d2[k] : farthest;
    }
    v->stats->widened++;
    v->stats->widened_exact++;
    if (sqrt((double)farthest) > sta_normal_halo_reach(v->chunk, p)) {
        v->stats->beyond_halo++;
    }
    store(v, i, ok, normal, v->radius[i]);
    return 0;
}

static sta_status fit_exact(normals_visit *v, float (*xyz)[3], int32_t (*grid)[3], size_t n,
                            size_t count, sta_error *err)
{
    size_t exact = 0;
    for (size_t i = 0; i < count; i++) {
        exact += v->code[i] == CODE_EXACT;
    }
    if (exact == 0) {
        return STA_OK;
    }
    size_t *index = sta_alloc_array(exact, sizeof(*index));
    if (!index) {
        return sta_fail(err, STA_ERR_NOMEM, "normals: out of memory for %zu points", exact);
    }
    for (size_t i = 0, j = 0; i < count; i++) {
        if (v->code[i] == CODE_EXACT) {
            // Position j holds no point still waiting (those lie at i > j): swap.
            float x[3];
            int32_t g[3];
            memcpy(x, xyz[j], sizeof(x));
            memcpy(g, grid[j], sizeof(g));
            memcpy(xyz[j], xyz[i], sizeof(x));
            memcpy(grid[j], grid[i], sizeof(g));
            memcpy(xyz[i], x, sizeof(x));
            memcpy(grid[i], g, sizeof(g));
            index[j++] = i;
        }
    }
    exact_visit e = { v, index };
    sta_status status = sta_knn_each((const float(*)[3])xyz, (const int32_t(*)[3])grid, n, exact,
                                     sta_normals_widest_k(v->chunk->k), finish_exact, &e, err);
    sta_free(index);
    return status;
}

// The block codes usable for a set of n points spanning `span` grid units an axis: from
// the finest level whose cells stay addressable (cell_moments.h) to the coarsest one;
// max_code -1 when there are none.
static void usable_codes(size_t n, const int64_t span[3], int *min_code, int *max_code)
{
    int level = 0;
    for (int a = 0; a < 3; a++) {
        while (level <= STA_MOMENTS_MAX_LEVEL &&
               (span[a] >> level) + 6 >= ((int64_t)1 << STA_MOMENTS_AXIS_BITS)) {
            level++;
        }
    }
    *min_code = 2 * level;
    *max_code = n > STA_MOMENTS_MAX_POINTS || level > STA_MOMENTS_MAX_LEVEL
                    ? -1
                    : 2 * STA_MOMENTS_MAX_LEVEL + 1;
}

sta_status sta_knn_normals_compute(const sta_normals_chunk *chunk, const sta_record_layout *layout,
                                   uint8_t *records, size_t count, const int32_t *halo,
                                   size_t halo_count, sta_normals_stats *stats, sta_error *err)
{
    // (the arguments were checked by sta_normals_compute, the one caller)
    size_t n = count + halo_count;
    if (count == 0) {
        return STA_OK;
    }
    float(*xyz)[3] = sta_alloc_array(n, sizeof(*xyz));
    int32_t(*grid)[3] = sta_alloc_array(n, sizeof(*grid));
    float *radius = sta_alloc_array(count, sizeof(*radius));
    uint8_t *code = sta_malloc(count);
    if (!xyz || !grid || !radius || !code) {
        sta_free(xyz);
        sta_free(grid);
        sta_free(radius);
        sta_free(code);
        return sta_fail(err, STA_ERR_NOMEM, "normals: out of memory for %zu points", n);
    }
    memset(code, CODE_DONE, count);
    int32_t lo[3] = { INT32_MAX, INT32_MAX, INT32_MAX },
            hi[3] = { INT32_MIN, INT32_MIN, INT32_MIN };
    sta_normal_gather_positions(layout, records, count, halo, halo_count, grid, lo, hi);
    for (size_t i = 0; i < n; i++) {
        for (int a = 0; a < 3; a++) {
            // From the scene's corner, not the chunk's: the same floats in every chunking.
            xyz[i][a] = (float)((double)(grid[i][a] - chunk->scene_min[a]) * chunk->scale[a]);
        }
    }
    int64_t span[3];
    for (int a = 0; a < 3; a++) {
        span[a] = (int64_t)hi[a] - lo[a];
    }
    double unit_m = fmax(chunk->scale[0], fmax(chunk->scale[1], chunk->scale[2]));
    normals_visit ctx = { .chunk = chunk,
                          .layout = layout,
                          .records = records,
                          .stats = stats,
                          .unit_m = unit_m,
                          .radius = radius,
                          .code = code };
    memcpy(ctx.lo, lo, sizeof(lo));
    memcpy(ctx.hi, hi, sizeof(hi));
    usable_codes(n, span, &ctx.min_code, &ctx.max_code);
    sta_status status = sta_knn_each((const float(*)[3])xyz, (const int32_t(*)[3])grid, n, count,
                                     chunk->k, finish_point, &ctx, err);
    if (status == STA_OK) {
        status = fit_blocks(&ctx, (const int32_t(*)[3])grid, n, count, err);
    }
    if (status == STA_OK) {
        status = fit_exact(&ctx, xyz, grid, n, count, err);
    }
    if (status == STA_OK) {
        stats->points += count;
    }
    sta_free(xyz);
    sta_free(grid);
    sta_free(radius);
    sta_free(code);
    return status;
}
