/* SPDX-License-Identifier: MIT
 * Katz's operator with R per region of a view (see katz_local.h). */
#include "bench/katz_local.h"

#include "core/alloc.h"

// Summed-area table of the occupied pixels: sum[(y + 1) * (w + 1) + x + 1] counts the
// points in [0, x] x [0, y].
static void occupancy_table(const uint32_t *pixel, size_t count, int w, int h, uint32_t *sum)
{
    const size_t stride = (size_t)w + 1;
    for (size_t i = 0; i < stride * ((size_t)h + 1); i++) {
        sum[i] = 0;
    }
    for (size_t i = 0; i < count; i++) {
        const size_t x = pixel[i] % (uint32_t)w, y = pixel[i] / (uint32_t)w;
        sum[(y + 1) * stride + x + 1] = 1;
    }
    for (size_t y = 1; y <= (size_t)h; y++) {
        for (size_t x = 1; x <= (size_t)w; x++) {
            sum[y * stride + x] +=
                sum[(y - 1) * stride + x] + sum[y * stride + x - 1] - sum[(y - 1) * stride + x - 1];
        }
    }
}

// Fraction of the pixels of the window around (x, y), clipped to the view, holding a point.
static double occupancy(const uint32_t *sum, int w, int h, int x, int y)
{
    const int r = STA_KATZ_LOCAL_WINDOW_PX;
    const int x0 = x - r > 0 ? x - r : 0, y0 = y - r > 0 ? y - r : 0;
    const int x1 = x + r < w - 1 ? x + r : w - 1, y1 = y + r < h - 1 ? y + r : h - 1;
    const size_t stride = (size_t)w + 1;
    const uint32_t n = sum[(size_t)(y1 + 1) * stride + (size_t)(x1 + 1)] -
                       sum[(size_t)y0 * stride + (size_t)(x1 + 1)] -
                       sum[(size_t)(y1 + 1) * stride + (size_t)x0] +
                       sum[(size_t)y0 * stride + (size_t)x0];
    return (double)n / (double)((x1 - x0 + 1) * (y1 - y0 + 1));
}

sta_status sta_katz_local_visible(const double (*relative)[3], const uint32_t *pixel, size_t count,
                                  int width, int height, const sta_katz_params *params,
                                  uint8_t *out_visible, size_t *out_sparse, sta_katz_stats *stats,
                                  sta_error *err)
{
    *out_sparse = 0;
    if (width <= 0 || height <= 0 || !(params->radius_m > 0.0)) {
        return sta_fail(err, STA_ERR_ARG, "katz local: a %dx%d view with R %g m", width, height,
                        params->radius_m);
    }
    const size_t pixels = (size_t)width * (size_t)height;
    for (size_t i = 0; i < count; i++) {
        if (pixel[i] >= pixels) {
            return sta_fail(err, STA_ERR_ARG,
                            "katz local: point %zu is in pixel %u of a %dx%d view", i, pixel[i],
                            width, height);
        }
    }
    uint32_t *sum = sta_alloc_array(((size_t)width + 1) * ((size_t)height + 1), sizeof(uint32_t));
    uint8_t *sparse_flags = sta_alloc_array(count ? count : 1, 1);
    sta_status s = STA_OK;
    if (!sum || !sparse_flags) {
        s = sta_fail(err, STA_ERR_NOMEM, "katz local: out of memory for a %dx%d view", width,
                     height);
        goto out;
    }
    s = sta_katz_visible(relative, count, (const double[3]){ 0.0, 0.0, 0.0 }, params, out_visible,
                         stats, err);
    if (s != STA_OK) {
        goto out;
    }
    sta_katz_params small = *params;
    small.radius_m = params->radius_m / STA_KATZ_LOCAL_DIVISOR;
    sta_katz_stats small_stats;
    s = sta_katz_visible(relative, count, (const double[3]){ 0.0, 0.0, 0.0 }, &small, sparse_flags,
                         &small_stats, err);
    if (s != STA_OK) {
        goto out;
    }
    stats->hull_ms += small_stats.hull_ms;
    stats->total_ms += small_stats.total_ms;
    occupancy_table(pixel, count, width, height, sum);
    size_t visible = 0;
    for (size_t i = 0; i < count; i++) {
        const int x = (int)(pixel[i] % (uint32_t)width), y = (int)(pixel[i] / (uint32_t)width);
        if (occupancy(sum, width, height, x, y) < STA_KATZ_LOCAL_SPARSE) {
            out_visible[i] = sparse_flags[i];
            (*out_sparse)++;
        }
        visible += out_visible[i];
    }
    stats->visible_count = visible;
out:
    sta_free(sum);
    sta_free(sparse_flags);
    return s;
}
