/* SPDX-License-Identifier: MIT
 * Staged stores: a compute shader that writes a whole RGBA32F texture writes its texels
 * into a shader storage buffer instead (row by row, vec4 per texel), and the buffer is
 * copied into the texture after the dispatch (a pixel unpack from the buffer).
 *
 * Why (issue 15, nineteenth round, docs/BENCHMARKS.md): on llvmpipe an imageStore of an
 * RGBA32F texel is stored channel by channel, lane by lane: 46 CPU ms for a 1920x1080
 * dispatch that stores a constant, against 11 ms for the same vec4s into a storage
 * buffer and 2.4 ms for the copy (bench/llvmpipe_cost.sh). A GPU stores images natively,
 * so staging is the default on llvmpipe (and softpipe) only; STRATA_STAGED_STORES=1 or 0
 * forces it. The texels are the same floats either way (tested).
 */
#ifndef STA_RENDER_GL_STAGED_H
#define STA_RENDER_GL_STAGED_H

#include <epoxy/gl.h>
#include <stdbool.h>

#include "core/status.h"

/* Whether the passes stage their RGBA32F stores in this process: STRATA_STAGED_STORES
 * (1 or 0) when set, else whether the current context's renderer is llvmpipe or
 * softpipe. Decided on the first call (a context must be current) unless forced. */
bool sta_gl_staged_stores(void);

/* STRATA_STAGED_STORES's value: 1 or 0 for "1" or "0", -1 (the renderer decides) for none
 * or anything else, which is named on stderr once. */
int sta_gl_staged_stores_from_env(const char *value);

/* Tests: 1 or 0 forces the decision for the passes initialised from now on, -1 goes back
 * to the automatic one. */
void sta_gl_staged_stores_force(int on);

/* The #define that selects the staged variant of a shader ("#define STA_STAGED_STORES 1\n"),
 * or "" when `staged` is false. */
const char *sta_gl_staged_define(bool staged);

/* A storage buffer that dispatches write their texels into, grown on demand. One serves every
 * pass of a pipeline (they run one after the other; sta_pipeline shares its own with them),
 * so that it costs one frame's RGBA32F (33 MB at 1920x1080), not one per pass. */
typedef struct sta_gl_staging {
    GLuint buffer;
    GLsizeiptr bytes;
    GLint alignment; /* GL_SHADER_STORAGE_BUFFER_OFFSET_ALIGNMENT, read on first use */
} sta_gl_staging;

/* Binds `count` ranges of width x height vec4s, one after the other, to the storage buffer
 * bindings first_binding .. first_binding + count - 1, growing the buffer if needed. */
sta_status sta_gl_staging_bind(sta_gl_staging *staging, GLuint first_binding, int count, int width,
                               int height, sta_error *err);

/* After the dispatch that wrote it: copies range `index` of the last bind (width x height
 * vec4s, rows of `width`) into the RGBA32F `texture` (mip level 0) at (x, y); a barrier for
 * the buffer's writes first. */
void sta_gl_staging_copy(const sta_gl_staging *staging, int index, GLuint texture, int x, int y,
                         int width, int height);

void sta_gl_staging_release(sta_gl_staging *staging);

/* The staging a pass writes through: `shared` where its owner gave one (a pipeline shares
 * one with all its passes), else the pass's own. */
static inline sta_gl_staging *sta_gl_staging_pick(sta_gl_staging *own, sta_gl_staging *shared)
{
    return shared ? shared : own;
}

#endif
