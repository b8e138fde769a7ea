/* SPDX-License-Identifier: MIT
 * The k-th smallest of an array of floats in linear expected time (quickselect), for
 * the kNN search (knn_grid.c): the K-th squared distance of a candidate set, below
 * which the neighbours are taken as a set, with no sorted list to insert into.
 */
#ifndef STA_PREPROCESS_KNN_SELECT_H
#define STA_PREPROCESS_KNN_SELECT_H

#include <stddef.h>

/* The value v[k] would have if v[0 .. n) were sorted ascending (0 <= k < n; no NaN).
 * Reorders v (not when n is small). */
float sta_knn_select_kth(float *v, size_t n, size_t k);

#endif
