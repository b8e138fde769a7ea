/* SPDX-License-Identifier: MIT
 * Conventions shared by every screen-space pass (GPU shader and CPU twin alike).
 *
 * Buffers (GL textures; CPU twins use sta_image with the same layout and row order):
 * - position: RGBA32F, camera space (camera at the origin looking down -Z, +X right,
 *   +Y up), xyz in metres, w = 1 where a point was drawn, w = 0 for background,
 *   w = STA_POSITION_W_MARKED where the drawn point has a volumetric class
 *   (volumetric_ref.h: shown as a point, no seed for the fill), w =
 *   STA_POSITION_W_SEE_THROUGH where it is a see-through return (below).
 *   Made from the reverse-Z depth buffer by the unproject pass.
 * - colour: RGBA32F (RGB in 0..1, A unused) or RGBA8 from the geometry pass.
 * - label: R32F holding one of STA_LABEL_* per pixel (HPR output).
 * - filled: RGBA32F, the pull-push result: xyz camera-space position (or depth in
 *   z only, see pull-push), w = weight / coverage in 0..1.
 * - filled colour: RGBA8 (issue 15, fourteenth round: an RGBA8 store costs llvmpipe
 *   half an RGBA32F one), rgb the pull-push colour rounded to 8 bits
 *   (sta_unorm8), alpha 0, except where the volumetric overlay drew a marked point
 *   (rgb its colour, alpha 1: the shade pass and the fill display show it unlit).
 * - normal: RGBA32F, xyz a unit camera-space normal facing the camera
 *   (dot(n, -p) >= 0 for the pixel's position p), w = 1 where valid, 0 where none.
 * "Depth" in these passes means the distance along the view axis, d = -z > 0.
 *
 * Every pass is a compute shader (workgroups STA_WORKGROUP_SIZE_X x _Y) with a C twin
 * in src/render/ref/ computing the same maths in the same order in float, so tests
 * compare them within stated tolerances.
 */
#ifndef STA_RENDER_REF_SCREEN_SPACE_H
#define STA_RENDER_REF_SCREEN_SPACE_H

#include <math.h>

/* HPR labels. */
#define STA_LABEL_BACKGROUND 0.0f /* no point, and nothing in front to fill: stays empty */
#define STA_LABEL_VISIBLE    1.0f /* a point that is visible */
#define STA_LABEL_HIDDEN     2.0f /* a point seen through a surface in front: removed */
#define STA_LABEL_HOLE       3.0f /* no point, but inside a surface: pull-push fills it */

/* The position's w of a pixel whose point has a volumetric class (> 0: still a drawn
 * point that HPR labels; pull-push takes no seed from it). Written by the unproject
 * pass (or the volumetric mark) before HPR: issue 15, tenth round. */
#define STA_POSITION_W_MARKED 2.0f

/* A drawn point closes other pixels' HPR sectors at any distance only when its w lies in
 * (0.5, STA_POSITION_W_OCCLUDER_MAX): w = 1, not marked. Scattered returns (canopy) are
 * no surface: a marked point hides only what lies right behind it, within
 * STA_HPR_MARKED_REACH_S0 (hpr_ref.h; issue 15, fourteenth round). */
#define STA_POSITION_W_OCCLUDER_MAX 1.5f

/* True when a position's w is a point that occludes for HPR (see above). */
static inline int sta_position_occludes(float w)
{
    return w > 0.5f && w < STA_POSITION_W_OCCLUDER_MAX;
}

/* The position's w of a drawn point without a volumetric class, with a LAS class from
 * STA_SEE_THROUGH_MIN_CLASS on, that is not the last return of its pulse (return number
 * < number of returns: window glass in the synth street, beam edges in real scans): the
 * compute rasteriser's resolve writes it (the GL_POINTS path has no returns per pixel and
 * writes 1). HPR lets such points close a point's sectors only where a solid occluder is
 * near (STA_HPR_SOLID_LEVELS, hpr_ref.h; issue 15, sixteenth round); pull-push takes
 * no value from glass in front of a room (STA_PULLPUSH_GLASS_SHARE, pullpush_ref.h);
 * everything else takes them as drawn points (w > 0.5, not STA_POSITION_W_MARKED). w from
 * STA_POSITION_W_SEE_THROUGH_MIN on is see-through. Classes 0 (never classified) and 1
 * (unclassified) are left out: there the earlier returns are mostly unlabelled canopy
 * (the lasR forest tiles: 40 % of a shaded view changed, the canopy's filled surface
 * speckled with the ground's points), which is the volumetric classes' business. */
#define STA_POSITION_W_SEE_THROUGH     3.0f
#define STA_POSITION_W_SEE_THROUGH_MIN 2.5f
#define STA_SEE_THROUGH_MIN_CLASS      2

/* True when a position's w is a see-through return (see above). */
static inline int sta_position_see_through(float w)
{
    return w >= STA_POSITION_W_SEE_THROUGH_MIN;
}

/* True when a drawn point closes HPR sectors only within the marked reach: marked, not
 * see-through. */
static inline int sta_position_reach_limited(float w)
{
    return w >= STA_POSITION_W_OCCLUDER_MAX && w < STA_POSITION_W_SEE_THROUGH_MIN;
}

/* A colour channel as an RGBA8 texel holds it (what a GL store into RGBA8 writes and a
 * load returns): clamped to 0..1, the nearest of the 256 steps. */
static inline float sta_unorm8(float c)
{
    c = c < 0.0f ? 0.0f : (c > 1.0f ? 1.0f : c);
    return (float)lrintf(c * 255.0f) / 255.0f;
}

/* HPR: an empty pixel is background (left empty) only when its sector minima average
 * at least this many fully open sectors out of 8 (and at least the threshold); see
 * docs/HPR.md for why 1 and not more. Reaches the shaders through render/bindings.h. */
#define STA_HPR_BACKGROUND_OPEN_SECTORS 1

/* What every pass needs to know about the view. */
typedef struct sta_view_params {
    int width_px, height_px;
    float fov_y;  /* vertical field of view, radians */
    float near_m; /* near plane of the reverse-Z projection (depth 1 there) */
    float s0;     /* sampling scale: typical distance between neighbouring points,
                     metres (Bouchiba's s0); from the hierarchy's spacing */
} sta_view_params;

/* Pixels per metre at depth d: height / (2 tan(fov/2) d). */
static inline float sta_view_pixels_per_metre(const sta_view_params *v, float depth_m)
{
    return (float)v->height_px / (2.0f * tanf(0.5f * v->fov_y) * depth_m);
}

#endif
