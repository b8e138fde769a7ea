/* SPDX-License-Identifier: MIT
 * Camera paths. */
#include "render/camera_path.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "core/alloc.h"
#include "core/array.h"
#include "core/json_out.h"
#include "render/json_file.h"

static const double pi = 3.14159265358979323846;

sta_status sta_camera_path_add(sta_camera_path *p, const sta_camera *c, double time_s,
                               sta_error *err)
{
    if (p->count > 0 && !(time_s > p->keys[p->count - 1].time_s)) {
        return sta_fail(err, STA_ERR_ARG, "keyframe time %.3f s is not after %.3f s", time_s,
                        p->keys[p->count - 1].time_s);
    }
    if (sta_array_reserve((void **)&p->keys, &p->capacity, p->count + 1, sizeof(*p->keys), 16,
                          NULL) != STA_OK) {
        return sta_fail(err, STA_ERR_NOMEM, "out of memory for keyframes");
    }
    sta_keyframe *k = &p->keys[p->count++];
    k->time_s = time_s;
    memcpy(k->position, c->position, sizeof(k->position));
    k->yaw = c->yaw;
    k->pitch = c->pitch;
    k->fov_y = c->fov_y;
    return STA_OK;
}

static double number_of(const cJSON *object, const char *key, bool *ok)
{
    const cJSON *item = cJSON_GetObjectItemCaseSensitive(object, key);
    if (!cJSON_IsNumber(item) || !isfinite(item->valuedouble)) {
        *ok = false;
        return 0.0;
    }
    return item->valuedouble;
}

sta_status sta_camera_path_load(const char *path, sta_camera_path *out, sta_error *err)
{
    memset(out, 0, sizeof(*out));
    cJSON *root = NULL;
    sta_status status = sta_json_file_load(path, &root, err);
    if (status != STA_OK) {
        return status;
    }
    const cJSON *keys = cJSON_GetObjectItemCaseSensitive(root, "keyframes");
    if (!cJSON_IsArray(keys) || cJSON_GetArraySize(keys) < 1) {
        cJSON_Delete(root);
        return sta_fail(err, STA_ERR_FORMAT, "%s: no \"keyframes\" array", path);
    }
    int index = 0;
    const cJSON *key;
    cJSON_ArrayForEach(key, keys)
    {
        bool ok = cJSON_IsObject(key);
        sta_camera c;
        memset(&c, 0, sizeof(c));
        double time_s = number_of(key, "time", &ok);
        const cJSON *position = cJSON_GetObjectItemCaseSensitive(key, "position");
        if (!cJSON_IsArray(position) || cJSON_GetArraySize(position) != 3) {
            ok = false;
        } else {
            for (int a = 0; a < 3; a++) {
                const cJSON *v = cJSON_GetArrayItem(position, a);
                ok = ok && cJSON_IsNumber(v) && isfinite(v->valuedouble);
                c.position[a] = ok ? v->valuedouble : 0.0;
            }
        }
        c.yaw = number_of(key, "yaw", &ok) * pi / 180.0;
        c.pitch = number_of(key, "pitch", &ok) * pi / 180.0;
        c.fov_y = number_of(key, "fov", &ok) * pi / 180.0;
        if (!ok || !(c.fov_y > 0 && c.fov_y < pi) || fabs(c.pitch) > pi / 2) {
            status = sta_fail(err, STA_ERR_FORMAT,
                              "%s: keyframe %d needs numbers time, position [x,y,z], yaw, "
                              "pitch (-90..90) and fov (0..180)",
                              path, index);
            break;
        }
        status = sta_camera_path_add(out, &c, time_s, err);
        if (status == STA_ERR_ARG) { // times that do not increase: the file is wrong
            status = STA_ERR_FORMAT;
            if (err) {
                err->code = STA_ERR_FORMAT;
            }
        }
        if (status != STA_OK) {
            sta_error_prefix(err, "%s: keyframe %d", path, index);
            break;
        }
        index++;
    }
    cJSON_Delete(root);
    if (status != STA_OK) {
        sta_camera_path_release(out);
    }
    return status;
}

sta_status sta_camera_path_save(const char *path, const sta_camera_path *p, sta_error *err)
{
    FILE *f = fopen(path, "w");
    if (!f) {
        return sta_fail(err, STA_ERR_IO, "%s: cannot write the camera path", path);
    }
    sta_json_out j;
    sta_json_init(&j, f, true);
    sta_json_begin_object(&j);
    sta_json_key(&j, "version");
    sta_json_int(&j, 1);
    sta_json_key(&j, "keyframes");
    sta_json_begin_array(&j);
    for (size_t i = 0; i < p->count; i++) {
        const sta_keyframe *k = &p->keys[i];
        sta_json_begin_object(&j);
        sta_json_key(&j, "time");
        sta_json_double(&j, k->time_s);
        sta_json_key(&j, "position");
        sta_json_begin_array(&j);
        for (int a = 0; a < 3; a++) {
            sta_json_double(&j, k->position[a]);
        }
        sta_json_end_array(&j);
        sta_json_key(&j, "yaw");
        sta_json_double(&j, k->yaw * 180.0 / pi);
        sta_json_key(&j, "pitch");
        sta_json_double(&j, k->pitch * 180.0 / pi);
        sta_json_key(&j, "fov");
        sta_json_double(&j, k->fov_y * 180.0 / pi);
        sta_json_end_object(&j);
    }
    sta_json_end_array(&j);
    sta_json_end_object(&j);
    sta_json_finish(&j);
    if (fclose(f) != 0) {
        return sta_fail(err, STA_ERR_IO, "%s: cannot finish writing the camera path", path);
    }
    return STA_OK;
}

// Position on segment i (keys i .. i+1) at s in 0..1: a Hermite curve whose tangent at
// each key is the difference of its neighbours over their time apart (Catmull-Rom with
// the keys' times; with evenly spaced keys it is the uniform Catmull-Rom spline). At
// the path's ends a neighbour is the key itself, one segment's time away.
static void spline_point(const sta_camera_path *p, size_t i, double s, double out[3])
{
    const sta_keyframe *k = p->keys, *a = &k[i], *b = &k[i + 1];
    double h = b->time_s - a->time_s;
    const sta_keyframe *before = i > 0 ? &k[i - 1] : a;
    const sta_keyframe *after = i + 2 < p->count ? &k[i + 2] : b;
    double t_before = i > 0 ? before->time_s : a->time_s - h;
    double t_after = i + 2 < p->count ? after->time_s : b->time_s + h;
    double s2 = s * s, s3 = s2 * s;
    double h00 = 2 * s3 - 3 * s2 + 1, h10 = s3 - 2 * s2 + s, h01 = -2 * s3 + 3 * s2, h11 = s3 - s2;
    for (int axis = 0; axis < 3; axis++) {
        double m_a = (b->position[axis] - before->position[axis]) / (b->time_s - t_before);
        double m_b = (after->position[axis] - a->position[axis]) / (t_after - a->time_s);
        out[axis] =
            h00 * a->position[axis] + h10 * h * m_a + h01 * b->position[axis] + h11 * h * m_b;
    }
}

static double angle_lerp(double a, double b, double t)
{
    double d = fmod(b - a + 3.0 * pi, 2.0 * pi) - pi; // shortest signed difference
    return a + d * t;
}

void sta_camera_path_sample(const sta_camera_path *p, double time_s, sta_camera *c)
{
    if (p->count == 0) {
        return;
    }
    const sta_keyframe *k = p->keys;
    size_t i = 0;
    if (time_s <= k[0].time_s || p->count == 1) {
        i = 0;
        time_s = k[0].time_s;
    } else if (time_s >= k[p->count - 1].time_s) {
        i = p->count - 2;
        time_s = k[p->count - 1].time_s;
    } else {
        while (i + 1 < p->count && k[i + 1].time_s <= time_s) {
            i++;
        }
    }
    if (p->count == 1) {
        memcpy(c->position, k[0].position, sizeof(c->position));
        c->yaw = k[0].yaw;
        c->pitch = k[0].pitch;
        c->fov_y = k[0].fov_y;
        return;
    }
    const sta_keyframe *a = &k[i], *b = &k[i + 1];
    double t = (time_s - a->time_s) / (b->time_s - a->time_s);
    spline_point(p, i, t, c->position);
    c->yaw = angle_lerp(a->yaw, b->yaw, t);
    c->pitch = a->pitch + (b->pitch - a->pitch) * t;
    c->fov_y = a->fov_y + (b->fov_y - a->fov_y) * t;
}

enum {
    CHORDS = 64, /* chords per segment when measuring its length */
    SUBKEYS = 16 /* keys per segment after retiming at constant speed */
};

// Cumulative length along segment i at t = j / CHORDS, j = 0 .. CHORDS.
static void segment_lengths(const sta_camera_path *p, size_t i, double out[CHORDS + 1])
{
    double previous[3], point[3];
    spline_point(p, i, 0.0, previous);
    out[0] = 0.0;
    for (int j = 1; j <= CHORDS; j++) {
        spline_point(p, i, (double)j / CHORDS, point);
        double d2 = 0.0;
        for (int axis = 0; axis < 3; axis++) {
            d2 += (point[axis] - previous[axis]) * (point[axis] - previous[axis]);
        }
        out[j] = out[j - 1] + sqrt(d2);
        memcpy(previous, point, sizeof(previous));
    }
}

// The spline parameter where the length along the segment reaches `s`.
static double parameter_at(const double lengths[CHORDS + 1], double s)
{
    int j = 1;
    while (j < CHORDS && lengths[j] < s) {
        j++;
    }
    double span = lengths[j] - lengths[j - 1];
    double f = span > 0 ? (s - lengths[j - 1]) / span : 0.0;
    return (j - 1 + fmax(0.0, fmin(1.0, f))) / CHORDS;
}

sta_status sta_camera_path_set_speed(sta_camera_path *p, double speed_mps, sta_error *err)
{
    if (!(speed_mps > 0) || !isfinite(speed_mps)) {
        return sta_fail(err, STA_ERR_ARG, "path speed must be a positive number of m/s, got %g",
                        speed_mps);
    }
    if (p->count < 2) {
        return STA_OK;
    }
    // Each segment becomes SUBKEYS keys at equal lengths along the original spline, so
    // that playback between them (nearly straight, nearly even) keeps the speed.
    sta_camera_path out = { 0 };
    const double turn_rate = STA_CAMERA_PATH_TURN_DEG_PER_S * pi / 180.0;
    double time_s = p->keys[0].time_s, lengths[CHORDS + 1];
    sta_status status = STA_OK;
    for (size_t i = 0; i + 1 < p->count && status == STA_OK; i++) {
        const sta_keyframe *a = &p->keys[i], *b = &p->keys[i + 1];
        segment_lengths(p, i, lengths);
        double turn = fmax(fabs(angle_lerp(a->yaw, b->yaw, 1.0) - a->yaw),
                           fmax(fabs(b->pitch - a->pitch), fabs(b->fov_y - a->fov_y)));
        double duration = fmax(lengths[CHORDS] / speed_mps, turn / turn_rate);
        duration = fmax(duration, 1e-3 * SUBKEYS); // keys stay strictly increasing
        int last = i + 2 == p->count ? SUBKEYS : SUBKEYS - 1;
        for (int k = 0; k <= last && status == STA_OK; k++) {
            double f = (double)k / SUBKEYS;
            // Where the segment only turns, spread the keys evenly in the spline's t.
            double t = lengths[CHORDS] > 0 ? parameter_at(lengths, f * lengths[CHORDS]) : f;
            sta_camera c;
            memset(&c, 0, sizeof(c));
            spline_point(p, i, t, c.position);
            c.yaw = angle_lerp(a->yaw, b->yaw, t);
            c.pitch = a->pitch + (b->pitch - a->pitch) * t;
            c.fov_y = a->fov_y + (b->fov_y - a->fov_y) * t;
            status = sta_camera_path_add(&out, &c, time_s + duration * f, err);
        }
        time_s += duration;
    }
    if (status != STA_OK) {
        sta_camera_path_release(&out);
        return status;
    }
    sta_camera_path_release(p);
    *p = out;
    return STA_OK;
}

double sta_camera_path_duration(const sta_camera_path *p)
{
    return p->count < 2 ? 0.0 : p->keys[p->count - 1].time_s - p->keys[0].time_s;
}

void sta_camera_path_release(sta_camera_path *p)
{
    sta_free(p->keys);
    memset(p, 0, sizeof(*p));
}
