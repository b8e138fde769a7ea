/* SPDX-License-Identifier: MIT
 * strata-synth: writes a synthetic scene as LAS plus a truth sidecar.
 *
 *   strata-synth SCENE -o OUT.las [--points N] [--seed S] [--format 3|7]
 *                [--origin zero|utm|ecef] [--mesh FILE.ply] [--noise M] [--quiet]
 *
 * Exit status: 0 success, 1 failure, 2 bad arguments.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/alloc.h"
#include "core/cli.h"
#include "core/clock.h"
#include "core/log.h"
#include "synth/synth.h"

static const char usage_text[] =
    "usage: strata-synth SCENE -o OUT.las [options]\n"
    "\n"
    "Writes a synthetic point cloud as LAS and its truth as OUT.truth.json.\n"
    "\n"
    "Scenes:\n"
    "  street   mobile-mapping run through a procedural street (scanner, multiple returns)\n"
    "  sphere   points uniformly on a sphere of radius 10 m\n"
    "  planes   five stacked 10 m squares at depth gaps of 1 cm, 10 cm, 1 m, 10 m\n"
    "  nested   a sphere (radius 3 m) inside a closed box (10 m), hidden from outside\n"
    "  mesh     uniform samples on the triangles of a PLY (--mesh FILE.ply)\n"
    "  mirror   a room with three mirrors scanned from three stations: ghost points behind\n"
    "           the mirrors (user_data = 1 + mirror index), the mirrors in OUT.mirrors.json\n";

typedef struct synth_args {
    sta_synth_params params;
    const char *output;
    bool quiet;
} synth_args;

/* Returns -1 to go on, else the exit status. */
static int parse(int argc, char **argv, synth_args *c)
{
    // The defaults, shown by --help from here.
    c->params.point_count = 1000000u;
    c->params.seed = 1u;
    c->params.point_format = 7;
    c->params.origin = STA_SYNTH_ORIGIN_UTM;
    static const char *const formats[] = { "3", "7", NULL };
    static const int format_values[] = { 3, 7 };
    static const char *const origins[] = { "zero", "utm", "ecef", NULL };
    static const int origin_values[] = { STA_SYNTH_ORIGIN_ZERO, STA_SYNTH_ORIGIN_UTM,
                                         STA_SYNTH_ORIGIN_ECEF };
    int origin = (int)c->params.origin;
    static const char *const ups[] = { "auto", "z", "y", NULL };
    static const int up_values[] = { STA_SYNTH_MESH_UP_AUTO, STA_SYNTH_MESH_UP_Z,
                                     STA_SYNTH_MESH_UP_Y };
    int mesh_up = STA_SYNTH_MESH_UP_AUTO;
    const sta_cli_option options[] = {
        { .name = "output",
          .short_name = 'o',
          .kind = STA_CLI_STRING,
          .dest = &c->output,
          .metavar = "FILE",
          .help = "output LAS file (required)" },
        { .name = "points",
          .kind = STA_CLI_COUNT,
          .dest = &c->params.point_count,
          .metavar = "N",
          .count_min = 1,
          .count_max = UINT64_MAX,
          .flags = STA_CLI_SUFFIX,
          .help = "number of points" },
        { .name = "seed",
          .kind = STA_CLI_COUNT,
          .dest = &c->params.seed,
          .metavar = "S",
          .flags = STA_CLI_SUFFIX,
          .help = "random seed, 0 .. 2^64-1" },
        { .name = "format",
          .kind = STA_CLI_CHOICE,
          .dest = &c->params.point_format,
          .metavar = "3|7",
          .choices = formats,
          .choice_values = format_values,
          .help = "3: LAS 1.2 format 3; 7: LAS 1.4 format 7" },
        { .name = "origin",
          .kind = STA_CLI_CHOICE,
          .dest = &origin,
          .metavar = "PLACE",
          .choices = origins,
          .choice_values = origin_values,
          .help = "where the scene sits" },
        { .name = "mesh",
          .kind = STA_CLI_STRING,
          .dest = &c->params.mesh_path,
          .metavar = "FILE",
          .help = "triangle mesh for the mesh scene: PLY or Wavefront OBJ (by content)" },
        { .name = "mesh-up",
          .kind = STA_CLI_CHOICE,
          .dest = &mesh_up,
          .metavar = "auto|z|y",
          .choices = ups,
          .choice_values = up_values,
          .help = "the mesh's up axis; y turns it to stand on z, as the LAS is z up (auto: y "
                  "unless z is its largest extent or it is flat in z, the converter's rule)" },
        { .name = "noise",
          .kind = STA_CLI_DOUBLE,
          .dest = &c->params.noise_m,
          .metavar = "M",
          .real_min = 0.0,
          .real_max = 10.0,
          .help = "Gaussian noise sigma in metres",
          .default_text = "street 0.015, mirror 0.003, others 0" },
        { .name = "quiet",
          .short_name = 'q',
          .kind = STA_CLI_FLAG,
          .dest = &c->quiet,
          .help = "no progress or summary on stderr" },
        { .name = NULL },
    };
    const sta_cli cli = { .program = "strata-synth",
                          .usage = usage_text,
                          .hint = "(try strata-synth --help)",
                          .options = options };
    c->params.noise_m = -1.0; // unset: the scene's own noise
    sta_cli_result r;
    int rc = sta_cli_parse_main(&cli, argc, argv, &r);
    if (rc >= 0) {
        return rc;
    }
    c->params.origin = (sta_synth_origin)origin;
    c->params.mesh_up = (sta_synth_mesh_up)mesh_up;
    c->params.has_noise = c->params.noise_m >= 0.0;
    if (!c->params.has_noise) {
        c->params.noise_m = 0.0;
    }
    if (r.positional_count > 1) {
        return sta_cli_usage_error(&cli, "unexpected argument '%s'", r.positional[1]);
    }
    const char *scene = r.positional_count ? r.positional[0] : NULL;
    if (!scene) {
        return sta_cli_usage_error(&cli,
                                   "no scene given (street, sphere, planes, nested, mesh, mirror)");
    }
    if (!sta_synth_kind_from_name(scene, &c->params.kind)) {
        return sta_cli_usage_error(
            &cli, "unknown scene '%s' (street, sphere, planes, nested, mesh, mirror)", scene);
    }
    if (!c->output) {
        return sta_cli_usage_error(&cli, "no output given (-o OUT.las)");
    }
    if (c->params.kind == STA_SYNTH_MESH && !c->params.mesh_path) {
        return sta_cli_usage_error(&cli, "the mesh scene needs --mesh FILE (PLY or OBJ)");
    }
    if (c->params.kind != STA_SYNTH_MESH && c->params.mesh_path) {
        return sta_cli_usage_error(&cli, "--mesh is only for the mesh scene, not '%s'", scene);
    }
    return -1;
}

typedef struct progress_state {
    double start_s;
    double last_s;
    bool drawn;
} progress_state;

static bool show_progress(void *user, uint64_t done, uint64_t total)
{
    progress_state *ps = user;
    double t = sta_clock_s();
    if (done < total && t - ps->last_s < 0.25) {
        return true;
    }
    ps->last_s = t;
    double elapsed = t - ps->start_s;
    double rate = elapsed > 0.0 ? (double)done / elapsed : 0.0;
    double eta = rate > 0.0 ? (double)(total - done) / rate : 0.0;
    fprintf(stderr, "\r%5.1f%%  %llu / %llu points  %.2f M points/s  ETA %.0f s   ",
            100.0 * (double)done / (double)total, (unsigned long long)done,
            (unsigned long long)total, rate / 1e6, eta);
    ps->drawn = true;
    return true;
}

int main(int argc, char **argv)
{
    synth_args c;
    memset(&c, 0, sizeof(c));
    int status = parse(argc, argv, &c);
    if (status >= 0) {
        return status;
    }
    progress_state ps = { .start_s = sta_clock_s() };
    bool draw = !c.quiet && sta_log_is_terminal();
    sta_error err = { 0 };
    sta_synth_report report;
    sta_status s = sta_synth_generate_reported(&c.params, c.output, draw ? show_progress : NULL,
                                               &ps, &report, &err);
    if (ps.drawn) {
        fputc('\n', stderr);
    }
    if (s != STA_OK) {
        fprintf(stderr, "strata-synth: %s\n", err.message);
        return 1;
    }
    if (!c.quiet) {
        double elapsed = sta_clock_s() - ps.start_s;
        char *truth = NULL;
        sta_synth_truth_path(c.output, &truth, NULL);
        fprintf(
            stderr,
            "strata-synth: wrote %llu points of '%s' to %s and %s in %.2f s (%.2f M points/s)\n",
            (unsigned long long)c.params.point_count, sta_synth_kind_name(c.params.kind), c.output,
            truth ? truth : "its truth sidecar", elapsed,
            elapsed > 0.0 ? (double)c.params.point_count / elapsed / 1e6 : 0.0);
        sta_free(truth);
        if (c.params.kind == STA_SYNTH_MESH) {
            fprintf(stderr, "strata-synth: up axis: %s%s\n", report.mesh_up_why,
                    report.mesh_y_up ? "; turned to stand on +Z (the LAS is z up)" : "");
        }
    }
    return 0;
}
