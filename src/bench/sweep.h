/* SPDX-License-Identifier: MIT
 * The benchmark's core: for each scene, camera, point budget and pipeline setting,
 * render the view headless once it is fully loaded, time every pass (median of
 * `repeat` frames) and, where truth exists, measure the errors (HPR against true
 * visibility, normals, filled depth, image against an unbudgeted reference; Katz's HPR
 * as an offline reference). One sta_bench_row per scene x camera x budget x setting.
 *
 * Design: each scene is opened once per budget (the budget is fixed when a scene is
 * opened) plus once without budget for the reference images; all stay open while the
 * cameras are visited, so nothing is loaded twice for the same view. Before timing,
 * each view is rendered until every selected node is resident (raw mode, timing off).
 * Needs a current GL 4.5 context (sta_gl_headless_create). Main thread only.
 */
#ifndef STA_BENCH_SWEEP_H
#define STA_BENCH_SWEEP_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "core/status.h"
#include "render/pipeline.h"
#include "render/point_size.h"
#include "stream/select.h"

typedef enum sta_bench_camera_kind {
    STA_BENCH_ORBIT = 0, /* sta_bench_orbit */
    STA_BENCH_STREET,    /* sta_bench_street */
    STA_BENCH_PATH,      /* keyframes of path_file */
} sta_bench_camera_kind;

enum {
    STA_BENCH_MAX_LIST = 16 /* entries per sweep list */
};

/* Configuration. Zero means default for each field (sta_bench_options_defaults). */
typedef struct sta_bench_options {
    const char *const *scenes; /* .strata paths (borrowed) */
    size_t scene_count;
    const char *const *truths; /* truth sidecars: none (look beside each scene for
                                  <stem>.truth.json), one per scene, or NULL entries */
    size_t truth_count;
    sta_bench_camera_kind cameras;
    int camera_count;                     /* orbit / street views; 0: 8 */
    const char *path_file;                /* STA_BENCH_PATH */
    int width_px, height_px;              /* 0: 1920 x 1080 */
    double fov_deg;                       /* 0: 60 */
    uint64_t budgets[STA_BENCH_MAX_LIST]; /* points per frame; 0 = all points */
    int budget_count;                     /* 0: one budget of STA_DEFAULT_BUDGET_POINTS */
    int modes[STA_BENCH_MAX_LIST];        /* sta_pipeline_mode */
    int mode_count;                       /* 0: shaded */
    int normals[STA_BENCH_MAX_LIST];      /* sta_normal_method */
    int normal_count;                     /* 0: pyramid */
    int samples[STA_BENCH_MAX_LIST];      /* LD/PD/PC/TI schemes */
    int sample_count;                     /* 0: 9 */
    bool hpr_variants[2];                 /* HPR variants: [0] pyramid, [1] exhaustive;
                                             neither set: pyramid only */
    bool hpr_every_pixel;                 /* the pyramid variant on every pixel, not sparse */
    bool hpr_block_gaps;                  /* empty pixels decided by blocks (--hpr-gaps blocks) */
    bool normals_every_pixel;             /* pyramidal normals gathered on every pixel */
    bool smooth;                          /* normal smoothing pass */
    bool fill_every_class;                /* no volumetric classes: every class filled and
                                             scored (before issue 15's fourteenth round);
                                             false: the viewer's default classes are drawn
                                             as points and left out of the fill metrics */
    int hpr_radius_px;                    /* exhaustive radius; 0: the pipeline's 8 */
    float hpr_threshold;                  /* 0: the pipeline's 0.1 */
    double s0_m;                          /* 0: the scene's estimate */
    int repeat;                           /* timed frames per setting; 0: 5 */
    double tolerance_s0;                  /* truth tolerance in s0; 0: 3 */
    double timeout_s;                     /* per view loading; 0: 300 */
    bool katz;                            /* run the Katz reference */
    bool katz_local;                      /* R per region of the view (bench/katz_local.h) */
    bool katz_drawn;                      /* feed it the drawn points' own positions (the id
                                             target), not pixel centres */
    double katz_perturbation;             /* Braga's perturbation for --katz and the live
                                             mode (0: none); > 0 also times the plain hull
                                             on the same input, interleaved */
    bool katz_live;                       /* the live Katz mode as a method (its own row) */
    uint64_t katz_points;                 /* live mode's points per hull; 0: its default */
    double katz_oversample;               /* live mode's candidates per hull point; 0: default */
    bool no_image_error;                  /* skip the unbudgeted reference renders */
    bool progress;                        /* progress line on stderr (a terminal only) */

    /* Point sizes, for the raw and edl modes only (render/point_size.h). */
    sta_point_size point_sizes[STA_BENCH_MAX_LIST]; /* none: one pixel */
    int point_size_count;
    double adaptive_px[2]; /* adaptive entries' smallest, largest diameter; 0: their own */
} sta_bench_options;

/* One pipeline setting of a sweep. */
typedef struct sta_bench_setting {
    int mode, normals, samples; /* normals/samples only where the mode estimates normals */
    bool hpr_exhaustive;        /* only where the mode runs HPR */
    sta_point_size point_size;  /* raw and edl; zero: one pixel */
} sta_bench_setting;

/* One result. Times in milliseconds (medians over `repeat` frames), errors NaN where
 * not measured. docs/BENCH.md defines every field. */
typedef struct sta_bench_row {
    char scene[256];       /* file name of the .strata */
    uint64_t scene_points; /* points in the file */
    int camera;            /* view index */
    char camera_kind[8];   /* "orbit", "street", "path" */
    double eye[3];         /* camera position, world metres */
    double yaw_deg, pitch_deg;
    int width_px, height_px;
    uint64_t budget;   /* requested (all points when 0 was given) */
    char setting[64];  /* e.g. "shaded/pyramid/hpr-pyr" */
    char pipeline[16]; /* mode name */
    char normals[16];  /* normal method name or "" */
    int samples;       /* LD/PD/PC/TI samples or 0 */
    char hpr[16];      /* "pyramid", "exhaustive" or "" */
    double s0_m;       /* used by the screen-space passes */
    int repeat;
    uint64_t points_drawn, points_selected;
    uint32_t nodes_resident, nodes_drawn;
    uint64_t loader_backlog;
    double load_s; /* wall time until the view was fully loaded */
    double geometry_ms, pass_ms[STA_PASS_COUNT], screen_ms, gpu_ms, frame_ms, cpu_ms;
    uint64_t truth_points; /* drawn pixels classified against the truth */
    uint64_t truly_hidden;
    uint64_t hpr_tp, hpr_fp, hpr_fn, hpr_tn;
    double hpr_precision, hpr_recall, hpr_f1;
    uint64_t hpr_face_points; /* points scored by the face rule (sta_pixel_masks hpr_face) */
    double hpr_face_f1;
    uint64_t hpr_face_glass_points; /* ... by the face and glass rules (hpr_face_glass) */
    double hpr_face_glass_f1;
    uint64_t hpr_volumetric_points; /* ... by the volumetric rule (hpr_volumetric) */
    double hpr_volumetric_f1;
    uint64_t normal_count;
    double normal_mean_deg, normal_median_deg, normal_p95_deg;
    uint64_t normal_sampled_count; /* the same over pixels whose true surface the drawn
                                      points sample (sta_view_truth_sampled) */
    double normal_sampled_mean_deg, normal_sampled_median_deg, normal_sampled_p95_deg;
    uint64_t normal_face_count; /* the same over pixels whose true face the drawn points
                                   sample (sta_view_truth_face_sampled: the face rule) */
    double normal_face_mean_deg, normal_face_median_deg, normal_face_p95_deg;
    double normal_off_share; /* share of the normal_count pixels off by more than 30
                                degrees (sta_eval_normals_off), on faces facing the
                                camera and on the others; the same under the face rule */
    double normal_off_facing_share, normal_off_other_share, normal_face_off_share;
    double normal_off_fill_share; /* of normal_off_share, the pixels whose filled depth is
                                     more than the truth tolerance off (another surface:
                                     sta_eval_normals_off_fill) */
    double normal_unknown_share;  /* share of the pixels with a filled point and a truth hit
                                     (left-out classes aside) that have no normal (unknown:
                                     shaded flat), and the errors over all of them with the
                                     unknown ones lit as facing the camera
                                     (sta_eval_normals_shaded) */
    double normal_shaded_median_deg, normal_shaded_p95_deg, normal_shaded_off_share;
    uint64_t depth_count;
    double depth_rel_mean, depth_rel_median, depth_rel_p95;
    char point_size[24];     /* "1 px", "3 px", "adaptive 1-8 px" (raw and edl) */
    uint64_t surface_pixels; /* raw and edl with truth: sta_eval_surface */
    double surface_hole, surface_see_through, surface_bleed, surface_error;
    uint64_t depth_sampled_count; /* the same over sampled pixels (sta_view_truth_sampled) */
    double depth_sampled_rel_mean, depth_sampled_rel_median, depth_sampled_rel_p95;
    uint64_t depth_glass_count; /* the same with window glass a surface (sta_eval_depth_glass) */
    double depth_glass_rel_mean, depth_glass_rel_median, depth_glass_rel_p95;
    uint64_t fill_left_out; /* pixels whose true surface has a volumetric class, left out
                               of the depth, normal and border metrics (docs/BENCH.md) */
    uint64_t border_count;  /* sta_eval_border: band pixels whose ray hits the scene */
    double border_empty;    /* the share of them the fill leaves empty */
    double gap_blocks_8;    /* sta_eval_gap_block_ratio of the HPR labels, 8-px lines */
    double gap_blocks_16;   /* the same, 16-px lines */
    double gap_blocks_32;   /* the same, 32-px lines */
    double psnr_db;         /* +inf for identical images */
    double ssim;
    double katz_ms;
    double katz_radius_m;         /* Katz's sphere radius R used (sta_katz_view_radius) */
    double katz_hull_ms;          /* median hull wall time (repeat runs when perturbed) */
    double katz_plain_hull_ms;    /* perturbed: median plain hull on the same input, interleaved */
    double katz_plain_f1;         /* perturbed: the plain operator's F1 */
    double katz_live_latency_ms;  /* live row: camera set to the set of this view shown */
    int katz_live_frames;         /* live row: frames drawn meanwhile */
    double katz_live_hull_cpu_ms; /* live row: CPU time of its hull (worker thread) */
    double katz_live_plain_hull_ms; /* live row, perturbed: plain hull on the same input */
    uint64_t katz_points, katz_visible;
    double katz_precision, katz_recall, katz_f1;
} sta_bench_row;

typedef struct sta_bench_results {
    sta_bench_row *rows; /* owned */
    size_t count, capacity;
} sta_bench_results;

/* Resolves zero fields to their defaults. */
void sta_bench_options_defaults(sta_bench_options *options);

/* Expands the sweep lists into settings (modes x HPR variants x normal methods x
 * samples x point sizes, each only where the mode uses it). *out is owned by the
 * caller (sta_free). */
sta_status sta_bench_settings(const sta_bench_options *options, sta_bench_setting **out,
                              size_t *out_count, sta_error *err);

/* A short label of a setting ("raw", "raw/3px", "edl/adaptive1-8", "hpr/exh",
 * "shaded/pd9/pyr"). */
void sta_bench_setting_label(const sta_bench_setting *setting, char *out, size_t size);

/* Runs the whole sweep, appending rows to `results` (zero-initialise it). Needs a
 * current GL context. Errors name the scene and view. */
sta_status sta_bench_run(const sta_bench_options *options, sta_bench_results *results,
                         sta_error *err);

void sta_bench_results_release(sta_bench_results *results);

#endif
