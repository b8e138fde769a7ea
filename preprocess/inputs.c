/* SPDX-License-Identifier: MIT
 * Opening the converter's inputs and choosing the output grid.
 *
 * Output grid: when every input has the same scale and offset (tiles of one survey,
 * usually), the output keeps it and integer coordinates pass through unchanged. When
 * they differ, output_grid.c chooses a common grid on which every input lies exactly
 * where one exists (then points move in integers, losslessly), and otherwise rounds
 * with a warning naming the input and axis.
 */
#include "inputs.h"

#include <math.h>
#include <string.h>

#include "core/alloc.h"
#include "core/log.h"

static bool same_grid(const sta_grid *a, const sta_grid *b)
{
    return memcmp(a->scale, b->scale, sizeof(a->scale)) == 0 &&
           memcmp(a->offset, b->offset, sizeof(a->offset)) == 0;
}

static bool same_extra_layout(const sta_cloud_info *a, const sta_cloud_info *b)
{
    if (a->extra_size != b->extra_size || a->extra_dim_count != b->extra_dim_count) {
        return false;
    }
    for (size_t i = 0; i < a->extra_dim_count; i++) {
        const sta_extra_dim *x = &a->extra_dims[i], *y = &b->extra_dims[i];
        if (strcmp(x->name, y->name) != 0 || x->data_type != y->data_type ||
            x->size_bytes != y->size_bytes || x->offset_bytes != y->offset_bytes) {
            return false;
        }
    }
    return true;
}

static int64_t to_output_int(const sta_grid *grid, int axis, double real)
{
    return (int64_t)llround((real - grid->offset[axis]) / grid->scale[axis]);
}

sta_status sta_inputs_open(const char *const *paths, size_t count, bool salvage, bool keep_extra,
                           sta_input_set *out_set, sta_error *err)
{
    memset(out_set, 0, sizeof(*out_set));
    if (count == 0) {
        return sta_fail(err, STA_ERR_ARG, "no input files");
    }
    out_set->readers = sta_calloc(count, sizeof(*out_set->readers));
    if (!out_set->readers) {
        return sta_fail(err, STA_ERR_NOMEM, "out of memory for %zu inputs", count);
    }
    out_set->paths = paths;
    out_set->salvage = salvage;
    sta_read_options options = { .salvage_truncated = salvage };
    for (size_t i = 0; i < count; i++) {
        sta_status status = sta_cloud_open(paths[i], &options, &out_set->readers[i], err);
        if (status != STA_OK) {
            sta_inputs_close(out_set);
            return status;
        }
        out_set->count = i + 1;
    }

    const sta_cloud_info *first = sta_cloud_reader_info(out_set->readers[0]);
    out_set->grid = first->grid;
    bool extra_agree = first->extra_size > 0;
    for (size_t i = 0; i < count; i++) {
        const sta_cloud_info *info = sta_cloud_reader_info(out_set->readers[i]);
        out_set->point_count += info->point_count;
        out_set->attributes |= info->attributes;
        out_set->is_regridded |= !same_grid(&info->grid, &first->grid);
        extra_agree = extra_agree && same_extra_layout(first, info);
    }
    if (keep_extra && first->extra_size > 0 && !extra_agree) {
        sta_log_warn("inputs have different extra-bytes layouts: extra dimensions dropped");
    }
    if (keep_extra && extra_agree) {
        out_set->extra_size = first->extra_size;
        out_set->extra_source = first;
    }
    if (out_set->is_regridded) {
        const sta_cloud_info **infos = sta_calloc(count, sizeof(*infos));
        out_set->regrids = sta_calloc(count, sizeof(*out_set->regrids));
        if (!infos || !out_set->regrids) {
            sta_free(infos);
            sta_inputs_close(out_set);
            return sta_fail(err, STA_ERR_NOMEM, "out of memory for %zu inputs", count);
        }
        for (size_t i = 0; i < count; i++) {
            infos[i] = sta_cloud_reader_info(out_set->readers[i]);
        }
        sta_output_grid_choose(infos, count, &out_set->grid, out_set->regrids);
        sta_free(infos);
        sta_log_warn("inputs use different scales/offsets: points are moved to one grid, scale "
                     "%g %g %g, offset %.9g %.9g %.9g",
                     out_set->grid.scale[0], out_set->grid.scale[1], out_set->grid.scale[2],
                     out_set->grid.offset[0], out_set->grid.offset[1], out_set->grid.offset[2]);
    }
    // Declared bounds as a first guess for the root box; the counting pass checks them.
    for (int a = 0; a < 3; a++) {
        out_set->header_min[a] = INT64_MAX;
        out_set->header_max[a] = INT64_MIN;
    }
    for (size_t i = 0; i < count; i++) {
        const sta_cloud_info *info = sta_cloud_reader_info(out_set->readers[i]);
        if (info->point_count == 0) {
            continue;
        }
        for (int a = 0; a < 3; a++) {
            double lo = info->header_min[a], hi = info->header_max[a];
            if (!isfinite(lo) || !isfinite(hi) || lo > hi ||
                fabs(lo - out_set->grid.offset[a]) / out_set->grid.scale[a] > 4e18 ||
                fabs(hi - out_set->grid.offset[a]) / out_set->grid.scale[a] > 4e18) {
                continue; // nonsense header bounds: the counting pass finds real ones
            }
            int64_t ilo = to_output_int(&out_set->grid, a, lo) - 1;
            int64_t ihi = to_output_int(&out_set->grid, a, hi) + 1;
            out_set->header_min[a] = ilo < out_set->header_min[a] ? ilo : out_set->header_min[a];
            out_set->header_max[a] = ihi > out_set->header_max[a] ? ihi : out_set->header_max[a];
        }
    }
    sta_record_layout_init(&out_set->layout, out_set->attributes, out_set->extra_size);
    return STA_OK;
}

void sta_inputs_close(sta_input_set *set)
{
    for (size_t i = 0; i < set->count; i++) {
        sta_cloud_close(set->readers[i]);
    }
    sta_free(set->readers);
    sta_free(set->regrids);
    memset(set, 0, sizeof(*set));
}

bool sta_inputs_to_output(const sta_input_set *set, size_t input, sta_point *point)
{
    if (!set->is_regridded) {
        return true;
    }
    const sta_grid *in = &sta_cloud_reader_info(set->readers[input])->grid;
    return sta_output_grid_apply(&set->regrids[input], in, &set->grid, point);
}
