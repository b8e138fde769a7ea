/* SPDX-License-Identifier: MIT
 * Octahedral normals and half-float radii (moved here from stream/gpu_splats.c so that
 * the format's SPLAT columns and the GPU records share one mapping). */
#include "core/octahedral.h"

#include <math.h>

static float sign_not_zero(float v)
{
    return v < 0.0f ? -1.0f : 1.0f;
}

static uint16_t snorm16(float v)
{
    v = v < -1.0f ? -1.0f : (v > 1.0f ? 1.0f : v);
    return (uint16_t)(int16_t)lrintf(v * 32767.0f);
}

static float from_snorm16(uint16_t u)
{
    float v = (float)(int16_t)u / 32767.0f;
    return v < -1.0f ? -1.0f : v;
}

void sta_octahedral_encode(const float normal[3], uint16_t out[2])
{
    float x = normal[0], y = normal[1], z = normal[2];
    float l1 = fabsf(x) + fabsf(y) + fabsf(z);
    if (!(l1 > 0.0f) || !isfinite(l1)) {
        x = 0.0f, y = 0.0f, z = 1.0f, l1 = 1.0f;
    }
    x /= l1, y /= l1, z /= l1;
    if (z < 0.0f) { /* fold the lower hemisphere over the diagonals */
        float fx = (1.0f - fabsf(y)) * sign_not_zero(x);
        float fy = (1.0f - fabsf(x)) * sign_not_zero(y);
        x = fx, y = fy;
    }
    out[0] = snorm16(x);
    out[1] = snorm16(y);
}

void sta_octahedral_decode(const uint16_t in[2], float normal[3])
{
    float x = from_snorm16(in[0]), y = from_snorm16(in[1]);
    float z = 1.0f - fabsf(x) - fabsf(y);
    if (z < 0.0f) {
        float fx = (1.0f - fabsf(y)) * sign_not_zero(x);
        float fy = (1.0f - fabsf(x)) * sign_not_zero(y);
        x = fx, y = fy;
    }
    float len = sqrtf(x * x + y * y + z * z);
    normal[0] = x / len, normal[1] = y / len, normal[2] = z / len;
}

uint16_t sta_half_from_float(float value)
{
    if (!(value > 0.0f)) {
        return 0; /* negative, zero and NaN */
    }
    if (value >= 65504.0f) {
        return 0x7bff;
    }
    int exponent;
    float mantissa = frexpf(value, &exponent); /* value = mantissa * 2^exponent, [0.5, 1) */
    int e = exponent - 1 + 15;                 /* biased half exponent */
    if (e <= 0) {                              /* subnormal: steps of 2^-24 */
        long q = lrintf(ldexpf(value, 24));
        return (uint16_t)q; /* q <= 1024 rounds up into the first normal exactly */
    }
    long q = lrintf(ldexpf(mantissa, 11)); /* 1024..2048 with the implicit bit */
    if (q == 2048) {
        q = 1024, e++;
    }
    if (e >= 31) {
        return 0x7bff;
    }
    return (uint16_t)((e << 10) | (q - 1024));
}

float sta_half_to_float(uint16_t half)
{
    int e = (half >> 10) & 31, m = half & 1023;
    float v = e == 0 ? ldexpf((float)m, -24) : ldexpf((float)(m + 1024), e - 25);
    if (e == 31) {
        v = m ? NAN : INFINITY;
    }
    return (half & 0x8000) ? -v : v;
}

void sta_splat_pack(const float normal[3], float radius, uint16_t out[3])
{
    sta_octahedral_encode(normal, out);
    out[2] = sta_half_from_float(radius);
}

void sta_splat_unpack(const uint16_t in[3], float normal[3], float *radius)
{
    sta_octahedral_decode(in, normal);
    *radius = sta_half_to_float(in[2]);
}
