/* SPDX-License-Identifier: MIT
 * Dense Cholesky factors of small symmetric matrices and their triangular solves. */
#include "cholesky.h"

#include <math.h>
#include <string.h>

bool sta_cholesky(const double *a, int n, double shift, double *l)
{
    memset(l, 0, sizeof(*l) * (size_t)n * (size_t)n);
    for (int j = 0; j < n; j++) {
        for (int i = j; i < n; i++) {
            double sum = a[i * n + j] + (i == j ? shift : 0.0);
            for (int k = 0; k < j; k++) {
                sum -= l[i * n + k] * l[j * n + k];
            }
            if (i == j) {
                if (!(sum > 0.0)) {
                    return false;
                }
                l[j * n + j] = sqrt(sum);
            } else {
                l[i * n + j] = sum / l[j * n + j];
            }
        }
    }
    return true;
}

void sta_cholesky_solve_lower(const double *l, int n, double *x)
{
    for (int i = 0; i < n; i++) {
        for (int k = 0; k < i; k++) {
            x[i] -= l[i * n + k] * x[k];
        }
        x[i] /= l[i * n + i];
    }
}

void sta_cholesky_solve_upper(const double *l, int n, double *x)
{
    for (int i = n - 1; i >= 0; i--) {
        for (int k = i + 1; k < n; k++) {
            x[i] -= l[k * n + i] * x[k];
        }
        x[i] /= l[i * n + i];
    }
}
