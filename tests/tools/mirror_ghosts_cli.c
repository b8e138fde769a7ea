/* SPDX-License-Identifier: MIT
 * mirror_ghosts: scores both ghost models against a mirror scene's truth (the bench
 * script's measuring tool; not installed).
 *
 *   mirror_ghosts --points N --seed S --origin zero|utm|ecef --las OUT.las
 *
 * Writes the scene with strata-synth's generator, then prints one line per model:
 * model points ghosts tp fp fn wrong_mirror precision recall.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/cli.h"
#include "synth/mirror_eval.h"

int main(int argc, char **argv)
{
    sta_synth_params p = { .kind = STA_SYNTH_MIRROR, .point_count = 1000000, .seed = 1 };
    const char *las = NULL, *mirrors_path = NULL;
    static const char *const origins[] = { "zero", "utm", "ecef", NULL };
    static const int origin_values[] = { STA_SYNTH_ORIGIN_ZERO, STA_SYNTH_ORIGIN_UTM,
                                         STA_SYNTH_ORIGIN_ECEF };
    int origin = STA_SYNTH_ORIGIN_UTM;
    const sta_cli_option options[] = {
        { .name = "points",
          .kind = STA_CLI_COUNT,
          .dest = &p.point_count,
          .metavar = "N",
          .count_min = 1,
          .count_max = UINT64_MAX,
          .flags = STA_CLI_SUFFIX,
          .help = "points of the scene" },
        { .name = "seed", .kind = STA_CLI_COUNT, .dest = &p.seed, .metavar = "S", .help = "seed" },
        { .name = "origin",
          .kind = STA_CLI_CHOICE,
          .dest = &origin,
          .metavar = "PLACE",
          .choices = origins,
          .choice_values = origin_values,
          .help = "where the scene sits" },
        { .name = "las",
          .kind = STA_CLI_STRING,
          .dest = &las,
          .metavar = "FILE",
          .help = "LAS to write (required)" },
        { .name = "mirrors",
          .kind = STA_CLI_STRING,
          .dest = &mirrors_path,
          .metavar = "FILE",
          .help = "score with this mirror file instead of the scene's" },
        { .name = NULL },
    };
    const sta_cli cli = { .program = "mirror_ghosts",
                          .usage = "usage: mirror_ghosts --las OUT.las [options]\n\nScores both "
                                   "ghost models against the mirror scene's truth.\n",
                          .hint = "(try mirror_ghosts --help)",
                          .options = options };
    sta_cli_result r;
    int rc = sta_cli_parse_main(&cli, argc, argv, &r);
    if (rc >= 0) {
        return rc;
    }
    if (!las) {
        return sta_cli_usage_error(&cli, "no --las FILE given");
    }
    p.origin = (sta_synth_origin)origin;
    sta_error err = { 0 };
    sta_mirror_set file = { 0 };
    sta_ghost_eval e;
    if (sta_synth_generate(&p, las, NULL, NULL, &err) != STA_OK ||
        (mirrors_path && sta_mirror_set_load(mirrors_path, &file, &err) != STA_OK) ||
        sta_synth_ghost_evaluate(las, &p, mirrors_path ? &file : NULL, &e, &err) != STA_OK) {
        fprintf(stderr, "mirror_ghosts: %s\n", err.message);
        return 1;
    }
    static const char *const names[] = { "scanner", "volume" };
    for (int m = 0; m < STA_GHOST_MODEL_COUNT; m++) {
        const sta_ghost_score *s = &e.models[m];
        printf("%s %llu %llu %llu %llu %llu %llu %.5f %.5f\n", names[m],
               (unsigned long long)e.points, (unsigned long long)e.truth_ghosts,
               (unsigned long long)s->true_positive, (unsigned long long)s->false_positive,
               (unsigned long long)s->false_negative, (unsigned long long)s->wrong_mirror,
               sta_ghost_precision(s), sta_ghost_recall(s));
        size_t count = file.count ? file.count : 3;
        for (size_t k = 0; k < count && k < STA_GHOST_EVAL_MIRRORS; k++) {
            const sta_ghost_score *sk = &e.mirrors[m][k];
            printf("  mirror %zu: tp %llu fp %llu fn %llu precision %.5f recall %.5f\n", k + 1,
                   (unsigned long long)sk->true_positive, (unsigned long long)sk->false_positive,
                   (unsigned long long)sk->false_negative, sta_ghost_precision(sk),
                   sta_ghost_recall(sk));
        }
    }
    sta_mirror_set_release(&file);
    return 0;
}
