/* SPDX-License-Identifier: MIT
 * Exact sums of the monomials up to the fourth order of points' offsets. */
#include "tensor_sums.h"

// (by degree: 1; x, y, z; the 6 of degree 2; the 10 of degree 3; the 15 of degree 4)
const uint8_t sta_tensor_exponent[STA_TENSOR_TERMS][3] = {
    { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 }, { 2, 0, 0 }, { 1, 1, 0 }, { 1, 0, 1 },
    { 0, 2, 0 }, { 0, 1, 1 }, { 0, 0, 2 }, { 3, 0, 0 }, { 2, 1, 0 }, { 2, 0, 1 }, { 1, 2, 0 },
    { 1, 1, 1 }, { 1, 0, 2 }, { 0, 3, 0 }, { 0, 2, 1 }, { 0, 1, 2 }, { 0, 0, 3 }, { 4, 0, 0 },
    { 3, 1, 0 }, { 3, 0, 1 }, { 2, 2, 0 }, { 2, 1, 1 }, { 2, 0, 2 }, { 1, 3, 0 }, { 1, 2, 1 },
    { 1, 1, 2 }, { 1, 0, 3 }, { 0, 4, 0 }, { 0, 3, 1 }, { 0, 2, 2 }, { 0, 1, 3 }, { 0, 0, 4 },
};

void sta_tensor_sums_add(sta_tensor_sums *sums, const uint64_t d[3])
{
    // Each monomial from one of degree one less (the terms of sta_tensor_exponent, written
    // out: a loop over the exponents took 470 instructions a point, this about 80).
    const uint64_t x = d[0], y = d[1], z = d[2];
    const uint64_t xx = x * x;
    const uint64_t xy = x * y;
    const uint64_t xz = x * z;
    const uint64_t yy = y * y;
    const uint64_t yz = y * z;
    const uint64_t zz = z * z;
    const uint64_t xxx = xx * x;
    const uint64_t xxy = xx * y;
    const uint64_t xxz = xx * z;
    const uint64_t xyy = xy * y;
    const uint64_t xyz = xy * z;
    const uint64_t xzz = xz * z;
    const uint64_t yyy = yy * y;
    const uint64_t yyz = yy * z;
    const uint64_t yzz = yz * z;
    const uint64_t zzz = zz * z;
    const uint64_t xxxx = xxx * x;
    const uint64_t xxxy = xxx * y;
    const uint64_t xxxz = xxx * z;
    const uint64_t xxyy = xxy * y;
    const uint64_t xxyz = xxy * z;
    const uint64_t xxzz = xxz * z;
    const uint64_t xyyy = xyy * y;
    const uint64_t xyyz = xyy * z;
    const uint64_t xyzz = xyz * z;
    const uint64_t xzzz = xzz * z;
    const uint64_t yyyy = yyy * y;
    const uint64_t yyyz = yyy * z;
    const uint64_t yyzz = yyz * z;
    const uint64_t yzzz = yzz * z;
    const uint64_t zzzz = zzz * z;
    const uint64_t term[STA_TENSOR_TERMS] = {
        1,    x,    y,    z,    xx,   xy,   xz,   yy,   yz,   zz,   xxx,  xxy,
        xxz,  xyy,  xyz,  xzz,  yyy,  yyz,  yzz,  zzz,  xxxx, xxxy, xxxz, xxyy,
        xxyz, xxzz, xyyy, xyyz, xyzz, xzzz, yyyy, yyyz, yyzz, yzzz, zzzz,
    };
    for (int k = 0; k < STA_TENSOR_TERMS; k++) {
        sums->s[k] += term[k];
    }
}
