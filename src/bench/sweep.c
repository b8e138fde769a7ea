/* SPDX-License-Identifier: MIT
 * The benchmark sweep. */
#include "bench/sweep.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "bench/bench_cameras.h"
#include "bench/bench_truth.h"
#include "bench/drawn_points.h"
#include "bench/gap_blocks.h"
#include "bench/katz_local.h"
#include "bench/metrics.h"
#include "bench/pixel_masks.h"
#include "bench/splat_score.h"
#include "bench/view_eval.h"
#include "core/alloc.h"
#include "core/array.h"
#include "core/clock.h"
#include "render/gl.h"
#include "render/gl_image.h"
#include "render/scene.h"
#include "visibility/katz_hpr.h"

static const double degrees = 3.14159265358979323846 / 180.0;

void sta_bench_options_defaults(sta_bench_options *o)
{
    if (!o->camera_count) {
        o->camera_count = 8;
    }
    if (!o->width_px || !o->height_px) {
        o->width_px = 1920;
        o->height_px = 1080;
    }
    if (!(o->fov_deg > 0)) {
        o->fov_deg = 60.0;
    }
    if (!o->budget_count) {
        o->budgets[0] = STA_DEFAULT_BUDGET_POINTS;
        o->budget_count = 1;
    }
    if (!o->mode_count) {
        o->modes[0] = STA_PIPELINE_SHADED;
        o->mode_count = 1;
    }
    if (!o->normal_count) {
        o->normals[0] = STA_NORMAL_PYRAMID;
        o->normal_count = 1;
    }
    if (!o->sample_count) {
        o->samples[0] = 9;
        o->sample_count = 1;
    }
    if (!o->point_size_count) {
        sta_point_size_defaults(&o->point_sizes[0]);
        o->point_size_count = 1;
    }
    if (!o->hpr_variants[0] && !o->hpr_variants[1]) {
        o->hpr_variants[0] = true;
    }
    if (!o->repeat) {
        o->repeat = 5;
    }
    if (!(o->tolerance_s0 > 0)) {
        o->tolerance_s0 = 3.0;
    }
    if (!(o->timeout_s > 0)) {
        o->timeout_s = 300.0;
    }
}

static bool mode_draws_sized(int mode)
{
    return mode == STA_PIPELINE_RAW || mode == STA_PIPELINE_EDL;
}

static bool mode_runs_hpr(int mode)
{
    return mode != STA_PIPELINE_RAW && mode != STA_PIPELINE_EDL && mode != STA_PIPELINE_SPLATS;
}

static bool mode_runs_fill(int mode)
{
    return mode_runs_hpr(mode) && mode != STA_PIPELINE_HPR;
}

static bool mode_runs_normals(int mode)
{
    return mode == STA_PIPELINE_NORMALS || mode == STA_PIPELINE_SHADED;
}

sta_status sta_bench_settings(const sta_bench_options *o, sta_bench_setting **out,
                              size_t *out_count, sta_error *err)
{
    size_t max = (size_t)o->mode_count * 2 * (size_t)o->normal_count * (size_t)o->sample_count *
                 (size_t)(o->point_size_count > 0 ? o->point_size_count : 1);
    sta_bench_setting *s = sta_alloc_array(max ? max : 1, sizeof(*s));
    if (!s) {
        return sta_fail(err, STA_ERR_NOMEM, "out of memory for %zu settings", max);
    }
    size_t n = 0;
    for (int m = 0; m < o->mode_count; m++) {
        const int mode = o->modes[m];
        for (int h = 0; h < 2; h++) {
            // raw and edl do not depend on the HPR variant: once, with the first given.
            if (!o->hpr_variants[h] || (!mode_runs_hpr(mode) && h == 1 && o->hpr_variants[0])) {
                continue;
            }
            for (int k = 0; k < (mode_runs_normals(mode) ? o->normal_count : 1); k++) {
                const int method = mode_runs_normals(mode) ? o->normals[k] : 0;
                // The pyramid and LD (right/up differences) take no sample count: once.
                const bool sampled = mode_runs_normals(mode) && method != STA_NORMAL_PYRAMID &&
                                     method != STA_NORMAL_LD;
                for (int j = 0; j < (sampled ? o->sample_count : 1); j++) {
                    // Point sizes only where the picture is the points (raw, edl).
                    int sizes = mode_draws_sized(mode) ? o->point_size_count : 0;
                    for (int z = 0; z < (sizes > 0 ? sizes : 1); z++) {
                        sta_bench_setting *t = &s[n++];
                        *t = (sta_bench_setting){ .mode = mode,
                                                  .normals = method,
                                                  .samples = sampled ? o->samples[j] : 0,
                                                  .hpr_exhaustive = mode_runs_hpr(mode) && h == 1 };
                        if (sizes > 0) {
                            t->point_size = o->point_sizes[z];
                            if (t->point_size.mode == STA_POINT_SIZE_ADAPTIVE &&
                                o->adaptive_px[0] > 0) {
                                t->point_size.min_px = o->adaptive_px[0];
                                t->point_size.max_px = o->adaptive_px[1];
                            }
                        }
                    }
                }
            }
        }
    }
    *out = s;
    *out_count = n;
    return STA_OK;
}

void sta_bench_setting_label(const sta_bench_setting *s, char *out, size_t size)
{
    char normals[24] = "";
    if (mode_runs_normals(s->mode)) {
        if (s->normals == STA_NORMAL_PYRAMID || s->normals == STA_NORMAL_LD) {
            snprintf(normals, sizeof(normals), "/%s", sta_normal_method_name(s->normals));
        } else {
            snprintf(normals, sizeof(normals), "/%s%d", sta_normal_method_name(s->normals),
                     s->samples);
        }
    }
    char points[48] = "";
    if (mode_draws_sized(s->mode) && !sta_point_size_is_one_pixel(&s->point_size)) {
        sta_point_size r;
        sta_point_size_resolve(&s->point_size, &r);
        if (r.mode == STA_POINT_SIZE_ADAPTIVE) {
            snprintf(points, sizeof(points), "/adaptive%g-%g", r.min_px, r.max_px);
        } else {
            snprintf(points, sizeof(points), "/%gpx", r.size_px);
        }
    }
    snprintf(out, size, "%s%s%s%s", sta_pipeline_mode_name(s->mode), normals,
             mode_runs_hpr(s->mode) ? (s->hpr_exhaustive ? "/hpr-exh" : "/hpr-pyr") : "", points);
}

void sta_bench_results_release(sta_bench_results *r)
{
    sta_free(r->rows);
    memset(r, 0, sizeof(*r));
}

static sta_status push_row(sta_bench_results *r, const sta_bench_row *row, sta_error *err)
{
    if (sta_array_reserve((void **)&r->rows, &r->capacity, r->count + 1, sizeof(*r->rows), 16,
                          NULL) != STA_OK) {
        return sta_fail(err, STA_ERR_NOMEM, "out of memory for %zu result rows", r->count + 1);
    }
    r->rows[r->count++] = *row;
    return STA_OK;
}

static const char *base_name(const char *path)
{
    const char *slash = strrchr(path, '/');
    return slash ? slash + 1 : path;
}

// "<dir>/<stem>.truth.json" beside "<dir>/<stem>.strata", when it exists.
static char *find_sidecar(const char *scene)
{
    size_t len = strlen(scene);
    const char *dot = strrchr(scene, '.');
    if (!dot || strchr(dot, '/')) {
        dot = scene + len;
    }
    size_t stem = (size_t)(dot - scene);
    char *path = sta_malloc(stem + 16);
    if (!path) {
        return NULL;
    }
    memcpy(path, scene, stem);
    memcpy(path + stem, ".truth.json", 12);
    if (access(path, R_OK) != 0) {
        sta_free(path);
        return NULL;
    }
    return path;
}

/* Everything open for one scene. */
typedef struct scene_run {
    const sta_bench_options *o;
    const char *path;
    sta_bench_truth truth;
    bool has_truth;
    sta_scene *reference; /* all points; NULL with no_image_error */
    sta_scene **budgeted; /* one per budget */
    uint64_t *budgets;    /* resolved */
    sta_render_target target;
    sta_bench_setting *settings;
    size_t setting_count;
    uint8_t *rgba;           /* budgeted render, one view */
    uint8_t *reference_rgba; /* one view per setting */
    bool *has_reference;     /* per setting, this camera */
    float *depth;            /* one view */
    uint32_t *ids;           /* one view: node, index per pixel (the id target) */
    uint64_t point_count;
    int camera_count;
} scene_run;

static void progress(const scene_run *run, int camera, int cameras, const char *what)
{
    if (!run->o->progress || !isatty(2)) {
        return;
    }
    fprintf(stderr, "\r\033[K%s: ", base_name(run->path));
    fprintf(stderr, "camera %d/%d: %s", camera, cameras, what);
    fflush(stderr);
}

static sta_status load_view(scene_run *run, sta_scene *scene, const sta_camera *camera,
                            double *out_load_s, sta_error *err)
{
    sta_pipeline_options raw = { .mode = STA_PIPELINE_RAW };
    sta_scene_set_pipeline(scene, &raw);
    sta_scene_set_timing(scene, false);
    double start = sta_clock_ms();
    for (;;) {
        sta_frame_stats stats;
        sta_status s = sta_scene_render(scene, camera, &run->target, &stats, err);
        if (s != STA_OK) {
            return s;
        }
        sta_gl_finish();
        if (stats.complete) {
            break;
        }
        if (sta_clock_ms() - start > run->o->timeout_s * 1e3) {
            return sta_fail(err, STA_ERR_IO, "%s: a view did not finish loading in %.0f s",
                            run->path, run->o->timeout_s);
        }
        struct timespec nap = { 0, 2000000 }; // let the loader work
        nanosleep(&nap, NULL);
    }
    *out_load_s = (sta_clock_ms() - start) * 1e-3;
    return STA_OK;
}

static void set_pipeline(const scene_run *run, sta_scene *scene, const sta_bench_setting *st)
{
    const sta_bench_options *o = run->o;
    sta_pipeline_options p = { .mode = st->mode,
                               .normals = st->normals,
                               .samples = st->samples,
                               .smooth = o->smooth && mode_runs_normals(st->mode),
                               .hpr_exhaustive = st->hpr_exhaustive,
                               .hpr_every_pixel = o->hpr_every_pixel,
                               .hpr_block_gaps = o->hpr_block_gaps,
                               .normals_every_pixel = o->normals_every_pixel,
                               .keep_normal_image = true, // read for the normal errors
                               .hpr_radius_px = o->hpr_radius_px,
                               .hpr_threshold = o->hpr_threshold,
                               .s0_m = (float)o->s0_m,
                               // The viewer's volumetric classes (drawn as points, no fill)
                               // unless every class is to be filled (docs/BENCH.md).
                               .no_fill_set = o->fill_every_class };
    sta_scene_set_pipeline(scene, &p);
    sta_scene_set_point_size(scene, &st->point_size);
}

static int compare_doubles(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : (x > y ? 1 : 0);
}

static double median_of(double *v, int n)
{
    qsort(v, (size_t)n, sizeof(double), compare_doubles);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

enum {
    T_GEOMETRY = 0,
    T_PASS0,
    T_SCREEN = T_PASS0 + STA_PASS_COUNT,
    T_GPU,
    T_FRAME,
    T_CPU,
    T_COUNT
};

// Renders `repeat` timed frames and fills the timing and counter fields of `row`.
static sta_status timed_frames(scene_run *run, sta_scene *scene, const sta_camera *camera,
                               sta_bench_row *row, sta_error *err)
{
    const int repeat = run->o->repeat;
    double *samples = sta_alloc_array((size_t)repeat * T_COUNT, sizeof(double));
    double *column = sta_alloc_array((size_t)repeat, sizeof(double));
    sta_status s = STA_OK;
    if (!samples || !column) {
        s = sta_fail(err, STA_ERR_NOMEM, "out of memory for %d timed frames", repeat);
        goto out_free;
    }
    sta_scene_set_timing(scene, true);
    sta_frame_stats stats = { 0 };
    for (int r = 0; r < repeat && s == STA_OK; r++) {
        sta_gl_finish();
        double wall0 = sta_clock_ms(), cpu0 = sta_clock_thread_cpu_ms();
        s = sta_scene_render(scene, camera, &run->target, &stats, err);
        sta_gl_finish();
        double *t = samples + (size_t)r * T_COUNT;
        t[T_FRAME] = sta_clock_ms() - wall0;
        t[T_CPU] = sta_clock_thread_cpu_ms() - cpu0;
        t[T_GEOMETRY] = stats.geometry_ms;
        for (int p = 0; p < STA_PASS_COUNT; p++) {
            t[T_PASS0 + p] = stats.timing.ms[p];
        }
        t[T_SCREEN] = stats.timing.total_ms;
        t[T_GPU] = stats.geometry_ms + stats.timing.total_ms;
    }
    sta_scene_set_timing(scene, false);
    if (s != STA_OK) {
        goto out_free;
    }
    double medians[T_COUNT];
    for (int k = 0; k < T_COUNT; k++) {
        for (int r = 0; r < repeat; r++) {
            column[r] = samples[(size_t)r * T_COUNT + (size_t)k];
        }
        medians[k] = median_of(column, repeat);
    }
    row->geometry_ms = medians[T_GEOMETRY];
    for (int p = 0; p < STA_PASS_COUNT; p++) {
        row->pass_ms[p] = medians[T_PASS0 + p];
    }
    row->screen_ms = medians[T_SCREEN];
    row->gpu_ms = medians[T_GPU];
    row->frame_ms = medians[T_FRAME];
    row->cpu_ms = medians[T_CPU];
    row->s0_m = (double)stats.s0_m;
    row->points_drawn = stats.points_drawn;
    row->points_selected = stats.points_selected;
    row->nodes_resident = stats.nodes_resident;
    row->nodes_drawn = stats.nodes_drawn;
    row->loader_backlog = stats.loader_backlog;
out_free:
    sta_free(samples);
    sta_free(column);
    return s;
}

// Reads one pipeline texture and scores it.
static sta_status score_buffers(scene_run *run, sta_scene *scene, const sta_bench_setting *st,
                                const sta_camera *camera, const sta_view_truth *view_truth,
                                const sta_view_points *points, const sta_pixel_masks *masks,
                                double tolerance_m, sta_bench_row *row, sta_error *err)
{
    // The fill metrics' pixels: with volumetric classes, not their true surfaces.
    const bool leave_out = masks->counted && mode_runs_fill(st->mode);
    const uint8_t *counted = leave_out ? masks->counted : NULL;
    const uint8_t *sampled = leave_out ? masks->sampled_counted : masks->sampled;
    row->fill_left_out = leave_out ? masks->left_out : 0;
    if (st->mode == STA_PIPELINE_SPLATS && run->has_truth) {
        sta_error_summary depth, normal;
        sta_status s =
            sta_bench_score_splats(scene, &run->target, camera, view_truth, &depth, &normal, err);
        if (s == STA_OK) {
            row->depth_count = depth.count;
            row->depth_rel_mean = depth.mean;
            row->depth_rel_median = depth.median;
            row->depth_rel_p95 = depth.p95;
            row->normal_count = normal.count;
            row->normal_mean_deg = normal.mean;
            row->normal_median_deg = normal.median;
            row->normal_p95_deg = normal.p95;
        }
        return s;
    }
    const sta_pipeline *p = sta_scene_pipeline(scene);
    if (!p || !run->has_truth) {
        return STA_OK;
    }
    sta_image image = { 0 };
    sta_status s = STA_OK;
    if (mode_runs_hpr(st->mode)) {
        s = sta_gl_texture_to_image(p->label, 0, 1, &image, err);
        if (s == STA_OK) {
            sta_confusion c;
            sta_eval_hpr(points, &image, &c);
            row->hpr_tp = c.tp;
            row->hpr_fp = c.fp;
            row->hpr_fn = c.fn;
            row->hpr_tn = c.tn;
            row->hpr_precision = sta_confusion_precision(&c);
            row->hpr_recall = sta_confusion_recall(&c);
            row->hpr_f1 = sta_confusion_f1(&c);
            sta_eval_hpr_masked(points, &image, masks->hpr_face, &c);
            row->hpr_face_points = c.tp + c.fp + c.fn + c.tn;
            row->hpr_face_f1 = sta_confusion_f1(&c);
            sta_eval_hpr_masked(points, &image, masks->hpr_face_glass, &c);
            row->hpr_face_glass_points = c.tp + c.fp + c.fn + c.tn;
            row->hpr_face_glass_f1 = sta_confusion_f1(&c);
            sta_eval_hpr_masked(points, &image, masks->hpr_volumetric, &c);
            row->hpr_volumetric_points = c.tp + c.fp + c.fn + c.tn;
            row->hpr_volumetric_f1 = sta_confusion_f1(&c);
            row->gap_blocks_8 = sta_eval_gap_block_ratio(&image, 8);
            row->gap_blocks_16 = sta_eval_gap_block_ratio(&image, 16);
            row->gap_blocks_32 = sta_eval_gap_block_ratio(&image, 32);
        }
        sta_image_release(&image);
    }
    if (s == STA_OK && mode_runs_fill(st->mode)) {
        s = sta_gl_texture_to_image(p->filled_position, 0, 4, &image, err);
        sta_error_summary e;
        if (s == STA_OK) {
            s = sta_eval_depth(view_truth, &image, counted, &e, err);
        }
        if (s == STA_OK) {
            row->depth_count = e.count;
            row->depth_rel_mean = e.mean;
            row->depth_rel_median = e.median;
            row->depth_rel_p95 = e.p95;
            s = sta_eval_border(view_truth, &image, sampled, &row->border_count, &row->border_empty,
                                err);
        }
        if (s == STA_OK) {
            s = sta_eval_depth(view_truth, &image, sampled, &e, err);
        }
        if (s == STA_OK) {
            row->depth_sampled_count = e.count;
            row->depth_sampled_rel_mean = e.mean;
            row->depth_sampled_rel_median = e.median;
            row->depth_sampled_rel_p95 = e.p95;
            s = sta_eval_depth_glass(view_truth, &image, sampled, &e, err);
        }
        if (s == STA_OK) {
            row->depth_glass_count = e.count;
            row->depth_glass_rel_mean = e.mean;
            row->depth_glass_rel_median = e.median;
            row->depth_glass_rel_p95 = e.p95;
        }
        sta_image_release(&image);
    }
    if (s == STA_OK && mode_runs_normals(st->mode)) {
        s = sta_gl_texture_to_image(p->normal, 0, 4, &image, err);
        sta_error_summary e;
        if (s == STA_OK) {
            s = sta_eval_normals(view_truth, &image, counted, &e, err);
        }
        if (s == STA_OK) {
            row->normal_count = e.count;
            row->normal_mean_deg = e.mean;
            row->normal_median_deg = e.median;
            row->normal_p95_deg = e.p95;
            s = sta_eval_normals(view_truth, &image, sampled, &e, err);
        }
        if (s == STA_OK) {
            row->normal_sampled_count = e.count;
            row->normal_sampled_mean_deg = e.mean;
            row->normal_sampled_median_deg = e.median;
            row->normal_sampled_p95_deg = e.p95;
            s = sta_eval_normals(view_truth, &image, masks->face_counted, &e, err);
        }
        if (s == STA_OK) {
            row->normal_face_count = e.count;
            row->normal_face_mean_deg = e.mean;
            row->normal_face_median_deg = e.median;
            row->normal_face_p95_deg = e.p95;
            sta_normal_off_share off;
            sta_image filled = { 0 };
            s = sta_eval_normals_off(view_truth, &image, counted, &off, err);
            if (s == STA_OK) {
                row->normal_off_share = off.all;
                row->normal_off_facing_share = off.facing;
                row->normal_off_other_share = off.other;
                s = sta_eval_normals_off(view_truth, &image, masks->face_counted, &off, err);
                row->normal_face_off_share = off.all;
            }
            if (s == STA_OK) {
                s = sta_gl_texture_to_image(p->filled_position, 0, 4, &filled, err);
            }
            if (s == STA_OK) {
                s = sta_eval_normals_off_fill(view_truth, &image, &filled, tolerance_m, counted,
                                              &row->normal_off_fill_share, err);
            }
            if (s == STA_OK) {
                sta_error_summary shaded;
                s = sta_eval_normals_shaded(view_truth, &image, &filled, counted,
                                            &row->normal_unknown_share, &shaded,
                                            &row->normal_shaded_off_share, err);
                row->normal_shaded_median_deg = shaded.median;
                row->normal_shaded_p95_deg = shaded.p95;
            }
            sta_image_release(&filled);
        }
        sta_image_release(&image);
    }
    return s;
}

static void clear_errors(sta_bench_row *row)
{
    row->hpr_precision = row->hpr_recall = row->hpr_f1 = (double)NAN;
    row->normal_mean_deg = row->normal_median_deg = row->normal_p95_deg = (double)NAN;
    row->normal_sampled_mean_deg = row->normal_sampled_median_deg = row->normal_sampled_p95_deg =
        (double)NAN;
    row->normal_face_mean_deg = row->normal_face_median_deg = row->normal_face_p95_deg =
        (double)NAN;
    row->normal_off_share = row->normal_off_facing_share = row->normal_off_other_share =
        row->normal_face_off_share = row->normal_off_fill_share = row->normal_unknown_share =
            row->normal_shaded_median_deg = row->normal_shaded_p95_deg =
                row->normal_shaded_off_share = (double)NAN;
    row->hpr_face_f1 = row->hpr_face_glass_f1 = row->hpr_volumetric_f1 = (double)NAN;
    row->depth_rel_mean = row->depth_rel_median = row->depth_rel_p95 = (double)NAN;
    row->depth_sampled_rel_mean = row->depth_sampled_rel_median = row->depth_sampled_rel_p95 =
        (double)NAN;
    row->depth_glass_rel_mean = row->depth_glass_rel_median = row->depth_glass_rel_p95 =
        (double)NAN;
    row->border_empty = (double)NAN;
    row->gap_blocks_8 = row->gap_blocks_16 = row->gap_blocks_32 = (double)NAN;
    row->psnr_db = row->ssim = (double)NAN;
    row->surface_hole = row->surface_see_through = row->surface_bleed = row->surface_error =
        (double)NAN;
    row->katz_ms = row->katz_radius_m = row->katz_hull_ms = row->katz_plain_hull_ms =
        row->katz_plain_f1 = row->katz_live_latency_ms = row->katz_live_hull_cpu_ms =
            row->katz_live_plain_hull_ms = row->katz_precision = row->katz_recall = row->katz_f1 =
                (double)NAN;
}

// Katz's operator on the view's points (relative to the eye, for precision).
// Confusion of Katz flags against the truth flags.
static void katz_score(const uint8_t *visible, const uint8_t *truth, size_t count, double *out_p,
                       double *out_r, double *out_f1)
{
    sta_confusion c = { 0 };
    for (size_t i = 0; i < count; i++) {
        sta_confusion_add(&c, visible[i], truth[i]);
    }
    *out_p = sta_confusion_precision(&c);
    *out_r = sta_confusion_recall(&c);
    *out_f1 = sta_confusion_f1(&c);
}

// Katz's flags of the view's points: one R, or with --katz-local R per region.
static sta_status katz_flags(const scene_run *run, const sta_camera *camera,
                             const sta_view_points *points, const double (*relative)[3],
                             const sta_katz_params *params, uint8_t *visible, sta_katz_stats *stats,
                             sta_error *err)
{
    const double origin[3] = { 0.0, 0.0, 0.0 };
    if (!run->o->katz_local) {
        return sta_katz_visible(relative, points->count, origin, params, visible, stats, err);
    }
    size_t sparse;
    return sta_katz_local_visible(relative, points->pixel, points->count, camera->width_px,
                                  camera->height_px, params, visible, &sparse, stats, err);
}

// Katz's operator on the view's points (relative to the eye, for precision). R follows
// the view's pixel pitch and the same depth tolerance as the truth (sta_katz_view_radius,
// docs/KATZ.md "Choosing R"). With a perturbation, the perturbed and the plain hull run
// on the same input, interleaved, `repeat` times each; medians reported.
static sta_status run_katz(const scene_run *run, const sta_camera *camera,
                           const sta_view_points *points, double tolerance_m, sta_bench_row *katz,
                           sta_error *err)
{
    const sta_bench_options *o = run->o;
    katz->katz_points = points->count;
    if (points->count == 0) {
        return STA_OK;
    }
    const bool compare = o->katz_perturbation > 0.0;
    const int repeat = compare ? o->repeat : 1;
    double(*relative)[3] = sta_alloc_array(points->count, sizeof(*relative));
    uint8_t *visible = sta_alloc_array(points->count, 1);
    uint8_t *plain = sta_alloc_array(points->count, 1);
    double *times = sta_alloc_array((size_t)repeat * 2, sizeof(double));
    sta_status s = STA_OK;
    if (!relative || !visible || !plain || !times) {
        s = sta_fail(err, STA_ERR_NOMEM, "out of memory for Katz on %zu points", points->count);
        goto out_free;
    }
    for (size_t i = 0; i < points->count; i++) {
        for (int a = 0; a < 3; a++) {
            relative[i][a] = points->world[i][a] - camera->position[a];
        }
    }
    const double radius_m = sta_katz_view_radius(tolerance_m, camera->fov_y / camera->height_px);
    const sta_katz_params params = { .radius_m = radius_m, .perturbation = o->katz_perturbation };
    const sta_katz_params exact = { .radius_m = radius_m };
    sta_katz_stats stats = { 0 }, plain_stats;
    for (int r = 0; r < repeat && s == STA_OK; r++) {
        s = katz_flags(run, camera, points, (const double(*)[3])relative, &params, visible, &stats,
                       err);
        times[r] = stats.hull_ms;
        if (s == STA_OK && compare) {
            s = katz_flags(run, camera, points, (const double(*)[3])relative, &exact, plain,
                           &plain_stats, err);
            times[repeat + r] = plain_stats.hull_ms;
        }
    }
    if (s != STA_OK) {
        goto out_free;
    }
    katz->katz_ms = stats.total_ms;
    katz->katz_radius_m = stats.radius;
    katz->katz_visible = stats.visible_count;
    katz->katz_hull_ms = median_of(times, repeat);
    if (compare) {
        katz->katz_plain_hull_ms = median_of(times + repeat, repeat);
    }
    if (run->has_truth) {
        katz_score(visible, points->visible, points->count, &katz->katz_precision,
                   &katz->katz_recall, &katz->katz_f1);
        if (compare) {
            double p, r;
            katz_score(plain, points->visible, points->count, &p, &r, &katz->katz_plain_f1);
        }
    }
out_free:
    sta_free(relative);
    sta_free(visible);
    sta_free(plain);
    sta_free(times);
    return s;
}

// --katz-drawn: the Katz reference on the points the view drew (one per pixel, at their own
// positions, from the id target read with `points`' depth), their truth at those positions
// (docs/KATZ.md, "Which points are fed": pixel centres score better).
static sta_status katz_on_drawn_points(scene_run *run, sta_scene *scene, const sta_camera *camera,
                                       const sta_view_points *points, double tolerance_m,
                                       sta_bench_row *katz, sta_error *err)
{
    const size_t n = points->count ? points->count : 1;
    sta_view_points drawn = { .count = points->count,
                              .pixel = points->pixel,
                              .world = sta_alloc_array(n, sizeof(*drawn.world)),
                              .visible = sta_calloc(n, 1) };
    sta_status s = STA_OK;
    if (!drawn.world || !drawn.visible) {
        s = sta_fail(err, STA_ERR_NOMEM, "out of memory for %zu drawn points", points->count);
    }
    if (s == STA_OK) {
        memcpy(drawn.world, points->world, points->count * sizeof(*drawn.world));
        s = sta_drawn_points_apply(sta_streamer_reader(sta_scene_streamer(scene)), run->path,
                                   camera, run->ids, &drawn, err);
    }
    if (s == STA_OK && run->has_truth) {
        sta_view_points_classify(&run->truth, camera, tolerance_m, &drawn);
    }
    if (s == STA_OK) {
        s = run_katz(run, camera, &drawn, tolerance_m, katz, err);
    }
    sta_free(drawn.world);
    sta_free(drawn.visible);
    return s;
}

// The live Katz mode (render/pass_katz.h) as a method, one row: the camera is set, frames
// are drawn until the set of this view is shown (latency), then timed frames; the set's
// points are scored against the truth (P / R / F1 in the hpr_* columns, its hull time in
// hpr_ms).
static sta_status run_katz_live(scene_run *run, sta_scene *scene, const sta_camera *camera,
                                double tolerance_m, const sta_bench_row *base,
                                sta_bench_results *results, sta_error *err)
{
    const sta_bench_options *o = run->o;
    sta_bench_row row = *base;
    snprintf(row.setting, sizeof(row.setting), "raw/katz-live");
    snprintf(row.pipeline, sizeof(row.pipeline), "%s", sta_pipeline_mode_name(STA_PIPELINE_RAW));
    snprintf(row.hpr, sizeof(row.hpr), "katz-live");
    set_pipeline(run, scene, &(sta_bench_setting){ .mode = STA_PIPELINE_RAW });
    sta_katz_view_options k = { .enabled = true,
                                .sample_points = o->katz_points,
                                .oversample = o->katz_oversample,
                                .perturbation = o->katz_perturbation,
                                .compare_plain = o->katz_perturbation > 0.0 };
    sta_scene_set_katz(scene, &k);
    sta_frame_stats stats = { 0 };
    sta_status s = STA_OK;
    double start = sta_clock_ms();
    int frames = 0;
    while (s == STA_OK && !stats.katz.current) {
        s = sta_scene_render(scene, camera, &run->target, &stats, err);
        sta_gl_finish();
        frames++;
        if (s == STA_OK && !stats.katz.current) {
            if ((sta_clock_ms() - start) * 1e-3 > o->timeout_s) {
                s = sta_fail(err, STA_ERR_IO, "%s: the live Katz set did not arrive in %.0f s",
                             run->path, o->timeout_s);
            }
            struct timespec nap = { 0, 1000000 };
            nanosleep(&nap, NULL);
        }
    }
    row.katz_live_latency_ms = sta_clock_ms() - start;
    row.katz_live_frames = frames;
    if (s == STA_OK) {
        s = timed_frames(run, scene, camera, &row, err);
    }
    const sta_pass_katz *pass = sta_scene_katz(scene);
    const sta_katz_set *set = sta_pass_katz_set(pass);
    if (s == STA_OK && set) {
        row.pass_ms[STA_PASS_HPR] = set->stats.hull_ms;
        row.katz_live_hull_cpu_ms = set->stats.hull_cpu_ms;
        row.katz_live_plain_hull_ms = k.compare_plain ? set->plain_hull_ms : (double)NAN;
        row.katz_points = set->count;
        row.katz_visible = set->visible_count;
        row.katz_radius_m = set->stats.radius;
        if (run->has_truth) {
            sta_confusion c = { 0 };
            for (size_t i = 0; i < set->count; i++) {
                double p[3];
                for (int a = 0; a < 3; a++) {
                    p[a] = (double)set->points[i][a] + pass->origin[a];
                }
                sta_confusion_add(
                    &c, set->visible[i],
                    sta_bench_truth_point_visible(&run->truth, camera->position, p, tolerance_m));
            }
            row.hpr_tp = c.tp;
            row.hpr_fp = c.fp;
            row.hpr_fn = c.fn;
            row.hpr_tn = c.tn;
            row.hpr_precision = sta_confusion_precision(&c);
            row.hpr_recall = sta_confusion_recall(&c);
            row.hpr_f1 = sta_confusion_f1(&c);
        }
    }
    k.enabled = false;
    sta_scene_set_katz(scene, &k);
    if (s == STA_OK) {
        s = push_row(results, &row, err);
    }
    return s;
}

static void fill_view_fields(const scene_run *run, const sta_camera *camera, int index,
                             sta_bench_row *row)
{
    static const char *const kinds[] = { "orbit", "street", "path" };
    snprintf(row->scene, sizeof(row->scene), "%s", base_name(run->path));
    row->scene_points = run->point_count;
    row->camera = index;
    snprintf(row->camera_kind, sizeof(row->camera_kind), "%s", kinds[run->o->cameras]);
    memcpy(row->eye, camera->position, sizeof(row->eye));
    row->yaw_deg = camera->yaw / degrees;
    row->pitch_deg = camera->pitch / degrees;
    row->width_px = camera->width_px;
    row->height_px = camera->height_px;
    row->repeat = run->o->repeat;
}

// The reference image of setting `k` for this camera (rendered on first use).
static sta_status reference_image(scene_run *run, const sta_camera *camera, size_t k,
                                  const uint8_t **out, sta_error *err)
{
    const size_t view = (size_t)camera->width_px * (size_t)camera->height_px * 4;
    *out = run->reference_rgba + k * view;
    if (run->has_reference[k]) {
        return STA_OK;
    }
    set_pipeline(run, run->reference, &run->settings[k]);
    sta_frame_stats stats;
    sta_status s = sta_scene_render(run->reference, camera, &run->target, &stats, err);
    if (s != STA_OK) {
        return s;
    }
    sta_render_target_read_rgba(&run->target, run->reference_rgba + k * view);
    run->has_reference[k] = true;
    return STA_OK;
}

static sta_status run_budget(scene_run *run, const sta_camera *camera, int cam_index, size_t b,
                             const sta_view_truth *view_truth, sta_bench_results *results,
                             sta_error *err)
{
    const sta_bench_options *o = run->o;
    sta_scene *scene = run->budgeted[b];
    sta_bench_row base = { 0 };
    clear_errors(&base);
    fill_view_fields(run, camera, cam_index, &base);
    base.budget = run->budgets[b];
    sta_status s = load_view(run, scene, camera, &base.load_s, err);
    sta_view_points points = { 0 };
    if (s == STA_OK && (run->has_truth || o->katz)) {
        sta_render_target_read_depth(&run->target, run->depth);
        if (o->katz_drawn) {
            sta_render_target_read_ids(&run->target, run->ids);
        }
        s = sta_view_points_from_depth(camera, run->depth, &points, err);
    }
    double tolerance_m = 0.0;
    if (s == STA_OK && (run->has_truth || o->katz || o->katz_live)) {
        // The tolerance needs s0: one raw frame gives the scene's estimate.
        sta_frame_stats stats;
        s = sta_scene_render(scene, camera, &run->target, &stats, err);
        double s0 = o->s0_m > 0 ? o->s0_m : (double)stats.s0_m;
        tolerance_m = o->tolerance_s0 * s0 + (run->has_truth ? 3.0 * run->truth.noise_m : 0.0);
    }
    sta_pixel_masks masks = { 0 };
    if (s == STA_OK && run->has_truth) {
        sta_view_points_classify(&run->truth, camera, tolerance_m, &points);
        base.truth_points = points.count;
        for (size_t i = 0; i < points.count; i++) {
            base.truly_hidden += !points.visible[i];
        }
        // With the viewer's volumetric classes, the fill metrics leave their true surfaces
        // out (they are drawn as points, not filled).
        uint32_t set[STA_VOLUMETRIC_CLASS_WORDS];
        sta_pipeline_options viewer = { .mode = STA_PIPELINE_SHADED };
        bool classes = !o->fill_every_class && sta_pipeline_volumetric_set(&viewer, set);
        s = sta_pixel_masks_compute(view_truth, camera, &points, tolerance_m, classes ? set : NULL,
                                    STA_VOLUMETRIC_CLASS_WORDS, &masks, err);
    }
    if (s == STA_OK && o->katz) {
        progress(run, cam_index + 1, run->camera_count, "Katz HPR");
        s = o->katz_drawn
                ? katz_on_drawn_points(run, scene, camera, &points, tolerance_m, &base, err)
                : run_katz(run, camera, &points, tolerance_m, &base, err);
    }
    const size_t view = (size_t)camera->width_px * (size_t)camera->height_px;
    for (size_t k = 0; k < run->setting_count && s == STA_OK; k++) {
        const sta_bench_setting *st = &run->settings[k];
        if (st->mode == STA_PIPELINE_SPLATS && !sta_scene_has_splats(scene)) {
            continue; // no normals: said once by the scene; not a row of the method
        }
        sta_bench_row row = base;
        sta_bench_setting_label(st, row.setting, sizeof(row.setting));
        snprintf(row.pipeline, sizeof(row.pipeline), "%s", sta_pipeline_mode_name(st->mode));
        if (mode_runs_normals(st->mode)) {
            snprintf(row.normals, sizeof(row.normals), "%s", sta_normal_method_name(st->normals));
            row.samples = st->samples;
        }
        if (mode_runs_hpr(st->mode)) {
            snprintf(row.hpr, sizeof(row.hpr), "%s", st->hpr_exhaustive ? "exhaustive" : "pyramid");
        }
        if (mode_draws_sized(st->mode)) {
            sta_point_size_describe(&st->point_size, row.point_size, sizeof(row.point_size));
        }
        progress(run, cam_index + 1, run->camera_count, row.setting);
        set_pipeline(run, scene, st);
        s = timed_frames(run, scene, camera, &row, err);
        if (s == STA_OK) {
            sta_render_target_read_rgba(&run->target, run->rgba);
            s = score_buffers(run, scene, st, camera, view_truth, &points, &masks, tolerance_m,
                              &row, err);
        }
        if (s == STA_OK && run->has_truth && mode_draws_sized(st->mode)) {
            sta_render_target_read_depth(&run->target, run->depth);
            sta_surface_error e;
            sta_eval_surface(view_truth, camera, run->depth, tolerance_m, &e);
            row.surface_pixels = e.pixels;
            row.surface_hole = e.hole;
            row.surface_see_through = e.see_through;
            row.surface_bleed = e.bleed;
            row.surface_error = e.error;
        }
        if (s == STA_OK && run->reference) {
            const uint8_t *reference = NULL;
            s = reference_image(run, camera, k, &reference, err);
            if (s == STA_OK) {
                row.psnr_db = sta_psnr_rgba8(run->rgba, reference, view);
                s = sta_ssim_rgba8(run->rgba, reference, camera->width_px, camera->height_px,
                                   &row.ssim, err);
            }
        }
        if (s == STA_OK) {
            s = push_row(results, &row, err);
        }
    }
    if (s == STA_OK && o->katz_live) {
        progress(run, cam_index + 1, run->camera_count, "live Katz");
        s = run_katz_live(run, scene, camera, tolerance_m, &base, results, err);
    }
    sta_view_points_release(&points);
    sta_pixel_masks_release(&masks);
    return s;
}

static sta_status make_cameras(scene_run *run, sta_camera **out, size_t *out_count, sta_error *err)
{
    const sta_bench_options *o = run->o;
    sta_scene *any = run->budgeted[0];
    const sta_strata_info *info = sta_scene_info(any);
    double min[3], max[3], extent = 0.0;
    sta_scene_robust_bounds(any, min, max);
    for (int a = 0; a < 3; a++) {
        extent = fmax(extent, info->bounds_max[a] - info->bounds_min[a]);
    }
    sta_camera base = { .fov_y = o->fov_deg * degrees,
                        .near_m = extent * 1e-5 > 1e-3 ? extent * 1e-5 : 1e-3,
                        .width_px = o->width_px,
                        .height_px = o->height_px };
    if (o->cameras == STA_BENCH_PATH) {
        return sta_bench_path_cameras(o->path_file, &base, out, out_count, err);
    }
    sta_camera *c = sta_alloc_array((size_t)o->camera_count, sizeof(*c));
    if (!c) {
        return sta_fail(err, STA_ERR_NOMEM, "out of memory for %d cameras", o->camera_count);
    }
    if (o->cameras == STA_BENCH_STREET) {
        sta_bench_street(&base, min, max, o->camera_count, run->has_truth ? &run->truth : NULL, c);
    } else {
        sta_bench_orbit(&base, min, max, o->camera_count, c);
    }
    *out = c;
    *out_count = (size_t)o->camera_count;
    return STA_OK;
}

static void close_run(scene_run *run)
{
    if (run->budgeted) {
        for (int b = 0; b < run->o->budget_count; b++) {
            sta_scene_close(run->budgeted[b]);
        }
    }
    sta_scene_close(run->reference);
    sta_free(run->budgeted);
    sta_free(run->budgets);
    sta_render_target_release(&run->target);
    sta_free(run->settings);
    sta_free(run->rgba);
    sta_free(run->reference_rgba);
    sta_free(run->has_reference);
    sta_free(run->depth);
    sta_free(run->ids);
    if (run->has_truth) {
        sta_bench_truth_release(&run->truth);
    }
}

static sta_status open_scenes(scene_run *run, sta_error *err)
{
    const sta_bench_options *o = run->o;
    // The file's point count decides what "all points" means.
    sta_scene *probe = NULL;
    sta_status s = sta_scene_open(run->path, NULL, &probe, err);
    if (s != STA_OK) {
        return s;
    }
    run->point_count = sta_scene_info(probe)->point_count;
    sta_scene_close(probe);
    run->budgeted = sta_calloc((size_t)o->budget_count, sizeof(*run->budgeted));
    run->budgets = sta_alloc_array((size_t)o->budget_count, sizeof(*run->budgets));
    if (!run->budgeted || !run->budgets) {
        return sta_fail(err, STA_ERR_NOMEM, "out of memory");
    }
    for (int b = 0; b < o->budget_count && s == STA_OK; b++) {
        uint64_t budget = o->budgets[b] ? o->budgets[b] : run->point_count;
        run->budgets[b] = budget;
        uint64_t need = (budget < run->point_count ? budget : run->point_count) * 16;
        sta_scene_options so = { .budget_points = budget,
                                 .gpu_bytes_cap = need + need / 4 > ((uint64_t)1 << 30)
                                                      ? need + need / 4
                                                      : ((uint64_t)1 << 30) };
        s = sta_scene_open(run->path, &so, &run->budgeted[b], err);
    }
    if (s == STA_OK && !o->no_image_error) {
        uint64_t need = run->point_count * 16;
        sta_scene_options so = { .budget_points = run->point_count,
                                 .gpu_bytes_cap = need + need / 4 > ((uint64_t)1 << 30)
                                                      ? need + need / 4
                                                      : ((uint64_t)1 << 30) };
        s = sta_scene_open(run->path, &so, &run->reference, err);
    }
    return s;
}

static sta_status run_scene(const sta_bench_options *o, size_t index, sta_bench_results *results,
                            sta_error *err)
{
    scene_run run = { .o = o, .path = o->scenes[index] };
    sta_camera *cameras = NULL;
    size_t camera_count = 0;
    const char *truth_path = index < o->truth_count ? o->truths[index] : NULL;
    char *found = NULL;
    if (o->truth_count == 0) {
        found = find_sidecar(run.path);
        truth_path = found;
    }
    sta_status s = STA_OK;
    if (truth_path) {
        s = sta_bench_truth_load(truth_path, &run.truth, err);
        run.has_truth = s == STA_OK;
    }
    sta_free(found);
    if (s == STA_OK) {
        s = sta_bench_settings(o, &run.settings, &run.setting_count, err);
    }
    if (s == STA_OK) {
        s = open_scenes(&run, err);
    }
    if (s == STA_OK) {
        s = make_cameras(&run, &cameras, &camera_count, err);
        run.camera_count = (int)camera_count;
    }
    const size_t view = (size_t)o->width_px * (size_t)o->height_px;
    if (s == STA_OK) {
        run.rgba = sta_alloc_array(view, 4);
        run.depth = sta_alloc_array(view, sizeof(float));
        run.ids = sta_alloc_array(view, 2 * sizeof(uint32_t));
        run.has_reference = sta_calloc(run.setting_count ? run.setting_count : 1, sizeof(bool));
        run.reference_rgba = sta_alloc_array(run.setting_count ? run.setting_count : 1, view * 4);
        if (!run.rgba || !run.depth || !run.ids || !run.has_reference || !run.reference_rgba) {
            s = sta_fail(err, STA_ERR_NOMEM, "%s: out of memory for %zu settings at %dx%d",
                         run.path, run.setting_count, o->width_px, o->height_px);
        }
    }
    for (size_t c = 0; c < camera_count && s == STA_OK; c++) {
        sta_view_truth view_truth = { 0 };
        memset(run.has_reference, 0, run.setting_count * sizeof(bool));
        if (run.has_truth) {
            progress(&run, (int)c + 1, (int)camera_count, "truth");
            s = sta_view_truth_compute(&run.truth, &cameras[c], &view_truth, err);
        }
        if (s == STA_OK && run.reference) {
            double load_s;
            s = load_view(&run, run.reference, &cameras[c], &load_s, err);
        }
        for (int b = 0; b < o->budget_count && s == STA_OK; b++) {
            s = run_budget(&run, &cameras[c], (int)c, (size_t)b, &view_truth, results, err);
        }
        sta_view_truth_release(&view_truth);
    }
    if (o->progress && isatty(2)) {
        fprintf(stderr, "\r\033[K");
    }
    sta_free(cameras);
    close_run(&run);
    return s;
}

sta_status sta_bench_run(const sta_bench_options *options, sta_bench_results *results,
                         sta_error *err)
{
    sta_bench_options o = *options;
    sta_bench_options_defaults(&o);
    if (o.truth_count > 1 && o.truth_count != o.scene_count) {
        return sta_fail(err, STA_ERR_ARG, "%zu truth files for %zu scenes (give one per scene)",
                        o.truth_count, o.scene_count);
    }
    if (o.cameras == STA_BENCH_PATH && !o.path_file) {
        return sta_fail(err, STA_ERR_ARG, "camera path views need a path file");
    }
    if (o.truth_count == 1 && o.scene_count > 1) {
        return sta_fail(err, STA_ERR_ARG, "one truth file for %zu scenes (give one per scene)",
                        o.scene_count);
    }
    for (size_t i = 0; i < o.scene_count; i++) {
        sta_status s = run_scene(&o, i, results, err);
        if (s != STA_OK) {
            return s;
        }
    }
    return STA_OK;
}
