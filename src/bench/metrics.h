/* SPDX-License-Identifier: MIT
 * Error measures of the benchmark, on plain arrays (no GL, no truth): classification
 * counts and precision / recall / F1, summaries of error samples (mean, median, 95th
 * percentile), angle between directions, and image error (PSNR, SSIM). The exact
 * definitions are in docs/BENCH.md.
 */
#ifndef STA_BENCH_METRICS_H
#define STA_BENCH_METRICS_H

#include <stddef.h>
#include <stdint.h>

#include "core/status.h"

/* Binary classification counts; the positive class is "visible". */
typedef struct sta_confusion {
    uint64_t tp; /* labelled visible, truly visible */
    uint64_t fp; /* labelled visible, truly hidden */
    uint64_t fn; /* labelled hidden, truly visible */
    uint64_t tn; /* labelled hidden, truly hidden */
} sta_confusion;

/* Adds one sample. */
void sta_confusion_add(sta_confusion *c, int labelled_visible, int truly_visible);

/* tp / (tp + fp), tp / (tp + fn), their harmonic mean 2 tp / (2 tp + fp + fn); NaN
 * when the denominator is 0. */
double sta_confusion_precision(const sta_confusion *c);
double sta_confusion_recall(const sta_confusion *c);
double sta_confusion_f1(const sta_confusion *c);

/* Summary of error samples. All NaN (count 0) for no samples. */
typedef struct sta_error_summary {
    uint64_t count;
    double mean;
    double median; /* middle value, mean of the two middle ones for even counts */
    double p95;    /* nearest rank: the ceil(0.95 count)-th smallest value */
    double max;
} sta_error_summary;

/* Summarises `count` values; sorts `values` in place (NaNs must not be present). */
void sta_error_summarise(double *values, size_t count, sta_error_summary *out);

/* Angle in degrees between two non-zero vectors, 0..180 (they need not be unit);
 * NaN when either is zero. */
double sta_angle_deg(const double a[3], const double b[3]);

/* PSNR in dB of two RGBA8 images of `pixel_count` pixels over the R, G, B channels
 * (alpha ignored): 10 log10(255^2 / MSE); +INFINITY when identical, NaN for 0 pixels. */
double sta_psnr_rgba8(const uint8_t *a, const uint8_t *b, size_t pixel_count);

/* Mean SSIM of the luma (0.299 R + 0.587 G + 0.114 B, 0..255) of two RGBA8 images of
 * width x height, with an 11 x 11 Gaussian window (sigma 1.5, weights normalised),
 * C1 = (0.01 * 255)^2, C2 = (0.03 * 255)^2, image edges clamped (replicated), averaged
 * over every pixel. 1 for identical images. STA_ERR_NOMEM, STA_ERR_ARG for empty
 * images. */
sta_status sta_ssim_rgba8(const uint8_t *a, const uint8_t *b, int width, int height,
                          double *out_ssim, sta_error *err);

#endif
