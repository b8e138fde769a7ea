/* SPDX-License-Identifier: MIT
 * Ground truth for the benchmark: the analytic or procedural scene behind a
 * strata-synth point cloud, rebuilt from its truth sidecar (OUT.truth.json) with the
 * synth API, and asked in world coordinates (the .strata file's real coordinates):
 * is a point truly visible from an eye, what surface does a pixel's ray hit first.
 * Not thread-safe (the street scene caches blocks): one truth per thread.
 */
#ifndef STA_BENCH_BENCH_TRUTH_H
#define STA_BENCH_BENCH_TRUTH_H

#include <stdbool.h>

#include "core/camera.h"
#include "core/status.h"
#include "synth/synth.h"

typedef struct sta_bench_truth {
    sta_synth_scene *scene; /* owned */
    double origin[3];       /* world coordinate of scene-local (0, 0, 0), metres */
    double noise_m;         /* sigma of the points' noise (sidecar noise_sigma_m) */
    double gps_time[2];     /* street: scanner run start and end; 0 otherwise */
} sta_bench_truth;

/* Reads a truth sidecar written by strata-synth and rebuilds its scene (the mesh scene
 * loads the PLY named in the sidecar, relative paths taken from the current folder).
 * Errors name the file and field: STA_ERR_IO, STA_ERR_FORMAT (not a sidecar, missing
 * or bad fields), the synth scene's errors. On success release with
 * sta_bench_truth_release. */
sta_status sta_bench_truth_load(const char *path, sta_bench_truth *out, sta_error *err);

/* Builds the truth from synth parameters directly (borrowed) and the world origin
 * of the local frame. For tests and for callers that generated the scene themselves. */
sta_status sta_bench_truth_init(const sta_synth_params *params, const double origin[3],
                                sta_bench_truth *out, sta_error *err);

/* Frees the scene; a zeroed truth is a no-op. */
void sta_bench_truth_release(sta_bench_truth *truth);

/* The nearest surface along the ray from `eye` (world) in unit direction `dir` for
 * 0 < t < max_t; false when nothing is hit. Window glass is passed through (the street's
 * rooms show behind it); sta_bench_truth_ray_glass reports it as a surface. */
bool sta_bench_truth_ray(sta_bench_truth *truth, const double eye[3], const double dir[3],
                         double max_t, sta_synth_hit *out_hit);
bool sta_bench_truth_ray_glass(sta_bench_truth *truth, const double eye[3], const double dir[3],
                               double max_t, sta_synth_hit *out_hit);

/* True visibility of a point (world) seen from `eye` (world): visible iff no surface
 * crosses the segment from the eye to the point closer than `tolerance_m` before the
 * point, i.e. the ray through the point hits the scene first at (about) the point.
 * A point at the eye is visible. */
bool sta_bench_truth_point_visible(sta_bench_truth *truth, const double eye[3],
                                   const double point[3], double tolerance_m);

/* The unit world direction of the ray through the centre of pixel (x, y) of `camera`,
 * in GL texture order (row 0 at the bottom of the image), and that direction's cosine
 * with the view axis (depth along the axis = t * cosine). */
void sta_bench_pixel_ray(const sta_camera *camera, int x, int y, double out_dir[3],
                         double *out_axis_cosine);

/* Camera-space vector (x right, y up, z towards the viewer) to world. */
void sta_bench_camera_to_world(const sta_camera *camera, const double v[3], double out[3]);

#endif
