/* SPDX-License-Identifier: MIT
 * Headless rendering. */
#include "app/view_headless.h"

#include <inttypes.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "app/view_setup.h"
#include "app/view_survey.h"
#include "core/alloc.h"
#include "core/clock.h"
#include "core/log.h"
#include "render/camera_path.h"
#include "render/gl.h"
#include "render/gl_image.h"
#include "render/hud_text.h"
#include "render/image_io.h"
#include "render/measure_file.h"
#include "render/scene.h"
#include "render/splat_normals.h"

static void print_stats(int frame, const sta_frame_stats *s, double ms)
{
    printf("frame %d: %.2f ms, %" PRIu64 " points drawn (%" PRIu64 " selected), %u/%u nodes "
           "drawn/selected, %u resident, %.1f MiB GPU, backlog %zu%s\n",
           frame, ms, s->points_drawn, s->points_selected, s->nodes_drawn, s->nodes_selected,
           s->nodes_resident, (double)s->gpu_bytes / 1048576.0, s->loader_backlog,
           s->complete ? ", complete" : "");
    printf("  gpu ms: geometry %.2f", s->geometry_ms);
    for (int pass = 0; pass < STA_PASS_COUNT; pass++) {
        if (s->timing.ms[pass] > 0) {
            printf(", %s %.2f", sta_pass_name(pass), s->timing.ms[pass]);
        }
    }
    printf("; s0 %.4g m\n", (double)s->s0_m);
    if (s->katz.generation > 0) {
        printf("  katz: set %" PRIu64 ", %" PRIu64 " frames old%s, %" PRIu64 " of %" PRIu64
               " points visible, R %.4g m, hull %.1f ms",
               s->katz.generation, s->katz.age_frames, s->katz.current ? " (current)" : "",
               s->katz.visible, s->katz.points, s->katz.radius_m, s->katz.hull_ms);
        if (s->katz.plain_hull_ms > 0) {
            printf(" (plain hull %.1f ms)", s->katz.plain_hull_ms);
        }
        printf("\n");
    }
    fflush(stdout); // line by line also when stdout is a pipe or a file
}

// Renders frames until the view is fully loaded (or --frames / the timeout).
static sta_status render_until_loaded(const sta_view_args *args, sta_scene *scene,
                                      const sta_camera *camera, sta_render_target *target,
                                      sta_frame_stats *stats, sta_error *err)
{
    double start = sta_clock_s();
    for (int frame = 1;; frame++) {
        double t0 = sta_clock_s();
        sta_status status = sta_scene_render(scene, camera, target, stats, err);
        if (status != STA_OK) {
            return status;
        }
        sta_gl_finish();
        if (args->stats) {
            if (frame == 1 && sta_scene_raster_choice(scene)) {
                printf("%s\n", sta_scene_raster_choice(scene)->reason);
            }
            if (frame == 1 && sta_scene_splat_method(scene)) {
                printf("splats: %s\n", sta_scene_splat_method(scene));
            }
            print_stats(frame, stats, (sta_clock_s() - t0) * 1e3);
        }
        if (args->max_frames ? frame >= args->max_frames : stats->complete) {
            if (args->stats) {
                printf("view loaded: %d frames, %.3f s from the first frame\n", frame,
                       sta_clock_s() - start);
                fflush(stdout);
            }
            return STA_OK;
        }
        if (sta_clock_s() - start > args->timeout_s) {
            return sta_fail(err, STA_ERR_IO, "%s: the view did not finish loading in %.0f s",
                            args->scene, args->timeout_s);
        }
        if (!stats->complete) {
            struct timespec nap = { 0, 2000000 }; // let the loader work
            nanosleep(&nap, NULL);
        }
    }
}

static int compare_doubles(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : (x > y ? 1 : 0);
}

// Renders the loaded view `args->repeat` more times and prints the median time of the
// whole frame and of each pass (timing on: the GPU is drained around each pass).
static sta_status time_repeats(const sta_view_args *args, sta_scene *scene,
                               const sta_camera *camera, sta_render_target *target, sta_error *err)
{
    enum {
        MAX_REPEAT = 256
    };
    int n = args->repeat < MAX_REPEAT ? args->repeat : MAX_REPEAT;
    static double frame_ms[MAX_REPEAT], geometry_ms[MAX_REPEAT];
    static double frame_cpu_ms[MAX_REPEAT], geometry_cpu_ms[MAX_REPEAT];
    static double pass_ms[STA_PASS_COUNT][MAX_REPEAT];
    sta_scene_set_timing(scene, true);
    sta_frame_stats stats;
    for (int i = 0; i < n; i++) {
        double t0 = sta_clock_s(), cpu0 = sta_clock_process_cpu_ms();
        sta_status status = sta_scene_render(scene, camera, target, &stats, err);
        if (status != STA_OK) {
            return status;
        }
        sta_gl_finish();
        frame_ms[i] = (sta_clock_s() - t0) * 1e3;
        frame_cpu_ms[i] = sta_clock_process_cpu_ms() - cpu0;
        geometry_ms[i] = stats.geometry_ms;
        geometry_cpu_ms[i] = stats.geometry_cpu_ms;
        for (int p = 0; p < STA_PASS_COUNT; p++) {
            pass_ms[p][i] = stats.timing.ms[p];
        }
    }
    qsort(frame_ms, (size_t)n, sizeof(double), compare_doubles);
    qsort(geometry_ms, (size_t)n, sizeof(double), compare_doubles);
    printf("median of %d frames: frame %.2f ms, geometry %.2f ms", n, frame_ms[n / 2],
           geometry_ms[n / 2]);
    for (int p = 0; p < STA_PASS_COUNT; p++) {
        qsort(pass_ms[p], (size_t)n, sizeof(double), compare_doubles);
        if (pass_ms[p][n / 2] > 0) {
            printf(", %s %.2f ms", sta_pass_name(p), pass_ms[p][n / 2]);
        }
    }
    printf("; %" PRIu64 " points drawn, %u nodes\n", stats.points_drawn, stats.nodes_drawn);
    // The process's CPU time (all threads; on llvmpipe the rasterising too) on a line of
    // its own, so that scripts reading the "median" line's passes see no new fields.
    qsort(frame_cpu_ms, (size_t)n, sizeof(double), compare_doubles);
    qsort(geometry_cpu_ms, (size_t)n, sizeof(double), compare_doubles);
    printf("cpu median of %d frames: frame %.2f ms, geometry %.2f ms\n", n, frame_cpu_ms[n / 2],
           geometry_cpu_ms[n / 2]);
    fflush(stdout);
    return STA_OK;
}

// The frame's normals (camera space) as three planes, top row first: the pipeline's, or
// the splats' (their stored normals, render/splat_normals.h); false when the frame has
// none.
static bool read_normals(const sta_scene *scene, const sta_camera *camera,
                         const sta_render_target *target, float *out_planes, sta_error *err)
{
    const sta_pipeline *pipeline = sta_scene_pipeline(scene);
    int mode = sta_scene_pipeline_mode(scene);
    bool splats = mode == STA_PIPELINE_SPLATS && sta_scene_has_splats(scene);
    if (mode == STA_PIPELINE_SPLATS && !splats) {
        mode = STA_PIPELINE_SHADED; // the fallback ran the shaded pipeline
    }
    sta_image normals;
    if (splats) {
        if (sta_splat_normal_image(sta_scene_gpu_cache(scene), target, camera, &normals, err) !=
            STA_OK) {
            return false;
        }
    } else if (!pipeline || (mode != STA_PIPELINE_NORMALS && mode != STA_PIPELINE_SHADED) ||
               sta_gl_texture_to_image(pipeline->normal, 0, 4, &normals, err) != STA_OK) {
        return false;
    }
    size_t pixels = (size_t)target->width_px * (size_t)target->height_px;
    for (int y = 0; y < target->height_px; y++) {
        for (int x = 0; x < target->width_px; x++) {
            const float *n =
                sta_image_at(&normals, x, target->height_px - 1 - y); // bottom row first
            size_t i = (size_t)y * (size_t)target->width_px + (size_t)x;
            for (int c = 0; c < 3; c++) {
                out_planes[(size_t)c * pixels + i] = n[3] > 0.0f ? n[c] : 0.0f;
            }
        }
    }
    sta_image_release(&normals);
    return true;
}

// Burns the readout into the image (top-left), with the default font.
static sta_status burn_readout(const sta_view_readout *readout, uint8_t *rgba, int width,
                               int height, sta_error *err)
{
    sta_hud_font *font = NULL;
    sta_status status = sta_hud_font_open(NULL, 0.0f, &font, err);
    if (status == STA_OK) {
        const char *lines[STA_VIEW_HUD_MAX_LINES];
        sta_view_readout_pointers(readout, lines);
        sta_hud_fill_rects(rgba, width, height, readout->marks, readout->mark_count);
        sta_hud_draw_lines(font, rgba, width, height, 8, 8, lines, readout->count);
    }
    sta_hud_font_close(font);
    return status;
}

static sta_status write_outputs(const sta_view_args *args, const sta_scene *scene,
                                const sta_camera *camera, const sta_render_target *target,
                                const sta_view_readout *readout, sta_error *err)
{
    size_t pixels = (size_t)target->width_px * (size_t)target->height_px;
    uint8_t *rgba = sta_alloc_array(pixels, 4);
    float *depth = sta_alloc_array(pixels, sizeof(float));
    float *planes = sta_alloc_array(pixels, 7 * sizeof(float));
    sta_status status = STA_OK;
    if (!rgba || !depth || !planes) {
        status = sta_fail(err, STA_ERR_NOMEM, "out of memory for a %dx%d image", target->width_px,
                          target->height_px);
    }
    if (status == STA_OK) {
        sta_render_target_read_rgba(target, rgba);
    }
    if (status == STA_OK && readout) {
        status = burn_readout(readout, rgba, target->width_px, target->height_px, err);
    }
    if (status == STA_OK && args->out_png) {
        status = sta_png_write_rgba(args->out_png, rgba, target->width_px, target->height_px, err);
    }
    if (status == STA_OK && args->out_exr) {
        sta_render_target_read_depth(target, depth);
        float *r = planes, *g = planes + pixels, *b = planes + 2 * pixels, *z = planes + 3 * pixels;
        for (size_t i = 0; i < pixels; i++) {
            r[i] = (float)rgba[4 * i] / 255.0f;
            g[i] = (float)rgba[4 * i + 1] / 255.0f;
            b[i] = (float)rgba[4 * i + 2] / 255.0f;
            // Reverse-Z depth d = near / distance along the view axis; empty pixels inf.
            z[i] = depth[i] > 0.0f ? (float)(camera->near_m / (double)depth[i]) : INFINITY;
        }
        float *n = planes + 4 * pixels;
        bool has_normals = read_normals(scene, camera, target, n, err);
        const sta_exr_channel channels[7] = { { "R", r },
                                              { "G", g },
                                              { "B", b },
                                              { "Z", z },
                                              { "N.X", n },
                                              { "N.Y", n + pixels },
                                              { "N.Z", n + 2 * pixels } };
        status = sta_exr_write(args->out_exr, channels, has_normals ? 7 : 4, target->width_px,
                               target->height_px, err);
    }
    sta_free(rgba);
    sta_free(depth);
    sta_free(planes);
    return status;
}

// Expands the one "%d" / "%05d"-style field of `pattern` with `index` (checked by
// the option parser), without handing a user string to printf.
static void frame_name(const char *pattern, int index, char *out, size_t size)
{
    const char *pc = strchr(pattern, '%');
    const char *end = pc + 1;
    bool zero = *end == '0';
    int width = 0;
    while (*end >= '0' && *end <= '9') {
        width = width * 10 + (*end - '0');
        end++;
    }
    char number[32];
    snprintf(number, sizeof(number), zero ? "%0*d" : "%*d", width > 20 ? 20 : width, index);
    snprintf(out, size, "%.*s%s%s", (int)(pc - pattern), pattern, number, end + 1);
}

// "path: frame 120/603 (20 %), 34 s, about 137 s left" on stderr: redrawn in place on a
// terminal, otherwise a line about every 5 seconds and one at the end.
static void path_progress(int done, int total, double start_s, double *last_line_s)
{
    double now = sta_clock_s(), elapsed = now - start_s;
    bool terminal = sta_log_is_terminal(), last = done == total;
    if (!terminal && !last && now - *last_line_s < 5.0) {
        return;
    }
    *last_line_s = now;
    double left = done > 0 ? elapsed / done * (total - done) : 0.0;
    fprintf(stderr, "%spath: frame %d/%d (%d %%), %.0f s, about %.0f s left%s",
            terminal ? "\r" : "", done, total, (int)(100.0 * done / total), elapsed, left,
            terminal && !last ? "" : "\n");
    fflush(stderr);
}

// Plays a camera path at 30 frames per second of path time (after --path-speed retimes
// it), each frame fully loaded, writing numbered PNGs when a pattern is given.
static sta_status play_path(const sta_view_args *args, sta_scene *scene, sta_camera *camera,
                            sta_render_target *target, sta_error *err)
{
    sta_camera_path path = { 0 };
    sta_status status = sta_camera_path_load(args->path_file, &path, err);
    if (status != STA_OK) {
        return status;
    }
    if (args->path_speed_mps > 0) {
        status = sta_camera_path_set_speed(&path, args->path_speed_mps, err);
        if (status != STA_OK) {
            sta_camera_path_release(&path);
            return status;
        }
    }
    double duration = sta_camera_path_duration(&path);
    int frames = (int)floor(duration * 30.0) + 1;
    double start_s = sta_clock_s(), last_line_s = start_s;
    size_t pixels = (size_t)camera->width_px * (size_t)camera->height_px;
    uint8_t *rgba = sta_alloc_array(pixels, 4);
    if (!rgba) {
        status = sta_fail(err, STA_ERR_NOMEM, "out of memory");
    }
    for (int i = 0; i < frames && status == STA_OK; i++) {
        sta_camera_path_sample(&path, path.keys[0].time_s + i / 30.0, camera);
        sta_frame_stats stats;
        status = render_until_loaded(args, scene, camera, target, &stats, err);
        if (status == STA_OK && args->frame_pattern) {
            char name[4096];
            frame_name(args->frame_pattern, i, name, sizeof(name));
            sta_render_target_read_rgba(target, rgba);
            status = sta_png_write_rgba(name, rgba, target->width_px, target->height_px, err);
        }
        if (status == STA_OK) {
            path_progress(i + 1, frames, start_s, &last_line_s);
        }
    }
    sta_free(rgba);
    sta_camera_path_release(&path);
    return status;
}

// --pick, --measure and --measure-csv after the last frame (lines on stdout).
// Also fills the readout burnt in by --hud.
static sta_status survey_outputs(const sta_view_args *args, const sta_scene *scene,
                                 const sta_camera *camera, const sta_frame_stats *stats,
                                 sta_view_readout *readout, sta_error *err)
{
    char line[1024];
    sta_status status = STA_OK;
    sta_pick_result pick;
    if (args->has_pick) {
        status = sta_view_pick(scene, camera, args->pick_px[0], args->pick_px[1], &pick, err);
        if (status == STA_OK) {
            sta_view_describe_pick(&pick, line, sizeof(line));
            printf("pick %g,%g: %s\n", args->pick_px[0], args->pick_px[1], line);
        }
    }
    sta_measure_list measures = { 0 };
    if (status == STA_OK && args->measure_file) {
        status = sta_measure_load_json(args->measure_file, &measures, err);
    }
    for (size_t i = 0; status == STA_OK && i < measures.count; i++) {
        sta_view_describe_measure(&measures.items[i], line, sizeof(line));
        printf("measure %zu %s\n", i + 1, line);
    }
    if (status == STA_OK && args->measure_csv) {
        status = sta_measure_save_csv(args->measure_csv, &measures, err);
    }
    sta_pipeline_options pipeline;
    sta_view_pipeline_options(args, &pipeline);
    char label[96];
    sta_view_pipeline_label(pipeline.mode, &args->point_size, (float)args->splat_scale, label,
                            sizeof(label));
    sta_view_readout_fill(readout, stats, 0.0, args->budget_points, label,
                          args->has_pick && status == STA_OK ? &pick : NULL, &measures);
    if (status == STA_OK && args->hud) {
        readout->marks = sta_alloc_array(STA_VIEW_MAX_MARKS, sizeof(*readout->marks));
        if (!readout->marks) {
            status = sta_fail(err, STA_ERR_NOMEM, "out of memory for the readout's markers");
        } else {
            readout->mark_count = sta_view_measure_marks(camera, &measures, NULL, 0, readout->marks,
                                                         STA_VIEW_MAX_MARKS);
        }
    }
    sta_measure_list_release(&measures);
    return status;
}

int sta_view_run_headless(const sta_view_args *args)
{
    sta_error err = { 0 };
    sta_gl_headless gl = { 0 };
    sta_scene *scene = NULL;
    sta_mirror_set mirrors = { 0 };
    sta_render_target target = { 0 };
    sta_status status = sta_gl_headless_create(&gl, &err);
    if (status == STA_OK) {
        status = sta_view_open_scene(args, &mirrors, &scene, &err);
    }
    if (status == STA_OK) {
        const sta_strata_info *info = sta_scene_info(scene);
        sta_camera camera;
        double frame_min[3], frame_max[3];
        sta_scene_robust_bounds(scene, frame_min, frame_max);
        char default_view[256];
        sta_view_initial_camera(args, info, frame_min, frame_max, &camera, default_view,
                                sizeof(default_view));
        sta_scene_set_colour_mode(scene, sta_view_initial_colour(args, info));
        sta_scene_set_ramps(scene, args->elevation_range[0], args->elevation_range[1],
                            args->intensity_max);
        sta_pipeline_options pipeline;
        sta_view_pipeline_options(args, &pipeline);
        sta_scene_set_pipeline(scene, &pipeline);
        sta_splat_options splats;
        sta_view_splat_options(args, &splats);
        sta_scene_set_splats(scene, &splats);
        sta_scene_set_katz(scene, &args->katz);
        sta_scene_set_timing(scene, args->stats);
        sta_scene_set_timing_clock(scene, args->stats_clock);
        if (args->stats) {
            char renderer[256];
            printf("renderer: %s\n", sta_gl_describe(renderer, sizeof(renderer)));
            if (default_view[0]) {
                char option[256];
                sta_view_camera_option(&camera, option, sizeof(option));
                printf("default view: %s\ndefault camera: %s\n", default_view, option);
            }
        }
        sta_geometry_options raster = { .raster = args->raster,
                                        .force_32bit_atomics = args->raster_32bit };
        sta_scene_set_raster(scene, &raster);
        sta_scene_set_point_size(scene, &args->point_size);
        sta_frame_stats stats = { 0 };
        if (args->path_file) {
            status = play_path(args, scene, &camera, &target, &err);
        } else {
            status = render_until_loaded(args, scene, &camera, &target, &stats, &err);
            if (status == STA_OK && args->repeat > 0) {
                status = time_repeats(args, scene, &camera, &target, &err);
            }
        }
        sta_view_readout readout = { .count = 0, .marks = NULL };
        if (status == STA_OK) {
            status = survey_outputs(args, scene, &camera, &stats, &readout, &err);
        }
        if (status == STA_OK && (args->out_png || args->out_exr)) {
            status =
                write_outputs(args, scene, &camera, &target, args->hud ? &readout : NULL, &err);
        }
        sta_free(readout.marks);
    }
    sta_render_target_release(&target);
    sta_scene_close(scene);
    sta_mirror_set_release(&mirrors);
    sta_gl_headless_destroy(&gl);
    if (status != STA_OK) {
        fprintf(stderr, "strata-view: %s\n", err.message);
        return 1;
    }
    return 0;
}
