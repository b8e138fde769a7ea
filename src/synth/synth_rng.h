/* SPDX-License-Identifier: MIT
 * Deterministic random numbers for the scene generators: splitmix64 for seeding and
 * hashing, xoshiro256** for streams. The integer streams (and the uniform doubles
 * made from their top 53 bits) are the same on every platform; Gaussians also go
 * through libm's log and sqrt.
 *
 * Based on: S. Vigna, "Further scramblings of Marsaglia's xorshift generators", 2017
 * (splitmix64); D. Blackman and S. Vigna, "Scrambled linear pseudorandom number
 * generators", 2018 (xoshiro256**); G. Marsaglia and T. A. Bray, "A convenient method
 * for generating normal variables", 1964 (polar method).
 */
#ifndef STA_SYNTH_RNG_H
#define STA_SYNTH_RNG_H

#include <math.h>
#include <stdbool.h>
#include <stdint.h>

/* One splitmix64 step: advances *state and returns a well-mixed 64-bit value. */
static inline uint64_t sta_splitmix64(uint64_t *state)
{
    uint64_t z = (*state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

/* A hash of two values (seed and an index), for per-object streams. */
static inline uint64_t sta_hash2(uint64_t a, uint64_t b)
{
    uint64_t state = a ^ (b * 0xD1B54A32D192ED03ull);
    sta_splitmix64(&state);
    return sta_splitmix64(&state);
}

typedef struct sta_rng {
    uint64_t s[4];  /* xoshiro256** state, never all zero */
    double spare;   /* second Gaussian of the last Box-Muller pair */
    bool has_spare; /* spare is valid */
} sta_rng;

/* Seeds a stream from one 64-bit value (any value, zero included). */
static inline void sta_rng_seed(sta_rng *rng, uint64_t seed)
{
    uint64_t state = seed;
    for (int i = 0; i < 4; i++) {
        rng->s[i] = sta_splitmix64(&state);
    }
    rng->has_spare = false;
    rng->spare = 0.0;
}

static inline uint64_t sta_rng_rotl(uint64_t x, int k)
{
    return (x << k) | (x >> (64 - k));
}

/* Next 64 random bits. */
static inline uint64_t sta_rng_next(sta_rng *rng)
{
    uint64_t *s = rng->s;
    uint64_t result = sta_rng_rotl(s[1] * 5, 7) * 9;
    uint64_t t = s[1] << 17;
    s[2] ^= s[0];
    s[3] ^= s[1];
    s[1] ^= s[2];
    s[0] ^= s[3];
    s[2] ^= t;
    s[3] = sta_rng_rotl(s[3], 45);
    return result;
}

/* Uniform double in [0, 1). */
static inline double sta_rng_uniform(sta_rng *rng)
{
    return (double)(sta_rng_next(rng) >> 11) * 0x1.0p-53;
}

/* Uniform double in [lo, hi). */
static inline double sta_rng_range(sta_rng *rng, double lo, double hi)
{
    return lo + (hi - lo) * sta_rng_uniform(rng);
}

/* Uniform integer in [0, n) for n > 0 (multiply-shift; bias below 2^-32 for small n). */
static inline uint32_t sta_rng_below(sta_rng *rng, uint32_t n)
{
    return (uint32_t)(((sta_rng_next(rng) >> 32) * (uint64_t)n) >> 32);
}

/* Standard normal deviate (Marsaglia's polar method, both values used). */
static inline double sta_rng_gauss(sta_rng *rng)
{
    if (rng->has_spare) {
        rng->has_spare = false;
        return rng->spare;
    }
    double u, v, s;
    do {
        u = 2.0 * sta_rng_uniform(rng) - 1.0;
        v = 2.0 * sta_rng_uniform(rng) - 1.0;
        s = u * u + v * v;
    } while (s >= 1.0 || s == 0.0);
    double f = sqrt(-2.0 * log(s) / s);
    rng->spare = v * f;
    rng->has_spare = true;
    return u * f;
}

#endif
