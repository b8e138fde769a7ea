/* SPDX-License-Identifier: MIT
 * GPS-time bins of point centroids: a hash of bins, merged across threads. */
#include "trajectory.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/alloc.h"
#include "key_slots.h"

/* Steps of one double from key * STA_TRAJECTORY_BIN_S to a bin's first time at most (it
 * lies a few roundings away). */
#define BOUND_STEPS 64

static sta_trajectory_bin *find(const sta_trajectory *t, int64_t key)
{
    if (t->capacity == 0) {
        return NULL;
    }
    size_t mask = t->capacity - 1;
    for (size_t s = sta_key_home_slot((uint64_t)key, mask + 1);; s = (s + 1) & mask) {
        if (t->bins[s].key == key || t->bins[s].key == INT64_MIN) {
            return &t->bins[s];
        }
    }
}

static sta_status grow(sta_trajectory *t, sta_error *err)
{
    size_t capacity = t->capacity ? 2 * t->capacity : 1024;
    sta_trajectory_bin *old = t->bins;
    size_t old_capacity = t->capacity;
    t->bins = sta_alloc_array(capacity, sizeof(*t->bins));
    if (!t->bins) {
        t->bins = old;
        return sta_fail(err, STA_ERR_NOMEM, "trajectory: out of memory");
    }
    t->capacity = capacity;
    t->last = 0;
    for (size_t s = 0; s < capacity; s++) {
        t->bins[s].key = INT64_MIN;
    }
    for (size_t s = 0; s < old_capacity; s++) {
        if (old[s].key != INT64_MIN) {
            *find(t, old[s].key) = old[s];
        }
    }
    sta_free(old);
    return STA_OK;
}

// The bin of `key`, created empty when new.
static sta_trajectory_bin *bin_for(sta_trajectory *t, int64_t key, sta_error *err)
{
    if (2 * (t->count + 1) > t->capacity && grow(t, err) != STA_OK) {
        return NULL;
    }
    sta_trajectory_bin *b = find(t, key);
    if (b->key == INT64_MIN) {
        *b = (sta_trajectory_bin){ .key = key,
                                   .min = { INT32_MAX, INT32_MAX, INT32_MAX },
                                   .max = { INT32_MIN, INT32_MIN, INT32_MIN } };
        t->count++;
    }
    return b;
}

static bool key_of(double gps_time, int64_t *key)
{
    double k = floor(gps_time / STA_TRAJECTORY_BIN_S);
    if (!(fabs(k) < 9e18)) {
        return false; // NaN, infinite or absurd times carry no path
    }
    *key = (int64_t)k;
    return true;
}

// The first time whose bin is at least `key` (key_of is monotonic: the division by a
// positive constant and floor both are): from key * BIN_S, a few roundings off, by steps
// of one double. -HUGE_VAL where it is not found within BOUND_STEPS (absurd times).
static double first_time(int64_t key)
{
    double t = (double)key * STA_TRAJECTORY_BIN_S;
    int64_t k;
    for (int i = 0;; i++) { // down to a time below the bin
        if (i == BOUND_STEPS || !key_of(t, &k)) {
            return -HUGE_VAL;
        }
        if (k < key) {
            break;
        }
        t = nextafter(t, -HUGE_VAL);
    }
    for (int i = 0; i < 2 * BOUND_STEPS; i++) { // then up to the first in the bin or above
        t = nextafter(t, HUGE_VAL);
        if (!key_of(t, &k)) {
            return -HUGE_VAL;
        }
        if (k >= key) {
            return t;
        }
    }
    return -HUGE_VAL;
}

// The times of bin `key` exactly, [*from, *to): a time in it has that key without the
// division (an empty range where not found).
static void bin_times(int64_t key, double *from, double *to)
{
    *from = first_time(key);
    *to = key < INT64_MAX ? first_time(key + 1) : -HUGE_VAL;
    if (*from == -HUGE_VAL || *to == -HUGE_VAL) {
        *from = HUGE_VAL;
        *to = -HUGE_VAL;
    }
}

sta_status sta_trajectory_add_elsewhere(sta_trajectory *t, double gps_time, const int32_t xyz[3],
                                        sta_error *err)
{
    // Points come in runs of one bin (scan order): sta_trajectory_add tested the last
    // slot's times (no division); then its key, then the hash.
    int64_t key;
    if (!key_of(gps_time, &key)) {
        return STA_OK;
    }
    sta_trajectory_bin *b =
        t->last > 0 && t->bins[t->last - 1].key == key ? &t->bins[t->last - 1] : NULL;
    if (!b) {
        b = bin_for(t, key, err);
        if (!b) {
            return STA_ERR_NOMEM;
        }
        t->last = (size_t)(b - t->bins) + 1;
    }
    bin_times(key, &t->last_from, &t->last_to);
    sta_trajectory_bin_add(b, xyz);
    return STA_OK;
}

sta_status sta_trajectory_merge(sta_trajectory *into, const sta_trajectory *from, sta_error *err)
{
    for (size_t s = 0; s < from->capacity; s++) {
        const sta_trajectory_bin *f = &from->bins[s];
        if (f->key == INT64_MIN) {
            continue;
        }
        sta_trajectory_bin *b = bin_for(into, f->key, err);
        if (!b) {
            return STA_ERR_NOMEM;
        }
        for (int a = 0; a < 3; a++) {
            b->sum[a] += f->sum[a];
            b->min[a] = f->min[a] < b->min[a] ? f->min[a] : b->min[a];
            b->max[a] = f->max[a] > b->max[a] ? f->max[a] : b->max[a];
        }
        b->count += f->count;
    }
    return STA_OK;
}

static int compare_i64(const void *a, const void *b)
{
    int64_t x = *(const int64_t *)a, y = *(const int64_t *)b;
    return x < y ? -1 : x > y;
}

void sta_trajectory_finish(sta_trajectory *t, const int64_t scene_min[3],
                           const int64_t scene_max[3])
{
    t->usable = false;
    if (t->count == 0) {
        return;
    }
    int64_t *extent = sta_alloc_array(t->count, sizeof(int64_t));
    if (!extent) {
        return; // no path: the fallback rule orients
    }
    size_t n = 0;
    for (size_t s = 0; s < t->capacity; s++) {
        const sta_trajectory_bin *b = &t->bins[s];
        if (b->key != INT64_MIN) {
            int64_t e = 0;
            for (int a = 0; a < 3; a++) {
                int64_t d = (int64_t)b->max[a] - b->min[a];
                e = d > e ? d : e;
            }
            extent[n++] = e;
        }
    }
    qsort(extent, n, sizeof(int64_t), compare_i64);
    int64_t scene = 0;
    for (int a = 0; a < 3; a++) {
        scene = scene_max[a] - scene_min[a] > scene ? scene_max[a] - scene_min[a] : scene;
    }
    t->usable = n >= 2 && (double)extent[n / 2] < STA_TRAJECTORY_COMPACT_FACTOR * (double)scene;
    sta_free(extent);
}

bool sta_trajectory_at(const sta_trajectory *t, double gps_time, double out[3])
{
    int64_t key;
    if (!key_of(gps_time, &key)) {
        return false;
    }
    const sta_trajectory_bin *b = find(t, key);
    if (!b || b->key != key || b->count == 0) {
        return false;
    }
    for (int a = 0; a < 3; a++) {
        out[a] = (double)b->sum[a] / (double)b->count;
    }
    return true;
}

bool sta_trajectory_memo_move(const sta_trajectory *t, sta_trajectory_memo *memo, double gps_time)
{
    int64_t key;
    if (!key_of(gps_time, &key)) {
        return false;
    }
    if (!memo->valid || memo->key != key) {
        memo->valid = true;
        memo->key = key;
        memo->seen = sta_trajectory_at(t, gps_time, memo->at);
    }
    bin_times(key, &memo->from, &memo->to);
    return true;
}

void sta_trajectory_release(sta_trajectory *t)
{
    sta_free(t->bins);
    t->bins = NULL;
    t->capacity = t->count = t->last = 0;
}
