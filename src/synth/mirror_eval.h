/* SPDX-License-Identifier: MIT
 * Ghost detection against the mirror scene's truth: reads the LAS that
 * sta_synth_generate wrote for a mirror scene, classifies each point with both ghost
 * models of mirror/mirror_set.h and counts agreement with the truth label (user_data).
 * Used by tests/test_mirror.c and bench/mirror_ghosts.sh (docs/MIRRORS.md).
 */
#ifndef STA_SYNTH_MIRROR_EVAL_H
#define STA_SYNTH_MIRROR_EVAL_H

#include <stdint.h>

#include "core/status.h"
#include "mirror/mirror_set.h"
#include "synth/synth.h"

enum {
    STA_GHOST_MODEL_SCANNER = 0,
    STA_GHOST_MODEL_VOLUME = 1,
    STA_GHOST_MODEL_COUNT = 2
};

typedef struct sta_ghost_score {
    uint64_t true_positive;  /* truth ghost, found */
    uint64_t false_positive; /* truth real, called a ghost */
    uint64_t false_negative; /* truth ghost, missed */
    uint64_t wrong_mirror;   /* found, but through another mirror than the truth's */
} sta_ghost_score;

#define STA_GHOST_EVAL_MIRRORS 16 /* mirrors scored one by one */

typedef struct sta_ghost_eval {
    uint64_t points;
    uint64_t truth_ghosts;
    sta_ghost_score models[STA_GHOST_MODEL_COUNT];
    /* Per mirror k: truth "through k" against found "through k" (first 16 mirrors). */
    sta_ghost_score mirrors[STA_GHOST_MODEL_COUNT][STA_GHOST_EVAL_MIRRORS];
} sta_ghost_eval;

/* Scores `las_path` (written by sta_synth_generate with `params`, kind mirror) with
 * `mirrors` in world coordinates (NULL: the scene's own). Errors: the reader's,
 * STA_ERR_ARG for another scene kind. */
sta_status sta_synth_ghost_evaluate(const char *las_path, const sta_synth_params *params,
                                    const sta_mirror_set *mirrors, sta_ghost_eval *out,
                                    sta_error *err);

/* tp / (tp + fp) and tp / (tp + fn); 1 when the denominator is 0. */
double sta_ghost_precision(const sta_ghost_score *score);
double sta_ghost_recall(const sta_ghost_score *score);

#endif
