/* SPDX-License-Identifier: MIT
 * The pull-push pass (Kraus 2009, as in Bouchiba et al. 2018 section 3.2): fills the
 * holes between the visible points of the position and colour textures and restores
 * the background found by HPR. Twin: render/ref/pullpush_ref.h; docs/PULLPUSH.md.
 *
 * Design: the pass owns one RGBA32F position texture and one RGBA32F colour texture per
 * pyramid level 1..count-1 (level l: max(1, ceil(W / 2^l)) x max(1, ceil(H / 2^l)),
 * which GL's mip chain cannot hold for sizes that are not powers of two, hence one
 * texture per level). They are (re)allocated when the view size changes and, after a
 * run, hold the pushed (filled) levels that the pyramidal normal estimator reads.
 * Main thread (GL) only.
 */
#ifndef STA_RENDER_PASS_PULLPUSH_H
#define STA_RENDER_PASS_PULLPUSH_H

#include <epoxy/gl.h>

#include "core/status.h"
#include "render/gl_staged.h"
#include "render/ref/pullpush_ref.h"
#include "render/ref/screen_space.h"

/* The filled pyramid of the last run. Index 0 is unused (0): level 0 is the output
 * position/colour texture of that run. */
typedef struct sta_pullpush_pyramid {
    int level_count;                       /* levels including level 0; 0 before a run */
    int width_px[STA_PULLPUSH_MAX_LEVELS]; /* level sizes, index 0 included */
    int height_px[STA_PULLPUSH_MAX_LEVELS];
    GLuint position[STA_PULLPUSH_MAX_LEVELS]; /* RGBA32F: filled point xyz, w = weight */
    GLuint colour[STA_PULLPUSH_MAX_LEVELS];   /* RGBA32F: rgb, a = weight */
} sta_pullpush_pyramid;

/* One compiled variant of pullpush_pull.comp or pullpush_push.comp. */
typedef struct sta_pullpush_program {
    GLuint program;
    GLint size, coarse_size;     /* pull: fine and coarse size; push: level and coarse size */
    GLint has_label, has_coarse; /* -1 where the variant has no such uniform */
} sta_pullpush_program;

typedef struct sta_pullpush_pass {
    sta_pullpush_program pull_input;  /* level 1 from the inputs */
    sta_pullpush_program pull_box;    /* the same with the 2x2 box (from 1080 px high) */
    sta_pullpush_program pull_level;  /* level l >= 2 from level l - 1 */
    sta_pullpush_program push_level;  /* level l >= 1 in place */
    sta_pullpush_program push_output; /* level 0 into the outputs */
    sta_pullpush_pyramid pyramid;     /* owned */
    bool staged; /* RGBA32F results through a staging buffer (render/gl_staged.h) */
    sta_gl_staging own_staging;
    sta_gl_staging *shared_staging; /* NULL: own_staging (the pipeline sets its own) */
} sta_pullpush_pass;

/* Compiles the shaders. Errors: STA_ERR_GL with the compiler's log. */
sta_status sta_pullpush_pass_init(sta_pullpush_pass *pass, sta_error *err);

/* Frees programs and pyramid; a zeroed pass is a no-op. */
void sta_pullpush_pass_release(sta_pullpush_pass *pass);

/* Runs pull and push. position_tex: RGBA32F camera-space points (w = 1 point, 0
 * empty); colour_tex: RGBA32F or RGBA8 (rgb used); label_tex: STA_GL_LABEL_FORMAT STA_LABEL_* of
 * HPR, or 0 for "all points visible, no background restored" (position and label are read as
 * images, so their formats must be exactly these); out_position_tex: RGBA32F of the view size,
 * written (filled point xyz, w = coverage 0..1; zero where BACKGROUND or unsupported);
 * out_colour_tex: RGBA8 (sta_gl_texture_create_rgba8) of the view size, written (filled rgb, alpha
 * 0: screen_space.h; zero where the position is). Inputs and outputs must be distinct textures.
 * Errors: STA_ERR_ARG for a view outside 1..32768 pixels, STA_ERR_GL when the pyramid cannot be
 * allocated or GL reports an error. */
sta_status sta_pullpush_pass_run(sta_pullpush_pass *pass, const sta_view_params *view,
                                 GLuint position_tex, GLuint colour_tex, GLuint label_tex,
                                 GLuint out_position_tex, GLuint out_colour_tex, sta_error *err);

/* The pyramid of the last run, owned by the pass and valid until the next run or
 * release. */
const sta_pullpush_pyramid *sta_pullpush_pass_pyramid(const sta_pullpush_pass *pass);

/* "#define PP_LABEL_..." lines for shaders including pullpush_common.glsl. */
const char *sta_pullpush_shader_defines(void);

#endif
