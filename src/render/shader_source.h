/* SPDX-License-Identifier: MIT
 * The GLSL sources of shaders/, embedded at build time.
 */
#ifndef STA_RENDER_SHADER_SOURCE_H
#define STA_RENDER_SHADER_SOURCE_H

typedef struct sta_shader_source {
    const char *name; /* file name in shaders/, e.g. "geometry.vert" */
    const char *text; /* NUL-terminated source */
} sta_shader_source;

/* Terminated by an entry with a NULL name. */
extern const sta_shader_source sta_shader_sources[];

#endif
