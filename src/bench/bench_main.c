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
#include "render/gl.h"

static const char usage[] =
    "usage: strata-bench [options] SCENE.strata...\n"
    "views (default --orbit 8):\n"
    "  --orbit N              N views around the scene, 30 degrees above the horizon\n"
    "  --street N             N street-level views (eye 1.7 m) along the scene\n"
    "  --path FILE.json       the keyframes of a strata-view camera path\n"
    "  --size WxH             viewport (default 1920x1080); --fov DEG (default 60)\n"
    "sweeps (comma-separated lists; every combination that applies is run):\n"
    "  --budgets LIST         points per frame, e.g. 1e6,3M,all (default 30M)\n"
    "  --pipelines LIST       raw,hpr,fill,normals,shaded,edl (default shaded)\n"
    "  --normals LIST         pyramid,ld,pd,pc,ti (default pyramid)\n"
    "  --samples LIST         LD/PD/PC/TI samples: 5,9,17,25 (default 9)\n"
    "  --hpr LIST             pyramid,exhaustive (default pyramid)\n"
    "  --smooth               add the normal smoothing pass\n"
    "  --hpr-radius PX        exhaustive HPR radius (default 8)\n"
    "  --hpr-threshold T      HPR threshold (default 0.1)\n"
    "  --s0 M                 sampling scale in metres (default: the scene's estimate)\n"
    "measuring:\n"
    "  --repeat R             timed frames per setting, median reported (default 5)\n"
    "  --truth FILE           strata-synth truth sidecar (once per scene; default:\n"
    "                         SCENE's <stem>.truth.json when it exists)\n"
    "  --tolerance K          truth visibility tolerance in s0 (default 3)\n"
    "  --katz                 Katz et al. HPR (Qhull) on the drawn points as reference\n"
    "  --no-image-error       no unbudgeted reference renders (no PSNR/SSIM)\n"
    "  --timeout S            seconds a view may take to load (default 300)\n"
    "output:\n"
    "  --out DIR              results.csv and results.json (default bench-out)\n"
    "  --quiet                no progress line\n"
    "  --help\n";

__attribute__((format(printf, 1, 2))) static int usage_error(const char *fmt, ...)
{
    fputs("strata-bench: ", stderr);
    va_list args;
    va_start(args, fmt);
    vfprintf(stderr, fmt, args);
    va_end(args);
    fputs("\n(see strata-bench --help)\n", stderr);
    return 2;
}

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

static bool parse_positive(const char *text, double *out)
{
    char *end = NULL;
    errno = 0;
    double v = strtod(text, &end);
    if (errno || end == text || *end || !(v > 0) || !isfinite(v)) {
        return false;
    }
    *out = v;
    return true;
}

static bool parse_count(const char *text, int *out)
{
    double v;
    if (!parse_positive(text, &v) || v != floor(v) || v > 100000) {
        return false;
    }
    *out = (int)v;
    return true;
}

int main(int argc, char **argv)
{
    sta_bench_options o = { .progress = true };
    const char *out_dir = "bench-out";
    const char **scenes = calloc((size_t)argc, sizeof(char *));
    const char **truths = calloc((size_t)argc, sizeof(char *));
    if (!scenes || !truths) {
        fputs("strata-bench: out of memory\n", stderr);
        return 1;
    }
    size_t scene_count = 0, truth_count = 0;
    int rc = 0;
    for (int i = 1; i < argc && rc == 0; i++) {
        const char *a = argv[i];
        const char *v = i + 1 < argc ? argv[i + 1] : NULL;
        double number = 0.0;
        int n = 0;
        if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
            fputs(usage, stdout);
            free(scenes);
            free(truths);
            return 0;
        }
        if (a[0] != '-') {
            scenes[scene_count++] = a;
            continue;
        }
        bool takes_value = strcmp(a, "--katz") != 0 && strcmp(a, "--smooth") != 0 &&
                           strcmp(a, "--quiet") != 0 && strcmp(a, "--no-image-error") != 0;
        if (takes_value && !v) {
            rc = usage_error("%s needs a value", a);
            break;
        }
        if (takes_value) {
            i++;
        }
        if (strcmp(a, "--orbit") == 0 || strcmp(a, "--street") == 0) {
            o.cameras = a[2] == 'o' ? STA_BENCH_ORBIT : STA_BENCH_STREET;
            if (!parse_count(v, &o.camera_count)) {
                rc = usage_error("bad view count '%s'", v);
            }
        } else if (strcmp(a, "--path") == 0) {
            o.cameras = STA_BENCH_PATH;
            o.path_file = v;
        } else if (strcmp(a, "--size") == 0) {
            if (sscanf(v, "%dx%d%n", &o.width_px, &o.height_px, &n) != 2 || v[n] ||
                o.width_px < 1 || o.height_px < 1 || o.width_px > 16384 || o.height_px > 16384) {
                rc = usage_error("bad size '%s' (want WxH, e.g. 1920x1080)", v);
            }
        } else if (strcmp(a, "--fov") == 0) {
            if (!parse_positive(v, &o.fov_deg) || o.fov_deg >= 179.0) {
                rc = usage_error("bad field of view '%s' (degrees, 0..179)", v);
            }
        } else if (strcmp(a, "--budgets") == 0) {
            if (!parse_list(v, parse_budget, o.budgets, &o.budget_count)) {
                rc = usage_error("bad budget list '%s' (e.g. 1e6,3M,all)", v);
            }
        } else if (strcmp(a, "--pipelines") == 0) {
            if (!parse_list(v, parse_mode, o.modes, &o.mode_count)) {
                rc = usage_error("bad pipeline list '%s' (raw,hpr,fill,normals,shaded,edl)", v);
            }
        } else if (strcmp(a, "--normals") == 0) {
            if (!parse_list(v, parse_normal, o.normals, &o.normal_count)) {
                rc = usage_error("bad normal method list '%s' (pyramid,ld,pd,pc,ti)", v);
            }
        } else if (strcmp(a, "--samples") == 0) {
            if (!parse_list(v, parse_samples, o.samples, &o.sample_count)) {
                rc = usage_error("bad samples list '%s' (5,9,17,25)", v);
            }
        } else if (strcmp(a, "--hpr") == 0) {
            int count = 0;
            if (!parse_list(v, parse_hpr, o.hpr_variants, &count)) {
                rc = usage_error("bad HPR list '%s' (pyramid,exhaustive)", v);
            }
        } else if (strcmp(a, "--hpr-radius") == 0) {
            if (!parse_count(v, &o.hpr_radius_px) || o.hpr_radius_px > 64) {
                rc = usage_error("bad HPR radius '%s' (1..64 pixels)", v);
            }
        } else if (strcmp(a, "--hpr-threshold") == 0) {
            if (!parse_positive(v, &number)) {
                rc = usage_error("bad HPR threshold '%s'", v);
            }
            o.hpr_threshold = (float)number;
        } else if (strcmp(a, "--s0") == 0) {
            if (!parse_positive(v, &o.s0_m)) {
                rc = usage_error("bad s0 '%s' (metres, > 0)", v);
            }
        } else if (strcmp(a, "--repeat") == 0) {
            if (!parse_count(v, &o.repeat)) {
                rc = usage_error("bad repeat count '%s'", v);
            }
        } else if (strcmp(a, "--truth") == 0) {
            truths[truth_count++] = v;
        } else if (strcmp(a, "--tolerance") == 0) {
            if (!parse_positive(v, &o.tolerance_s0)) {
                rc = usage_error("bad tolerance '%s' (in s0, > 0)", v);
            }
        } else if (strcmp(a, "--timeout") == 0) {
            if (!parse_positive(v, &o.timeout_s)) {
                rc = usage_error("bad timeout '%s' (seconds)", v);
            }
        } else if (strcmp(a, "--out") == 0) {
            out_dir = v;
        } else if (strcmp(a, "--katz") == 0) {
            o.katz = true;
        } else if (strcmp(a, "--smooth") == 0) {
            o.smooth = true;
        } else if (strcmp(a, "--no-image-error") == 0) {
            o.no_image_error = true;
        } else if (strcmp(a, "--quiet") == 0) {
            o.progress = false;
        } else {
            rc = usage_error("unknown option '%s'", a);
        }
    }
    if (rc == 0 && scene_count == 0) {
        rc = usage_error("%s", "no scene given");
    }
    if (rc == 0 && truth_count > 0 && truth_count != scene_count) {
        rc = usage_error("%s", "give --truth once per scene, in the order of the scenes");
    }
    if (rc != 0) {
        free(scenes);
        free(truths);
        return rc;
    }
    o.scenes = scenes;
    o.scene_count = scene_count;
    o.truths = truths;
    o.truth_count = truth_count;

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
    free(scenes);
    free(truths);
    if (s != STA_OK) {
        fprintf(stderr, "strata-bench: %s\n", err.message);
        return 1;
    }
    return 0;
}
