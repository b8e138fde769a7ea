/* SPDX-License-Identifier: MIT
 * Ghost detection scored against the mirror scene's truth (mirror_eval.h). */
#include "synth/mirror_eval.h"

#include <string.h>

#include "io/cloud.h"

#define BATCH 65536

static void score_one(sta_ghost_score *s, uint8_t truth, uint8_t found)
{
    if (truth && found) {
        s->true_positive++;
        s->wrong_mirror += truth != found;
    } else if (found) {
        s->false_positive++;
    } else if (truth) {
        s->false_negative++;
    }
}

sta_status sta_synth_ghost_evaluate(const char *las_path, const sta_synth_params *params,
                                    const sta_mirror_set *mirrors, sta_ghost_eval *out,
                                    sta_error *err)
{
    memset(out, 0, sizeof(*out));
    if (params->kind != STA_SYNTH_MIRROR) {
        return sta_fail(err, STA_ERR_ARG, "%s: ghosts are scored on the mirror scene only",
                        las_path);
    }
    sta_synth_scene *scene = NULL;
    sta_cloud_reader *reader = NULL;
    sta_point_batch batch = { 0 };
    sta_mirror_set own = { 0 };
    sta_synth_georef georef;
    sta_synth_georef_init(params->origin, &georef);
    sta_status s = sta_synth_scene_create(params, &scene, err);
    if (s == STA_OK && !mirrors) {
        s = sta_mirror_set_translated(sta_synth_scene_mirrors(scene), georef.origin, &own, err);
        mirrors = &own;
    }
    s = s == STA_OK ? sta_cloud_open(las_path, NULL, &reader, err) : s;
    const sta_cloud_info *info = reader ? sta_cloud_reader_info(reader) : NULL;
    s = s == STA_OK ? sta_point_batch_init(&batch, BATCH, info->extra_size, err) : s;
    while (s == STA_OK) {
        s = sta_cloud_read(reader, &batch, err);
        if (s != STA_OK || batch.count == 0) {
            break;
        }
        for (size_t i = 0; i < batch.count && s == STA_OK; i++) {
            const sta_point *p = &batch.points[i];
            double world[3] = { sta_grid_apply(&info->grid, 0, p->X),
                                sta_grid_apply(&info->grid, 1, p->Y),
                                sta_grid_apply(&info->grid, 2, p->Z) };
            double scanner[3];
            s = sta_synth_scene_scanner_position(scene, p->gps_time, scanner, err);
            for (int a = 0; a < 3; a++) {
                scanner[a] += georef.origin[a];
            }
            out->points++;
            out->truth_ghosts += p->user_data != 0;
            uint8_t found[STA_GHOST_MODEL_COUNT] = {
                sta_mirror_ghost_from_scanner(mirrors, scanner, world),
                sta_mirror_ghost_in_volume(mirrors, world),
            };
            for (int m = 0; m < STA_GHOST_MODEL_COUNT; m++) {
                score_one(&out->models[m], p->user_data, found[m]);
                for (int k = 0; k < STA_GHOST_EVAL_MIRRORS; k++) {
                    score_one(&out->mirrors[m][k], p->user_data == k + 1, found[m] == k + 1);
                }
            }
        }
    }
    sta_point_batch_release(&batch);
    sta_cloud_close(reader);
    sta_mirror_set_release(&own);
    sta_synth_scene_destroy(scene);
    return s;
}

double sta_ghost_precision(const sta_ghost_score *s)
{
    uint64_t d = s->true_positive + s->false_positive;
    return d ? (double)s->true_positive / (double)d : 1.0;
}

double sta_ghost_recall(const sta_ghost_score *s)
{
    uint64_t d = s->true_positive + s->false_negative;
    return d ? (double)s->true_positive / (double)d : 1.0;
}
