// SPDX-License-Identifier: MIT
// HPR functions shared by hpr_occlusion.comp and hpr_exhaustive.comp. Twin:
// src/render/ref/hpr_ref.c (same rules, same order; `precise` keeps the compiler from
// fusing or reordering the float maths the twin does step by step).
// Needs the defines STA_HPR_SECTOR_TAN_NUM/_DEN, STA_HPR_MIN_LENGTH2_M2 and
// STA_LABEL_* (added by src/render/pass_hpr.c from the C headers).

// Sector 0..7 (counter-clockwise from +x, 45 deg each, centred on multiples of 45 deg)
// of a screen direction given in half pixels.
int hpr_sector(ivec2 v2)
{
    ivec2 a = abs(v2);
    if (STA_HPR_SECTOR_TAN_DEN * a.y <= STA_HPR_SECTOR_TAN_NUM * a.x) {
        return v2.x >= 0 ? 0 : 4;
    }
    if (STA_HPR_SECTOR_TAN_DEN * a.x <= STA_HPR_SECTOR_TAN_NUM * a.y) {
        return v2.y > 0 ? 2 : 6;
    }
    if (v2.x > 0) {
        return v2.y > 0 ? 1 : 7;
    }
    return v2.y > 0 ? 3 : 5;
}

// The sectors an empty pixel's candidate landing at v (pixels from the pixel's centre)
// closes, as bits: the two whose axes (multiples of 45 deg) enclose its direction, and
// where it lies within STA_HPR_AXIS_TOL (tangent) of an axis, the three around that
// axis, so that points on a regular grid close the same sectors whatever the rounding.
// Selects and shifts only (no branches: llvmpipe runs both sides). Twin: landing_sectors.
int hpr_landing_sectors(vec2 v)
{
    vec2 a = abs(v);
    // Octant o: the direction lies in [o 45 deg, (o + 1) 45 deg).
    int o = v.y >= 0.0 ? (v.x > 0.0 ? (v.y < v.x ? 0 : 1) : (v.y > -v.x ? 2 : 3))
                       : (v.x < 0.0 ? (-v.y < -v.x ? 4 : 5) : (-v.y > v.x ? 6 : 7));
    bool on_axis = min(a.x, a.y) <= STA_HPR_AXIS_TOL * max(a.x, a.y);
    bool on_diagonal = abs(a.x - a.y) <= STA_HPR_AXIS_TOL * (a.x + a.y);
    // Octant o lies between axis o and axis o + 1; an even o starts at a sector axis of
    // the image (x or y), an odd one at a diagonal. Near its lower axis it also closes
    // sector o - 1, near its upper one o + 2: a 4-sector window from o - 1, rotated.
    bool even = (o & 1) == 0;
    bool near_lower = even ? on_axis : on_diagonal;
    bool near_upper = even ? on_diagonal : on_axis;
    int window = (near_lower ? 1 : 0) | 6 | (near_upper ? 8 : 0);
    int shifted = window << ((o + 7) & 7);
    return (shifted | (shifted >> 8)) & 255;
}

// The sector whose axis lies nearest direction v: within 22.5 deg of it (the borders as
// hpr_sector's, in float; twin: nearest_sector).
int hpr_nearest_sector(vec2 v)
{
    vec2 a = abs(v);
    precise float num_x = float(STA_HPR_SECTOR_TAN_NUM) * a.x;
    precise float num_y = float(STA_HPR_SECTOR_TAN_NUM) * a.y;
    precise float den_x = float(STA_HPR_SECTOR_TAN_DEN) * a.x;
    precise float den_y = float(STA_HPR_SECTOR_TAN_DEN) * a.y;
    if (den_y <= num_x) {
        return v.x >= 0.0 ? 0 : 4;
    }
    if (den_x <= num_y) {
        return v.y > 0.0 ? 2 : 6;
    }
    if (v.x > 0.0) {
        return v.y > 0.0 ? 1 : 7;
    }
    return v.y > 0.0 ? 3 : 5;
}

// The unknown sectors (bits of `outside`) next to a known one: the flanks of the unknown
// runs (twin: flanks).
int hpr_flanks(int outside)
{
    int known = ~outside & 255;
    return outside & ((known << 1) | (known >> 1) | (known << 7) | (known >> 7)) & 255;
}

// An empty pixel's mean: the share of its known sectors that are open (bits: `closed`
// by a candidate, `outside` unknown unless closed); 1 when none is known. Twin:
// empty_mean.
float hpr_empty_mean(int closed, int outside)
{
    int known = closed | (~outside & 255);
    int n = bitCount(known);
    return n > 0 ? float(bitCount(known & ~closed)) / float(n) : 1.0;
}

// For an empty pixel, whose candidates close the sectors around where they land,
// sector s spans the directions of sectors s - 1 .. s + 1: it is unknown when any of
// those leaves the image (bits of `outside`, hpr_reach_outside; twin: wedge_outside).
int hpr_wedge_outside(int outside, bool is_point)
{
    int wide = outside | (outside << 1) | (outside >> 1) | (outside << 7) | (outside >> 7);
    return is_point ? outside : wide & 255;
}

// True when a texel holds a point that closes sectors: drawn (w > 0.5) and not marked
// as a volumetric class (w = STA_POSITION_W_MARKED; twin: sta_position_occludes).
bool hpr_occludes(float w)
{
    return w > 0.5 && w < STA_POSITION_W_OCCLUDER_MAX;
}

// True when a drawn point closes sectors only within the marked reach: a marked point
// (volumetric class), not a see-through one (twin: sta_position_reach_limited).
bool hpr_reach_limited(float w)
{
    return w >= STA_POSITION_W_OCCLUDER_MAX && w < STA_POSITION_W_SEE_THROUGH_MIN;
}

// True when a drawn point is a see-through return (w = STA_POSITION_W_SEE_THROUGH: not
// the last return of its pulse; twin: sta_position_see_through).
bool hpr_see_through(float w)
{
    return w >= STA_POSITION_W_SEE_THROUGH_MIN;
}

// The pixel's own point, or for background the point at depth far_m on its ray.
vec3 hpr_centre_point(vec4 own, ivec2 p, ivec2 size, vec2 tan_half, float far_m)
{
    if (own.w > 0.5) {
        return own.xyz;
    }
    precise float ndc_x = (float(p.x) + 0.5) / float(size.x) * 2.0 - 1.0;
    precise float ndc_y = (float(p.y) + 0.5) / float(size.y) * 2.0 - 1.0;
    precise float cx = ndc_x * tan_half.x * far_m;
    precise float cy = ndc_y * tan_half.y * far_m;
    return vec3(cx, cy, -far_m);
}

// Neighbour y's occlusion value seen from x: 1 - dot((y - x) / |y - x|, -y / |y|);
// false when y coincides with x or with the eye (the neighbour is skipped).
bool hpr_occlusion(vec3 x, vec3 y, out float value)
{
    precise float d0 = y.x - x.x;
    precise float d1 = y.y - x.y;
    precise float d2 = y.z - x.z;
    precise float dd = d0 * d0 + d1 * d1 + d2 * d2;
    precise float yy = y.x * y.x + y.y * y.y + y.z * y.z;
    if (!(dd >= STA_HPR_MIN_LENGTH2_M2) || !(yy >= STA_HPR_MIN_LENGTH2_M2)) {
        value = 1.0;
        return false;
    }
    precise float c = d0 * -y.x + d1 * -y.y + d2 * -y.z;
    precise float v = 1.0 - c * (1.0 / sqrt(dd)) * (1.0 / sqrt(yy));
    value = v;
    return true;
}

// The pixel's own surface (twin: own_surface, fit_own_surface): a plane through its
// point in inverse depth over the screen, d0 / d = 1 + g . (v - v0), fitted by least
// squares to its direct neighbours. sums: dx dx, dx dy, dy dy, dx dw, dy dw, dw dw over
// n neighbours (dx, dy: offset from the point on screen, dw: d0 / d - 1). `ok` when they
// fit within tol_m (root of the summed squared residuals); an occluder must then lie
// front_m = STA_HPR_SURFACE_FRONT_SHARE tol_m in front of the surface (docs/HPR.md).
struct HprSurface {
    bool ok;
    vec2 v0;
    vec2 g;
    float d0;
    float tol_m;
    float front_m;
};

HprSurface hpr_surface_solve(vec2 v0, float d0, float tol_m, int n, float sums[6])
{
    HprSurface s;
    s.ok = false;
    s.v0 = v0;
    s.g = vec2(0.0);
    s.d0 = d0;
    s.tol_m = tol_m;
    s.front_m = STA_HPR_SURFACE_FRONT_SHARE * tol_m;
    precise float det = sums[0] * sums[2] - sums[1] * sums[1];
    if (n < STA_HPR_SURFACE_MIN_POINTS || !(det >= STA_HPR_SURFACE_MIN_DET)) {
        return s;
    }
    precise float gx = (sums[2] * sums[3] - sums[1] * sums[4]) / det;
    precise float gy = (sums[0] * sums[4] - sums[1] * sums[3]) / det;
    precise float ssr = sums[5] - gx * sums[3] - gy * sums[4];
    precise float tol = tol_m / d0;
    s.g = vec2(gx, gy);
    s.ok = ssr <= tol * tol;
    return s;
}

// True when a point at depth d landing at v (pixels from the pixel's centre) lies nearer
// than the surface there by more than its tolerance, or where the surface does not reach
// (inverse depth not positive). Twin: in_front_of_surface.
bool hpr_in_front_of_surface(HprSurface s, float d, float vx, float vy)
{
    precise float w = 1.0 + s.g.x * (vx - s.v0.x) + s.g.y * (vy - s.v0.y);
    precise float lhs = d * w;
    precise float rhs = s.d0 - s.front_m * w;
    return !(w > 0.0) || lhs < rhs; // d < d0 / w - front_m, without a division
}

// The label from the point flag and the mean of the 8 sector minima.
float hpr_label(bool is_point, float mean, float threshold)
{
    if (is_point) {
        return mean >= threshold ? STA_LABEL_VISIBLE : STA_LABEL_HIDDEN;
    }
    float background = float(STA_HPR_BACKGROUND_OPEN_SECTORS) * 0.125;
    return mean >= max(threshold, background) ? STA_LABEL_BACKGROUND : STA_LABEL_HOLE;
}

// The 8 sector minima live in two vec4 (sectors 0-3, 4-7) and are lowered by selects
// rather than by indexing an array with a per-pixel sector, which compilers (llvmpipe
// among them) turn into slow scratch memory. `value < min` as in the twin.
void hpr_lower_sector(int sector, float value, inout vec4 min_lo, inout vec4 min_hi)
{
    const ivec4 lo = ivec4(0, 1, 2, 3), hi = ivec4(4, 5, 6, 7);
    bvec4 take_lo = bvec4(uvec4(equal(lo, ivec4(sector))) & uvec4(lessThan(vec4(value), min_lo)));
    bvec4 take_hi = bvec4(uvec4(equal(hi, ivec4(sector))) & uvec4(lessThan(vec4(value), min_hi)));
    min_lo = mix(min_lo, vec4(value), take_lo);
    min_hi = mix(min_hi, vec4(value), take_hi);
}

// Bit s set when the disc of radius `reach` around pixel p crosses the image border in
// sector s's direction (the exhaustive operator's outside sectors; twin: reach_outside).
int hpr_reach_outside(ivec2 p, ivec2 size, float reach)
{
    const vec2 DIR[8] = vec2[8](vec2(1.0, 0.0), vec2(STA_HPR_SQRT_HALF, STA_HPR_SQRT_HALF),
                                vec2(0.0, 1.0), vec2(-STA_HPR_SQRT_HALF, STA_HPR_SQRT_HALF),
                                vec2(-1.0, 0.0), vec2(-STA_HPR_SQRT_HALF, -STA_HPR_SQRT_HALF),
                                vec2(0.0, -1.0), vec2(STA_HPR_SQRT_HALF, -STA_HPR_SQRT_HALF));
    int outside = 0;
    for (int s = 0; s < 8; s++) {
        precise float ex = (float(p.x) + 0.5) + reach * DIR[s].x;
        precise float ey = (float(p.y) + 0.5) + reach * DIR[s].y;
        if (ex < 0.0 || ey < 0.0 || ex >= float(size.x) || ey >= float(size.y)) {
            outside |= 1 << s;
        }
    }
    return outside;
}

// Mean of the known sectors' minima, summed in sector order; 1 when none is known. For
// an empty pixel, a sector is unknown when nothing closes it (its minimum is still 1)
// and part of its neighbourhood lies outside the image (bit s of `outside`): what lies
// there could have closed it. A point keeps all 8 sectors (twin: sector_mean).
float hpr_sector_mean(vec4 min_lo, vec4 min_hi, bool is_point, int outside)
{
    float m[8] = float[8](min_lo.x, min_lo.y, min_lo.z, min_lo.w, min_hi.x, min_hi.y, min_hi.z,
                          min_hi.w);
    precise float sum = 0.0;
    int known = 0;
    for (int s = 0; s < 8; s++) {
        if (is_point || m[s] < 1.0 || ((outside >> s) & 1) == 0) {
            sum += m[s];
            known++;
        }
    }
    return known > 0 ? sum / float(known) : 1.0;
}

// The mean below which a pixel is closed: HIDDEN for a point, HOLE for an empty pixel
// (as hpr_label decides).
float hpr_closed_bound(bool is_point, float threshold)
{
    float background = float(STA_HPR_BACKGROUND_OPEN_SECTORS) * 0.125;
    return is_point ? threshold : max(threshold, background);
}

// True when the pixel is closed whatever further neighbours add: the plain mean of all
// 8 minima (an empty sector counting 1) bounds every later mean from above, since
// minima only fall and leaving out an unclosed outside sector (value 1) only lowers a
// mean below 1. Both that mean and the label's own mean must be below the bound.
bool hpr_settled(vec4 min_lo, vec4 min_hi, bool is_point, int outside, float bound)
{
    return hpr_sector_mean(min_lo, min_hi, true, 0) < bound &&
           hpr_sector_mean(min_lo, min_hi, is_point, outside) < bound;
}
