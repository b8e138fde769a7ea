/* SPDX-License-Identifier: MIT
 * strata-export: the points of a .strata scene, or a selection, back out as LAS.
 */
#include <inttypes.h>
#include <stdio.h>

#include "core/alloc.h"
#include "core/cli.h"
#include "core/log.h"
#include "export/export.h"
#include "stream/clip_cli.h"

static const char usage_text[] =
    "usage: strata-export [options] SCENE.strata -o OUT.las\n"
    "\n"
    "Writes the points of a .strata scene, or a selection of them, as LAS 1.2 or 1.4\n"
    "with the scene's scale and offset and the original integer coordinates and\n"
    "attributes; the point format is the one the scene's LAS input had (the fields it\n"
    "holds), extra bytes kept by strata-convert --attributes extra come back too.\n"
    "Points are written in file order: nodes breadth-first (coarse levels first), each\n"
    "node's points as stored. The output appears only when complete.\n";

static const char exit_text[] = "exit status: 0 done, 1 failed (nothing written), 2 bad usage\n";

int main(int argc, char **argv)
{
    sta_export_options options = { 0 };
    const char *polygon_path = NULL;
    int level = -1;
    bool quiet = false;
    static const char *const versions[] = { "1.2", "1.4", NULL };
    static const int version_minors[] = { 2, 4 };
    const sta_cli_option table[] = {
        { .name = "output",
          .short_name = 'o',
          .kind = STA_CLI_STRING,
          .dest = &options.output,
          .metavar = "FILE.las",
          .help = "the LAS file to write (required)" },
        { .name = "box",
          .kind = STA_CLI_CALLBACK,
          .dest = &options.clip,
          .metavar = "X0,Y0,Z0,X1,Y1,Z1",
          .parse = sta_clip_cli_box,
          .heading = "selection (all terms must hold):",
          .help = STA_CLIP_HELP_BOX },
        { .name = "polygon",
          .kind = STA_CLI_STRING,
          .dest = &polygon_path,
          .metavar = "FILE",
          .help = "keep points inside this 2D outline: one \"x y\" vertex per line, scene CRS" },
        { .name = "classes",
          .kind = STA_CLI_CALLBACK,
          .dest = &options.clip,
          .metavar = "LIST",
          .parse = sta_clip_cli_classes,
          .help = STA_CLIP_HELP_CLASSES },
        { .name = "returns",
          .kind = STA_CLI_CALLBACK,
          .dest = &options.clip,
          .metavar = "LIST",
          .parse = sta_clip_cli_returns,
          .help = STA_CLIP_HELP_RETURNS },
        { .name = "level",
          .kind = STA_CLI_INT,
          .dest = &level,
          .metavar = "N",
          .int_min = 0,
          .int_max = 32,
          .help = "keep only nodes of level N or coarser (a light preview)",
          .default_text = "all levels" },
        { .name = "spacing",
          .kind = STA_CLI_DOUBLE,
          .dest = &options.clip.min_spacing,
          .metavar = "M",
          .real_min = 0.0,
          .real_max = 1e12,
          .flags = STA_CLI_ABOVE_MIN,
          .help = "keep only nodes whose point spacing is M metres or more",
          .default_text = "all" },
        { .name = "max-points",
          .kind = STA_CLI_COUNT,
          .dest = &options.max_points,
          .metavar = "N",
          .count_min = 1,
          .count_max = UINT64_MAX,
          .flags = STA_CLI_SUFFIX,
          .help = "stop after N points (coarse levels first, so a uniform subsample)",
          .default_text = "no limit" },
        { .name = "las-version",
          .kind = STA_CLI_CHOICE,
          .dest = &options.version_minor,
          .metavar = "VERSION",
          .choices = versions,
          .choice_values = version_minors,
          .heading = "output:",
          .help = "LAS version to write",
          .default_text = "1.2 for point formats 0-3, else 1.4" },
        { .name = "force",
          .kind = STA_CLI_FLAG,
          .dest = &options.force,
          .help = "overwrite OUT.las if it exists" },
        { .name = "quiet",
          .short_name = 'q',
          .kind = STA_CLI_FLAG,
          .dest = &quiet,
          .help = "no progress line and no summary" },
        { .name = NULL },
    };
    const sta_cli cli = {
        .program = "strata-export", .usage = usage_text, .epilog = exit_text, .options = table
    };
    sta_cli_result r;
    int rc = sta_cli_parse_main(&cli, argc, argv, &r);
    if (rc >= 0) {
        return rc;
    }
    if (r.positional_count != 1 || !options.output) {
        return sta_cli_usage_error(&cli, "%s",
                                   r.positional_count != 1 ? "one input scene is needed"
                                                           : "no output file (-o OUT.las)");
    }
    options.input = r.positional[0];
    if (level >= 0) {
        options.clip.has_max_level = true;
        options.clip.max_level = (unsigned)level;
    }
    options.progress = !quiet && sta_log_is_terminal();
    sta_error err = { 0 };
    double *polygon = NULL;
    sta_status status = STA_OK;
    if (polygon_path) {
        status = sta_clip_read_polygon(polygon_path, &polygon, &options.clip.polygon_count, &err);
        options.clip.polygon = polygon;
    }
    sta_export_report report;
    if (status == STA_OK) {
        status = sta_export(&options, &report, &err);
    }
    sta_free(polygon);
    if (status != STA_OK) {
        fprintf(stderr, "strata-export: %s\n", err.message);
        return 1;
    }
    if (!quiet) {
        fprintf(stderr,
                "%s: %" PRIu64 " points (LAS 1.%d, point format %d, %u extra bytes) from %" PRIu32
                " nodes (%" PRIu32 " skipped unread)\n",
                options.output, report.points_written, report.version_minor, report.point_format,
                report.extra_size, report.nodes_read, report.nodes_culled);
    }
    return 0;
}
