/* SPDX-License-Identifier: MIT
 * Which way is up in a model file (PLY, OBJ): the rule the converter's up axis and the
 * synth's mesh scene share (docs/CONVERTER.md, "Up axis").
 */
#ifndef STA_IO_MODEL_UP_H
#define STA_IO_MODEL_UP_H

#include <stdbool.h>
#include <stddef.h>

/* A model whose vertical extent is below this share of its larger horizontal one is
 * flat, map-like data (terrain, a scanned floor): +Z up. */
#define STA_MODEL_FLAT_RATIO 0.25

/* Whether a model with extents ex, ey, ez along x, y, z is +Y up, the convention of
 * scanned models (the Stanford bunny and dragon): yes unless z is its largest extent (a
 * z-up figure) or below STA_MODEL_FLAT_RATIO of the larger of x and y (flat data). `why`
 * (may be NULL) gets one line naming `kind` ("PLY", "mesh") and the extents. */
bool sta_model_is_y_up(double ex, double ey, double ez, const char *kind, char *why,
                       size_t why_size);

#endif
