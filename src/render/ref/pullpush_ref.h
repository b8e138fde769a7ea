/* SPDX-License-Identifier: MIT
 * CPU twin of the pull-push reconstruction (shaders/pullpush_pull.comp and
 * shaders/pullpush_push.comp), and the pyramid level sizes shared with the GL pass.
 *
 * Based on: M. Kraus, "The pull-push algorithm revisited", GRAPP 2009 (weighted pull
 * with weights clamped to 1, bilinear 4x4 analysis and 2x2 synthesis filters), as used
 * by H. Bouchiba et al., "Raw point cloud deferred shading through screen space
 * pyramidal operators", Eurographics 2018, section 3.2. docs/PULLPUSH.md states every
 * choice made here.
 *
 * The pyramid carries, per texel, a camera-space point (xyz), a colour (rgb) and a
 * weight w in 0..1. Level l has size sta_pullpush_level_size(width, l) x
 * sta_pullpush_level_size(height, l): max(1, ceil(size / 2^l)), and texel (i, j) of
 * level l covers level-0 pixels [i 2^l, (i + 1) 2^l) x [j 2^l, (j + 1) 2^l) (the same
 * convention as the HPR point pyramid). The last level is 1 x 1.
 */
#ifndef STA_RENDER_REF_PULLPUSH_REF_H
#define STA_RENDER_REF_PULLPUSH_REF_H

#include <stdbool.h>

#include "core/status.h"
#include "render/ref/image.h"
#include "render/ref/screen_space.h"

/* Push: a coarse tap's weight is divided by 1 + x + x^2/2 + x^3/6 (exp(x) to third
 * order: plain arithmetic, which the shader and the twin compute alike, where GLSL's exp
 * and expf part ways), x = ((d - d_near) / (TAU d_near))^2, d its depth and d_near the
 * depth of the 9/16 tap (the coarse texel holding the fine one) where its coverage is full
 * (w = 1, since issue 15's eighteenth round; before it, wherever it had weight), else the nearest
 * depth among the (up to 4) taps: a hole at an outline takes one surface rather than a depth
 * between both, and a sparse near surface keeps its own holes (issue 15; 0.2 since the
 * eighth round, with the references below: docs/BENCHMARKS.md, docs/PULLPUSH.md). */
#define STA_PULLPUSH_DEPTH_TAU      0.2f
/* Pull: the same factor against the nearest of the inner 2x2 fine taps (the coarse
 * texel's own footprint; the nearest of all 16 where those four are empty) divides each
 * tap's weight in the values (not in the coverage, the plain weight sum): a coarse texel
 * over a depth edge holds its own surface, not a depth between both, which the push then
 * spread as fill floating between the surfaces (issue 15, sixth and eighth rounds; 0.15:
 * with the inner reference, smaller values gain on the street and on sphere and the
 * bunny, down to where the far street's normal median starts to rise, docs/BENCHMARKS.md). */
#define STA_PULLPUSH_PULL_DEPTH_TAU 0.15f

/* Windows (issue 15, part 2): each pyramid texel carries, in its colour's alpha, the share
 * of its value that comes from see-through returns (STA_POSITION_W_SEE_THROUGH,
 * screen_space.h: window glass); a texel from this share on is glass. Where a pull's or a
 * push's taps (levels >= 1; the level-0 push has no test) hold a solid texel (below the
 * share) deeper than a glass tap by more than STA_PULLPUSH_GLASS_GAP of the glass's depth
 * (the room behind the window), that glass tap gives no value and no depth reference (the
 * pull keeps its coverage), and a glass texel of levels >= 1 in front of the push's solid
 * taps takes their value: the room fills the window and the glass stays as specks, instead
 * of a blotchy mix of glass fill and room fill. Glass beside the wall it sits in (within the
 * gap) seeds as before. Street view 0: filled depth p95 over sampled surfaces 6.83 -> 3.92 %,
 * glass rule 2.95 -> 3.11 % (docs/BENCHMARKS.md, "Sixteenth round, third part"). */
#define STA_PULLPUSH_GLASS_SHARE 0.5f
#define STA_PULLPUSH_GLASS_GAP   0.05f

/* Pull of level 1 from the inputs: from this view height on, Kraus' 2x2 box (the inner 2x2
 * fine taps, weight 1 each; the coarse texel's own footprint) instead of the 4x4 kernel
 * (issue 15, twelfth round, a trade of time against error: at 1920x1080 -15 to -20 CPU ms,
 * the smooth surfaces' filled-depth p95 +7 to +15 % relative, docs/BENCHMARKS.md). */
#define STA_PULLPUSH_BOX_PULL_HEIGHT_PX 1080

/* Whether a view `height_px` pixels high pulls level 1 with the 2x2 box (above). */
static inline bool sta_pullpush_box_first_pull(int height_px)
{
    return height_px >= STA_PULLPUSH_BOX_PULL_HEIGHT_PX;
}

/* Levels of the largest view accepted (32768 pixels on a side). */
#define STA_PULLPUSH_MAX_LEVELS 16

/* max(1, ceil(size_px / 2^level)) for size_px >= 1 and 0 <= level < 31. */
static inline int sta_pullpush_level_size(int size_px, int level)
{
    return (int)(((unsigned)size_px + (1u << level) - 1u) >> level);
}

/* Number of levels down to 1 x 1: 1 + ceil(log2(max(width, height))); 1 for a 1 x 1
 * view. Views wider or taller than 32768 pixels are out of range (returns 0). */
int sta_pullpush_level_count(int width_px, int height_px);

/* The pushed (filled) pyramid of one run. Index l holds level l for 1 <= l < count;
 * index 0 stays empty (zeroed images): level 0 is the pass output itself. */
typedef struct sta_pullpush_levels {
    int count;                                   /* levels, 0 before a run */
    sta_image position[STA_PULLPUSH_MAX_LEVELS]; /* 4 channels: xyz camera space, w weight */
    sta_image colour[STA_PULLPUSH_MAX_LEVELS];   /* 4 channels: rgb, a = weight */
} sta_pullpush_levels;

/* Frees the images; a zeroed struct is a no-op. */
void sta_pullpush_levels_release(sta_pullpush_levels *levels);

/* Pull-push reconstruction on the CPU, the same maths in the same order as the shaders.
 * view: size and camera; position: 4 channels, camera space, w = 1 point / 0 empty;
 * colour: 3 or 4 channels, rgb in 0..1 (alpha ignored); label: 1 channel of
 * STA_LABEL_* from HPR, or NULL for "every point visible, no background to restore".
 * Initial weight: 1 where a point is drawn (w > 0) and labelled VISIBLE, else 0.
 * out_position / out_colour: initialised 4-channel images of the view size, written:
 * the filled point (xyz) with w = coverage in 0..1, and the colour as the RGBA8 filled
 * colour holds it (rgb rounded to 8 bits, sta_unorm8; alpha 0: screen_space.h); pixels
 * labelled BACKGROUND and pixels without any support are zero. out_levels (may be NULL):
 * zeroed or released struct, receives levels 1..count-1 after the push (owned by the
 * caller, free with sta_pullpush_levels_release). Errors: STA_ERR_ARG for mismatched
 * sizes, STA_ERR_NOMEM. */
sta_status sta_pullpush_ref(const sta_view_params *view, const sta_image *position,
                            const sta_image *colour, const sta_image *label,
                            sta_image *out_position, sta_image *out_colour,
                            sta_pullpush_levels *out_levels, sta_error *err);

#endif
