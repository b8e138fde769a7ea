/* SPDX-License-Identifier: MIT
 * Point statistics from a full scan. */
#include "io/cloud_stats.h"

#include <math.h>
#include <string.h>

enum {
    STATS_BATCH_POINTS = 65536
};

static void add_point(sta_cloud_stats *s, uint32_t attributes, const sta_point *p, int32_t imin[3],
                      int32_t imax[3])
{
    const int32_t xyz[3] = { p->X, p->Y, p->Z };
    for (int a = 0; a < 3; a++) {
        if (xyz[a] < imin[a]) {
            imin[a] = xyz[a];
        }
        if (xyz[a] > imax[a]) {
            imax[a] = xyz[a];
        }
    }
    s->by_return[p->return_number & 15]++;
    s->by_class[p->classification]++;
    if (attributes & STA_ATTR_GPS_TIME) {
        if (!isfinite(p->gps_time)) {
            s->gps_nan_count++;
        } else if (s->point_count == s->gps_nan_count) {
            s->gps_min = s->gps_max = p->gps_time; // first finite time
        } else {
            s->gps_min = fmin(s->gps_min, p->gps_time);
            s->gps_max = fmax(s->gps_max, p->gps_time);
        }
    }
    if (attributes & STA_ATTR_RGB) {
        uint16_t m = p->red > p->green ? p->red : p->green;
        m = m > p->blue ? m : p->blue;
        s->rgb_max = m > s->rgb_max ? m : s->rgb_max;
    }
    if (attributes & STA_ATTR_INTENSITY) {
        if (s->point_count == 0 || p->intensity < s->intensity_min) {
            s->intensity_min = p->intensity;
        }
        if (p->intensity > s->intensity_max) {
            s->intensity_max = p->intensity;
        }
    }
    s->point_count++;
}

sta_status sta_cloud_scan_stats(sta_cloud_reader *reader, sta_cloud_stats *out_stats,
                                sta_error *err)
{
    memset(out_stats, 0, sizeof(*out_stats));
    const sta_cloud_info *info = sta_cloud_reader_info(reader);
    sta_point_batch batch;
    sta_status status = sta_point_batch_init(&batch, STATS_BATCH_POINTS, info->extra_size, err);
    if (status != STA_OK) {
        return status;
    }
    status = sta_cloud_seek(reader, 0, err);
    int32_t imin[3] = { INT32_MAX, INT32_MAX, INT32_MAX };
    int32_t imax[3] = { INT32_MIN, INT32_MIN, INT32_MIN };
    while (status == STA_OK) {
        status = sta_cloud_read(reader, &batch, err);
        if (status != STA_OK || batch.count == 0) {
            break;
        }
        for (size_t i = 0; i < batch.count; i++) {
            add_point(out_stats, info->attributes, &batch.points[i], imin, imax);
        }
    }
    sta_point_batch_release(&batch);
    if (status != STA_OK) {
        return status;
    }
    if (out_stats->point_count > 0) {
        // Bounds from the extreme integers: exact, and one multiply per axis.
        for (int a = 0; a < 3; a++) {
            out_stats->min[a] = sta_grid_apply(&info->grid, a, imin[a]);
            out_stats->max[a] = sta_grid_apply(&info->grid, a, imax[a]);
        }
    }
    if (info->attributes & STA_ATTR_RGB) {
        out_stats->colour_bits = out_stats->rgb_max <= 255 ? 8 : 16;
    }
    return sta_cloud_seek(reader, 0, err);
}
