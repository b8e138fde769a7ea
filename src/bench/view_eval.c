/* SPDX-License-Identifier: MIT
 * Scoring one view against the truth. */
#include "bench/view_eval.h"

#include <math.h>
#include <stdbool.h>
#include <string.h>

#include "core/alloc.h"
#include "render/ref/screen_space.h"

sta_status sta_view_truth_compute(sta_bench_truth *truth, const sta_camera *camera,
                                  sta_view_truth *out, sta_error *err)
{
    memset(out, 0, sizeof(*out));
    const int w = camera->width_px, h = camera->height_px;
    const size_t n = (size_t)w * (size_t)h;
    out->depth_m = sta_alloc_array(n, sizeof(float));
    out->normal = sta_alloc_array(n, 3 * sizeof(float));
    out->glass_depth_m = sta_alloc_array(n, sizeof(float));
    out->classification = sta_calloc(n ? n : 1, 1);
    if (!out->depth_m || !out->normal || !out->glass_depth_m || !out->classification) {
        sta_view_truth_release(out);
        return sta_fail(err, STA_ERR_NOMEM, "out of memory for the truth of a %dx%d view", w, h);
    }
    out->width = w;
    out->height = h;
    double f[3], r[3], u[3];
    sta_camera_basis(camera, f, r, u);
    for (int y = 0; y < h; y++) {
        for (int x = 0; x < w; x++) {
            size_t i = (size_t)y * (size_t)w + (size_t)x;
            double dir[3], cosine;
            sta_bench_pixel_ray(camera, x, y, dir, &cosine);
            sta_synth_hit hit;
            float *n3 = out->normal + 3 * i;
            if (!sta_bench_truth_ray(truth, camera->position, dir, (double)INFINITY, &hit)) {
                out->depth_m[i] = out->glass_depth_m[i] = NAN;
                n3[0] = n3[1] = n3[2] = 0.0f;
                continue;
            }
            out->hit_count++;
            out->classification[i] = hit.classification;
            out->depth_m[i] = (float)(hit.t * cosine);
            sta_synth_hit glass;
            out->glass_depth_m[i] =
                sta_bench_truth_ray_glass(truth, camera->position, dir, hit.t, &glass)
                    ? (float)(glass.t * cosine)
                    : out->depth_m[i];
            const double *nw = hit.normal;
            double side = nw[0] * dir[0] + nw[1] * dir[1] + nw[2] * dir[2] > 0.0 ? -1.0 : 1.0;
            n3[0] = (float)(side * (nw[0] * r[0] + nw[1] * r[1] + nw[2] * r[2]));
            n3[1] = (float)(side * (nw[0] * u[0] + nw[1] * u[1] + nw[2] * u[2]));
            n3[2] = (float)(-side * (nw[0] * f[0] + nw[1] * f[1] + nw[2] * f[2]));
        }
    }
    return STA_OK;
}

void sta_view_truth_release(sta_view_truth *v)
{
    sta_free(v->depth_m);
    sta_free(v->normal);
    sta_free(v->glass_depth_m);
    sta_free(v->classification);
    memset(v, 0, sizeof(*v));
}

uint64_t sta_view_truth_leave_out_classes(const sta_view_truth *v, const uint32_t *set, int words,
                                          uint8_t *counted, uint8_t *sampled)
{
    const size_t n = (size_t)v->width * (size_t)v->height;
    uint64_t left_out = 0;
    for (size_t i = 0; i < n; i++) {
        int c = v->classification && !isnan(v->depth_m[i]) ? v->classification[i] : -1;
        bool out = c >= 0 && c / 32 < words && ((set[c / 32] >> (c % 32)) & 1u);
        counted[i] = !out;
        if (sampled && out) {
            sampled[i] = 0;
        }
        left_out += out;
    }
    return left_out;
}

sta_status sta_view_points_from_depth(const sta_camera *camera, const float *depth,
                                      sta_view_points *out, sta_error *err)
{
    memset(out, 0, sizeof(*out));
    const int w = camera->width_px, h = camera->height_px;
    const size_t n = (size_t)w * (size_t)h;
    size_t count = 0;
    for (size_t i = 0; i < n; i++) {
        count += depth[i] > 0.0f;
    }
    size_t alloc = count ? count : 1;
    out->pixel = sta_alloc_array(alloc, sizeof(*out->pixel));
    out->world = sta_alloc_array(alloc, sizeof(*out->world));
    out->visible = sta_calloc(alloc, 1);
    if (!out->pixel || !out->world || !out->visible) {
        sta_view_points_release(out);
        return sta_fail(err, STA_ERR_NOMEM, "out of memory for %zu view points", count);
    }
    const double tan_y = tan(0.5 * camera->fov_y);
    const double tan_x = tan_y * (double)w / (double)h;
    for (int row = 0; row < h; row++) {
        const int y = h - 1 - row; // read-back rows run top first
        for (int x = 0; x < w; x++) {
            float d = depth[(size_t)row * (size_t)w + (size_t)x];
            if (!(d > 0.0f)) {
                continue;
            }
            double distance = camera->near_m / (double)d;
            double cam[3] = { (((double)x + 0.5) / w * 2.0 - 1.0) * tan_x * distance,
                              (((double)y + 0.5) / h * 2.0 - 1.0) * tan_y * distance, -distance };
            double offset[3];
            sta_bench_camera_to_world(camera, cam, offset);
            size_t k = out->count++;
            out->pixel[k] = (uint32_t)((size_t)y * (size_t)w + (size_t)x);
            for (int a = 0; a < 3; a++) {
                out->world[k][a] = camera->position[a] + offset[a];
            }
        }
    }
    return STA_OK;
}

void sta_view_points_classify(sta_bench_truth *truth, const sta_camera *camera, double tolerance_m,
                              sta_view_points *points)
{
    for (size_t i = 0; i < points->count; i++) {
        points->visible[i] =
            sta_bench_truth_point_visible(truth, camera->position, points->world[i], tolerance_m);
    }
}

void sta_view_points_release(sta_view_points *p)
{
    sta_free(p->pixel);
    sta_free(p->world);
    sta_free(p->visible);
    memset(p, 0, sizeof(*p));
}

void sta_eval_hpr(const sta_view_points *points, const sta_image *label, sta_confusion *out)
{
    sta_eval_hpr_masked(points, label, NULL, out);
}

void sta_eval_hpr_masked(const sta_view_points *points, const sta_image *label,
                         const uint8_t *scored, sta_confusion *out)
{
    memset(out, 0, sizeof(*out));
    for (size_t i = 0; i < points->count; i++) {
        if (scored && !scored[points->pixel[i]]) {
            continue;
        }
        float l = label->data[(size_t)points->pixel[i] * (size_t)label->channels];
        sta_confusion_add(out, l == STA_LABEL_VISIBLE, points->visible[i]);
    }
}

static sta_status check_size(const sta_view_truth *v, const sta_image *image, const char *what,
                             sta_error *err)
{
    if (image->width != v->width || image->height != v->height || image->channels < 4) {
        return sta_fail(err, STA_ERR_ARG, "%s buffer is %dx%d with %d channels, the view %dx%d",
                        what, image->width, image->height, image->channels, v->width, v->height);
    }
    return STA_OK;
}

// The point the ray through pixel (x, y) truly hits, world coordinates; false on a miss.
// Both images of the normal metrics that read the fill, checked against the view's size.
static sta_status check_normal_and_filled(const sta_view_truth *v, const sta_image *normal,
                                          const sta_image *filled, sta_error *err)
{
    sta_status s = check_size(v, normal, "normal", err);
    return s == STA_OK ? check_size(v, filled, "filled", err) : s;
}

static bool truth_hit(const sta_view_truth *v, const sta_camera *camera, int x, int y,
                      double out[3])
{
    double depth = (double)v->depth_m[(size_t)y * (size_t)v->width + (size_t)x];
    if (!(depth > 0.0)) {
        return false;
    }
    double dir[3], cosine;
    sta_bench_pixel_ray(camera, x, y, dir, &cosine);
    for (int a = 0; a < 3; a++) {
        out[a] = camera->position[a] + dir[a] * (depth / cosine);
    }
    return true;
}

// Marks the pixels sampled by a view point within radius_m of the true hit; with
// `face`, only by points on their own pixel's true surface whose normal agrees.
static sta_status sampled_search(const sta_view_truth *v, const sta_camera *camera,
                                 const sta_view_points *points, double radius_m, bool face,
                                 uint8_t *out_sampled, sta_error *err)
{
    const int w = v->width, h = v->height;
    const size_t n = (size_t)w * (size_t)h;
    memset(out_sampled, 0, n);
    int32_t *at = sta_alloc_array(n ? n : 1, sizeof(int32_t)); // pixel -> view point
    if (!at) {
        return sta_fail(err, STA_ERR_NOMEM, "out of memory for the sampled pixels of %dx%d", w, h);
    }
    for (size_t i = 0; i < n; i++) {
        at[i] = -1;
    }
    const double r2 = radius_m * radius_m;
    for (size_t k = 0; k < points->count; k++) {
        uint32_t p = points->pixel[k];
        double own[3], d2 = 0.0;
        if (face) { // on its own pixel's true surface, else it samples no face
            if (!truth_hit(v, camera, (int)(p % (uint32_t)w), (int)(p / (uint32_t)w), own)) {
                continue;
            }
            for (int a = 0; a < 3; a++) {
                double d = points->world[k][a] - own[a];
                d2 += d * d;
            }
            if (!(d2 <= r2)) {
                continue;
            }
        }
        at[p] = (int32_t)k;
    }
    const double face_cos = cos(STA_VIEW_FACE_ANGLE_DEG * 3.14159265358979323846 / 180.0);
    const double px_per_m = (double)h / (2.0 * tan(0.5 * camera->fov_y)); // at depth 1
    for (int y = 0; y < h; y++) {
        for (int x = 0; x < w; x++) {
            size_t i = (size_t)y * (size_t)w + (size_t)x;
            double depth = (double)v->depth_m[i], hit[3];
            if (!truth_hit(v, camera, x, y, hit)) {
                continue;
            }
            const float *normal = v->normal + 3 * i;
            double reach = ceil(radius_m * px_per_m / depth);
            int r_px = reach < 1.0 ? 1
                                   : (reach > STA_VIEW_SAMPLED_MAX_PX ? STA_VIEW_SAMPLED_MAX_PX
                                                                      : (int)reach);
            bool found = false;
            for (int ring = 0; ring <= r_px && !found; ring++) {
                for (int dy = -ring; dy <= ring && !found; dy++) {
                    int step = (dy == -ring || dy == ring) ? 1 : 2 * ring; // the ring only
                    for (int dx = -ring; dx <= ring && !found; dx += step > 0 ? step : 1) {
                        int xx = x + dx, yy = y + dy;
                        if (xx < 0 || yy < 0 || xx >= w || yy >= h) {
                            continue;
                        }
                        size_t q = (size_t)yy * (size_t)w + (size_t)xx;
                        int32_t k = at[q];
                        if (k < 0) {
                            continue;
                        }
                        if (face) {
                            const float *m = v->normal + 3 * q;
                            double dot = (double)normal[0] * (double)m[0] +
                                         (double)normal[1] * (double)m[1] +
                                         (double)normal[2] * (double)m[2];
                            if (!(dot >= face_cos)) {
                                continue;
                            }
                        }
                        double d2 = 0.0;
                        for (int a = 0; a < 3; a++) {
                            double d = points->world[k][a] - hit[a];
                            d2 += d * d;
                        }
                        found = d2 <= r2;
                    }
                }
            }
            out_sampled[i] = found;
        }
    }
    sta_free(at);
    return STA_OK;
}

sta_status sta_view_truth_sampled(const sta_view_truth *v, const sta_camera *camera,
                                  const sta_view_points *points, double radius_m,
                                  uint8_t *out_sampled, sta_error *err)
{
    return sampled_search(v, camera, points, radius_m, false, out_sampled, err);
}

sta_status sta_view_truth_face_sampled(const sta_view_truth *v, const sta_camera *camera,
                                       const sta_view_points *points, double radius_m,
                                       uint8_t *out_sampled, sta_error *err)
{
    return sampled_search(v, camera, points, radius_m, true, out_sampled, err);
}

// The angle in degrees between pixel i's estimated normal and the truth's, or NAN where
// the pixel has no normal, no truth hit, is not counted (`sampled`), or the estimate is a
// zero vector. `truth_z` takes the truth normal's z (camera space: the view axis).
static double counted_normal_angle(const sta_view_truth *v, const sta_image *normal,
                                   const uint8_t *sampled, size_t i, double *truth_z)
{
    const float *e = normal->data + 4 * i;
    if (!(e[3] > 0.5f) || isnan(v->depth_m[i]) || (sampled && !sampled[i])) {
        return (double)NAN;
    }
    const double estimated[3] = { (double)e[0], (double)e[1], (double)e[2] };
    const float *t = v->normal + 3 * i;
    const double truth[3] = { (double)t[0], (double)t[1], (double)t[2] };
    if (truth_z) {
        *truth_z = truth[2];
    }
    return sta_angle_deg(estimated, truth);
}

sta_status sta_eval_normals(const sta_view_truth *v, const sta_image *normal,
                            const uint8_t *sampled, sta_error_summary *out, sta_error *err)
{
    sta_status s = check_size(v, normal, "normal", err);
    if (s != STA_OK) {
        return s;
    }
    const size_t n = (size_t)v->width * (size_t)v->height;
    double *values = sta_alloc_array(n ? n : 1, sizeof(double));
    if (!values) {
        return sta_fail(err, STA_ERR_NOMEM, "out of memory for %zu normal errors", n);
    }
    size_t count = 0;
    for (size_t i = 0; i < n; i++) {
        double angle = counted_normal_angle(v, normal, sampled, i, NULL);
        if (!isnan(angle)) {
            values[count++] = angle;
        }
    }
    sta_error_summarise(values, count, out);
    sta_free(values);
    return STA_OK;
}

sta_status sta_eval_normals_off(const sta_view_truth *v, const sta_image *normal,
                                const uint8_t *sampled, sta_normal_off_share *out, sta_error *err)
{
    out->all = out->facing = out->other = (double)NAN;
    sta_status s = check_size(v, normal, "normal", err);
    if (s != STA_OK) {
        return s;
    }
    const double facing_cos = cos(STA_VIEW_FACING_ANGLE_DEG * 3.14159265358979323846 / 180.0);
    const size_t n = (size_t)v->width * (size_t)v->height;
    uint64_t count = 0, off_facing = 0, off_other = 0;
    for (size_t i = 0; i < n; i++) {
        double truth_z = 0.0;
        double angle = counted_normal_angle(v, normal, sampled, i, &truth_z);
        if (isnan(angle)) {
            continue; // as sta_eval_normals
        }
        count++;
        if (angle > STA_VIEW_NORMAL_OFF_DEG) {
            if (fabs(truth_z) >= facing_cos) {
                off_facing++;
            } else {
                off_other++;
            }
        }
    }
    if (count > 0) {
        out->facing = (double)off_facing / (double)count;
        out->other = (double)off_other / (double)count;
        out->all = (double)(off_facing + off_other) / (double)count;
    }
    return STA_OK;
}

// The depth error of each counted pixel; with `glass`, the lesser of the errors against
// the surface behind the glass and against the glass.
sta_status sta_eval_normals_shaded(const sta_view_truth *v, const sta_image *normal,
                                   const sta_image *filled, const uint8_t *counted,
                                   double *out_unknown_share, sta_error_summary *out_shaded,
                                   double *out_off_share, sta_error *err)
{
    *out_unknown_share = *out_off_share = (double)NAN;
    sta_status s = check_normal_and_filled(v, normal, filled, err);
    if (s != STA_OK) {
        return s;
    }
    const size_t n = (size_t)v->width * (size_t)v->height;
    double *values = sta_alloc_array(n ? n : 1, sizeof(double));
    if (!values) {
        return sta_fail(err, STA_ERR_NOMEM, "out of memory for %zu normal errors", n);
    }
    size_t count = 0, unknown = 0, off = 0;
    for (size_t i = 0; i < n; i++) {
        const float *p = filled->data + 4 * i;
        if (!(p[3] > 0.0f) || isnan(v->depth_m[i]) || (counted && !counted[i])) {
            continue;
        }
        const float *e = normal->data + 4 * i;
        // Unknown (no normal): lit as if facing the camera (shade.comp).
        const bool known = e[3] > 0.5f;
        double estimated[3];
        for (int k = 0; k < 3; k++) {
            estimated[k] = known ? (double)e[k] : -(double)p[k];
        }
        const float *t = v->normal + 3 * i;
        const double truth[3] = { (double)t[0], (double)t[1], (double)t[2] };
        double angle = sta_angle_deg(estimated, truth);
        if (isnan(angle)) {
            continue; // as sta_eval_normals (a zero vector)
        }
        values[count++] = angle;
        if (!known) {
            unknown++;
        }
        if (angle > STA_VIEW_NORMAL_OFF_DEG) {
            off++;
        }
    }
    sta_error_summarise(values, count, out_shaded);
    if (count > 0) {
        *out_unknown_share = (double)unknown / (double)count;
        *out_off_share = (double)off / (double)count;
    }
    sta_free(values);
    return STA_OK;
}

sta_status sta_eval_normals_off_fill(const sta_view_truth *v, const sta_image *normal,
                                     const sta_image *filled, double tolerance_m,
                                     const uint8_t *sampled, double *out_share, sta_error *err)
{
    *out_share = (double)NAN;
    sta_status s = check_normal_and_filled(v, normal, filled, err);
    if (s != STA_OK) {
        return s;
    }
    const size_t n = (size_t)v->width * (size_t)v->height;
    uint64_t count = 0, off_fill = 0;
    for (size_t i = 0; i < n; i++) {
        double angle = counted_normal_angle(v, normal, sampled, i, NULL);
        if (isnan(angle)) {
            continue; // as sta_eval_normals
        }
        count++;
        const float *p = filled->data + 4 * i;
        double depth = -(double)p[2];
        bool depth_right = p[3] > 0.0f && fabs(depth - (double)v->depth_m[i]) <= tolerance_m;
        if (angle > STA_VIEW_NORMAL_OFF_DEG && !depth_right) {
            off_fill++;
        }
    }
    if (count > 0) {
        *out_share = (double)off_fill / (double)count;
    }
    return STA_OK;
}

static sta_status eval_depth(const sta_view_truth *v, const sta_image *filled,
                             const uint8_t *sampled, bool glass, sta_error_summary *out,
                             sta_error *err)
{
    sta_status s = check_size(v, filled, "filled", err);
    if (s != STA_OK) {
        return s;
    }
    const size_t n = (size_t)v->width * (size_t)v->height;
    double *values = sta_alloc_array(n ? n : 1, sizeof(double));
    if (!values) {
        return sta_fail(err, STA_ERR_NOMEM, "out of memory for %zu depth errors", n);
    }
    size_t count = 0;
    for (size_t i = 0; i < n; i++) {
        const float *p = filled->data + 4 * i;
        double truth = (double)v->depth_m[i];
        if (!(p[3] > 0.0f) || isnan(truth) || !(truth > 0.0) || (sampled && !sampled[i])) {
            continue;
        }
        double d = -(double)p[2];
        if (!isfinite(d)) {
            continue;
        }
        double e = fabs(d - truth) / truth;
        double g = glass && v->glass_depth_m ? (double)v->glass_depth_m[i] : truth;
        if (g > 0.0 && g < truth) {
            e = fmin(e, fabs(d - g) / g);
        }
        values[count++] = e;
    }
    sta_error_summarise(values, count, out);
    sta_free(values);
    return STA_OK;
}

sta_status sta_eval_depth(const sta_view_truth *v, const sta_image *filled, const uint8_t *sampled,
                          sta_error_summary *out, sta_error *err)
{
    return eval_depth(v, filled, sampled, false, out, err);
}

sta_status sta_eval_depth_glass(const sta_view_truth *v, const sta_image *filled,
                                const uint8_t *sampled, sta_error_summary *out, sta_error *err)
{
    return eval_depth(v, filled, sampled, true, out, err);
}

void sta_eval_surface(const sta_view_truth *v, const sta_camera *camera, const float *depth,
                      double tolerance_m, sta_surface_error *out)
{
    memset(out, 0, sizeof(*out));
    uint64_t hole = 0, see_through = 0, bleed = 0;
    const int w = v->width, h = v->height;
    for (int row = 0; row < h; row++) {
        const int y = h - 1 - row; // read-back rows run top first, the truth's from the bottom
        for (int x = 0; x < w; x++) {
            float d = depth[(size_t)row * (size_t)w + (size_t)x];
            double truth = (double)v->depth_m[(size_t)y * (size_t)w + (size_t)x];
            bool drawn = d > 0.0f, hit = !isnan(truth) && truth > 0.0;
            if (!drawn && !hit) {
                continue;
            }
            out->pixels++;
            if (!drawn) {
                hole++;
                continue;
            }
            double distance = camera->near_m / (double)d; // along the view axis, as the truth
            if (!hit || distance < truth - tolerance_m) {
                bleed++;
            } else if (distance > truth + tolerance_m) {
                see_through++;
            }
        }
    }
    double n = out->pixels ? (double)out->pixels : 1.0;
    out->hole = (double)hole / n;
    out->see_through = (double)see_through / n;
    out->bleed = (double)bleed / n;
    out->error = (double)(hole + see_through + bleed) / n;
}

sta_status sta_eval_border(const sta_view_truth *v, const sta_image *filled, const uint8_t *sampled,
                           uint64_t *out_count, double *out_share, sta_error *err)
{
    sta_status s = check_size(v, filled, "filled", err);
    if (s != STA_OK) {
        return s;
    }
    uint64_t count = 0, empty = 0;
    for (int y = 0; y < v->height; y++) {
        for (int x = 0; x < v->width; x++) {
            bool band = x < STA_BORDER_BAND_PX || y < STA_BORDER_BAND_PX ||
                        x >= v->width - STA_BORDER_BAND_PX || y >= v->height - STA_BORDER_BAND_PX;
            size_t i = (size_t)y * (size_t)v->width + (size_t)x;
            if (!band || isnan(v->depth_m[i]) || (sampled && !sampled[i])) {
                continue;
            }
            count++;
            empty += !(filled->data[4 * i + 3] > 0.0f);
        }
    }
    *out_count = count;
    *out_share = count ? (double)empty / (double)count : (double)NAN;
    return STA_OK;
}
