/* SPDX-License-Identifier: MIT
 * Scoring one rendered view against the truth: what each pixel's ray truly hits (depth
 * and normal, once per camera), which drawn points are truly visible (from the depth
 * buffer, once per camera and budget), and the errors of the pipeline's buffers (HPR
 * labels, normals, filled depth) read back as sta_image. CPU only, no GL.
 * Images are in GL texture order (row 0 at the bottom), as sta_image.
 */
#ifndef STA_BENCH_VIEW_EVAL_H
#define STA_BENCH_VIEW_EVAL_H

#include <stddef.h>
#include <stdint.h>

#include "bench/bench_truth.h"
#include "bench/metrics.h"
#include "core/camera.h"
#include "core/status.h"
#include "render/ref/image.h"

/* Per pixel truth of one view. */
typedef struct sta_view_truth {
    int width, height;
    float *depth_m;       /* per pixel: true depth along the view axis; NAN where the ray misses */
    float *normal;        /* 3 per pixel: unit camera-space normal facing the camera (0 on miss) */
    float *glass_depth_m; /* per pixel: the true depth with window glass as a surface
                             (sta_bench_truth_ray_glass): less than depth_m where the
                             ray passes a window, depth_m elsewhere; NULL: as depth_m */
    uint8_t *classification; /* per pixel: LAS class of the true surface (0 on a miss);
                                NULL: unknown */
    uint64_t hit_count;
} sta_view_truth;

/* Leaves the pixels whose true surface has a class of `set` (bit c % 32 of word c / 32
 * is class c; `words` words) out of the fill metrics: counted[i] = 0 there and 1
 * elsewhere, and sampled[i] (may be NULL) is cleared there too. The viewer fills no
 * surface for those classes (volumetric classes, docs/BENCH.md). Returns the number
 * of pixels with a truth hit left out; with no classification, none. */
uint64_t sta_view_truth_leave_out_classes(const sta_view_truth *view_truth, const uint32_t *set,
                                          int words, uint8_t *counted, uint8_t *sampled);

/* Casts one ray through each pixel centre. */
sta_status sta_view_truth_compute(sta_bench_truth *truth, const sta_camera *camera,
                                  sta_view_truth *out, sta_error *err);
void sta_view_truth_release(sta_view_truth *view_truth);

/* Per pixel agreement of the geometry pass's depth with the true surface: the image
 * error of raw points of any size (render/point_size.h). Fractions of `pixels`, the
 * pixels where the truth or the picture has a surface. */
typedef struct sta_surface_error {
    uint64_t pixels;
    double hole;        /* the truth has a surface, nothing is drawn */
    double see_through; /* drawn behind the true surface by more than the tolerance */
    double bleed;       /* drawn where the truth has none, or in front of it by more than the
                           tolerance (points wider than the surface they sample) */
    double error;       /* hole + see_through + bleed */
} sta_surface_error;

/* Compares `depth` (reverse-Z, rows top first as sta_render_target_read_depth gives
 * them, 0 where empty) of `camera`'s viewport with the view's true depths. */
void sta_eval_surface(const sta_view_truth *view_truth, const sta_camera *camera,
                      const float *depth, double tolerance_m, sta_surface_error *out);

/* The points of a view: one per pixel the geometry pass drew, at the pixel centre and
 * the depth buffer's depth (unprojected in double). */
typedef struct sta_view_points {
    size_t count;
    uint32_t *pixel;    /* texture-order index y * width + x */
    double (*world)[3]; /* world coordinates, metres */
    uint8_t *visible;   /* truth (sta_view_points_classify), 1 visible / 0 hidden */
} sta_view_points;

/* Unprojects `depth` (reverse-Z as sta_render_target_read_depth gives it: top row
 * first, 0 = nothing drawn) of `camera`'s viewport. */
sta_status sta_view_points_from_depth(const sta_camera *camera, const float *depth,
                                      sta_view_points *out, sta_error *err);

/* Fills out->visible with sta_bench_truth_point_visible from the camera's eye. */
void sta_view_points_classify(sta_bench_truth *truth, const sta_camera *camera, double tolerance_m,
                              sta_view_points *points);
void sta_view_points_release(sta_view_points *points);

/* HPR labels (R32F, STA_LABEL_*) against the points' truth: a point pixel labelled
 * STA_LABEL_VISIBLE counts as labelled visible, any other label as hidden. */
void sta_eval_hpr(const sta_view_points *points, const sta_image *label, sta_confusion *out);
/* The same over the points whose pixel has scored[pixel] != 0 (NULL: all). */
void sta_eval_hpr_masked(const sta_view_points *points, const sta_image *label,
                         const uint8_t *scored, sta_confusion *out);

/* Farthest pixel offset sta_view_truth_sampled searches. */
#define STA_VIEW_SAMPLED_MAX_PX 16

/* Marks (1, else 0; one byte per pixel, texture order) the pixels whose true surface
 * the drawn points sample: some view point lies within radius_m (3D) of the point the
 * pixel's ray truly hits. Searched among the pixels within radius_m of the hit on the
 * screen (radius_m * pixels per metre at its depth, 1 .. STA_VIEW_SAMPLED_MAX_PX), the
 * nearest rings first. A scanner leaves some surfaces unsampled (a profiler sees the
 * faces across its driving direction edge-on): no estimator can know their normals.
 * Errors: STA_ERR_NOMEM. */
sta_status sta_view_truth_sampled(const sta_view_truth *view_truth, const sta_camera *camera,
                                  const sta_view_points *points, double radius_m,
                                  uint8_t *out_sampled, sta_error *err);

/* Two true normals belong to one face when they are within this angle. */
#define STA_VIEW_FACE_ANGLE_DEG 30.0

/* As sta_view_truth_sampled, but a view point counts only when it lies on the true
 * surface of its own pixel (within radius_m of that pixel's hit) and that surface's
 * normal is within STA_VIEW_FACE_ANGLE_DEG of the pixel's true normal: the pixel's
 * true face is sampled. A window reveal or a car's back, which the profiler sees
 * edge-on, lies within the tolerance of points on the facade or the car's side, but no
 * point lies on the face itself (the face-sampled rule, docs/BENCH.md). */
sta_status sta_view_truth_face_sampled(const sta_view_truth *view_truth, const sta_camera *camera,
                                       const sta_view_points *points, double radius_m,
                                       uint8_t *out_sampled, sta_error *err);

/* Angle (degrees) between the normal buffer (RGBA32F, w > 0.5 valid) and the true
 * normal, over pixels with a valid normal whose ray hits the scene and, when `sampled`
 * is not NULL, whose byte in it is 1 (sta_view_truth_sampled). */
sta_status sta_eval_normals(const sta_view_truth *view_truth, const sta_image *normal,
                            const uint8_t *sampled, sta_error_summary *out, sta_error *err);

/* A true face "faces the camera" when its normal is within this angle of the view
 * axis: the street's faces along the driving direction (car backs, building ends,
 * window reveals' sides), which the profile scanner sees edge-on (issue 15, part 3). */
#define STA_VIEW_FACING_ANGLE_DEG 37.0

/* Normal error above this angle counts as "off" (issue 15's p95 target). */
#define STA_VIEW_NORMAL_OFF_DEG 30.0

/* Shares of the pixels sta_eval_normals counts whose normal is off by more than
 * STA_VIEW_NORMAL_OFF_DEG: all of them, and split by the true face's orientation
 * (facing + other = all). p95 <= 30 degrees needs `all` <= 0.05. */
typedef struct sta_normal_off_share {
    double all;
    double facing; /* true normal within STA_VIEW_FACING_ANGLE_DEG of the view axis */
    double other;
} sta_normal_off_share;

/* The shares above over the pixels that sta_eval_normals(view_truth, normal, sampled)
 * counts; NAN where none is counted. */
sta_status sta_eval_normals_off(const sta_view_truth *view_truth, const sta_image *normal,
                                const uint8_t *sampled, sta_normal_off_share *out, sta_error *err);

/* The share of the pixels that sta_eval_normals(view_truth, normal, sampled) counts whose
 * normal is off by more than STA_VIEW_NORMAL_OFF_DEG and whose filled depth (-z of
 * `filled`, RGBA32F camera space, w > 0) lies more than `tolerance_m` from the true depth
 * along the view axis (or which has no filled point): there the fill holds another
 * surface, and no estimator that reads the filled points can give the true one's normal
 * (issue 15, sixteenth round). The rest of sta_normal_off_share.all is the estimator's.
 * NAN where none is counted. Errors: STA_ERR_ARG (sizes differ). */
/* The normals as the shade pass lights them (issue 15, sixteenth round): over the pixels
 * with a filled point (`filled`, RGBA32F camera space, w > 0) whose ray hits the scene and,
 * when `counted` is not NULL, whose byte in it is 1, a pixel without a normal (`normal` w
 * <= 0.5: unknown, sta_normals_pyramid_params.min_coverage) counts with the normal the
 * shade pass lights it by, facing the camera (-p / |p|). Writes the share of those pixels
 * that are unknown, the summary of the angle errors and the share off by more than
 * STA_VIEW_NORMAL_OFF_DEG; NAN and a zero count where none is counted. The errors of
 * sta_eval_normals leave the unknown pixels out; these say what that leaves out.
 * Errors: STA_ERR_ARG (sizes differ), STA_ERR_NOMEM. */
sta_status sta_eval_normals_shaded(const sta_view_truth *view_truth, const sta_image *normal,
                                   const sta_image *filled, const uint8_t *counted,
                                   double *out_unknown_share, sta_error_summary *out_shaded,
                                   double *out_off_share, sta_error *err);

sta_status sta_eval_normals_off_fill(const sta_view_truth *view_truth, const sta_image *normal,
                                     const sta_image *filled, double tolerance_m,
                                     const uint8_t *sampled, double *out_share, sta_error *err);

/* Relative depth error |d - d_true| / d_true of the filled buffer (RGBA32F, camera
 * space xyz, w > 0 covered; d = -z), over covered pixels whose ray hits the scene and,
 * when `sampled` is not NULL, whose byte in it is 1 (sta_view_truth_sampled). */
sta_status sta_eval_depth(const sta_view_truth *view_truth, const sta_image *filled,
                          const uint8_t *sampled, sta_error_summary *out, sta_error *err);

/* As sta_eval_depth, with window glass accepted as a surface: where the pixel's ray
 * passes glass (glass_depth_m < depth_m), the lesser of the errors against the glass
 * and against the surface behind it. The street's scanner reports glass now and then
 * and the rooms behind it; both are sampled surfaces on the same ray (docs/BENCH.md). */
sta_status sta_eval_depth_glass(const sta_view_truth *view_truth, const sta_image *filled,
                                const uint8_t *sampled, sta_error_summary *out, sta_error *err);

/* Width of the image border band of sta_eval_border, pixels (issue 15's edge metric). */
#define STA_BORDER_BAND_PX 16

/* Surfaces filled to the image edge: over the pixels of the STA_BORDER_BAND_PX-wide band
 * along the image border whose ray hits the scene and, when `sampled` is not NULL, whose
 * true surface the drawn points sample (sta_view_truth_sampled), the count (*out_count)
 * and the share left empty by the filled buffer (RGBA32F, w > 0 covered; *out_share,
 * NAN for none). Sky (the ray misses) is not counted: empty is right there; nor, with
 * `sampled`, surfaces the data does not reach (beyond the end of a scan). */
sta_status sta_eval_border(const sta_view_truth *view_truth, const sta_image *filled,
                           const uint8_t *sampled, uint64_t *out_count, double *out_share,
                           sta_error *err);

#endif
