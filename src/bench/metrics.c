/* SPDX-License-Identifier: MIT
 * Error measures. */
#include "bench/metrics.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/alloc.h"

void sta_confusion_add(sta_confusion *c, int labelled_visible, int truly_visible)
{
    if (labelled_visible) {
        if (truly_visible) {
            c->tp++;
        } else {
            c->fp++;
        }
    } else if (truly_visible) {
        c->fn++;
    } else {
        c->tn++;
    }
}

static double ratio(uint64_t num, uint64_t den)
{
    return den ? (double)num / (double)den : (double)NAN;
}

double sta_confusion_precision(const sta_confusion *c)
{
    return ratio(c->tp, c->tp + c->fp);
}

double sta_confusion_recall(const sta_confusion *c)
{
    return ratio(c->tp, c->tp + c->fn);
}

double sta_confusion_f1(const sta_confusion *c)
{
    return ratio(2 * c->tp, 2 * c->tp + c->fp + c->fn);
}

static int compare_doubles(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : (x > y ? 1 : 0);
}

void sta_error_summarise(double *v, size_t n, sta_error_summary *out)
{
    out->count = n;
    if (n == 0) {
        out->mean = out->median = out->p95 = out->max = (double)NAN;
        return;
    }
    qsort(v, n, sizeof(double), compare_doubles);
    double sum = 0.0;
    for (size_t i = 0; i < n; i++) {
        sum += v[i];
    }
    out->mean = sum / (double)n;
    out->median = n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
    // Nearest rank: the smallest value with at least 95 % of the samples at or below.
    size_t rank = (size_t)ceil(0.95 * (double)n);
    out->p95 = v[(rank > 0 ? rank : 1) - 1];
    out->max = v[n - 1];
}

double sta_angle_deg(const double a[3], const double b[3])
{
    double la = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    double lb = sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
    if (la == 0.0 || lb == 0.0) {
        return (double)NAN;
    }
    // atan2 of |a x b| and a.b stays accurate near 0 and 180 degrees (acos does not).
    double c[3] = { a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                    a[0] * b[1] - a[1] * b[0] };
    double cross = sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
    double dot = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    return atan2(cross, dot) * (180.0 / 3.14159265358979323846);
}

double sta_psnr_rgba8(const uint8_t *a, const uint8_t *b, size_t n)
{
    if (n == 0) {
        return (double)NAN;
    }
    uint64_t sum = 0;
    for (size_t i = 0; i < n; i++) {
        for (int c = 0; c < 3; c++) {
            int d = (int)a[4 * i + c] - (int)b[4 * i + c];
            sum += (uint64_t)(d * d);
        }
    }
    if (sum == 0) {
        return (double)INFINITY;
    }
    double mse = (double)sum / (3.0 * (double)n);
    return 10.0 * log10(255.0 * 255.0 / mse);
}

enum {
    SSIM_RADIUS = 5 /* 11 x 11 window */
};

// Separable Gaussian blur with clamped edges; `tmp` holds one image.
static void blur(const double *in, double *tmp, double *out, int w, int h, const double *k)
{
    for (int y = 0; y < h; y++) {
        for (int x = 0; x < w; x++) {
            double s = 0.0;
            for (int i = -SSIM_RADIUS; i <= SSIM_RADIUS; i++) {
                int xx = x + i < 0 ? 0 : (x + i >= w ? w - 1 : x + i);
                s += k[i + SSIM_RADIUS] * in[(size_t)y * (size_t)w + (size_t)xx];
            }
            tmp[(size_t)y * (size_t)w + (size_t)x] = s;
        }
    }
    for (int y = 0; y < h; y++) {
        for (int x = 0; x < w; x++) {
            double s = 0.0;
            for (int i = -SSIM_RADIUS; i <= SSIM_RADIUS; i++) {
                int yy = y + i < 0 ? 0 : (y + i >= h ? h - 1 : y + i);
                s += k[i + SSIM_RADIUS] * tmp[(size_t)yy * (size_t)w + (size_t)x];
            }
            out[(size_t)y * (size_t)w + (size_t)x] = s;
        }
    }
}

sta_status sta_ssim_rgba8(const uint8_t *a, const uint8_t *b, int w, int h, double *out_ssim,
                          sta_error *err)
{
    if (w <= 0 || h <= 0) {
        return sta_fail(err, STA_ERR_ARG, "SSIM of an empty %dx%d image", w, h);
    }
    const size_t n = (size_t)w * (size_t)h;
    // Planes: x, y, then x^2, y^2, xy; five blurred planes; one scratch.
    double *mem = sta_alloc_array(n, 11 * sizeof(double));
    if (!mem) {
        return sta_fail(err, STA_ERR_NOMEM, "out of memory for SSIM of %dx%d", w, h);
    }
    double *in[5], *mu[5], *tmp = mem + 10 * n;
    for (int p = 0; p < 5; p++) {
        in[p] = mem + (size_t)p * n;
        mu[p] = mem + (size_t)(5 + p) * n;
    }
    for (size_t i = 0; i < n; i++) {
        double x = 0.299 * a[4 * i] + 0.587 * a[4 * i + 1] + 0.114 * a[4 * i + 2];
        double y = 0.299 * b[4 * i] + 0.587 * b[4 * i + 1] + 0.114 * b[4 * i + 2];
        in[0][i] = x;
        in[1][i] = y;
        in[2][i] = x * x;
        in[3][i] = y * y;
        in[4][i] = x * y;
    }
    double k[2 * SSIM_RADIUS + 1], ksum = 0.0;
    for (int i = -SSIM_RADIUS; i <= SSIM_RADIUS; i++) {
        k[i + SSIM_RADIUS] = exp(-(double)(i * i) / (2.0 * 1.5 * 1.5));
        ksum += k[i + SSIM_RADIUS];
    }
    for (int i = 0; i < 2 * SSIM_RADIUS + 1; i++) {
        k[i] /= ksum;
    }
    for (int p = 0; p < 5; p++) {
        blur(in[p], tmp, mu[p], w, h, k);
    }
    const double c1 = (0.01 * 255.0) * (0.01 * 255.0), c2 = (0.03 * 255.0) * (0.03 * 255.0);
    double sum = 0.0;
    for (size_t i = 0; i < n; i++) {
        double mx = mu[0][i], my = mu[1][i];
        double vx = mu[2][i] - mx * mx, vy = mu[3][i] - my * my, cxy = mu[4][i] - mx * my;
        sum +=
            ((2.0 * mx * my + c1) * (2.0 * cxy + c2)) / ((mx * mx + my * my + c1) * (vx + vy + c2));
    }
    *out_ssim = sum / (double)n;
    sta_free(mem);
    return STA_OK;
}
