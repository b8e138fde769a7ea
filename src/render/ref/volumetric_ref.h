/* SPDX-License-Identifier: MIT
 * Volumetric classes (vegetation): pixels whose drawn point has a class in a set are
 * shown as points, not as a surface. CPU twin of shaders/volumetric_mark.comp and
 * shaders/volumetric_overlay.comp (render/pass_volumetric.c).
 *
 * Mark (before HPR): a drawn pixel (position w > 0, z < 0) whose id names a resident
 * point whose classification is in `classes` gets w = STA_POSITION_W_MARKED
 * (screen_space.h): HPR still sees it as a point (an occluder), pull-push takes no seed
 * from it (the surface behind it, or the background, is reconstructed from the other
 * points) and keeps its colour in the filled colour's alpha (screen_space.h). HPR's
 * labels play no part in the mark: HPR-hidden canopy points are kept too, since
 * scattered returns are no closed surface, so canopy behind canopy is seen through the
 * gaps (HPR would remove it and leave black holes between crowns). Overlay (after
 * shading): each marked point is drawn as a square splat of radius
 * STA_VOLUMETRIC_SPLAT_RADIUS_PX: a pixel takes the colour of the nearest marked point in
 * that window unless a drawn point of another class (an occluder, HPR-hidden or not: a
 * nearer point of another class is a surface in front) is in the same window and as
 * near or nearer: crowns read as crowns and a wall in front, even a sparsely sampled
 * one, still hides them. (The filled depth is no test: pull-push
 * averages depths across wide gaps.) No lighting: an eye-dome term over the same window
 * does nothing by construction (the splat is the window's nearest point), a wider one
 * would double the reads (docs/PIPELINE.md). Until issue 15's tenth round the mark ran
 * after HPR and wrote an image of marked points and of the visible points as occluders.
 */
#ifndef STA_RENDER_REF_VOLUMETRIC_REF_H
#define STA_RENDER_REF_VOLUMETRIC_REF_H

#include <stdbool.h>
#include <stdint.h>

#include "render/ref/image.h"

/* Half the side of a volumetric point's square splat, pixels (1: 3 x 3). */
#define STA_VOLUMETRIC_SPLAT_RADIUS_PX 1

/* Words in a class set: bit c of word c / 32 is classification c (0..255). */
#define STA_VOLUMETRIC_CLASS_WORDS 8

typedef struct sta_volumetric_input {
    const uint32_t *ids;   /* width * height (slot, index) pairs, image rows (GL order) */
    const uint32_t *nodes; /* per slot: first arena point, point count (0: not resident) */
    uint32_t node_count;
    const uint8_t *classes; /* classification per arena point */
    uint32_t arena_points;
    uint32_t class_set[STA_VOLUMETRIC_CLASS_WORDS];
} sta_volumetric_input;

/* True when classification `c` is in `set`. */
static inline bool sta_volumetric_has_class(const uint32_t *set, uint32_t c)
{
    return c < 32u * STA_VOLUMETRIC_CLASS_WORDS && ((set[c / 32u] >> (c % 32u)) & 1u) != 0;
}

/* Mark: `position` RGBA (camera space, w > 0 where a point was drawn) read and updated,
 * the same size as the id image. Ids out of range (slot past node_count, index past the
 * node's count or the arena) are ignored. */
void sta_volumetric_mark_ref(const sta_volumetric_input *in, sta_image *position);

/* Overlay: `position` from mark, `colour` the geometry pass's point colours (rgb in
 * 0..1; a marked point's is drawn rounded to 8 bits, sta_unorm8), `out` RGBA: covered
 * pixels get the colour and alpha 1, the others are left alone (the GL pass writes the
 * RGBA8 filled colour, screen_space.h). */
void sta_volumetric_overlay_ref(const sta_image *position, const sta_image *colour, sta_image *out);

#endif
