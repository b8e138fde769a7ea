/* SPDX-License-Identifier: MIT
 * Little-endian loads and stores through memcpy (never pointer casts), for parsing
 * mapped files and writing portable ones. Big-endian variants serve binary PLY.
 */
#ifndef STA_CORE_BYTES_H
#define STA_CORE_BYTES_H

#include <stdint.h>
#include <string.h>

static inline uint16_t sta_load_u16le(const uint8_t *p)
{
    return (uint16_t)(p[0] | (p[1] << 8));
}

static inline uint32_t sta_load_u32le(const uint8_t *p)
{
    return (uint32_t)p[0] | ((uint32_t)p[1] << 8) | ((uint32_t)p[2] << 16) | ((uint32_t)p[3] << 24);
}

static inline uint64_t sta_load_u64le(const uint8_t *p)
{
    return (uint64_t)sta_load_u32le(p) | ((uint64_t)sta_load_u32le(p + 4) << 32);
}

static inline int16_t sta_load_i16le(const uint8_t *p)
{
    return (int16_t)sta_load_u16le(p);
}

static inline int32_t sta_load_i32le(const uint8_t *p)
{
    return (int32_t)sta_load_u32le(p);
}

static inline int64_t sta_load_i64le(const uint8_t *p)
{
    return (int64_t)sta_load_u64le(p);
}

static inline float sta_load_f32le(const uint8_t *p)
{
    uint32_t bits = sta_load_u32le(p);
    float value;
    memcpy(&value, &bits, sizeof(value));
    return value;
}

static inline double sta_load_f64le(const uint8_t *p)
{
    uint64_t bits = sta_load_u64le(p);
    double value;
    memcpy(&value, &bits, sizeof(value));
    return value;
}

static inline uint16_t sta_load_u16be(const uint8_t *p)
{
    return (uint16_t)((p[0] << 8) | p[1]);
}

static inline uint32_t sta_load_u32be(const uint8_t *p)
{
    return ((uint32_t)p[0] << 24) | ((uint32_t)p[1] << 16) | ((uint32_t)p[2] << 8) | (uint32_t)p[3];
}

static inline uint64_t sta_load_u64be(const uint8_t *p)
{
    return ((uint64_t)sta_load_u32be(p) << 32) | (uint64_t)sta_load_u32be(p + 4);
}

static inline void sta_store_u16le(uint8_t *p, uint16_t v)
{
    p[0] = (uint8_t)v;
    p[1] = (uint8_t)(v >> 8);
}

static inline void sta_store_u32le(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)v;
    p[1] = (uint8_t)(v >> 8);
    p[2] = (uint8_t)(v >> 16);
    p[3] = (uint8_t)(v >> 24);
}

static inline void sta_store_u64le(uint8_t *p, uint64_t v)
{
    sta_store_u32le(p, (uint32_t)v);
    sta_store_u32le(p + 4, (uint32_t)(v >> 32));
}

static inline void sta_store_i16le(uint8_t *p, int16_t v)
{
    sta_store_u16le(p, (uint16_t)v);
}

static inline void sta_store_i32le(uint8_t *p, int32_t v)
{
    sta_store_u32le(p, (uint32_t)v);
}

static inline void sta_store_f32le(uint8_t *p, float v)
{
    uint32_t bits;
    memcpy(&bits, &v, sizeof(bits));
    sta_store_u32le(p, bits);
}

static inline void sta_store_f64le(uint8_t *p, double v)
{
    uint64_t bits;
    memcpy(&bits, &v, sizeof(bits));
    sta_store_u64le(p, bits);
}

#endif
