/* SPDX-License-Identifier: MIT
 * Binding points, attribute locations and workgroup sizes shared by C and GLSL.
 * sta_gl_program_create injects each of these into every shader as a #define, so
 * the numbers live only here.
 */
#ifndef STA_RENDER_BINDINGS_H
#define STA_RENDER_BINDINGS_H

#include "render/ref/screen_space.h" /* STA_HPR_BACKGROUND_OPEN_SECTORS */

#define STA_ATTRIB_POSITION_INTENSITY 0 /* uvec4: qx, qy, qz, intensity */
#define STA_ATTRIB_COLOUR_CLASS       1 /* uvec4: r, g, b, classification */
#define STA_ATTRIB_RETURNS            2 /* uvec4: return number, number of returns, 0, 0 */

#define STA_WORKGROUP_SIZE_X 8
#define STA_WORKGROUP_SIZE_Y 8

/* Colour modes of the geometry pass. */
#define STA_COLOUR_RGB            0
#define STA_COLOUR_INTENSITY      1
#define STA_COLOUR_ELEVATION      2
#define STA_COLOUR_CLASSIFICATION 3
#define STA_COLOUR_RETURN_NUMBER  4
#define STA_COLOUR_MODE_COUNT     5


/* Every define above, as "name value" pairs for the shader preamble. */
#define STA_BINDING_DEFINES                                                                        \
 X(STA_ATTRIB_POSITION_INTENSITY)                                                                  \
 X(STA_ATTRIB_COLOUR_CLASS)                                                                        \
 X(STA_ATTRIB_RETURNS)                                                                             \
 X(STA_WORKGROUP_SIZE_X)                                                                           \
 X(STA_WORKGROUP_SIZE_Y)                                                                           \
 X(STA_COLOUR_RGB)                                                                                 \
 X(STA_COLOUR_INTENSITY)                                                                           \
 X(STA_COLOUR_ELEVATION)                                                                           \
 X(STA_COLOUR_CLASSIFICATION)                                                                      \
 X(STA_COLOUR_RETURN_NUMBER)                                                                       \
 X(STA_HPR_BACKGROUND_OPEN_SECTORS)

#endif
