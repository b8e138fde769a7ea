// SPDX-License-Identifier: MIT
// Dot products and the facing test of the pyramidal normals, computed exactly as their
// twin (src/render/ref/normals_pyramid_ref.c) does: `precise`, so the compiler neither
// fuses a * b + c into an fma nor reorders the terms (llvmpipe fuses otherwise), and
// the thresholds and the facing test decide identically on both sides. Edge-on,
// n . p is 0 within rounding and the facing sign is a tie (23 x 1080 in
// test_pullpush.c: the fused dot gave a positive, the twin's exactly 0).
float np_dot(vec3 a, vec3 b)
{
    precise float d = a.x * b.x + a.y * b.y + a.z * b.z;
    return d;
}

// -1 where the normal n of the point p faces away from the camera at the origin
// (n . p > 0), else 1 (n . p == 0 keeps n). Twin: facing_sign.
float np_facing_sign(vec3 n, vec3 p)
{
    return np_dot(n, p) > 0.0 ? -1.0 : 1.0;
}

// The level of detail of a normal radius of r_px pixels: lambda = log2(r_px) (at least 0,
// at most count - 1), split into its level la and fraction t. la is the float's
// exponent, exact on both sides: from log2 (llvmpipe's approximation against libm's
// log2f) la flipped where r_px is within a few ulp of a power of 2 (31 x 1081 half
// resolution in test_pullpush.c: lambda 6.99999952 in the twin, level 7 here). Twin:
// level_of_detail.
int np_level_of_detail(float r_px, int count, out float t)
{
    float x = max(r_px, 1.0);
    int la = min((floatBitsToInt(x) >> 23) - 127, count - 1); // x >= 1: normal, sign 0
    t = la == count - 1 ? 0.0 : clamp(log2(x) - float(la), 0.0, 1.0);
    return la;
}
