/* SPDX-License-Identifier: MIT
 * OpenGL plumbing: a headless EGL context (Mesa's llvmpipe works without a GPU),
 * shader programs from the embedded sources, error checks.
 */
#ifndef STA_RENDER_GL_H
#define STA_RENDER_GL_H

#include <epoxy/gl.h>
#include <stddef.h>

#include "core/status.h"

/* A surfaceless EGL display and OpenGL 4.5 core context, current on the calling
 * thread. Zero-initialise; release with sta_gl_headless_destroy. */
typedef struct sta_gl_headless {
    void *display; /* EGLDisplay */
    void *context; /* EGLContext */
} sta_gl_headless;

/* Creates the context and makes it current. Errors: STA_ERR_GL with EGL's reason. */
sta_status sta_gl_headless_create(sta_gl_headless *out, sta_error *err);

void sta_gl_headless_destroy(sta_gl_headless *gl);

/* Builds a program from embedded shaders named in `names` (stage from the
 * extension: .vert, .frag, .comp; names ending in .glsl are function libraries
 * inserted, in order, before every stage's own source). `extra_defines` (may be
 * NULL) is added to the preamble after the bindings.h defines. Errors name the
 * shader and give the compiler's log. */
sta_status sta_gl_program_create(const char *const *names, size_t count, const char *extra_defines,
                                 GLuint *out_program, sta_error *err);

/* STA_ERR_GL naming `what` and the GL error if glGetError reports one. */
sta_status sta_gl_check(const char *what, sta_error *err);

/* Waits until every GL command issued so far has run (for honest wall-clock timings
 * outside render/, which makes no GL calls itself). */
void sta_gl_finish(void);

/* "renderer | version" of the current context into buf. */
const char *sta_gl_describe(char *buf, size_t size);

#endif
