/* SPDX-License-Identifier: MIT
 * Which pixels and drawn points each truth metric of one view scores (docs/BENCH.md):
 * the fill metrics leave out the true surfaces of the viewer's volumetric classes (drawn
 * as points, never filled); the "sampled" and "face" rules keep only surfaces the drawn
 * points sample; the ruled HPR F1 leaves out points whose truth the data cannot show
 * (an occluder no point samples, a room seen through sampled window glass), and the
 * volumetric rule points hidden by a volumetric class's true surface. CPU only.
 */
#ifndef STA_BENCH_PIXEL_MASKS_H
#define STA_BENCH_PIXEL_MASKS_H

#include <stddef.h>
#include <stdint.h>

#include "bench/view_eval.h"
#include "core/camera.h"
#include "core/status.h"

/* One byte per pixel each (1: scored), texture order. */
typedef struct sta_pixel_masks {
    uint8_t *sampled;         /* sta_view_truth_sampled */
    uint8_t *counted;         /* not of a volumetric class; NULL: no classes given, all */
    uint8_t *sampled_counted; /* sampled and counted */
    uint8_t *face_counted;    /* sta_view_truth_face_sampled and counted */
    uint8_t *hpr_face;        /* a drawn point here is scored by the face rule: all but a
                                 truly hidden point whose pixel's true face (its occluder)
                                 no drawn point samples */
    uint8_t *hpr_face_glass;  /* the face rule and the glass rule: also leaves out a truly
                                 visible point behind window glass (either label is right) */
    uint8_t *hpr_volumetric;  /* the volumetric rule: all but a truly hidden point whose
                                 pixel's true surface has a volumetric class (a crown or a
                                 wire, which the viewer draws as points and the synth's
                                 scanner sees through: either label is right); NULL
                                 without classes (every point scored) */
    uint64_t left_out;        /* pixels with a truth hit of a volumetric class */
} sta_pixel_masks;

/* Computes the masks of a view whose points are classified (sta_view_points_classify)
 * with `tolerance_m`. `volumetric` (NULL: none) is a class set of `words` words (bit
 * c % 32 of word c / 32 is class c). Errors: STA_ERR_NOMEM. */
sta_status sta_pixel_masks_compute(const sta_view_truth *view_truth, const sta_camera *camera,
                                   const sta_view_points *points, double tolerance_m,
                                   const uint32_t *volumetric, int words, sta_pixel_masks *out,
                                   sta_error *err);
void sta_pixel_masks_release(sta_pixel_masks *masks);

#endif
