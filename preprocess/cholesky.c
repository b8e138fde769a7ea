/* SPDX-License-Identifier: MIT
 * Dense Cholesky factors of small symmetric matrices and their triangular solves. */
#include "cholesky.h"

#include <math.h>
#include <string.h>

bool sta_cholesky(const double *a, int n, double shift, double *l, double *inv)
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
                inv[j] = 1.0 / l[j * n + j];
            } else {
                l[i * n + j] = sum * inv[j];
            }
        }
    }
    return true;
}
