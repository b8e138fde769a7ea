/* SPDX-License-Identifier: MIT
 * Benchmark views. */
#include "bench/bench_cameras.h"

#include <math.h>
#include <string.h>

#include "core/alloc.h"
#include "render/camera_path.h"

static const double degrees = 3.14159265358979323846 / 180.0;

static double extent_of(const double min[3], const double max[3])
{
    double e = 0.0;
    for (int a = 0; a < 3; a++) {
        e = fmax(e, max[a] - min[a]);
    }
    return e;
}

void sta_bench_orbit(const sta_camera *base, const double min[3], const double max[3], int count,
                     sta_camera *out)
{
    for (int i = 0; i < count; i++) {
        sta_camera c = *base;
        c.yaw = (45.0 + 360.0 * i / count) * degrees;
        c.pitch = -30.0 * degrees;
        sta_camera_frame_box(&c, min, max);
        out[i] = c;
    }
}

void sta_bench_street(const sta_camera *base, const double min[3], const double max[3], int count,
                      sta_bench_truth *truth, sta_camera *out)
{
    const double near_m = fmax(1e-3, fmin(0.05, extent_of(min, max) * 1e-5));
    bool scanner = truth && truth->gps_time[1] > truth->gps_time[0];
    for (int i = 0; i < count; i++) {
        sta_camera c = *base;
        c.near_m = near_m;
        c.pitch = -5.0 * degrees;
        double s = count > 1 ? 0.1 + 0.8 * i / (count - 1) : 0.5;
        if (scanner) {
            double t0 = truth->gps_time[0], t1 = truth->gps_time[1];
            double t = t0 + s * (t1 - t0), dt = 0.05 * (t1 - t0) / (count > 1 ? count : 1);
            double p[3], q[3];
            sta_error err = { 0 };
            if (sta_synth_scene_scanner_position(truth->scene, t, p, &err) == STA_OK &&
                sta_synth_scene_scanner_position(truth->scene, t + dt, q, &err) == STA_OK) {
                for (int a = 0; a < 3; a++) {
                    c.position[a] = truth->origin[a] + p[a];
                }
                c.position[2] -= 0.8;
                c.yaw = atan2(q[1] - p[1], q[0] - p[0]);
                out[i] = c;
                continue;
            }
        }
        int axis = max[0] - min[0] >= max[1] - min[1] ? 0 : 1;
        c.position[axis] = min[axis] + s * (max[axis] - min[axis]);
        c.position[1 - axis] = 0.5 * (min[1 - axis] + max[1 - axis]);
        c.position[2] = min[2] + 1.7;
        c.yaw = axis == 0 ? 0.0 : 90.0 * degrees;
        out[i] = c;
    }
}

sta_status sta_bench_path_cameras(const char *path, const sta_camera *base,
                                  sta_camera **out_cameras, size_t *out_count, sta_error *err)
{
    *out_cameras = NULL;
    *out_count = 0;
    sta_camera_path p = { 0 };
    sta_status s = sta_camera_path_load(path, &p, err);
    if (s != STA_OK) {
        return s;
    }
    if (p.count == 0) {
        sta_camera_path_release(&p);
        return sta_fail(err, STA_ERR_FORMAT, "%s: the path has no keyframes", path);
    }
    sta_camera *cameras = sta_alloc_array(p.count, sizeof(*cameras));
    if (!cameras) {
        sta_camera_path_release(&p);
        return sta_fail(err, STA_ERR_NOMEM, "%s: out of memory", path);
    }
    for (size_t i = 0; i < p.count; i++) {
        cameras[i] = *base;
        sta_camera_path_sample(&p, p.keys[i].time_s, &cameras[i]);
    }
    *out_cameras = cameras;
    *out_count = p.count;
    sta_camera_path_release(&p);
    return STA_OK;
}
