// SPDX-License-Identifier: MIT
// HPR, the pyramidal adaptive operator (Bouchiba et al. 2018, section 3.1.2, eq. 1,
// Figure 3). Every pixel (point or background) gets a neighbourhood level from the
// coarse depth of its ancestor, then takes the 8-texel ring around its ancestor at each
// level 0..level, keeps the least occlusion value per sector and compares their mean
// with the threshold. Ring candidates farther than STA_HPR_CUT_FACTOR K / z pixels are
// dropped, and for empty pixels sectors with ring texels outside the image that nothing
// closes are left out of the mean (docs/HPR.md). A point whose direct neighbours fit a
// plane through it (its own surface) is hidden only by candidates in front of that
// surface (the own-surface rule, fit_own_surface); see-through returns (window glass)
// close a point's sectors only where a solid candidate is near (g_solid; HPR_SEE_THROUGH). With HPR_SMOOTH_GAPS (the default's
// variant; without it sta_hpr_params.block_gaps) an empty pixel's candidates close the
// sectors around where they land, within 2^level pixels, with 4 more texels 2 away along
// the axes below the top level, so that hole and background part along the points, not
// along the pyramid's blocks (issue 15, part 2; docs/HPR.md "Empty pixels"). Points and
// empty pixels share the loops of the full and anchor programs: on llvmpipe a SIMD group
// holding both kinds would run two separate paths one after the other; the refinement
// takes them from two lists (HPR_REFINE, HPR_EMPTY_LIST). Twin:
// sta_hpr_ref_pyramid_labels (empty_pixel_mean).
//
// Early exit: the sector minima only fall as neighbours are added, so once a pixel's
// mean is below its bound (HIDDEN or HOLE) no further level can open it again; the
// remaining levels are skipped (hpr_settled), and the label is the one the full loop
// gives (the twin runs every level). Most empty pixels inside a surface settle after
// the first levels.
//
// Neighbours are loaded from the images, not staged in shared memory: on llvmpipe a
// shared-memory version was 3x slower (per-lane gathers), and on GPUs the cache serves
// the overlapping rings of a workgroup. imageLoad, not texelFetch: the same texels, and
// on llvmpipe (Mesa 22.3) a float texelFetch costs ~2.5x an imageLoad (issue 15,
// fourteenth round), so the pyramid's levels lie side by side in one image.
layout(local_size_x = STA_WORKGROUP_SIZE_X, local_size_y = STA_WORKGROUP_SIZE_Y) in;
// level 0 (RGBA32F, screen_space.h)
layout(binding = STA_HPR_OCCLUSION_IMAGE_POSITION, rgba32f) readonly uniform image2D u_position;
// level l >= 1 at u_level_origin[l] (pass_hpr.h)
layout(binding = STA_HPR_OCCLUSION_IMAGE_PYRAMID, rgba32f) readonly uniform image2D u_pyramid;
layout(binding = STA_HPR_OCCLUSION_IMAGE_LABEL, r16f) writeonly uniform image2D u_label;
#ifdef HPR_REFINE // sparse operator, a copy step's refinement: the listed pixels only
// Two lists in one buffer (hpr_sparse_classify.comp): points from the front, empty pixels
// from the back; HPR_EMPTY_LIST reads the second, whose pixels are all empty, so its
// program carries no occlusion value and no surface fit, and the points' program no
// landing code.
layout(std430, binding = STA_HPR_OCCLUSION_BUFFER_LIST) readonly buffer RefineList
{
    uint u_count;       // points listed
    uint u_empty_count; // empty pixels listed
    uint u_pixels[];
};
#endif
uniform ivec2 u_size;       // width, height in pixels
uniform int u_level_count;  // pyramid levels, level 0 included (>= 2)
uniform int u_coarse_level; // already clamped to [1, u_level_count - 1]
uniform float u_level_depth[STA_HPR_MAX_LEVELS]; // sta_hpr_level_depths
uniform ivec2 u_level_origin[STA_HPR_MAX_LEVELS]; // level l's texel (0, 0) in u_pyramid
uniform vec2 u_tan_half;    // tan(fov_y / 2) * aspect, tan(fov_y / 2)
uniform float u_far;        // depth of background pixels, metres
uniform float u_threshold;
uniform float u_radius_k;   // K of eq. 1: the neighbourhood radius is K / z pixels
uniform float u_gap;       // sta_hpr_occluder_gap_m: occluders lie this much nearer
uniform float u_marked_reach; // sta_hpr_marked_reach_px_m: a marked point's reach times depth
uniform vec2 u_scale;       // pixels per unit of x / d and y / d: size / (2 tan)
uniform float u_surface_tol; // sta_hpr_surface_tol_m: own-surface tolerance, 0: rule off
uniform float u_empty_border; // sta_hpr_empty_border_px: empty pixels' border band
// sta_hpr_params.smooth_gaps: empty pixels' sectors by landing. A variant of its own
// (pass_hpr.c): as a uniform, llvmpipe ran both sides of every test of it, the default
// 30 CPU ms dearer at 1080p.
#ifdef HPR_SMOOTH_GAPS
const bool SMOOTH_GAPS = true;
#else
const bool SMOOTH_GAPS = false;
#endif
#ifdef HPR_ANCHORS
uniform int u_anchor_stride; // sta_hpr_anchor_stride
#endif

const ivec2 RING[8] = ivec2[8](ivec2(-1, -1), ivec2(0, -1), ivec2(1, -1), ivec2(-1, 0),
                               ivec2(1, 0), ivec2(-1, 1), ivec2(0, 1), ivec2(1, 1));
// The ring's axis directions (an empty pixel's radius-2 texels).
const ivec2 AXES[4] = ivec2[4](ivec2(0, -1), ivec2(-1, 0), ivec2(1, 0), ivec2(0, 1));

// The pixel's own surface (fit_own_surface), while the own-surface rule applies.
HprSurface g_surface;
#ifdef HPR_SEE_THROUGH
// See-through returns (issue 15, sixteenth round): their sector minima apart (the other
// candidates' go to min_lo / min_hi), and whether a solid candidate was seen: an
// occluding (unmarked, not see-through) one of a ring level up to STA_HPR_SOLID_LEVELS
// whose occlusion value is below STA_HPR_SOLID_VALUE. A point takes the see-through
// minima only then (add_neighbour; twin: sta_hpr_ref_pyramid_labels). Without
// HPR_SEE_THROUGH (sta_hpr_params.no_see_through: positions from depth, which hold no
// see-through returns) none of this is compiled and every candidate lowers min_lo / min_hi.
vec4 g_see_lo, g_see_hi;
bool g_solid;
bool g_solid_level; // the current ring level is one of those
#endif

// Lowers the sector minima by neighbour y at ring offset `ring` (its sector: each ring
// position is one sector, as in the paper's Figure 3). Ring candidates of levels >= 1
// (`cut`) whose points land farther than the cut radius (squared: cut2) from pixel p's
// centre are dropped, which makes the decision per pixel rather than per block, and so
// are neighbours not nearer than `limit` (the centre's depth less the occluder gap), and
// marked points (volumetric classes) landing beyond their reach, u_marked_reach / depth
// pixels: scattered returns hide what lies right behind them, their gaps are no surface.
// On the pixel's own surface (g_surface.ok) a neighbour must lie in front of that surface.
// A see-through return lowers the see-through minima (g_see_lo / g_see_hi) instead, at
// any distance like an unmarked point; an occluding neighbour of a solid level with a value
// below STA_HPR_SOLID_VALUE sets g_solid.
// For an empty pixel with SMOOTH_GAPS (`by_landing`) the neighbour closes the sectors
// around where it lands (bits in `closed`, hpr_landing_sectors) instead: seen from the
// far centre point every nearer candidate closes, no occlusion value is needed.
void add_neighbour(vec4 y, ivec2 ring, ivec2 p, vec3 x, bool cut, float cut2, float limit,
                   bool by_landing, inout int closed, inout vec4 min_lo, inout vec4 min_hi)
{
    if (!(y.w > 0.5) || !(-y.z > 0.0) || !(-y.z < limit)) {
        return;
    }
    precise float inv = 1.0 / -y.z;
    precise float vx = y.x * inv * u_scale.x + 0.5 * float(u_size.x) - (float(p.x) + 0.5);
    precise float vy = y.y * inv * u_scale.y + 0.5 * float(u_size.y) - (float(p.y) + 0.5);
    precise float dist2 = vx * vx + vy * vy;
    if (hpr_reach_limited(y.w)) {
        precise float reach = u_marked_reach * inv;
        if (!(dist2 <= reach * reach)) {
            return;
        }
    }
    float value;
    if (!(!cut || dist2 <= cut2)) {
        return;
    }
    if (by_landing) {
        closed |= hpr_landing_sectors(vec2(vx, vy));
    } else if (!(g_surface.ok && !hpr_in_front_of_surface(g_surface, -y.z, vx, vy)) &&
               hpr_occlusion(x, y.xyz, value)) {
#ifdef HPR_SEE_THROUGH
        if (hpr_see_through(y.w)) {
            hpr_lower_sector(hpr_sector(2 * ring), value, g_see_lo, g_see_hi);
        } else {
            hpr_lower_sector(hpr_sector(2 * ring), value, min_lo, min_hi);
            g_solid = g_solid || (g_solid_level && hpr_occludes(y.w) && value < STA_HPR_SOLID_VALUE);
        }
#else
        hpr_lower_sector(hpr_sector(2 * ring), value, min_lo, min_hi);
#endif
    }
}

// The sectors an empty pixel's candidates among the 5 x 5 texels around its ancestor at
// level k >= 1 close within sqrt(cut2) (the sparse-surface rule below). Twin:
// closed_by_level with span 2.
int wide_closed(ivec2 p, vec3 x, int k, float cut2, float limit)
{
    int closed = 0;
    vec4 min_lo = vec4(1.0), min_hi = vec4(1.0); // unused with by_landing
    ivec2 a = p >> k;
    ivec2 size_k = (u_size + (1 << k) - 1) >> k;
    for (int dy = -2; dy <= 2; dy++) {
        for (int dx = -2; dx <= 2; dx++) {
            ivec2 n = a + ivec2(dx, dy);
            if ((dx != 0 || dy != 0) && all(greaterThanEqual(n, ivec2(0))) &&
                all(lessThan(n, size_k))) {
                add_neighbour(imageLoad(u_pyramid, u_level_origin[k] + n), ivec2(dx, dy), p, x,
                              true, cut2, limit, true, closed, min_lo, min_hi);
            }
        }
    }
    return closed;
}

// Where point y lands, in pixels from pixel p's centre (y in front of the eye).
vec2 screen_offset(vec4 y, ivec2 p)
{
    precise float inv = 1.0 / -y.z;
    precise float vx = y.x * inv * u_scale.x + 0.5 * float(u_size.x) - (float(p.x) + 0.5);
    precise float vy = y.y * inv * u_scale.y + 0.5 * float(u_size.y) - (float(p.y) + 0.5);
    return vec2(vx, vy);
}

// What an empty pixel's candidate tells the border rule's flank test (add_neighbour's
// landing path): the sectors it closes go to `closed`, the sector whose axis lies nearest
// its direction to `axis_closed`, and its squared distance to `near2`. Its first tests repeat
// add_neighbour's on purpose: one function for both (with out parameters) made llvmpipe's
// hot walk 6 CPU ms slower at 1080p (issue 15, twentieth round).
void flank_candidate(vec4 y, ivec2 p, bool cut, float cut2, float limit, inout int closed,
                     inout int axis_closed, inout float near2)
{
    if (!(y.w > 0.5) || !(-y.z > 0.0) || !(-y.z < limit)) {
        return;
    }
    vec2 v = screen_offset(y, p);
    precise float dist2 = v.x * v.x + v.y * v.y;
    if (hpr_reach_limited(y.w)) {
        precise float reach = u_marked_reach * (1.0 / -y.z);
        if (!(dist2 <= reach * reach)) {
            return;
        }
    }
    if (!(!cut || dist2 <= cut2)) {
        return;
    }
    closed |= hpr_landing_sectors(v);
    axis_closed |= 1 << hpr_nearest_sector(v);
    near2 = min(near2, dist2);
}

// The border rule's flank test (issue 15, part 2, twentieth round; twin: the flank test in
// empty_pixel_mean). An empty pixel that is a hole only by the border rule (an unknown
// sector open, `outside`) lies in open space between a silhouette and the border, not in a
// surface running off-screen, when one of its `flanks` has no candidate within 22.5 deg of
// its axis and no candidate lies within sqrt(near2) pixels: among every level's ring and
// axis texels within the reach and the direct neighbours, and then among the top level's
// 5 x 5 texels within twice the reach (these inform the test only). The candidates are
// walked again here, since the main walk may have settled early; the sectors they close
// (`closed` on entry: the main walk's) decide whether an unknown sector stays open.
bool flank_test_fires(ivec2 p, int level, float cut, float limit, int outside, int flanks,
                      float near2, int closed)
{
    int axis_closed = 0;
    float near = 3.0e38;
    precise float reach = min(cut, STA_HPR_EMPTY_CUT_BLOCKS * float(1 << level));
    precise float cut2 = reach * reach;
    for (int k = level; k >= 1; k--) {
        ivec2 a = p >> k;
        ivec2 size_k = (u_size + (1 << k) - 1) >> k;
        for (int i = 0; i < 12; i++) {
            // the ring, then (below the top level) the texels 2 away along the axes
            ivec2 n = i < 8 ? a + RING[i] : a + 2 * AXES[i - 8];
            if ((i < 8 || k < level) && all(greaterThanEqual(n, ivec2(0))) &&
                all(lessThan(n, size_k))) {
                flank_candidate(imageLoad(u_pyramid, u_level_origin[k] + n), p, true, cut2, limit,
                                closed, axis_closed, near);
            }
        }
    }
    for (int i = 0; i < 8; i++) {
        ivec2 n = p + RING[i];
        if (all(greaterThanEqual(n, ivec2(0))) && all(lessThan(n, u_size))) {
            flank_candidate(imageLoad(u_position, n), p, false, cut2, limit, closed, axis_closed,
                            near);
        }
    }
    bool open_space = (flanks & ~axis_closed) != 0 && near > near2;
    if (open_space && level > 0 && (outside & ~closed) != 0) {
        precise float wide = min(cut, STA_HPR_EMPTY_CUT_BLOCKS * float(2 << level));
        ivec2 a = p >> level;
        ivec2 size_k = (u_size + (1 << level) - 1) >> level;
        int unused = 0;
        for (int dy = -2; dy <= 2; dy++) {
            for (int dx = -2; dx <= 2; dx++) {
                ivec2 n = a + ivec2(dx, dy);
                if ((dx != 0 || dy != 0) && all(greaterThanEqual(n, ivec2(0))) &&
                    all(lessThan(n, size_k))) {
                    flank_candidate(imageLoad(u_pyramid, u_level_origin[level] + n), p, true,
                                    wide * wide, limit, unused, axis_closed, near);
                }
            }
        }
        open_space = (flanks & ~axis_closed) != 0 && near > near2;
    }
    return open_space && (outside & ~closed) != 0;
}

// The pixel's own surface from its 8 direct neighbours `nb` (hpr_surface_solve; texels
// outside the image hold w = 0); not ok for an empty pixel, a marked point or with the
// rule off (`on` false). Twin: fit_own_surface.
HprSurface fit_own_surface(vec4 own, ivec2 p, bool on, vec4 nb[8])
{
    float d0 = -own.z;
    vec2 v0 = on ? screen_offset(own, p) : vec2(0.0);
    precise float sums[6] = float[6](0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    int n = 0;
    for (int i = 0; i < 8 && on; i++) {
        vec4 y = nb[i];
        if (!hpr_occludes(y.w) || !(-y.z > 0.0)) {
            continue;
        }
        vec2 v = screen_offset(y, p);
        precise float dx = v.x - v0.x;
        precise float dy = v.y - v0.y;
        precise float dw = d0 * (1.0 / -y.z) - 1.0;
        sums[0] += dx * dx;
        sums[1] += dx * dy;
        sums[2] += dy * dy;
        sums[3] += dx * dw;
        sums[4] += dy * dw;
        sums[5] += dw * dw;
        n++;
    }
    if (!on) {
        n = 0;
    }
    return hpr_surface_solve(v0, d0, u_surface_tol, n, sums);
}

// The depth of texel q of the coarse level (clamped to that level): its point's, else
// that of the first ancestor above holding a point, else the far depth.
float coarse_depth(ivec2 q)
{
    ivec2 last = ((u_size + (1 << u_coarse_level) - 1) >> u_coarse_level) - 1;
    q = clamp(q, ivec2(0), last);
    for (int k = u_coarse_level; k < u_level_count; k++) {
        vec4 a = imageLoad(u_pyramid, u_level_origin[k] + (q >> (k - u_coarse_level)));
        if (a.w > 0.5) {
            return -a.z;
        }
    }
    return u_far;
}

// An empty pixel's coarse depth (issue 15, part 2, twentieth round): the depths of the
// four coarse texels nearest the pixel's centre, interpolated bilinearly in 1 / z. With
// one coarse texel's depth for its whole block, the level, the cut and so the hole or
// background decision changed at the 16-px block lines, and scan-shadow gaps kept square
// notches and stair steps there; interpolated, the reach varies smoothly from pixel to
// pixel. The weights are exact (multiples of 2^-2c), so the twin gets the same sum.
float empty_coarse_depth(ivec2 p)
{
    precise vec2 f = (vec2(p) + 0.5) / float(1 << u_coarse_level) - 0.5;
    ivec2 b = ivec2(floor(f));
    precise vec2 t = f - vec2(b);
    precise float inv = 0.0;
    for (int j = 0; j < 4; j++) {
        precise float wx = (j & 1) != 0 ? t.x : 1.0 - t.x;
        precise float wy = (j & 2) != 0 ? t.y : 1.0 - t.y;
        precise float w = wx * wy;
        inv += w / coarse_depth(b + ivec2(j & 1, j >> 1));
    }
    return 1.0 / inv;
}

void main()
{
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
#ifdef HPR_REFINE
    // Consecutive entries to one workgroup (the classify step lists a tile's pixels
    // together): neighbouring pixels in each SIMD row, as in the full-screen dispatch.
    uint group = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
    uint i = group * uint(STA_WORKGROUP_SIZE_X * STA_WORKGROUP_SIZE_Y) + gl_LocalInvocationIndex;
#ifdef HPR_EMPTY_LIST
    if (i >= u_empty_count) {
        return;
    }
    uint entry = u_pixels[uint(u_pixels.length()) - 1u - i];
#else
    if (i >= u_count) {
        return;
    }
    uint entry = u_pixels[i];
#endif
    p = ivec2(int(entry & 0xffffu), int(entry >> 16));
#endif
#ifdef HPR_ANCHORS // sparse operator, first step: the anchors only (x, y multiples of the stride)
    p *= u_anchor_stride;
#endif
    if (p.x >= u_size.x || p.y >= u_size.y) {
        return;
    }
#ifdef HPR_EMPTY_LIST
    // Known empty (listed so by the copy step): no position to load.
    vec4 own = vec4(0.0);
    const bool is_point = false;
    const bool on = false;
#else
    vec4 own = imageLoad(u_position, p);
#ifdef HPR_REFINE
    const bool is_point = true; // the points' list: no empty pixel's code
#else
    bool is_point = own.w > 0.5;
#endif
#endif
    // Coarse depth: a point's from its ancestor at the coarse level; an empty pixel's
    // (with SMOOTH_GAPS) interpolated between the four coarse texels nearest it
    // (empty_coarse_depth). Level: the largest l with z <= u_level_depth[l].
    float z = !is_point && SMOOTH_GAPS ? empty_coarse_depth(p) : coarse_depth(p >> u_coarse_level);
    int level = 0;
    for (int l = 1; l < u_level_count; l++) {
        if (z <= u_level_depth[l]) {
            level = l;
        }
    }
    // The neighbourhood radius K / z (eq. 1 unrounded) and the cut radius.
    precise float radius = u_radius_k / z;
    precise float cut = STA_HPR_CUT_FACTOR * radius;
    precise float cut2 = cut * cut;
#ifndef HPR_EMPTY_LIST
    bool on = u_surface_tol > 0.0 && hpr_occludes(own.w) && -own.z > 0.0;
#endif
    vec3 x = hpr_centre_point(own, p, u_size, u_tan_half, u_far);
    precise float limit = -x.z - u_gap;
    // The 8 direct neighbours, loaded once for the fit and level 0 when the own-surface
    // rule applies (on); otherwise level 0 loads them if the pixel gets there.
    vec4 nb[8];
    for (int i = 0; i < 8; i++) {
        ivec2 n = p + RING[i];
        bool inside = all(greaterThanEqual(n, ivec2(0))) && all(lessThan(n, u_size));
        nb[i] = on && inside ? imageLoad(u_position, n) : vec4(0.0);
    }
    g_surface = fit_own_surface(own, p, on, nb);
    vec4 min_lo = vec4(1.0), min_hi = vec4(1.0);
#ifdef HPR_SEE_THROUGH
    g_see_lo = vec4(1.0);
    g_see_hi = vec4(1.0);
    g_solid = false;
    g_solid_level = level <= STA_HPR_SOLID_LEVELS;
#endif
    int outside = 0; // sectors with ring texels outside the image within the reach
    // Off (the default): empty pixels as points, by ring position (main's blocky rule).
    bool by_landing = !is_point && SMOOTH_GAPS;
    float bound = hpr_closed_bound(is_point, u_threshold);
    // An empty pixel (issue 15, part 2): candidates of levels >= 1 count within
    // min(cut, 2^level) pixels, where every non-empty block has a candidate in the rings
    // wherever the pixel sits in its ancestor blocks; a sector is unknown where its wedge
    // leaves the image within that reach, up to u_empty_border (per pixel, not
    // from the ring texels outside, which are block-shaped).
    int closed = 0;
    int empty_outside = 0;
    // The border rule's flanks (hpr_flanks), for the flank test below.
    int flanks = 0;
    if (by_landing) {
        precise float reach = min(cut, STA_HPR_EMPTY_CUT_BLOCKS * float(1 << level));
        cut2 = reach * reach;
        float border = clamp(reach, STA_HPR_MIN_REACH_PX, u_empty_border);
        empty_outside = hpr_wedge_outside(hpr_reach_outside(p, u_size, border), false);
        flanks = hpr_flanks(empty_outside);
    }
    // Levels level..1, coarse first (their rings close an empty pixel inside a surface
    // at once, so it settles early): the ring around the ancestor, from the pyramid. An
    // empty pixel also takes the 4 texels 2 away along the axes below the top level: a
    // block's point is its nearest, which on a receding surface sits at the block's near
    // edge, so the axis texels of the ring alone leave a pixel at a block's edge without a
    // candidate straight across it; a texel 2 away lies within 45 deg of its axis from
    // every pixel of the ancestor block (a diagonal ring texel always does).
    bool settled = false;
    for (int k = level; k >= 1 && !settled; k--) {
#ifdef HPR_SEE_THROUGH
        g_solid_level = k <= STA_HPR_SOLID_LEVELS;
#endif
        ivec2 a = p >> k;
        ivec2 size_k = (u_size + (1 << k) - 1) >> k;
        ivec2 origin = u_level_origin[k];
        for (int i = 0; i < 8; i++) {
            ivec2 n = a + RING[i];
            if (all(greaterThanEqual(n, ivec2(0))) && all(lessThan(n, size_k))) {
                add_neighbour(imageLoad(u_pyramid, origin + n), RING[i], p, x, true, cut2, limit,
                              by_landing, closed, min_lo, min_hi);
            } else {
                // Outside the image: its sector may have been closed out there.
                outside |= 1 << hpr_sector(2 * RING[i]);
            }
        }
        for (int i = 0; i < 4 && by_landing && k < level; i++) {
            ivec2 n = a + 2 * AXES[i];
            if (all(greaterThanEqual(n, ivec2(0))) && all(lessThan(n, size_k))) {
                add_neighbour(imageLoad(u_pyramid, origin + n), AXES[i], p, x, true, cut2, limit,
                              true, closed, min_lo, min_hi);
            }
        }
        // An empty pixel with a closed sector and every known sector closed is a hole
        // whatever else closes (with none closed and none known it is background so far).
        // A point settles on the minima without the see-through returns (never below
        // those it takes), an empty pixel on all.
#ifdef HPR_SEE_THROUGH
        vec4 lo = is_point ? min_lo : min(min_lo, g_see_lo);
        vec4 hi = is_point ? min_hi : min(min_hi, g_see_hi);
#else
        vec4 lo = min_lo, hi = min_hi;
#endif
        settled = by_landing ? closed != 0 && (closed | empty_outside) == 255
                             : hpr_settled(lo, hi, is_point, outside, bound);
    }
#ifdef HPR_SEE_THROUGH
    g_solid_level = true;
#endif
    // Level 0: the 8 direct neighbours, from the position texture.
    for (int i = 0; i < 8 && !settled; i++) {
        ivec2 n = p + RING[i];
        if (all(greaterThanEqual(n, ivec2(0))) && all(lessThan(n, u_size))) {
            vec4 y = on ? nb[i] : imageLoad(u_position, n);
            add_neighbour(y, RING[i], p, x, false, cut2, limit, by_landing, closed, min_lo,
                          min_hi);
        } else {
            outside |= 1 << hpr_sector(2 * RING[i]);
        }
    }
    // A sparse surface (issue 15, part 2, sixteenth round): an empty pixel without unknown
    // sectors whose open ones form one run of at most STA_HPR_EMPTY_WIDEN_OPEN also takes
    // its top level's 5 x 5 texels within min(cut, 2^(level + 1)): points a few pixels
    // apart leave a wedge without a candidate within 2^level; a gap's pixels have more
    // open, or two runs across a band. Twin: empty_pixel_mean.
    int open = ~(closed | empty_outside) & 255;
    int starts = open & ~((open << 1) | (open >> 7)); // first sectors of open runs
    if (by_landing && level > 0 && (empty_outside & ~closed) == 0 && bitCount(starts) == 1 &&
        bitCount(open) <= STA_HPR_EMPTY_WIDEN_OPEN) {
        precise float reach = min(cut, STA_HPR_EMPTY_CUT_BLOCKS * float(2 << level));
        closed |= wide_closed(p, x, level, reach * reach, limit);
    }
    // The border rule beside the data only (issue 15, part 2, twentieth round): a pixel that
    // is a hole only by the border rule (an unknown sector open) lies in open space between
    // a silhouette and the border, not in a surface running off-screen, when a flank has no
    // candidate near its axis, also among the top level's 5 x 5 texels within twice the
    // reach, and no candidate lands within `near` (fragments of fill floated there): its
    // unknown sectors count as open (flank_test_fires); few pixels get here.
    if (by_landing && flanks != 0 && closed != 0 && (closed | empty_outside) == 255 &&
        (empty_outside & ~closed) != 0) {
        // At most the band's width: in a sparse scene K / z spans the image, and a band
        // pixel never found its far points beyond `near` (a frame of fill round the view).
        precise float near = min(max(STA_HPR_EMPTY_NEAR_RADII * radius, STA_HPR_EMPTY_NEAR_MIN_PX),
                                 u_empty_border);
        if (flank_test_fires(p, level, cut, limit, empty_outside, flanks, near * near, closed)) {
            empty_outside = 0;
        }
    }
    // See-through returns close an empty pixel's sectors, and a point's where a solid
    // candidate is near (the point lies behind a wall, not only behind the glass).
#ifdef HPR_SEE_THROUGH
    if (!is_point || g_solid) {
        min_lo = min(min_lo, g_see_lo);
        min_hi = min(min_hi, g_see_hi);
    }
#endif
    float mean = by_landing ? hpr_empty_mean(closed, empty_outside)
                            : hpr_sector_mean(min_lo, min_hi, is_point, outside);
    imageStore(u_label, p, vec4(hpr_label(is_point, mean, u_threshold), 0.0, 0.0, 0.0));
}
