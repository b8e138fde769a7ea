/* SPDX-License-Identifier: MIT
 * CPU twin of the HPR shaders (hpr_common.glsl, hpr_pyramid.comp, hpr_occlusion.comp,
 * hpr_exhaustive.comp): the same rules, in float, in the same order.
 *
 * Based on: Bouchiba, Deschaud, Goulette 2018, section 3.1 and eq. 1; Pintus, Gobbetti,
 * Agus 2011 (exhaustive operator).
 */
#include "render/ref/hpr_ref.h"

#include <float.h>
#include <math.h>
#include <stdbool.h>
#include <string.h>

void sta_hpr_params_defaults(sta_hpr_params *config)
{
    if (config->threshold == 0.0f) {
        config->threshold = STA_HPR_DEFAULT_THRESHOLD;
    }
    if (config->coarse_level <= 0) {
        config->coarse_level = STA_HPR_DEFAULT_COARSE_LEVEL;
    }
    if (!(config->far_m > 0.0f) || !isfinite(config->far_m)) {
        config->far_m = STA_HPR_DEFAULT_FAR_M;
    }
    if (config->occluder_gap_s0 == 0.0f) {
        config->occluder_gap_s0 = STA_HPR_OCCLUDER_GAP_S0;
    }
    if (config->marked_reach_s0 == 0.0f) {
        config->marked_reach_s0 = STA_HPR_MARKED_REACH_S0;
    }
    if (config->surface_fit_s0 == 0.0f) {
        config->surface_fit_s0 = STA_HPR_SURFACE_FIT_S0;
    }
}

float sta_hpr_surface_tol_m(const sta_view_params *view, const sta_hpr_params *resolved)
{
    float tol = resolved->surface_fit_s0 * view->s0;
    return resolved->surface_fit_s0 > 0.0f && tol > 0.0f && isfinite(tol) ? tol : 0.0f;
}

float sta_hpr_marked_reach_px_m(const sta_view_params *view, const sta_hpr_params *resolved)
{
    float scale_y = 0.5f * (float)view->height_px / tanf(0.5f * view->fov_y);
    float reach = resolved->marked_reach_s0 * view->s0 * scale_y;
    return resolved->marked_reach_s0 > 0.0f && reach > 0.0f && isfinite(reach) ? reach : FLT_MAX;
}

float sta_hpr_occluder_gap_m(const sta_view_params *view, const sta_hpr_params *resolved)
{
    float gap = resolved->occluder_gap_s0 * view->s0;
    return resolved->occluder_gap_s0 > 0.0f && gap > 0.0f && isfinite(gap) ? gap : -FLT_MAX;
}

float sta_hpr_s_hpr_m(const sta_view_params *view, const sta_hpr_params *config)
{
    return config->s_hpr != 0.0f ? config->s_hpr : STA_HPR_DEFAULT_S_HPR_FACTOR * view->s0;
}

// `params` (may be NULL) through sta_hpr_params_defaults.
static sta_hpr_params resolve(const sta_hpr_params *params)
{
    sta_hpr_params p = params ? *params : (sta_hpr_params){ 0 };
    sta_hpr_params_defaults(&p);
    return p;
}

int sta_hpr_pyramid_levels(int width_px, int height_px)
{
    if (width_px < 1 || height_px < 1) {
        return 0;
    }
    int largest = width_px > height_px ? width_px : height_px;
    int levels = 1;
    while (levels <= STA_HPR_MAX_LEVELS && (1L << (levels - 1)) < (long)largest) {
        levels++;
    }
    if (levels > STA_HPR_MAX_LEVELS) {
        return 0;
    }
    return levels < 2 ? 2 : levels;
}

float sta_hpr_radius_k(const sta_view_params *view, const sta_hpr_params *resolved)
{
    // K = s_hpr h / (2 tan(theta)): the neighbourhood size in pixels times the depth.
    float s_hpr = sta_hpr_s_hpr_m(view, resolved);
    float k = s_hpr * (float)view->height_px / (2.0f * tanf(0.5f * view->fov_y));
    return k > 0.0f && isfinite(k) ? k : 0.0f; // no s0: level 0 everywhere
}

void sta_hpr_level_depths(const sta_view_params *view, const sta_hpr_params *resolved,
                          int level_count, float out_depth_m[STA_HPR_MAX_LEVELS])
{
    float k = sta_hpr_radius_k(view, resolved);
    for (int l = 0; l < STA_HPR_MAX_LEVELS; l++) {
        // round(log2(K / z)) >= l  <=>  z <= K 2^(0.5 - l)
        out_depth_m[l] =
            l == 0 ? INFINITY : (l < level_count ? ldexpf(k * 1.41421356f, -l) : -1.0f);
    }
}

int sta_hpr_sector(int vx2, int vy2)
{
    int ax = vx2 < 0 ? -vx2 : vx2;
    int ay = vy2 < 0 ? -vy2 : vy2;
    if (STA_HPR_SECTOR_TAN_DEN * ay <= STA_HPR_SECTOR_TAN_NUM * ax) {
        return vx2 >= 0 ? 0 : 4; // within 22.5 deg of the x axis
    }
    if (STA_HPR_SECTOR_TAN_DEN * ax <= STA_HPR_SECTOR_TAN_NUM * ay) {
        return vy2 > 0 ? 2 : 6; // within 22.5 deg of the y axis
    }
    if (vx2 > 0) {
        return vy2 > 0 ? 1 : 7;
    }
    return vy2 > 0 ? 3 : 5;
}

sta_status sta_hpr_ref_build_pyramid(const sta_image *position, sta_hpr_pyramid *out,
                                     sta_error *err)
{
    memset(out, 0, sizeof(*out));
    int level_count = sta_hpr_pyramid_levels(position->width, position->height);
    if (level_count == 0 || position->channels != 4) {
        return sta_fail(err, STA_ERR_ARG, "hpr: position image %dx%dx%d is not RGBA of 1..%d px",
                        position->width, position->height, position->channels,
                        1 << (STA_HPR_MAX_LEVELS - 1));
    }
    sta_status status = sta_image_init(&out->levels[0], position->width, position->height, 4, err);
    if (status != STA_OK) {
        return status;
    }
    out->level_count = level_count;
    memcpy(out->levels[0].data, position->data,
           (size_t)position->width * (size_t)position->height * 4 * sizeof(float));
    for (int l = 1; l < level_count; l++) {
        const sta_image *src = &out->levels[l - 1];
        sta_image *dst = &out->levels[l];
        status = sta_image_init(dst, sta_hpr_level_size(src->width, 1),
                                sta_hpr_level_size(src->height, 1), 4, err);
        if (status != STA_OK) {
            sta_hpr_ref_pyramid_release(out);
            return status;
        }
        for (int j = 0; j < dst->height; j++) {
            for (int i = 0; i < dst->width; i++) {
                const float *best = NULL;
                for (int bj = 0; bj < 2; bj++) {
                    for (int bi = 0; bi < 2; bi++) {
                        int qx = 2 * i + bi, qy = 2 * j + bj;
                        if (qx >= src->width || qy >= src->height) {
                            continue;
                        }
                        const float *v = sta_image_at(src, qx, qy);
                        if (v[3] > 0.5f && (!best || -v[2] < -best[2])) {
                            best = v;
                        }
                    }
                }
                if (best) {
                    memcpy(sta_image_at(dst, i, j), best, 4 * sizeof(float));
                }
            }
        }
    }
    return STA_OK;
}

void sta_hpr_ref_pyramid_release(sta_hpr_pyramid *pyramid)
{
    for (int l = 0; l < STA_HPR_MAX_LEVELS; l++) {
        sta_image_release(&pyramid->levels[l]);
    }
    memset(pyramid, 0, sizeof(*pyramid));
}

// What the shaders' hpr_common.glsl computes, one function for one function.

typedef struct occlusion_frame {
    float tan_x, tan_y;     // tan of the half field of view, horizontally and vertically
    float scale_x, scale_y; // pixels per unit of x / d and y / d: size / (2 tan)
    float far_m;
    float threshold;
    int width, height;
} occlusion_frame;

static occlusion_frame frame_of(const sta_view_params *view, const sta_hpr_params *resolved)
{
    occlusion_frame f;
    f.tan_y = tanf(0.5f * view->fov_y);
    f.tan_x = f.tan_y * (float)view->width_px / (float)view->height_px;
    f.scale_x = 0.5f * (float)view->width_px / f.tan_x;
    f.scale_y = 0.5f * (float)view->height_px / f.tan_y;
    f.far_m = resolved->far_m;
    f.threshold = resolved->threshold;
    f.width = view->width_px;
    f.height = view->height_px;
    return f;
}

// The pixel's own point, or for background the point at depth far_m on its ray.
static void centre_point(const occlusion_frame *f, const float *own, int px, int py, float out[3])
{
    if (own[3] > 0.5f) {
        out[0] = own[0];
        out[1] = own[1];
        out[2] = own[2];
        return;
    }
    float ndc_x = ((float)px + 0.5f) / (float)f->width * 2.0f - 1.0f;
    float ndc_y = ((float)py + 0.5f) / (float)f->height * 2.0f - 1.0f;
    out[0] = ndc_x * f->tan_x * f->far_m;
    out[1] = ndc_y * f->tan_y * f->far_m;
    out[2] = -f->far_m;
}

// Neighbour y's occlusion value seen from x; false for coincident points (and a
// neighbour at the eye), which are skipped.
static bool occlusion_value(const float x[3], const float *y, float *value)
{
    float d0 = y[0] - x[0], d1 = y[1] - x[1], d2 = y[2] - x[2];
    float dd = d0 * d0 + d1 * d1 + d2 * d2;
    float yy = y[0] * y[0] + y[1] * y[1] + y[2] * y[2];
    if (!(dd >= STA_HPR_MIN_LENGTH2_M2) || !(yy >= STA_HPR_MIN_LENGTH2_M2)) {
        return false;
    }
    float c = d0 * -y[0] + d1 * -y[1] + d2 * -y[2];
    *value = 1.0f - c * (1.0f / sqrtf(dd)) * (1.0f / sqrtf(yy));
    return true;
}

static void add_neighbour(const float x[3], const float *y, int sector, float sector_min[8])
{
    float value;
    if (occlusion_value(x, y, &value) && value < sector_min[sector]) {
        sector_min[sector] = value;
    }
}

// The sectors an empty pixel's candidate landing at v (pixels from the pixel's centre)
// closes, as bits: the two whose axes (multiples of 45 deg) enclose its direction, and
// where it lies within STA_HPR_AXIS_TOL (tangent) of an axis, the three around that
// axis, so that points on a regular grid close the same sectors whatever the rounding
// (shader: hpr_landing_sectors).
static unsigned landing_sectors(const float v[2])
{
    float ax = fabsf(v[0]), ay = fabsf(v[1]);
    int o; // octant: the direction lies in [o 45 deg, (o + 1) 45 deg)
    if (v[1] >= 0.0f) {
        o = v[0] > 0.0f ? (v[1] < v[0] ? 0 : 1) : (v[1] > -v[0] ? 2 : 3);
    } else {
        o = v[0] < 0.0f ? (-v[1] < -v[0] ? 4 : 5) : (-v[1] > v[0] ? 6 : 7);
    }
    bool on_axis = fminf(ax, ay) <= STA_HPR_AXIS_TOL * fmaxf(ax, ay);
    bool on_diagonal = fabsf(ax - ay) <= STA_HPR_AXIS_TOL * (ax + ay);
    // Octant o lies between axis o and axis o + 1 (even o: an image axis first, odd: a
    // diagonal); near its lower axis it also closes sector o - 1, near its upper one
    // o + 2: a 4-sector window from o - 1, rotated.
    bool even = (o & 1) == 0;
    bool near_lower = even ? on_axis : on_diagonal;
    bool near_upper = even ? on_diagonal : on_axis;
    unsigned window = (near_lower ? 1u : 0u) | 6u | (near_upper ? 8u : 0u);
    unsigned shifted = window << ((o + 7) & 7);
    return (shifted | (shifted >> 8)) & 255u;
}

// The sector whose axis lies nearest direction v: within 22.5 deg of it (the borders as
// sta_hpr_sector's, in float; shader: hpr_nearest_sector).
static int nearest_sector(const float v[2])
{
    float ax = fabsf(v[0]), ay = fabsf(v[1]);
    float num_x = (float)STA_HPR_SECTOR_TAN_NUM * ax, num_y = (float)STA_HPR_SECTOR_TAN_NUM * ay;
    float den_x = (float)STA_HPR_SECTOR_TAN_DEN * ax, den_y = (float)STA_HPR_SECTOR_TAN_DEN * ay;
    if (den_y <= num_x) {
        return v[0] >= 0.0f ? 0 : 4;
    }
    if (den_x <= num_y) {
        return v[1] > 0.0f ? 2 : 6;
    }
    if (v[0] > 0.0f) {
        return v[1] > 0.0f ? 1 : 7;
    }
    return v[1] > 0.0f ? 3 : 5;
}

// Where point y lands on screen relative to pixel (px, py)'s centre, in pixels; false
// for a point not in front of the eye.
static bool screen_offset(const occlusion_frame *f, const float *y, int px, int py, float v[2])
{
    float d = -y[2];
    if (!(d > 0.0f)) {
        return false;
    }
    float inv = 1.0f / d;
    v[0] = y[0] * inv * f->scale_x + 0.5f * (float)f->width - ((float)px + 0.5f);
    v[1] = y[1] * inv * f->scale_y + 0.5f * (float)f->height - ((float)py + 0.5f);
    return true;
}

// The pixel's own surface: a plane through its point in inverse depth over the screen,
// w(v) = 1 + g . (v - v0) times 1 / d0 (exact for a plane under perspective), fitted by
// least squares to its direct neighbours; `ok` when they fit within the tolerance.
typedef struct own_surface {
    bool ok;
    float v0[2];   // where the pixel's point lands, pixels from the pixel's centre
    float g[2];    // gradient of d0 / d per pixel
    float d0;      // the point's depth
    float tol_m;   // the fit's tolerance, metres
    float front_m; // how much nearer than the surface an occluder lies
} own_surface;

static const int ring_offset[8][2] = { { -1, -1 }, { 0, -1 }, { 1, -1 }, { -1, 0 },
                                       { 1, 0 },   { -1, 1 }, { 0, 1 },  { 1, 1 } };

static own_surface fit_own_surface(const occlusion_frame *f, const sta_image *level0, int px,
                                   int py, float tol_m)
{
    own_surface s = { 0 };
    const float *own = sta_image_at(level0, px, py);
    if (!(tol_m > 0.0f) || !sta_position_occludes(own[3]) || !screen_offset(f, own, px, py, s.v0)) {
        return s;
    }
    s.d0 = -own[2];
    s.tol_m = tol_m;
    s.front_m = STA_HPR_SURFACE_FRONT_SHARE * tol_m;
    float sxx = 0.0f, sxy = 0.0f, syy = 0.0f, sxw = 0.0f, syw = 0.0f, sww = 0.0f;
    int n = 0;
    for (int i = 0; i < 8; i++) {
        int nx = px + ring_offset[i][0], ny = py + ring_offset[i][1];
        if (nx < 0 || ny < 0 || nx >= f->width || ny >= f->height) {
            continue;
        }
        const float *y = sta_image_at(level0, nx, ny);
        float v[2];
        if (!sta_position_occludes(y[3]) || !screen_offset(f, y, px, py, v)) {
            continue;
        }
        float dx = v[0] - s.v0[0], dy = v[1] - s.v0[1];
        float dw = s.d0 * (1.0f / -y[2]) - 1.0f;
        sxx += dx * dx;
        sxy += dx * dy;
        syy += dy * dy;
        sxw += dx * dw;
        syw += dy * dw;
        sww += dw * dw;
        n++;
    }
    float det = sxx * syy - sxy * sxy;
    if (n < STA_HPR_SURFACE_MIN_POINTS || !(det >= STA_HPR_SURFACE_MIN_DET)) {
        return s;
    }
    s.g[0] = (syy * sxw - sxy * syw) / det;
    s.g[1] = (sxx * syw - sxy * sxw) / det;
    // The squared residuals' sum, in units of d0 / d: within (tol / d0)^2.
    float ssr = sww - s.g[0] * sxw - s.g[1] * syw;
    float tol = tol_m / s.d0;
    s.ok = ssr <= tol * tol;
    return s;
}

// True when point y, landing at v (pixels from the pixel's centre), lies nearer than the
// pixel's own surface there by more than the tolerance (or the surface does not reach
// that far: its inverse depth is not positive there).
static bool in_front_of_surface(const own_surface *s, const float *y, const float v[2])
{
    float w = 1.0f + s->g[0] * (v[0] - s->v0[0]) + s->g[1] * (v[1] - s->v0[1]);
    return !(w > 0.0f) || -y[2] * w < s->d0 - s->front_m * w; // d < d0 / w - front
}

// For an empty pixel, sector s is unknown when nothing in it closes it and part of its
// neighbourhood lies outside the image (bit s of `outside`): what lies there could have
// closed it, so it is left out of the mean rather than counted open (surfaces running
// off-screen are filled to the edge). A point keeps all 8 sectors, outside counting
// open: without evidence of a surface in front it stays visible. The exhaustive
// operator sets bit s when the disc of radius `reach_px` crosses the border in the
// sector's direction.
static const float sector_dir[8][2] = { { 1, 0 },  { STA_HPR_SQRT_HALF, STA_HPR_SQRT_HALF },
                                        { 0, 1 },  { -STA_HPR_SQRT_HALF, STA_HPR_SQRT_HALF },
                                        { -1, 0 }, { -STA_HPR_SQRT_HALF, -STA_HPR_SQRT_HALF },
                                        { 0, -1 }, { STA_HPR_SQRT_HALF, -STA_HPR_SQRT_HALF } };

static bool sector_leaves_image(const occlusion_frame *f, int px, int py, int sector,
                                float reach_px)
{
    float ex = ((float)px + 0.5f) + reach_px * sector_dir[sector][0];
    float ey = ((float)py + 0.5f) + reach_px * sector_dir[sector][1];
    return ex < 0.0f || ey < 0.0f || ex >= (float)f->width || ey >= (float)f->height;
}

static unsigned reach_outside(const occlusion_frame *f, int px, int py, float reach_px)
{
    unsigned outside = 0;
    for (int s = 0; s < 8; s++) {
        outside |= (unsigned)sector_leaves_image(f, px, py, s, reach_px) << s;
    }
    return outside;
}

// Mean of the known sectors' minima (summed in sector order); 1 when none is known.
static float sector_mean(const float sector_min[8], bool is_point, unsigned outside)
{
    float sum = 0.0f;
    int known = 0;
    for (int s = 0; s < 8; s++) {
        if (is_point || sector_min[s] < 1.0f || !((outside >> s) & 1u)) {
            sum += sector_min[s];
            known++;
        }
    }
    return known > 0 ? sum / (float)known : 1.0f;
}

static float label_of(bool is_point, float mean, float threshold)
{
    if (is_point) {
        return mean >= threshold ? STA_LABEL_VISIBLE : STA_LABEL_HIDDEN;
    }
    float background = (float)STA_HPR_BACKGROUND_OPEN_SECTORS * 0.125f;
    return mean >= fmaxf(threshold, background) ? STA_LABEL_BACKGROUND : STA_LABEL_HOLE;
}

// Sector s of an empty pixel spans the directions of sectors s - 1 .. s + 1 (its
// candidates close the sectors around where they land): unknown when any of those
// leaves the image within `reach_px` (shader: hpr_wedge_outside of hpr_reach_outside).
static unsigned wedge_outside(const occlusion_frame *f, int px, int py, float reach_px)
{
    unsigned o = reach_outside(f, px, py, reach_px);
    return (o | (o << 1) | (o >> 1) | (o << 7) | (o >> 7)) & 255u;
}

// The sectors closed by the candidates of level k around pixel (px, py) (shader:
// add_neighbour with by_landing): the texels within `span` (1 or 2) of the ancestor
// and, with `axes2`, the 4 texels 2 away along the axes; a candidate closes the sectors
// around where it lands (landing_sectors) when it is drawn, nearer than
// `occluder_limit`, within `cut2` (squared pixels) and, for a marked point, within its
// reach; `extra` gathers what they tell the flank test.
// What an empty pixel's closing candidates tell the border rule's flank test (shader:
// flank_candidate's axis_closed and near2).
typedef struct landing_extra {
    unsigned axis_closed; /* sectors whose axis lies nearest a candidate's direction */
    float near2;          /* least squared distance of a candidate, pixels */
} landing_extra;

static unsigned closed_by_level(const occlusion_frame *f, const sta_image *lk, int k, int span,
                                bool axes2, int px, int py, float cut2, float occluder_limit,
                                float marked_reach, landing_extra *extra)
{
    unsigned closed = 0;
    int ax = px >> k, ay = py >> k;
    for (int dy = -2; dy <= 2; dy++) {
        for (int dx = -2; dx <= 2; dx++) {
            int nx = ax + dx, ny = ay + dy;
            int adx = dx < 0 ? -dx : dx, ady = dy < 0 ? -dy : dy;
            bool axis2 = axes2 && adx + ady == 2 && (adx == 0 || ady == 0);
            if ((dx == 0 && dy == 0) || (adx > span && !axis2) || (ady > span && !axis2) ||
                nx < 0 || ny < 0 || nx >= lk->width || ny >= lk->height) {
                continue;
            }
            const float *y = sta_image_at(lk, nx, ny);
            float v[2];
            if (y[3] <= 0.5f || !screen_offset(f, y, px, py, v) || !(-y[2] < occluder_limit)) {
                continue;
            }
            float dist2 = v[0] * v[0] + v[1] * v[1];
            float marked = marked_reach * (1.0f / -y[2]);
            bool reached = !sta_position_reach_limited(y[3]) || dist2 <= marked * marked;
            if (reached && dist2 <= cut2) {
                closed |= landing_sectors(v);
                extra->axis_closed |= 1u << nearest_sector(v);
                extra->near2 = fminf(extra->near2, dist2);
            }
        }
    }
    return closed;
}

// Sectors of an empty pixel that are unknown: their wedge leaves the image within the
// candidates' reach, up to sta_hpr_empty_border_px.
static unsigned empty_outside(const occlusion_frame *f, int px, int py, float reach)
{
    float band = sta_hpr_empty_border_px(f->height);
    return wedge_outside(f, px, py, fminf(fmaxf(reach, STA_HPR_MIN_REACH_PX), band));
}

// The sectors of an empty pixel closed by its candidates: the ring of every level up to
// `level` and, below it, the 4 texels 2 away along the axes, within `reach` pixels
// (levels >= 1; level 0: the direct neighbours, no cut).
static unsigned empty_closed(const occlusion_frame *f, const sta_hpr_pyramid *pyramid, int px,
                             int py, int level, float reach, float occluder_limit,
                             float marked_reach, landing_extra *extra)
{
    unsigned closed = 0;
    for (int k = 0; k <= level; k++) {
        float cut2 = k > 0 ? reach * reach : INFINITY;
        closed |= closed_by_level(f, &pyramid->levels[k], k, 1, k > 0 && k < level, px, py, cut2,
                                  occluder_limit, marked_reach, extra);
    }
    return closed;
}

// The unknown sectors (bits of `outside`) next to a known one: the flanks of the unknown
// runs (shader: hpr_flanks).
static unsigned flanks_of(unsigned outside)
{
    unsigned known = ~outside & 255u;
    return outside & ((known << 1) | (known >> 1) | (known << 7) | (known >> 7)) & 255u;
}

// An empty pixel's mean (shader: empty_pixel_mean, docs/HPR.md "Empty pixels"): the
// share of its known sectors that no candidate closes (empty_closed, within min(cut,
// 2^level)). A pixel without unknown sectors whose open ones form one run of at most
// STA_HPR_EMPTY_WIDEN_OPEN also takes its top level's 5 x 5 texels within min(cut,
// 2^(level + 1)) (the unknown sectors as before): a sparse surface leaves a wedge
// without a candidate within 2^level, a gap's pixels have more open, or two runs across
// a band; near the image border (unknown sectors) the wider reach filled the gaps that
// touch the border up to the band's edge, in straight lines.
static float empty_pixel_mean(const occlusion_frame *f, const sta_hpr_pyramid *pyramid, int px,
                              int py, int level, float radius, float occluder_limit,
                              float marked_reach)
{
    float cut = STA_HPR_CUT_FACTOR * radius;
    // At most the border band's width (shader: the same min with u_empty_border).
    float near = fminf(fmaxf(STA_HPR_EMPTY_NEAR_RADII * radius, STA_HPR_EMPTY_NEAR_MIN_PX),
                       sta_hpr_empty_border_px(f->height));
    float near2 = near * near;
    landing_extra extra = { 0u, 3.0e38f };
    float reach = fminf(cut, STA_HPR_EMPTY_CUT_BLOCKS * (float)(1 << level));
    unsigned outside = empty_outside(f, px, py, reach);
    unsigned flanks = flanks_of(outside);
    unsigned closed =
        empty_closed(f, pyramid, px, py, level, reach, occluder_limit, marked_reach, &extra);
    unsigned open = ~(closed | outside) & 255u;
    unsigned starts = open & ~((open << 1) | (open >> 7)); // first sectors of open runs
    if (level > 0 && (outside & ~closed) == 0 && __builtin_popcount(starts) == 1 &&
        __builtin_popcount(open) <= STA_HPR_EMPTY_WIDEN_OPEN) {
        reach = fminf(cut, STA_HPR_EMPTY_CUT_BLOCKS * (float)(2 << level));
        closed |= closed_by_level(f, &pyramid->levels[level], level, 2, false, px, py,
                                  reach * reach, occluder_limit, marked_reach, &extra);
    }
    // The border rule beside the data only (STA_HPR_EMPTY_NEAR_RADII; shader:
    // flank_test_fires): a hole only by the border rule (an unknown sector open) with a
    // flank without a candidate near its axis, also among the top level's 5 x 5 texels
    // within twice the reach (which inform this test only), and no candidate within `near`:
    // the unknown sectors count as open.
    if (flanks != 0 && closed != 0 && ((closed | outside) & 255u) == 255u &&
        (outside & ~closed) != 0 && (flanks & ~extra.axis_closed) != 0 && extra.near2 > near2) {
        if (level > 0) {
            float wide = fminf(cut, STA_HPR_EMPTY_CUT_BLOCKS * (float)(2 << level));
            (void)closed_by_level(f, &pyramid->levels[level], level, 2, false, px, py, wide * wide,
                                  occluder_limit, marked_reach, &extra);
        }
        if ((flanks & ~extra.axis_closed) != 0 && extra.near2 > near2) {
            outside = 0;
        }
    }
    unsigned known = closed | (~outside & 255u);
    int n = __builtin_popcount(known);
    return n > 0 ? (float)__builtin_popcount(known & ~closed) / (float)n : 1.0f;
}

// The depth of texel (qx, qy) of the coarse level (clamped to that level): its point's,
// else that of the first ancestor above holding a point, else the far depth (shader:
// coarse_depth).
static float coarse_depth(const occlusion_frame *f, const sta_hpr_pyramid *pyramid, int coarse,
                          int qx, int qy)
{
    const sta_image *lc = &pyramid->levels[coarse];
    qx = qx < 0 ? 0 : qx >= lc->width ? lc->width - 1 : qx;
    qy = qy < 0 ? 0 : qy >= lc->height ? lc->height - 1 : qy;
    for (int k = coarse; k < pyramid->level_count; k++) {
        const float *a = sta_image_at(&pyramid->levels[k], qx >> (k - coarse), qy >> (k - coarse));
        if (a[3] > 0.5f) {
            return -a[2];
        }
    }
    return f->far_m;
}

// An empty pixel's coarse depth (issue 15, part 2, twentieth round; shader:
// empty_coarse_depth): the four coarse texels nearest the pixel's centre, their depths
// interpolated bilinearly in 1 / z, so that the level and the cut, and with them the hole
// or background decision, vary smoothly instead of changing at the coarse block lines.
// The weights are exact (multiples of 2^-2c): the same sum as the shader's, in its order.
static float empty_coarse_depth(const occlusion_frame *f, const sta_hpr_pyramid *pyramid,
                                int coarse, int px, int py)
{
    float scale = (float)(1 << coarse);
    float fx = ((float)px + 0.5f) / scale - 0.5f;
    float fy = ((float)py + 0.5f) / scale - 0.5f;
    int bx = (int)floorf(fx), by = (int)floorf(fy);
    float tx = fx - (float)bx, ty = fy - (float)by;
    float inv = 0.0f;
    for (int j = 0; j < 4; j++) {
        float wx = (j & 1) ? tx : 1.0f - tx;
        float wy = (j & 2) ? ty : 1.0f - ty;
        float w = wx * wy;
        inv += w / coarse_depth(f, pyramid, coarse, bx + (j & 1), by + (j >> 1));
    }
    return 1.0f / inv;
}

void sta_hpr_ref_pyramid_labels(const sta_view_params *view, const sta_hpr_params *params,
                                const sta_hpr_pyramid *pyramid, sta_image *out_label,
                                sta_image *out_mean, sta_image *out_level)
{
    sta_hpr_params p = resolve(params);
    occlusion_frame f = frame_of(view, &p);
    int level_count = pyramid->level_count;
    float level_depth[STA_HPR_MAX_LEVELS];
    sta_hpr_level_depths(view, &p, level_count, level_depth);
    float radius_k = sta_hpr_radius_k(view, &p);
    float gap_m = sta_hpr_occluder_gap_m(view, &p);
    float marked_reach = sta_hpr_marked_reach_px_m(view, &p);
    float surface_tol = sta_hpr_surface_tol_m(view, &p);
    // Without the see-through rule see_min stays 1 and a see-through return counts as any
    // drawn point (shader: no HPR_SEE_THROUGH).
    const bool see_rule = !p.no_see_through;
    // Level 1 at least (coarse_level >= 1 and level_count >= 2).
    int coarse = p.coarse_level < level_count - 1 ? p.coarse_level : level_count - 1;
    for (int py = 0; py < f.height; py++) {
        for (int px = 0; px < f.width; px++) {
            const float *own = sta_image_at(&pyramid->levels[0], px, py);
            float x[3];
            centre_point(&f, own, px, py, x);
            // Coarse depth: a point's is the nearest point of its ancestor block at the
            // coarse level, else of the first ancestor above holding one, else the far
            // depth; an empty pixel's (smooth gaps) is interpolated between the four
            // coarse texels nearest it (empty_coarse_depth).
            bool empty_smooth = !(own[3] > 0.5f) && !p.block_gaps;
            float z = empty_smooth ? empty_coarse_depth(&f, pyramid, coarse, px, py)
                                   : coarse_depth(&f, pyramid, coarse, px >> coarse, py >> coarse);
            int level = 0;
            for (int l = 1; l < level_count; l++) {
                if (z <= level_depth[l]) {
                    level = l;
                }
            }
            // The neighbourhood radius is K / z pixels (eq. 1 without rounding).
            // Candidates of the rings at levels >= 1 whose points land farther than
            // STA_HPR_CUT_FACTOR radii from the pixel's centre are dropped: all pixels of
            // an ancestor block share its rings, and without the cut the whole block
            // flips between hole and background at once (square, stair-stepped gaps).
            float radius = radius_k / z;
            float cut = STA_HPR_CUT_FACTOR * radius;
            float cut2 = cut * cut;
            // Only neighbours nearer than the centre point by more than the gap occlude.
            float occluder_limit = -x[2] - gap_m;
            if (empty_smooth) {
                float mean = empty_pixel_mean(&f, pyramid, px, py, level, radius, occluder_limit,
                                              marked_reach);
                *sta_image_at(out_label, px, py) = label_of(false, mean, f.threshold);
                if (out_mean) {
                    *sta_image_at(out_mean, px, py) = mean;
                }
                if (out_level) {
                    *sta_image_at(out_level, px, py) = (float)level;
                }
                continue;
            }
            // On its own surface, a neighbour must also lie in front of that surface.
            own_surface surface = fit_own_surface(&f, &pyramid->levels[0], px, py, surface_tol);
            float sector_min[8] = { 1, 1, 1, 1, 1, 1, 1, 1 };
            // See-through returns' minima apart, and whether a solid candidate was seen
            // (STA_HPR_SOLID_LEVELS; shader: g_see_lo / g_see_hi, g_solid).
            float see_min[8] = { 1, 1, 1, 1, 1, 1, 1, 1 };
            bool solid = false;
            unsigned outside = 0;
            for (int k = 0; k <= level; k++) {
                const sta_image *lk = &pyramid->levels[k];
                int ax = px >> k, ay = py >> k;
                for (int dy = -1; dy <= 1; dy++) {
                    for (int dx = -1; dx <= 1; dx++) {
                        int nx = ax + dx, ny = ay + dy;
                        if (dx == 0 && dy == 0) {
                            continue;
                        }
                        if (nx < 0 || ny < 0 || nx >= lk->width || ny >= lk->height) {
                            // A ring texel outside the image: its sector may have been
                            // closed out there.
                            outside |= 1u << sta_hpr_sector(2 * dx, 2 * dy);
                            continue;
                        }
                        const float *y = sta_image_at(lk, nx, ny);
                        float v[2];
                        if (y[3] <= 0.5f || !screen_offset(&f, y, px, py, v) ||
                            !(-y[2] < occluder_limit)) {
                            continue;
                        }
                        float dist2 = v[0] * v[0] + v[1] * v[1];
                        if (k > 0 && dist2 > cut2) {
                            continue;
                        }
                        if (surface.ok && !in_front_of_surface(&surface, y, v)) {
                            continue;
                        }
                        // A marked point (scattered returns) occludes only near its own
                        // position on screen: the gaps between such points are no surface.
                        float reach = marked_reach * (1.0f / -y[2]);
                        if (sta_position_reach_limited(y[3]) && !(dist2 <= reach * reach)) {
                            continue;
                        }
                        // Each ring position is its own sector (Figure 3's colours). The
                        // direction from the pixel to where the point lands would leave
                        // sectors empty (the ring's points cluster), opening holes.
                        int sector = sta_hpr_sector(2 * dx, 2 * dy);
                        float value;
                        if (!occlusion_value(x, y, &value)) {
                            continue;
                        }
                        float *minima =
                            see_rule && sta_position_see_through(y[3]) ? see_min : sector_min;
                        if (value < minima[sector]) {
                            minima[sector] = value;
                        }
                        solid =
                            solid || (k <= STA_HPR_SOLID_LEVELS && sta_position_occludes(y[3]) &&
                                      value < STA_HPR_SOLID_VALUE);
                    }
                }
            }
            // See-through returns close an empty pixel's sectors, and a point's where a
            // solid candidate is near (behind a wall, not only behind the glass).
            if (!(own[3] > 0.5f) || solid) {
                for (int s = 0; s < 8; s++) {
                    sector_min[s] = fminf(sector_min[s], see_min[s]);
                }
            }
            float mean = sector_mean(sector_min, own[3] > 0.5f, outside);
            *sta_image_at(out_label, px, py) = label_of(own[3] > 0.5f, mean, f.threshold);
            if (out_mean) {
                *sta_image_at(out_mean, px, py) = mean;
            }
            if (out_level) {
                *sta_image_at(out_level, px, py) = (float)level;
            }
        }
    }
}

sta_status sta_hpr_ref_pyramid(const sta_view_params *view, const sta_hpr_params *params,
                               const sta_image *position, sta_image *out_label, sta_error *err)
{
    sta_hpr_pyramid pyramid;
    sta_status status = sta_hpr_ref_build_pyramid(position, &pyramid, err);
    if (status != STA_OK) {
        return status;
    }
    sta_hpr_ref_pyramid_labels(view, params, &pyramid, out_label, NULL, NULL);
    sta_hpr_ref_pyramid_release(&pyramid);
    return STA_OK;
}

void sta_hpr_ref_exhaustive(const sta_view_params *view, const sta_hpr_params *params,
                            int radius_px, const sta_image *position, sta_image *out_label,
                            sta_image *out_mean)
{
    sta_hpr_params p = resolve(params);
    occlusion_frame f = frame_of(view, &p);
    for (int py = 0; py < f.height; py++) {
        for (int px = 0; px < f.width; px++) {
            const float *own = sta_image_at(position, px, py);
            float x[3];
            centre_point(&f, own, px, py, x);
            float sector_min[8] = { 1, 1, 1, 1, 1, 1, 1, 1 };
            for (int dy = -radius_px; dy <= radius_px; dy++) {
                for (int dx = -radius_px; dx <= radius_px; dx++) {
                    int nx = px + dx, ny = py + dy;
                    if ((dx == 0 && dy == 0) || nx < 0 || ny < 0 || nx >= f.width ||
                        ny >= f.height) {
                        continue;
                    }
                    const float *y = sta_image_at(position, nx, ny);
                    if (y[3] > 0.5f) {
                        add_neighbour(x, y, sta_hpr_sector(2 * dx, 2 * dy), sector_min);
                    }
                }
            }
            float reach =
                fminf(fmaxf((float)radius_px, STA_HPR_MIN_REACH_PX), STA_HPR_MAX_REACH_PX);
            float mean = sector_mean(sector_min, own[3] > 0.5f, reach_outside(&f, px, py, reach));
            *sta_image_at(out_label, px, py) = label_of(own[3] > 0.5f, mean, f.threshold);
            if (out_mean) {
                *sta_image_at(out_mean, px, py) = mean;
            }
        }
    }
}
