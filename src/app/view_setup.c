/* SPDX-License-Identifier: MIT
 * Initial camera and colour. */
#include "app/view_setup.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app/view_sample.h"
#include "core/alloc.h"
#include "core/camera_frame.h"
#include "core/json_out.h"
#include "format/strata_reader.h"
#include "render/bindings.h"
#include "render/ref/hpr_ref.h"

static const double degrees = 3.14159265358979323846 / 180.0;

// The robust box grown by STA_VIEW_FRAME_GROW of its size on every side.
static void grown_box(const double box_min[3], const double box_max[3], double min[3],
                      double max[3])
{
    for (int a = 0; a < 3; a++) {
        double grow = STA_VIEW_FRAME_GROW * (box_max[a] - box_min[a]);
        min[a] = box_min[a] - grow;
        max[a] = box_max[a] + grow;
    }
}

// The samples (sta_view_sample_build) of the points inside the robust box grown by
// STA_VIEW_FRAME_GROW of its size on every side (far strays stay out, a model's
// extremities that the percentiles cut, such as the bunny's ear tips, come back in).
// Empty when the file cannot be read here (the caller falls back to the box).
static void scene_sample(const sta_strata_info *info, const double box_min[3],
                         const double box_max[3], sta_view_sample *out)
{
    double min[3], max[3];
    grown_box(box_min, box_max, min, max);
    memset(out, 0, sizeof(*out));
    sta_strata_reader *reader = NULL;
    if (sta_strata_open(info->path, NULL, &reader, NULL) == STA_OK) {
        (void)sta_view_sample_build(reader, min, max, out);
        sta_strata_close(reader);
    }
}

void sta_view_initial_camera(const sta_view_args *args, const sta_strata_info *info,
                             const double frame_min[3], const double frame_max[3], sta_camera *c,
                             char *why, size_t why_size)
{
    if (why && why_size > 0) {
        why[0] = '\0';
    }
    c->width_px = args->width_px;
    c->height_px = args->height_px;
    c->fov_y = args->camera[5] * degrees;
    // The up axis is the file's (strata-convert decides it from the source): yaw and
    // pitch, given or default, are about it.
    c->up_axis = info->up_axis == STA_STRATA_UP_Y ? STA_CAMERA_UP_Y : STA_CAMERA_UP_Z;
    if (args->has_camera) {
        for (int a = 0; a < 3; a++) {
            double centre = 0.5 * (info->bounds_min[a] + info->bounds_max[a]);
            c->position[a] = args->camera[a] + (args->camera_relative ? centre : 0.0);
        }
        c->yaw = args->camera[3] * degrees;
        c->pitch = args->camera[4] * degrees;
        double extent = 0.0;
        for (int a = 0; a < 3; a++) {
            double e = info->bounds_max[a] - info->bounds_min[a];
            extent = e > extent ? e : extent;
        }
        // Near plane: small against the scene, but never below a millimetre.
        c->near_m = extent * 1e-5 > 1e-3 ? extent * 1e-5 : 1e-3;
        return;
    }
    sta_view_sample sample;
    scene_sample(info, frame_min, frame_max, &sample);
    sta_view_direction d = sta_view_default_direction(
        c, sample.weighted ? &sample.weighted[0][0] : NULL, sample.weighted_count);
    c->yaw = d.yaw;
    c->pitch = d.pitch;
    if (why) {
        sta_view_direction_describe(&d, why, why_size);
    }
    // A corridor is framed on the weighted sample around its mean (the root's even spread
    // gave the ground streaks of a street's cross streets as much room as the street);
    // other scenes as before the sample, on the root's points around the robust box's
    // centre (the weighted sample's extremities are thinner: it framed models tighter,
    // cut at the top).
    double centre[3] = { 0.5 * (frame_min[0] + frame_max[0]), 0.5 * (frame_min[1] + frame_max[1]),
                         0.5 * (frame_min[2] + frame_max[2]) };
    if (d.along && sample.weighted_count > 0) {
        for (int a = 0; a < 3; a++) {
            centre[a] = 0.0;
            for (size_t i = 0; i < sample.weighted_count; i++) {
                centre[a] += sample.weighted[i][a] / (double)sample.weighted_count;
            }
        }
        // The weighted sample's tails (ground streaks down the cross streets) run on in
        // small steps too: cut at the share alone; the street runs off the edges.
        const sta_camera_frame_rule corridor = { .keep = STA_VIEW_FRAME_KEEP };
        sta_camera_frame_points(c, centre, &sample.weighted[0][0], sample.weighted_count,
                                &corridor);
    } else if (sample.root_count > 0) {
        // The whole scene, clear of the border band (where the screen passes fill
        // surfaces as if they ran on past the edge).
        const sta_camera_frame_rule whole = {
            .keep = STA_VIEW_FRAME_KEEP,
            .stray_gap = STA_VIEW_FRAME_STRAY_GAP,
            .margin_px = (double)sta_hpr_empty_border_px(c->height_px) + STA_VIEW_FRAME_CLEAR_PX,
        };
        sta_camera_frame_points(c, centre, &sample.root[0][0], sample.root_count, &whole);
    } else {
        sta_camera_frame_box(c, frame_min, frame_max);
    }
    sta_view_sample_release(&sample);
}

static int compare_doubles(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

// 5-95 % quantiles of `values` (sorted in place).
static void spread(double *values, size_t count, double *lo, double *hi)
{
    qsort(values, count, sizeof(double), compare_doubles);
    *lo = values[count / 20];
    *hi = values[count - 1 - count / 20];
}

// Whether points elongated along `yaw` (in the camera's z-up frame) make a corridor: the
// 5-95 % spread of their heights more than STA_VIEW_CORRIDOR_DEPTH times that across the
// axis, and open above the axis: of the points in the middle third across it, at most
// STA_VIEW_CORRIDOR_OPEN in the upper half of the heights (a street: the road in the
// middle, the facades at the sides; an elongated model such as the dragon is solid there).
static bool is_corridor(const sta_camera *c, const double *points, size_t count, double yaw)
{
    double *across = sta_alloc_array(count ? count : 1, sizeof(double));
    double *height = sta_alloc_array(count ? count : 1, sizeof(double));
    double *sorted = sta_alloc_array(count ? count : 1, sizeof(double));
    bool corridor = false;
    if (across && height && sorted && count >= 20) {
        for (size_t i = 0; i < count; i++) {
            double f[3];
            sta_camera_to_frame(c, points + 3 * i, f);
            across[i] = -sin(yaw) * f[0] + cos(yaw) * f[1];
            height[i] = f[2];
        }
        double a_lo, a_hi, z_lo, z_hi;
        memcpy(sorted, across, count * sizeof(double));
        spread(sorted, count, &a_lo, &a_hi);
        memcpy(sorted, height, count * sizeof(double));
        spread(sorted, count, &z_lo, &z_hi);
        double width = a_hi - a_lo, third = width / 3.0, mid_z = 0.5 * (z_lo + z_hi);
        size_t middle = 0, upper = 0;
        for (size_t i = 0; i < count; i++) {
            if (across[i] > a_lo + third && across[i] < a_hi - third) {
                middle++;
                upper += height[i] > mid_z;
            }
        }
        corridor = width > 0.0 && (z_hi - z_lo) > STA_VIEW_CORRIDOR_DEPTH * width && middle > 0 &&
                   (double)upper <= STA_VIEW_CORRIDOR_OPEN * (double)middle;
    }
    sta_free(across);
    sta_free(height);
    sta_free(sorted);
    return corridor;
}

sta_view_direction sta_view_default_direction(const sta_camera *c, const double *points,
                                              size_t count)
{
    sta_view_direction d = { STA_VIEW_DEFAULT_YAW_DEG * degrees,
                             STA_VIEW_DEFAULT_PITCH_DEG * degrees, false, 0.0, 1.0 };
    double long_yaw = sta_camera_points_long_yaw(c, points, count, &d.elongation);
    d.axis_yaw = long_yaw;
    if (!(d.elongation > STA_VIEW_ELONGATED_RATIO)) {
        return d;
    }
    if (!is_corridor(c, points, count, long_yaw)) {
        // An airborne strip, an elongated model: across the long axis, turned so that
        // depth still shows, and the long axis spans the width of the view.
        d.yaw = long_yaw + (90.0 - STA_VIEW_ACROSS_TURN_DEG) * degrees;
        return d;
    }
    // A corridor (a street): along it from one end, as from the vehicle that scanned
    // it, but from above. Seen across, the near side showed its backs, which a mobile
    // scan never samples, and the far side beyond them.
    const double half_turn = 180.0 * degrees;
    double yaw = fmod(long_yaw, half_turn); // the axis, either way along it
    if (yaw < 0.0) {
        yaw += half_turn;
    }
    d.yaw = yaw < 0.5 * half_turn ? yaw + half_turn : yaw;
    d.pitch = STA_VIEW_ALONG_PITCH_DEG * degrees;
    d.along = true;
    return d;
}

void sta_view_camera_option(const sta_camera *c, char *out, size_t size)
{
    // Angles to a nanodegree: 45 rather than 45.000000000000007 (45 reads back to the
    // very radians the default view computed from 45).
    const double values[6] = { c->position[0],
                               c->position[1],
                               c->position[2],
                               round(c->yaw / degrees * 1e9) / 1e9,
                               round(c->pitch / degrees * 1e9) / 1e9,
                               round(c->fov_y / degrees * 1e9) / 1e9 };
    size_t used = (size_t)snprintf(out, size, "--camera=");
    for (int i = 0; i < 6 && used < size; i++) {
        char number[40];
        used += (size_t)snprintf(out + used, size - used, "%s%s", i ? "," : "",
                                 sta_format_double(values[i], number, sizeof(number)));
    }
}

void sta_view_direction_describe(const sta_view_direction *d, char *out, size_t size)
{
    const char *kind = d->along                                   ? "a corridor"
                       : d->elongation > STA_VIEW_ELONGATED_RATIO ? "elongated"
                                                                  : "not elongated";
    const char *view = d->along                                   ? "along it from its end"
                       : d->elongation > STA_VIEW_ELONGATED_RATIO ? "across its axis"
                                                                  : "from the south-west";
    snprintf(out, size, "%s (axis %.1f deg, elongation %.2f): %s, %.0f deg from above", kind,
             d->axis_yaw / degrees, d->elongation, view, -d->pitch / degrees);
}

int sta_view_initial_colour(const sta_view_args *args, const sta_strata_info *info)
{
    if (args->colour_mode >= 0) {
        return args->colour_mode;
    }
    return (info->layout.attributes & STA_STRATA_ATTR_RGB) ? STA_COLOUR_RGB : STA_COLOUR_ELEVATION;
}

void sta_view_pipeline_options(const sta_view_args *args, sta_pipeline_options *out)
{
    memset(out, 0, sizeof(*out));
    out->mode = args->pipeline;
    out->normals = args->normals;
    out->samples = args->samples;
    out->smooth = args->smooth;
    out->hpr_exhaustive = args->hpr_exhaustive;
    out->hpr_every_pixel = args->hpr_every_pixel;
    out->hpr_block_gaps = args->hpr_block_gaps;
    out->normals_every_pixel = args->normals_every_pixel;
    out->hpr_radius_px = args->hpr_radius_px;
    out->hpr_threshold = (float)args->hpr_threshold;
    out->s0_m = (float)args->s0_m;
    out->no_fill_set = args->no_fill_set;
    memcpy(out->no_fill_classes, args->no_fill, sizeof(out->no_fill_classes));
}

void sta_view_pipeline_label(int mode, const sta_point_size *size, float splat_scale,
                             char *out_text, size_t text_size)
{
    bool sized = mode == STA_PIPELINE_RAW || mode == STA_PIPELINE_EDL;
    if (sized && !sta_point_size_is_one_pixel(size)) {
        char points[64];
        sta_point_size_describe(size, points, sizeof(points));
        snprintf(out_text, text_size, "%s, points %s", sta_pipeline_mode_name(mode), points);
    } else if (mode == STA_PIPELINE_SPLATS && splat_scale != 1.0f) {
        snprintf(out_text, text_size, "%s x%.3g", sta_pipeline_mode_name(mode),
                 (double)splat_scale);
    } else {
        snprintf(out_text, text_size, "%s", sta_pipeline_mode_name(mode));
    }
}

void sta_view_splat_options(const sta_view_args *args, sta_splat_options *out)
{
    memset(out, 0, sizeof(*out));
    out->method = args->splat_method;
    out->scale = (float)args->splat_scale;
}

sta_status sta_view_open_scene(const sta_view_args *args, sta_mirror_set *mirrors,
                               sta_scene **out_scene, sta_error *err)
{
    *out_scene = NULL;
    memset(mirrors, 0, sizeof(*mirrors));
    if (args->mirrors_file) {
        sta_status status = sta_mirror_set_load(args->mirrors_file, mirrors, err);
        if (status != STA_OK) {
            return status;
        }
    }
    sta_scene_options options = { .budget_points = args->budget_points,
                                  .gpu_bytes_cap = args->gpu_mem_mib << 20,
                                  .clip = args->clip,
                                  .min_spacing_px = args->min_spacing_px,
                                  .mirrors = args->mirrors_file ? mirrors : NULL };
    sta_status status = sta_scene_open(args->scene, &options, out_scene, err);
    if (status == STA_OK) {
        sta_scene_set_hide_flags(*out_scene,
                                 args->show_ghosts ? 0u : (unsigned)STA_SCENE_DEFAULT_HIDE_FLAGS);
        sta_scene_set_mirrors(*out_scene, mirrors, args->mirrors_file && !args->no_reflections);
    }
    return status;
}
