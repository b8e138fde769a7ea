/* SPDX-License-Identifier: MIT
 * Quickselect (median-of-three pivot, Hoare partition) on floats, insertion sort once
 * the range is small; short arrays (the K = 10 search's ~1.3 K candidates) by counting
 * ranks instead, which has no data-dependent branch but the hit. */
#include "knn_select.h"

#include <stdint.h>

/* Ranges this short are sorted outright; arrays up to RANK_MAX long are selected by
 * rank (n^2 compares in a loop the compiler vectorises: on the 4 M street's K = 10
 * search, where n is mostly 11-32, cheaper than quickselect's mispredicted branches). */
enum {
    SMALL = 12,
    RANK_MAX = 32
};

// The value whose rank range [less, less + ties) holds k: the k-th of the sorted array.
static float select_by_rank(const float *v, size_t n, size_t k)
{
    for (size_t j = 0; j < n; j++) {
        const float x = v[j];
        size_t less = 0, le = 0;
        for (size_t i = 0; i < n; i++) {
            less += v[i] < x;
            le += v[i] <= x;
        }
        if (less <= k && k < le) {
            return x;
        }
    }
    return v[0]; // only with a NaN or k >= n (outside the contract): no endless loop
}

static inline void swap(float *v, ptrdiff_t a, ptrdiff_t b)
{
    float t = v[a];
    v[a] = v[b];
    v[b] = t;
}

float sta_knn_select_kth(float *v, size_t n, size_t k)
{
    if (n <= RANK_MAX) {
        return select_by_rank(v, n, k);
    }
    ptrdiff_t lo = 0, hi = (ptrdiff_t)n - 1, want = (ptrdiff_t)k;
    while (hi - lo >= SMALL) {
        ptrdiff_t mid = lo + (hi - lo) / 2;
        if (v[mid] < v[lo]) {
            swap(v, mid, lo);
        }
        if (v[hi] < v[lo]) {
            swap(v, hi, lo);
        }
        if (v[hi] < v[mid]) {
            swap(v, hi, mid);
        }
        // v[lo] <= pivot <= v[hi]: both scans stop inside the range.
        float pivot = v[mid];
        ptrdiff_t i = lo, j = hi;
        while (i <= j) {
            while (v[i] < pivot) {
                i++;
            }
            while (v[j] > pivot) {
                j--;
            }
            if (i <= j) {
                swap(v, i, j);
                i++;
                j--;
            }
        }
        // [lo, j] <= pivot, (j, i) == pivot, [i, hi] >= pivot
        if (want <= j) {
            hi = j;
        } else if (want >= i) {
            lo = i;
        } else {
            return v[want];
        }
    }
    for (ptrdiff_t i = lo + 1; i <= hi; i++) {
        float x = v[i];
        ptrdiff_t j = i;
        while (j > lo && v[j - 1] > x) {
            v[j] = v[j - 1];
            j--;
        }
        v[j] = x;
    }
    return v[want];
}
