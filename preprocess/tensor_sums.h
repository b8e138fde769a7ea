/* SPDX-License-Identifier: MIT
 * The moments up to the fourth order of a set of points, summed exactly: what the
 * quadric (quadric_fit.h) and the cylinder (cylinder_fit.h) of a rough box are fitted
 * from (strata-convert --normals, moments method; moment_normals.c sums a box's points
 * from its runs of the cell order when its fit is first asked for).
 *
 * Design: the 35 sums of d^a over the points, one for each monomial x^i y^j z^k with
 * i + j + k <= 4 (d the offset from the box's corner, grid units), in 64-bit integers
 * modulo 2^64: order-free, so the same bits in any chunking, and exact wherever the true
 * sum fits (a box whose n (2 edge)^4 stays under 2^62; quadric_fit.c checks it).
 * (Until the eighteenth round of docs/BENCHMARKS.md they were also kept per cell and
 * moved to a box's corner; the boxes' own points proved cheaper.)
 */
#ifndef STA_PREPROCESS_TENSOR_SUMS_H
#define STA_PREPROCESS_TENSOR_SUMS_H

#include <stdint.h>

/* Monomials of degree 0..4 in three variables. */
#define STA_TENSOR_TERMS 35

/* The exponents (x, y, z) of each term, by degree then lexicographically descending. */
extern const uint8_t sta_tensor_exponent[STA_TENSOR_TERMS][3];

/* Sums of the monomials of d over a set of points, by sta_tensor_exponent's terms. */
typedef struct sta_tensor_sums {
    uint64_t s[STA_TENSOR_TERMS];
} sta_tensor_sums;

/* Adds the monomials of one point's offset d (grid units, >= 0) to sums, modulo 2^64. */
void sta_tensor_sums_add(sta_tensor_sums *sums, const uint64_t d[3]);

#endif
