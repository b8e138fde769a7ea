/* SPDX-License-Identifier: MIT
 * strata-bench: frame times and errors of the renderer on .strata scenes, headless
 * (EGL on Mesa llvmpipe works without a GPU). Usage in docs/BENCH.md.
 */
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench/report.h"
#include "bench/sweep.h"
#include "core/alloc.h"
#include "core/cli.h"
#include "render/gl.h"
#include "render/pass_katz.h"
#include "render/ref/hpr_ref.h"
#include "stream/point_sample.h"

enum {
    MAX_SIZE_PX = 16384 /* --size: the largest side */
};

static const char usage_text[] =
    "usage: strata-bench [options] SCENE.strata...\n"
    "\n"
    "Frame times and errors of the renderer on .strata scenes, headless; every\n"
    "combination of the sweep lists that applies is run (docs/BENCH.md).\n";

// Splits a comma-separated list, calling parse on each item; false on a bad item.
typedef bool (*item_parser)(const char *item, void *out, int index);

static bool parse_list(const char *text, item_parser parse, void *out, int *out_count)
{
    char buf[1024];
    if (snprintf(buf, sizeof(buf), "%s", text) >= (int)sizeof(buf)) {
        return false;
    }
    int n = 0;
    char *save = NULL;
    for (char *item = strtok_r(buf, ",", &save); item; item = strtok_r(NULL, ",", &save)) {
        if (n >= STA_BENCH_MAX_LIST || !parse(item, out, n)) {
            return false;
        }
        n++;
    }
    *out_count = n;
    return n > 0;
}

static bool parse_budget(const char *item, void *out, int i)
{
    if (strcmp(item, "all") == 0) {
        ((uint64_t *)out)[i] = 0;
        return true;
    }
    char *end = NULL;
    errno = 0;
    double v = strtod(item, &end);
    double scale = 1.0;
    if (end && (*end == 'k' || *end == 'K')) {
        scale = 1e3;
        end++;
    } else if (end && *end == 'M') {
        scale = 1e6;
        end++;
    } else if (end && *end == 'G') {
        scale = 1e9;
        end++;
    }
    v *= scale;
    if (errno || end == item || *end || !(v >= 1.0) || v > 1e15) {
        return false;
    }
    ((uint64_t *)out)[i] = (uint64_t)llround(v);
    return true;
}

static bool parse_mode(const char *item, void *out, int i)
{
    int m = sta_pipeline_mode_from_name(item);
    ((int *)out)[i] = m;
    return m >= 0;
}

static bool parse_normal(const char *item, void *out, int i)
{
    int m = sta_normal_method_from_name(item);
    ((int *)out)[i] = m;
    return m >= 0;
}

static bool parse_samples(const char *item, void *out, int i)
{
    int v = atoi(item);
    ((int *)out)[i] = v;
    return v == 5 || v == 9 || v == 17 || v == 25;
}

static bool parse_point_size_item(const char *item, void *out, int i)
{
    sta_point_size *size = &((sta_point_size *)out)[i];
    sta_point_size_defaults(size);
    sta_error ignored = { 0 };
    return sta_point_size_parse(item, size, &ignored) == STA_OK;
}

static bool parse_hpr(const char *item, void *out, int i)
{
    (void)i;
    bool *variants = out;
    if (strcmp(item, "pyramid") == 0) {
        variants[0] = true;
    } else if (strcmp(item, "exhaustive") == 0) {
        variants[1] = true;
    } else {
        return false;
    }
    return true;
}

// The callbacks' view of their list options: the option's dest is sta_bench_options.
static sta_status parse_list_option(const sta_cli_option *option, const char *value,
                                    item_parser parse, void *items, int *count,
                                    const char *expected, sta_error *err)
{
    int n = 0;
    if (!parse_list(value, parse, items, &n)) {
        char text[160];
        snprintf(text, sizeof(text), "a list of at most %d %s", STA_BENCH_MAX_LIST, expected);
        return sta_cli_fail_value(err, option, value, text);
    }
    *count = n;
    return STA_OK;
}

static sta_status parse_budgets(const sta_cli_option *option, const char *value, sta_error *err)
{
    sta_bench_options *o = option->dest;
    return parse_list_option(option, value, parse_budget, o->budgets, &o->budget_count,
                             "point counts or 'all' (e.g. 1e6,3M,all)", err);
}

static sta_status parse_modes(const sta_cli_option *option, const char *value, sta_error *err)
{
    sta_bench_options *o = option->dest;
    return parse_list_option(option, value, parse_mode, o->modes, &o->mode_count,
                             "pipeline modes (raw,hpr,fill,normals,shaded,edl,splats)", err);
}

static sta_status parse_normals(const sta_cli_option *option, const char *value, sta_error *err)
{
    sta_bench_options *o = option->dest;
    return parse_list_option(option, value, parse_normal, o->normals, &o->normal_count,
                             "normal methods (pyramid,ld,pd,pc,ti)", err);
}

static sta_status parse_sample_list(const sta_cli_option *option, const char *value, sta_error *err)
{
    sta_bench_options *o = option->dest;
    return parse_list_option(option, value, parse_samples, o->samples, &o->sample_count,
                             "sample counts (5,9,17,25)", err);
}

static sta_status parse_point_sizes(const sta_cli_option *option, const char *value, sta_error *err)
{
    sta_bench_options *o = option->dest;
    return parse_list_option(
        option, value, parse_point_size_item, o->point_sizes, &o->point_size_count,
        "point diameters in pixels (1 to 64) or 'adaptive' (e.g. 1,2,3,adaptive)", err);
}

// --point-size-range MIN,MAX: the adaptive entries' clamp.
static sta_status parse_point_size_range(const sta_cli_option *option, const char *value,
                                         sta_error *err)
{
    sta_bench_options *o = option->dest;
    double lo = 0, hi = 0;
    char tail = 0;
    if (sscanf(value, "%lf,%lf%c", &lo, &hi, &tail) != 2 || !(lo >= 1.0) || !(hi >= lo) ||
        hi > STA_POINT_SIZE_LIMIT_PX) {
        return sta_cli_fail_value(err, option, value, "MIN,MAX pixels, 1 <= MIN <= MAX <= 64");
    }
    o->adaptive_px[0] = lo;
    o->adaptive_px[1] = hi;
    return STA_OK;
}

static void show_point_size_range(const sta_cli_option *option, char *out_text, size_t size)
{
    const sta_bench_options *o = option->dest;
    bool given = o->adaptive_px[0] > 0;
    snprintf(out_text, size, "%g,%g", given ? o->adaptive_px[0] : STA_POINT_SIZE_DEFAULT_MIN_PX,
             given ? o->adaptive_px[1] : STA_POINT_SIZE_DEFAULT_MAX_PX);
}

static void show_point_sizes(const sta_cli_option *option, char *out_text, size_t size)
{
    const sta_bench_options *o = option->dest;
    size_t used = 0;
    out_text[0] = '\0';
    for (int i = 0; i < o->point_size_count && used < size; i++) {
        const sta_point_size *p = &o->point_sizes[i];
        int n = p->mode == STA_POINT_SIZE_ADAPTIVE
                    ? snprintf(out_text + used, size - used, "%sadaptive", i ? "," : "")
                    : snprintf(out_text + used, size - used, "%s%g", i ? "," : "", p->size_px);
        used += n > 0 ? (size_t)n : 0;
    }
}

// --hpr: the variants of every --hpr given add up; the first replaces the default.
typedef struct hpr_list {
    bool *variants; /* sta_bench_options.hpr_variants */
    bool given;     /* an --hpr was read */
} hpr_list;

static sta_status parse_hpr_list(const sta_cli_option *option, const char *value, sta_error *err)
{
    hpr_list *h = option->dest;
    bool variants[2] = { false, false };
    int count = 0;
    if (!parse_list(value, parse_hpr, variants, &count)) {
        return sta_cli_fail_value(err, option, value, "a list of pyramid,exhaustive");
    }
    if (!h->given) {
        h->variants[0] = h->variants[1] = false;
    }
    h->given = true;
    h->variants[0] |= variants[0];
    h->variants[1] |= variants[1];
    return STA_OK;
}

// --orbit N and --street N: the view count goes through the option's own INT range.
static sta_status parse_views(const sta_cli_option *option, const char *value, sta_error *err)
{
    sta_bench_options *o = option->dest;
    sta_cli_option count = *option;
    count.kind = STA_CLI_INT;
    count.dest = &o->camera_count;
    sta_status status = sta_cli_parse_value(&count, value, err);
    if (status == STA_OK) {
        o->cameras = strcmp(option->name, "orbit") == 0 ? STA_BENCH_ORBIT : STA_BENCH_STREET;
    }
    return status;
}

static sta_status parse_path(const sta_cli_option *option, const char *value, sta_error *err)
{
    (void)err;
    sta_bench_options *o = option->dest;
    o->cameras = STA_BENCH_PATH;
    o->path_file = value;
    return STA_OK;
}

static sta_status parse_size(const sta_cli_option *option, const char *value, sta_error *err)
{
    sta_bench_options *o = option->dest;
    int w = 0, h = 0, n = 0;
    if (sscanf(value, "%dx%d%n", &w, &h, &n) != 2 || value[n] || w < 1 || h < 1 ||
        w > MAX_SIZE_PX || h > MAX_SIZE_PX) {
        char expected[96];
        snprintf(expected, sizeof(expected), "WxH, each from 1 to %d (e.g. 1920x1080)",
                 MAX_SIZE_PX);
        return sta_cli_fail_value(err, option, value, expected);
    }
    o->width_px = w;
    o->height_px = h;
    return STA_OK;
}

// --truth FILE, once per scene (dest: truth_list).
typedef struct truth_list {
    const char **items; /* argc entries */
    size_t count;
} truth_list;

static sta_status parse_truth(const sta_cli_option *option, const char *value, sta_error *err)
{
    (void)err;
    truth_list *t = option->dest;
    t->items[t->count++] = value; // at most one per argument: items has argc entries
    return STA_OK;
}

/* Help's defaults, read from the options as sta_bench_options_defaults set them. */

static void show_views(const sta_cli_option *option, char *out_text, size_t size)
{
    const sta_bench_options *o = option->dest;
    snprintf(out_text, size, "%d", o->camera_count);
    if (o->cameras != STA_BENCH_ORBIT || strcmp(option->name, "orbit") != 0) {
        out_text[0] = '\0';
    }
}

static void show_size(const sta_cli_option *option, char *out_text, size_t size)
{
    const sta_bench_options *o = option->dest;
    snprintf(out_text, size, "%dx%d", o->width_px, o->height_px);
}

static void show_budgets(const sta_cli_option *option, char *out_text, size_t size)
{
    const sta_bench_options *o = option->dest;
    size_t used = 0;
    out_text[0] = '\0';
    for (int i = 0; i < o->budget_count && used < size; i++) {
        uint64_t b = o->budgets[i];
        const char *sep = i ? "," : "";
        int n = b == 0 ? snprintf(out_text + used, size - used, "%sall", sep)
                : b % 1000000u == 0u
                    ? snprintf(out_text + used, size - used, "%s%lluM", sep,
                               (unsigned long long)(b / 1000000u))
                    : snprintf(out_text + used, size - used, "%s%llu", sep, (unsigned long long)b);
        used += n > 0 ? (size_t)n : 0;
    }
}

// Names of a list of enum values, comma-separated.
static void show_names(const int *values, int count, const char *(*name)(int), char *out_text,
                       size_t size)
{
    size_t used = 0;
    out_text[0] = '\0';
    for (int i = 0; i < count && used < size; i++) {
        int n = snprintf(out_text + used, size - used, "%s%s", i ? "," : "", name(values[i]));
        used += n > 0 ? (size_t)n : 0;
    }
}

static void show_modes(const sta_cli_option *option, char *out_text, size_t size)
{
    const sta_bench_options *o = option->dest;
    show_names(o->modes, o->mode_count, sta_pipeline_mode_name, out_text, size);
}

static void show_normals(const sta_cli_option *option, char *out_text, size_t size)
{
    const sta_bench_options *o = option->dest;
    show_names(o->normals, o->normal_count, sta_normal_method_name, out_text, size);
}

static void show_samples(const sta_cli_option *option, char *out_text, size_t size)
{
    const sta_bench_options *o = option->dest;
    size_t used = 0;
    out_text[0] = '\0';
    for (int i = 0; i < o->sample_count && used < size; i++) {
        int n = snprintf(out_text + used, size - used, "%s%d", i ? "," : "", o->samples[i]);
        used += n > 0 ? (size_t)n : 0;
    }
}

static void show_hpr(const sta_cli_option *option, char *out_text, size_t size)
{
    const hpr_list *h = option->dest;
    snprintf(out_text, size, "%s%s%s", h->variants[0] ? "pyramid" : "",
             h->variants[0] && h->variants[1] ? "," : "", h->variants[1] ? "exhaustive" : "");
}

int main(int argc, char **argv)
{
    // The defaults, shown by --help from here: the sweep's own (resolving them twice is
    // harmless), a local copy of the threshold the pipeline uses for 0.
    sta_bench_options o = { .progress = true,
                            .katz_points = STA_DEFAULT_KATZ_SAMPLE_POINTS,
                            .katz_oversample = STA_KATZ_VIEW_OVERSAMPLE };
    sta_bench_options_defaults(&o);
    o.hpr_radius_px = 8;
    double hpr_threshold = (double)STA_HPR_DEFAULT_THRESHOLD;
    const char *out_dir = "bench-out";
    bool quiet = false;
    hpr_list hpr = { .variants = o.hpr_variants };
    int gaps = 1; // index into gaps_names: smooth
    static const char *const gaps_names[] = { "blocks", "smooth", NULL };
    truth_list truths = { .items = calloc((size_t)argc, sizeof(char *)) };
    if (!truths.items) {
        fputs("strata-bench: out of memory\n", stderr);
        return 1;
    }
    const sta_cli_option options[] = {
        { .heading = "views:",
          .name = "orbit",
          .kind = STA_CLI_CALLBACK,
          .dest = &o,
          .metavar = "N",
          .int_min = 1,
          .int_max = 100000,
          .flags = STA_CLI_ANY_NOTATION,
          .parse = parse_views,
          .show = show_views,
          .help = "N views around the scene, 30 degrees above the horizon" },
        { .name = "street",
          .kind = STA_CLI_CALLBACK,
          .dest = &o,
          .metavar = "N",
          .int_min = 1,
          .int_max = 100000,
          .flags = STA_CLI_ANY_NOTATION,
          .parse = parse_views,
          .help = "N street-level views (eye 1.7 m) along the scene" },
        { .name = "path",
          .kind = STA_CLI_CALLBACK,
          .dest = &o,
          .metavar = "FILE.json",
          .parse = parse_path,
          .help = "the keyframes of a strata-view camera path" },
        { .name = "size",
          .kind = STA_CLI_CALLBACK,
          .dest = &o,
          .metavar = "WxH",
          .parse = parse_size,
          .show = show_size,
          .help = "viewport" },
        { .name = "fov",
          .kind = STA_CLI_DOUBLE,
          .dest = &o.fov_deg,
          .metavar = "DEG",
          .real_min = 0.0,
          .real_max = 179.0,
          .flags = STA_CLI_ABOVE_MIN | STA_CLI_BELOW_MAX,
          .help = "vertical field of view in degrees" },
        { .heading = "sweeps (comma-separated lists; every combination that applies is run):",
          .name = "budgets",
          .kind = STA_CLI_CALLBACK,
          .dest = &o,
          .metavar = "LIST",
          .parse = parse_budgets,
          .show = show_budgets,
          .help = "points per frame, e.g. 1e6,3M,all" },
        { .name = "pipelines",
          .kind = STA_CLI_CALLBACK,
          .dest = &o,
          .metavar = "LIST",
          .parse = parse_modes,
          .show = show_modes,
          .help = "raw,hpr,fill,normals,shaded,edl,splats" },
        { .name = "normals",
          .kind = STA_CLI_CALLBACK,
          .dest = &o,
          .metavar = "LIST",
          .parse = parse_normals,
          .show = show_normals,
          .help = "pyramid,ld,pd,pc,ti" },
        { .name = "point-sizes",
          .kind = STA_CLI_CALLBACK,
          .dest = &o,
          .metavar = "LIST",
          .parse = parse_point_sizes,
          .show = show_point_sizes,
          .help = "raw and edl pipelines: point diameters in pixels and/or adaptive, e.g. "
                  "1,2,3,5,adaptive (image error against the truth: surface_* columns)" },
        { .name = "point-size-range",
          .kind = STA_CLI_CALLBACK,
          .dest = &o,
          .metavar = "MIN,MAX",
          .parse = parse_point_size_range,
          .show = show_point_size_range,
          .help = "adaptive point size: smallest and largest diameter, pixels" },
        { .name = "samples",
          .kind = STA_CLI_CALLBACK,
          .dest = &o,
          .metavar = "LIST",
          .parse = parse_sample_list,
          .show = show_samples,
          .help = "LD/PD/PC/TI samples: 5,9,17,25" },
        { .name = "hpr",
          .kind = STA_CLI_CALLBACK,
          .dest = &hpr,
          .metavar = "LIST",
          .parse = parse_hpr_list,
          .show = show_hpr,
          .help = "pyramid,exhaustive" },
        { .name = "hpr-every-pixel",
          .kind = STA_CLI_FLAG,
          .dest = &o.hpr_every_pixel,
          .help = "the pyramid variant on every pixel instead of the sparse operator (a "
                  "quarter of the pixels, refined where 2x2 blocks disagree; docs/HPR.md)" },
        { .name = "hpr-gaps",
          .kind = STA_CLI_CHOICE,
          .dest = &gaps,
          .metavar = "MODE",
          .choices = gaps_names,
          .help = "the pyramid's hole / background decision for empty pixels: by the "
                  "pyramid's blocks (gaps' borders on block lines) or per pixel (smooth: "
                  "gaps' borders follow the points; docs/HPR.md)" },
        { .name = "normals-every-pixel",
          .kind = STA_CLI_FLAG,
          .dest = &o.normals_every_pixel,
          .help = "pyramidal normals gathered on every pixel instead of on a quarter of "
                  "them (a sixteenth from 1080 px high) and upsampled within each surface "
                  "(docs/PULLPUSH.md)" },
        { .name = "fill-every-class",
          .kind = STA_CLI_FLAG,
          .dest = &o.fill_every_class,
          .help = "no volumetric classes: fill and score every class (the measure before "
                  "issue 15's fourteenth round); by default the viewer's classes 3-5, 13, 14 "
                  "are drawn as points and their true surfaces left out of the fill metrics "
                  "(fill_left_out; docs/BENCH.md)" },
        { .name = "smooth",
          .kind = STA_CLI_FLAG,
          .dest = &o.smooth,
          .help = "add the normal smoothing pass" },
        { .name = "hpr-radius",
          .kind = STA_CLI_INT,
          .dest = &o.hpr_radius_px,
          .metavar = "PX",
          .int_min = 1,
          .int_max = 64,
          .flags = STA_CLI_ANY_NOTATION,
          .help = "exhaustive HPR radius" },
        { .name = "hpr-threshold",
          .kind = STA_CLI_DOUBLE,
          .dest = &hpr_threshold,
          .metavar = "T",
          .real_min = 0.0,
          .real_max = HUGE_VAL,
          .flags = STA_CLI_ABOVE_MIN,
          .help = "HPR threshold" },
        { .name = "s0",
          .kind = STA_CLI_DOUBLE,
          .dest = &o.s0_m,
          .metavar = "M",
          .real_min = 0.0,
          .real_max = HUGE_VAL,
          .flags = STA_CLI_ABOVE_MIN,
          .help = "sampling scale in metres",
          .default_text = "the scene's estimate" },
        { .heading = "measuring:",
          .name = "repeat",
          .kind = STA_CLI_INT,
          .dest = &o.repeat,
          .metavar = "R",
          .int_min = 1,
          .int_max = 100000,
          .flags = STA_CLI_ANY_NOTATION,
          .help = "timed frames per setting, median reported" },
        { .name = "truth",
          .kind = STA_CLI_CALLBACK,
          .dest = &truths,
          .metavar = "FILE",
          .parse = parse_truth,
          .help = "strata-synth truth sidecar, once per scene",
          .default_text = "SCENE's <stem>.truth.json when it exists" },
        { .name = "tolerance",
          .kind = STA_CLI_DOUBLE,
          .dest = &o.tolerance_s0,
          .metavar = "K",
          .real_min = 0.0,
          .real_max = HUGE_VAL,
          .flags = STA_CLI_ABOVE_MIN,
          .help = "truth visibility tolerance in s0" },
        { .name = "katz",
          .kind = STA_CLI_FLAG,
          .dest = &o.katz,
          .help = "Katz et al. HPR (Qhull) on the drawn points as reference" },
        { .name = "katz-local",
          .kind = STA_CLI_FLAG,
          .dest = &o.katz_local,
          .help = "--katz with R per region: a smaller R where the drawn points are sparse "
                  "(docs/KATZ.md)" },
        { .name = "katz-drawn",
          .kind = STA_CLI_FLAG,
          .dest = &o.katz_drawn,
          .help = "--katz on the drawn points' own positions (from the point id target), "
                  "truth there too, instead of pixel centres at the depth buffer's depth" },
        { .name = "katz-live",
          .kind = STA_CLI_FLAG,
          .dest = &o.katz_live,
          .help = "the viewer's live Katz mode as a method (latency, F1, hull time)" },
        { .name = "katz-points",
          .kind = STA_CLI_COUNT,
          .dest = &o.katz_points,
          .metavar = "N",
          .count_min = 4,
          .count_max = 100000000,
          .flags = STA_CLI_SUFFIX,
          .help = "live Katz: points per hull" },
        { .name = "katz-oversample",
          .kind = STA_CLI_DOUBLE,
          .dest = &o.katz_oversample,
          .metavar = "K",
          .real_min = 1.0,
          .real_max = 1000.0,
          .help = "live Katz: candidates gathered per hull point (the nearest of each screen "
                  "cell is kept)" },
        { .name = "katz-perturbation",
          .kind = STA_CLI_DOUBLE,
          .dest = &o.katz_perturbation,
          .metavar = "A",
          .real_min = 0.0,
          .real_max = 1.0,
          .help = "Braga's perturbation in model radii for --katz and --katz-live; above 0 "
                  "also times the plain hull on the same input" },
        { .name = "no-image-error",
          .kind = STA_CLI_FLAG,
          .dest = &o.no_image_error,
          .help = "no unbudgeted reference renders (no PSNR/SSIM)" },
        { .name = "timeout",
          .kind = STA_CLI_DOUBLE,
          .dest = &o.timeout_s,
          .metavar = "S",
          .real_min = 0.0,
          .real_max = HUGE_VAL,
          .flags = STA_CLI_ABOVE_MIN,
          .help = "seconds a view may take to load" },
        { .heading = "output:",
          .name = "out",
          .kind = STA_CLI_STRING,
          .dest = &out_dir,
          .metavar = "DIR",
          .help = "folder for results.csv and results.json" },
        { .name = "quiet", .kind = STA_CLI_FLAG, .dest = &quiet, .help = "no progress line" },
        { .name = NULL },
    };
    const sta_cli cli = { .program = "strata-bench",
                          .usage = usage_text,
                          .hint = "(see strata-bench --help)",
                          .options = options };
    sta_cli_result r;
    int rc = sta_cli_parse_main(&cli, argc, argv, &r);
    if (rc < 0 && r.positional_count == 0) {
        rc = sta_cli_usage_error(&cli, "%s", "no scene given");
    }
    if (rc < 0 && truths.count > 0 && truths.count != (size_t)r.positional_count) {
        rc = sta_cli_usage_error(&cli, "%s",
                                 "give --truth once per scene, in the order of the scenes");
    }
    if (rc >= 0) {
        free(truths.items);
        return rc;
    }
    o.hpr_threshold = (float)hpr_threshold;
    o.hpr_block_gaps = gaps == 0;
    o.progress = !quiet;
    o.scenes = (const char *const *)r.positional;
    o.scene_count = (size_t)r.positional_count;
    o.truths = truths.items;
    o.truth_count = truths.count;

    sta_error err = { 0 };
    sta_gl_headless gl = { 0 };
    sta_bench_results results = { 0 };
    char renderer[256] = "";
    sta_status s = sta_gl_headless_create(&gl, &err);
    if (s == STA_OK) {
        sta_gl_describe(renderer, sizeof(renderer));
        s = sta_bench_run(&o, &results, &err);
    }
    if (s == STA_OK) {
        s = sta_bench_write_reports(out_dir, renderer, &results, &err);
    }
    if (s == STA_OK && o.progress) {
        fprintf(stderr, "strata-bench: %zu rows in %s/results.csv and results.json\n",
                results.count, out_dir);
    }
    sta_bench_results_release(&results);
    sta_gl_headless_destroy(&gl);
    free(truths.items);
    if (s != STA_OK) {
        fprintf(stderr, "strata-bench: %s\n", err.message);
        return 1;
    }
    return 0;
}
