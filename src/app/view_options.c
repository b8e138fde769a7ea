/* SPDX-License-Identifier: MIT
 * strata-view's command line: one option table (core/cli.h) holds each option, its range
 * and, through the values set before parsing, its default. */
#include "app/view_options.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app/view_no_fill.h"
#include "core/cli.h"
#include "core/navigation.h"
#include "render/bindings.h"
#include "render/pass_geometry.h"
#include "render/pass_splats.h"
#include "render/pipeline.h"
#include "render/ref/hpr_ref.h"
#include "render/ref/normals_screen_ref.h"
#include "stream/clip_cli.h"
#include "stream/streamer.h"

enum {
    MAX_SIZE_PX = 16384 /* --size: the largest side */
};

static const char usage_text[] =
    "usage: strata-view [options] SCENE.strata\n"
    "\n"
    "Opens a .strata scene in a window and streams it to the GPU within a point budget.\n"
    "With --headless it renders through EGL (no display needed) to a PNG / EXR.\n";

static const char keys_text[] =
    "window keys and mouse:\n"
    "  left drag      orbit around the picked point      right drag / shift  pan\n"
    "  wheel          zoom towards the cursor             double-click  focus a point\n"
    "  W A S D Q E    fly (hold shift: faster)            F       toggle fly / orbit\n"
    "  1..6           colour: rgb, intensity, elevation, class, returns, height\n"
    "  M / N          next pipeline mode / next normal method\n"
    "  H              pyramidal / exhaustive HPR     G    normal smoothing on/off\n"
    "  K              live Katz HPR on/off (drawn subsample, hull on worker threads)\n"
    "  O              splats on/off (--pipeline splats)   [ / ]   splat radius / 1.25, x 1.25\n"
    "  R              reset to the whole scene            P       add path keyframe\n"
    "  V              show / hide mirror ghost points (docs/MIRRORS.md)\n"
    "  O              mirror tool on/off: Ctrl+click vertices, Enter closes and saves to\n"
    "                 --mirrors FILE (default mirrors.json), Backspace undoes\n"
    "  Esc            quit\n";

static const char *const colour_names[] = { "rgb",     "intensity", "elevation", "class",
                                            "returns", "height",    NULL };
_Static_assert(sizeof(colour_names) / sizeof(colour_names[0]) == STA_COLOUR_MODE_COUNT + 1,
               "one name per colour mode");

int sta_view_colour_mode(const char *name)
{
    for (int i = 0; colour_names[i]; i++) {
        if (strcmp(name, colour_names[i]) == 0) {
            return i;
        }
    }
    return -1;
}

static int parse_doubles(const char *text, double *out, int min_count, int max_count)
{
    int n = 0;
    const char *p = text;
    while (*p && n < max_count) {
        char *end = NULL;
        errno = 0;
        double v = strtod(p, &end);
        if (end == p || errno) {
            return -1;
        }
        out[n++] = v;
        p = end;
        if (*p == ',') {
            p++;
        } else if (*p) {
            return -1;
        }
    }
    return n >= min_count && *p == '\0' ? n : -1;
}

// --size WxH (dest: sta_view_args).
static sta_status parse_size(const sta_cli_option *option, const char *value, sta_error *err)
{
    sta_view_args *a = option->dest;
    int w = 0, h = 0;
    char tail = 0;
    if (sscanf(value, "%dx%d%c", &w, &h, &tail) != 2 || w < 1 || h < 1 || w > MAX_SIZE_PX ||
        h > MAX_SIZE_PX) {
        char expected[96];
        snprintf(expected, sizeof(expected), "WxH, each from 1 to %d (e.g. 1920x1080)",
                 MAX_SIZE_PX);
        return sta_cli_fail_value(err, option, value, expected);
    }
    a->width_px = w;
    a->height_px = h;
    return STA_OK;
}

static void show_size(const sta_cli_option *option, char *out_text, size_t size)
{
    const sta_view_args *a = option->dest;
    snprintf(out_text, size, "%dx%d", a->width_px, a->height_px);
}

// --point-size N|adaptive (dest: sta_point_size).
static sta_status parse_point_size(const sta_cli_option *option, const char *value, sta_error *err)
{
    sta_point_size size = *(const sta_point_size *)option->dest;
    if (sta_point_size_parse(value, &size, err) != STA_OK) {
        char expected[96];
        snprintf(expected, sizeof(expected), "'adaptive' or a diameter in pixels from 1 to %g",
                 STA_POINT_SIZE_LIMIT_PX);
        return sta_cli_fail_value(err, option, value, expected);
    }
    *(sta_point_size *)option->dest = size;
    return STA_OK;
}

static void show_point_size(const sta_cli_option *option, char *out_text, size_t size)
{
    const sta_point_size *p = option->dest;
    if (p->mode == STA_POINT_SIZE_ADAPTIVE) {
        snprintf(out_text, size, "adaptive");
    } else {
        snprintf(out_text, size, "%g", p->size_px);
    }
}

// --camera and --look X,Y,Z,YAW,PITCH[,FOV] (dest: sta_view_args).
static sta_status parse_camera(const sta_cli_option *option, const char *value, sta_error *err)
{
    sta_view_args *a = option->dest;
    if (parse_doubles(value, a->camera, 5, 6) < 0) {
        return sta_cli_fail_value(err, option, value, "X,Y,Z,YAW,PITCH[,FOV]");
    }
    a->has_camera = true;
    a->camera_relative = strcmp(option->name, "look") == 0;
    return STA_OK;
}

// --elevation-range MIN,MAX (dest: sta_view_args).
static sta_status parse_elevation(const sta_cli_option *option, const char *value, sta_error *err)
{
    sta_view_args *a = option->dest;
    double v[2];
    if (parse_doubles(value, v, 2, 2) < 0 || !(v[1] > v[0])) {
        return sta_cli_fail_value(err, option, value, "MIN,MAX in metres with MIN < MAX");
    }
    memcpy(a->elevation_range, v, sizeof(v));
    return STA_OK;
}

// --pick X,Y (dest: sta_view_args).
static sta_status parse_pick(const sta_cli_option *option, const char *value, sta_error *err)
{
    sta_view_args *a = option->dest;
    if (parse_doubles(value, a->pick_px, 2, 2) < 0) {
        return sta_cli_fail_value(err, option, value, "X,Y in pixels");
    }
    a->has_pick = true;
    return STA_OK;
}

static void show_camera(const sta_cli_option *option, char *out_text, size_t size)
{
    const sta_view_args *a = option->dest;
    snprintf(out_text, size,
             "the whole scene: a street along its axis, else from the south-west; FOV %g; "
             "--stats prints it as a --camera option",
             a->camera[5]);
}

// --frames-out PATTERN: exactly one %d-style conversion, as the pattern reaches snprintf.
static sta_status parse_orbit_pitch(const sta_cli_option *option, const char *value, sta_error *err)
{
    sta_view_args *a = option->dest;
    double lo, hi;
    char tail;
    if (sscanf(value, "%lf,%lf%c", &lo, &hi, &tail) != 2 || !(lo >= -89.0) || !(hi <= 89.0) ||
        !(lo < hi)) {
        return sta_cli_fail_value(err, option, value, "MIN,MAX degrees, -89 <= MIN < MAX <= 89");
    }
    a->orbit_pitch_deg[0] = lo;
    a->orbit_pitch_deg[1] = hi;
    return STA_OK;
}

static void show_orbit_pitch(const sta_cli_option *option, char *out, size_t size)
{
    const sta_view_args *a = option->dest;
    snprintf(out, size, "%g,%g", a->orbit_pitch_deg[0], a->orbit_pitch_deg[1]);
}

static sta_status parse_frame_pattern(const sta_cli_option *option, const char *value,
                                      sta_error *err)
{
    const char *pc = strchr(value, '%');
    const char *d = pc ? pc + 1 : NULL;
    while (d && *d >= '0' && *d <= '9') {
        d++;
    }
    if (!pc || *d != 'd' || strchr(pc + 1, '%')) {
        return sta_cli_fail_value(err, option, value, "one %d (e.g. f/%05d.png)");
    }
    *(const char **)option->dest = value;
    return STA_OK;
}

int sta_view_parse_args(int argc, char **argv, sta_view_args *a)
{
    // The defaults, shown by --help from here.
    memset(a, 0, sizeof(*a));
    a->width_px = 1280;
    a->height_px = 720;
    a->colour_mode = -1;
    a->timeout_s = 300.0;
    a->camera[5] = 60.0;
    a->budget_points = STA_DEFAULT_BUDGET_POINTS;
    a->min_spacing_px = STA_DEFAULT_MIN_SPACING_PX;
    a->orbit_pitch_deg[0] = STA_ORBIT_DEFAULT_PITCH_MIN_DEG;
    a->orbit_pitch_deg[1] = STA_ORBIT_DEFAULT_PITCH_MAX_DEG;
    a->gpu_mem_mib = (int)(STA_DEFAULT_GPU_BYTES_CAP >> 20);
    a->pipeline = STA_PIPELINE_SHADED;
    a->normals = STA_NORMAL_PYRAMID;
    a->samples = STA_NORMALS_SCREEN_DEFAULT_SAMPLES;
    a->hpr_radius_px = STA_PIPELINE_DEFAULT_HPR_RADIUS_PX;
    a->hpr_threshold = (double)STA_HPR_DEFAULT_THRESHOLD;
    sta_katz_view_options_defaults(&a->katz);
    a->raster = STA_RASTER_DEFAULT; // resolved (and so named in the log) by render/
    sta_point_size_defaults(&a->point_size);
    a->splat_scale = STA_SPLAT_DEFAULT_SCALE;
    a->splat_method = STA_SPLAT_DEFAULT;
    static const char *const splat_method_names[] = { "instanced", "geometry", "pulled", NULL };
    static const int splat_method_values[] = { STA_SPLAT_INSTANCED, STA_SPLAT_GEOMETRY,
                                               STA_SPLAT_PULLED };
    static const char *const raster_names[] = { "compute", "points", NULL };
    static const char *const clock_names[] = { "wall", "cpu", NULL };
    static const int clock_values[] = { STA_TIMING_WALL, STA_TIMING_CPU };
    static const int raster_values[] = { STA_RASTER_COMPUTE, STA_RASTER_POINTS };
    int hpr = 0; // index into hpr_names
    static const char *const hpr_names[] = { "sparse", "exhaustive", "katz", "pyramid", NULL };
    int gaps = 1; // index into gaps_names: smooth
    static const char *const gaps_names[] = { "blocks", "smooth", NULL };
    static const char *const sample_names[] = { "5", "9", "17", "25", NULL };
    static const int sample_values[] = { 5, 9, 17, 25 };
    const char *pipeline_names[STA_PIPELINE_MODE_COUNT + 1] = { NULL };
    for (int i = 0; i < STA_PIPELINE_MODE_COUNT; i++) {
        pipeline_names[i] = sta_pipeline_mode_name(i);
    }
    const char *normal_names[STA_NORMAL_METHOD_COUNT + 1] = { NULL };
    for (int i = 0; i < STA_NORMAL_METHOD_COUNT; i++) {
        normal_names[i] = sta_normal_method_name(i);
    }
    const sta_cli_option options[] = {
        { .name = "headless",
          .kind = STA_CLI_FLAG,
          .dest = &a->headless,
          .help = "render offscreen; needs --out, --exr, --frames-out, --stats, --pick or "
                  "--measure" },
        { .name = "out",
          .kind = STA_CLI_STRING,
          .dest = &a->out_png,
          .metavar = "FILE.png",
          .help = "write the colour image (headless)" },
        { .name = "exr",
          .kind = STA_CLI_STRING,
          .dest = &a->out_exr,
          .metavar = "FILE.exr",
          .help = "write colour and depth as float channels (headless)" },
        { .name = "size",
          .kind = STA_CLI_CALLBACK,
          .dest = a,
          .metavar = "WxH",
          .parse = parse_size,
          .show = show_size,
          .help = "image or window size in pixels" },
        { .name = "camera",
          .kind = STA_CLI_CALLBACK,
          .dest = a,
          .metavar = "X,Y,Z,YAW,PITCH[,FOV]",
          .parse = parse_camera,
          .show = show_camera,
          .help = "camera in world coordinates; angles in degrees, yaw 0 looks along +X, 90 "
                  "along +Y; FOV vertical" },
        { .name = "look",
          .kind = STA_CLI_CALLBACK,
          .dest = a,
          .metavar = "DX,DY,DZ,YAW,PITCH[,FOV]",
          .parse = parse_camera,
          .help = "the same, relative to the centre of the scene's bounds" },
        { .name = "frames",
          .kind = STA_CLI_INT,
          .dest = &a->max_frames,
          .metavar = "N",
          .int_min = 1,
          .int_max = 1000000,
          .help = "stop after N frames",
          .default_text = "headless: until every wanted node is loaded" },
        { .name = "repeat",
          .kind = STA_CLI_INT,
          .dest = &a->repeat,
          .metavar = "N",
          .int_min = 1,
          .int_max = 256,
          .help = "headless: once loaded, time N more frames and print their median time" },
        { .name = "clip",
          .kind = STA_CLI_CALLBACK,
          .dest = &a->clip,
          .metavar = "X0,Y0,Z0,X1,Y1,Z1",
          .parse = sta_clip_cli_box,
          .help = STA_CLIP_HELP_BOX "; nodes outside are not loaded" },
        { .name = "classes",
          .kind = STA_CLI_CALLBACK,
          .dest = &a->clip,
          .metavar = "LIST",
          .parse = sta_clip_cli_classes,
          .help = STA_CLIP_HELP_CLASSES },
        { .name = "returns",
          .kind = STA_CLI_CALLBACK,
          .dest = &a->clip,
          .metavar = "LIST",
          .parse = sta_clip_cli_returns,
          .help = STA_CLIP_HELP_RETURNS },
        { .name = "pick",
          .kind = STA_CLI_CALLBACK,
          .dest = a,
          .metavar = "X,Y",
          .parse = parse_pick,
          .help = "headless: after the last frame, print the point drawn at pixel X,Y "
                  "(origin top-left): coordinates and attributes" },
        { .name = "measure",
          .kind = STA_CLI_STRING,
          .dest = &a->measure_file,
          .metavar = "FILE.json",
          .help = "load measurements (as the window saves them with S) and list their values" },
        { .name = "measure-csv",
          .kind = STA_CLI_STRING,
          .dest = &a->measure_csv,
          .metavar = "FILE.csv",
          .help = "write the measurements as CSV (headless: those of --measure)" },
        { .name = "mirrors",
          .kind = STA_CLI_STRING,
          .dest = &a->mirrors_file,
          .metavar = "FILE",
          .help = "mirror file (docs/MIRRORS.md): draw its mirrors by reflection, and flag the "
                  "ghost points behind them at load in scenes converted without "
                  "strata-convert --mirrors" },
        { .name = "no-reflections",
          .kind = STA_CLI_FLAG,
          .dest = &a->no_reflections,
          .help = "do not draw the --mirrors mirrors by reflection (one extra pass each)" },
        { .name = "show-ghosts",
          .kind = STA_CLI_FLAG,
          .dest = &a->show_ghosts,
          .help = "draw mirror ghost points (hidden by default; window: V toggles)" },
        { .name = "no-readout",
          .kind = STA_CLI_FLAG,
          .dest = &a->no_readout,
          .help = "window: no readout (figures, pick, measurements) over the frame" },
        { .name = "elevation-range",
          .kind = STA_CLI_CALLBACK,
          .dest = a,
          .metavar = "MIN,MAX",
          .parse = parse_elevation,
          .help = "heights (scene CRS) the elevation colour ramp spans",
          .default_text = "the scene's" },
        { .name = "intensity-max",
          .kind = STA_CLI_DOUBLE,
          .dest = &a->intensity_max,
          .metavar = "I",
          .real_min = 0.0,
          .real_max = 65535.0,
          .flags = STA_CLI_ABOVE_MIN,
          .help = "intensity at the top of the intensity ramp",
          .default_text = "the largest in the scene's root node" },
        { .name = "hud",
          .kind = STA_CLI_FLAG,
          .dest = &a->hud,
          .help = "headless: burn the readout (budget use, nodes, pipeline, pick, "
                  "measurements) into the image, as the window shows it" },
        { .name = "budget",
          .kind = STA_CLI_COUNT,
          .dest = &a->budget_points,
          .metavar = "POINTS",
          .count_min = 1000,
          .count_max = 2000000000u,
          .help = "points drawn per frame at most" },
        { .name = "gpu-mem",
          .kind = STA_CLI_COUNT,
          .dest = &a->gpu_mem_mib,
          .metavar = "MIB",
          .count_min = 16,
          .count_max = 1u << 20,
          .help = "GPU memory for resident nodes" },
        { .name = "min-spacing",
          .kind = STA_CLI_DOUBLE,
          .dest = &a->min_spacing_px,
          .metavar = "PX",
          .real_min = 0.0,
          .real_max = 1e3,
          .flags = STA_CLI_ABOVE_MIN,
          .help = "stop refining the LOD cut below this on-screen point spacing (smaller: "
                  "more points per pixel, as in rasteriser benchmarks)" },
        { .name = "colour",
          .kind = STA_CLI_CHOICE,
          .dest = &a->colour_mode,
          .metavar = "MODE",
          .choices = colour_names,
          .help = "point colours",
          .default_text = "rgb when the scene has colour, else elevation" },
        { .name = "color",
          .kind = STA_CLI_CHOICE,
          .dest = &a->colour_mode,
          .choices = colour_names,
          .flags = STA_CLI_HIDDEN },
        { .name = "path",
          .kind = STA_CLI_STRING,
          .dest = &a->path_file,
          .metavar = "FILE.json",
          .help = "play a recorded camera path (window or headless)" },
        { .name = "frames-out",
          .kind = STA_CLI_CALLBACK,
          .dest = &a->frame_pattern,
          .metavar = "PATTERN",
          .parse = parse_frame_pattern,
          .help = "headless path playback: write frame i to PATTERN with %d replaced (e.g. "
                  "frames/%05d.png)" },
        { .name = "path-speed",
          .kind = STA_CLI_DOUBLE,
          .dest = &a->path_speed_mps,
          .metavar = "M/S",
          .real_min = 0.0,
          .real_max = 1e6,
          .flags = STA_CLI_ABOVE_MIN,
          .help = "play --path at this constant speed along the path instead of its key times",
          .default_text = "the key times" },
        { .name = "orbit-pitch",
          .kind = STA_CLI_CALLBACK,
          .dest = a,
          .metavar = "MIN,MAX",
          .parse = parse_orbit_pitch,
          .show = show_orbit_pitch,
          .help = "window: the camera's elevation above the orbit centre stays in MIN..MAX "
                  "degrees" },
        { .name = "record",
          .kind = STA_CLI_STRING,
          .dest = &a->record_file,
          .metavar = "FILE.json",
          .help = "window: record the camera path (key P adds a keyframe)" },
        { .name = "stats",
          .kind = STA_CLI_FLAG,
          .dest = &a->stats,
          .help = "print one line of frame statistics per frame, with the GPU time of every pass" },
        { .name = "stats-clock",
          .kind = STA_CLI_CHOICE,
          .dest = &a->stats_clock,
          .metavar = "CLOCK",
          .choices = clock_names,
          .choice_values = clock_values,
          .help = "--stats pass times: wall (elapsed, the GPU drained around each pass) or cpu "
                  "(CPU time of all the process's threads meanwhile: the work of a pass on "
                  "llvmpipe, steady on a busy machine)",
          .default_text = "wall" },
        { .name = "raster",
          .kind = STA_CLI_CHOICE,
          .dest = &a->raster,
          .metavar = "METHOD",
          .choices = raster_names,
          .choice_values = raster_values,
          .help = "geometry pass: compute (compute-shader rasteriser) or points (GL_POINTS)",
          .default_text = sta_raster_method_name(STA_RASTER_DEFAULT_METHOD) },
        { .name = "raster-32bit",
          .kind = STA_CLI_FLAG,
          .dest = &a->raster_32bit,
          .help = "compute rasteriser: two passes with 32-bit atomics even where 64-bit "
                  "ones exist" },
        { .name = "point-size",
          .kind = STA_CLI_CALLBACK,
          .dest = &a->point_size,
          .metavar = "PX|adaptive",
          .parse = parse_point_size,
          .show = show_point_size,
          .help = "raw and edl pipelines: point diameter in pixels (round, with a depth per "
                  "pixel), or adaptive: the node's point spacing on screen, within "
                  "--point-size-min and --point-size-max (keys + - and Z in the window)" },
        { .name = "point-size-min",
          .kind = STA_CLI_DOUBLE,
          .dest = &a->point_size.min_px,
          .metavar = "PX",
          .real_min = 1.0,
          .real_max = STA_POINT_SIZE_LIMIT_PX,
          .help = "adaptive point size: smallest diameter" },
        { .name = "point-size-max",
          .kind = STA_CLI_DOUBLE,
          .dest = &a->point_size.max_px,
          .metavar = "PX",
          .real_min = 1.0,
          .real_max = STA_POINT_SIZE_LIMIT_PX,
          .help = "adaptive point size: largest diameter" },
        { .heading = "screen-space pipeline (after the one-pixel-per-point geometry pass):",
          .name = "pipeline",
          .kind = STA_CLI_CHOICE,
          .dest = &a->pipeline,
          .metavar = "MODE",
          .choices = pipeline_names,
          .help = "raw: points only; hpr: hidden point removal labels; fill: pull-push; "
                  "normals; shaded; edl: eye-dome lighting; splats: oriented round splats "
                  "from the scene's normals and radii (strata-convert --normals; without "
                  "them: shaded)" },
        { .name = "splat-scale",
          .kind = STA_CLI_DOUBLE,
          .dest = &a->splat_scale,
          .metavar = "F",
          .real_min = 0.0,
          .real_max = 1e3,
          .flags = STA_CLI_ABOVE_MIN,
          .help = "splats: factor on the stored radii (window keys [ and ] change it)" },
        { .name = "splat-method",
          .kind = STA_CLI_CHOICE,
          .dest = &a->splat_method,
          .metavar = "METHOD",
          .choices = splat_method_names,
          .choice_values = splat_method_values,
          .help = "splats: instanced (quads), geometry (a geometry shader on points) or pulled "
                  "(quads reading the arenas, no instancing)",
          .default_text = "geometry on llvmpipe, instanced on a GPU" },
        { .name = "normals",
          .kind = STA_CLI_CHOICE,
          .dest = &a->normals,
          .metavar = "METHOD",
          .choices = normal_names,
          .help = "normal estimation method" },
        { .name = "samples",
          .kind = STA_CLI_CHOICE,
          .dest = &a->samples,
          .metavar = "N",
          .choices = sample_names,
          .choice_values = sample_values,
          .help = "sampling scheme of pd, pc and ti" },
        { .name = "smooth",
          .kind = STA_CLI_FLAG,
          .dest = &a->smooth,
          .help = "smooth the normals (one extra pass)" },
        { .name = "normals-every-pixel",
          .kind = STA_CLI_FLAG,
          .dest = &a->normals_every_pixel,
          .help = "pyramidal normals gathered on every pixel (by default on a quarter of "
                  "them, a sixteenth from 1080 px high, upsampled within each surface; "
                  "docs/PULLPUSH.md)" },
        { .name = "hpr",
          .kind = STA_CLI_CHOICE,
          .dest = &hpr,
          .metavar = "MODE",
          .choices = hpr_names,
          .help = "pyramidal HPR on a quarter of the pixels, refined where 2x2 blocks "
                  "disagree (docs/HPR.md), the fixed-radius baseline, live Katz HPR (CPU "
                  "threads: the visible points of a subsample are drawn; docs/KATZ.md), or "
                  "pyramidal HPR on every pixel (a third dearer)" },
        { .name = "hpr-gaps",
          .kind = STA_CLI_CHOICE,
          .dest = &gaps,
          .metavar = "MODE",
          .choices = gaps_names,
          .help = "pyramidal HPR's hole / background decision for empty pixels: by the "
                  "pyramid's blocks (gaps' borders step along 16-32 px block lines; the rule "
                  "before issue 15), or per pixel (borders follow the points; docs/HPR.md)" },
        { .name = "katz-points",
          .kind = STA_CLI_COUNT,
          .dest = &a->katz.sample_points,
          .metavar = "N",
          .count_min = 4,
          .count_max = 100000000,
          .flags = STA_CLI_SUFFIX,
          .help = "live Katz: points per hull (a subsample of the drawn points)" },
        { .name = "katz-threads",
          .kind = STA_CLI_INT,
          .dest = &a->katz.threads,
          .metavar = "N",
          .int_min = 1,
          .int_max = STA_KATZ_WORKER_MAX_THREADS,
          .help = "live Katz: hull threads" },
        { .name = "katz-perturbation",
          .kind = STA_CLI_DOUBLE,
          .dest = &a->katz.perturbation,
          .metavar = "A",
          .real_min = 0.0,
          .real_max = 1.0,
          .help = "live Katz: Braga's perturbation, in model radii (0: none)" },
        { .name = "katz-compare",
          .kind = STA_CLI_FLAG,
          .dest = &a->katz.compare_plain,
          .help = "live Katz: also time the plain hull on each input (--stats shows both)" },
        { .name = "hpr-radius",
          .kind = STA_CLI_INT,
          .dest = &a->hpr_radius_px,
          .metavar = "PX",
          .int_min = 1,
          .int_max = 64,
          .help = "radius of the exhaustive operator" },
        { .name = "hpr-threshold",
          .kind = STA_CLI_DOUBLE,
          .dest = &a->hpr_threshold,
          .metavar = "T",
          .real_min = 0.0,
          .real_max = 1e6,
          .flags = STA_CLI_ABOVE_MIN,
          .help = "visibility threshold" },
        { .name = "s0",
          .kind = STA_CLI_DOUBLE,
          .dest = &a->s0_m,
          .metavar = "METRES",
          .real_min = 0.0,
          .real_max = 1e6,
          .flags = STA_CLI_ABOVE_MIN,
          .help = "sampling scale",
          .default_text = "from the hierarchy's spacing" },
        { .name = "no-fill-classes",
          .kind = STA_CLI_CALLBACK,
          .dest = a,
          .metavar = "LIST",
          .parse = sta_view_parse_no_fill,
          .help = STA_VIEW_NO_FILL_HELP,
          .default_text = "3-5,13,14 (vegetation, wires)" },
        { .name = NULL },
    };
    const sta_cli cli = {
        .program = "strata-view", .usage = usage_text, .epilog = keys_text, .options = options
    };
    sta_cli_result r;
    int rc = sta_cli_parse_main(&cli, argc, argv, &r);
    if (rc >= 0) {
        return rc == 0 ? -1 : rc;
    }
    a->hpr_exhaustive = hpr == 1;
    a->hpr_every_pixel = hpr == 3;
    a->hpr_block_gaps = gaps == 0;
    a->katz.enabled = hpr == 2;
    if (r.positional_count == 0) {
        return sta_cli_usage_error(&cli, "no scene given (see --help)");
    }
    if (r.positional_count > 1) {
        return sta_cli_usage_error(&cli, "one scene at a time (got %s and %s)", r.positional[0],
                                   r.positional[1]);
    }
    a->scene = r.positional[0];
    if (a->headless && !a->out_png && !a->out_exr && !a->frame_pattern && !a->stats &&
        !a->has_pick && !a->measure_file) {
        return sta_cli_usage_error(
            &cli, "--headless needs --out, --exr, --frames-out, --stats, --pick or --measure");
    }
    if (a->point_size.min_px > a->point_size.max_px) {
        return sta_cli_usage_error(&cli, "--point-size-min %g is larger than --point-size-max %g",
                                   a->point_size.min_px, a->point_size.max_px);
    }
    if (!sta_point_size_is_one_pixel(&a->point_size) && a->pipeline != STA_PIPELINE_RAW &&
        a->pipeline != STA_PIPELINE_EDL) {
        fprintf(stderr,
                "strata-view: note: --point-size applies to the raw and edl pipelines; "
                "the %s pipeline draws one pixel per point\n",
                sta_pipeline_mode_name(a->pipeline));
    }
    return 0;
}
