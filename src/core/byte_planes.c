/* SPDX-License-Identifier: MIT
 * Byte planes (see byte_planes.h). The plain loop moves one byte per load and store
 * and cannot be vectorised (the record size is only known at run time); here 8
 * records x 8 bytes are loaded as eight 64-bit words, transposed as an 8x8 byte
 * matrix in registers (three rounds of masked swaps) and stored as eight words, one
 * per plane. Records left over (count % 8) and bytes left over (rec % 8) take the
 * plain loop. Loads and stores never reach past a record's own bytes.
 */
#include "core/byte_planes.h"

#include <string.h>

static uint64_t load64(const uint8_t *p)
{
    uint64_t v;
    memcpy(&v, p, sizeof(v));
    return v;
}

static void store64(uint8_t *p, uint64_t v)
{
    memcpy(p, &v, sizeof(v));
}

// Swaps the bytes of `a` selected by mask << shift with those of `b` selected by mask.
static inline void swap_masked(uint64_t *a, uint64_t *b, int shift, uint64_t mask)
{
    uint64_t t = ((*a >> shift) ^ *b) & mask;
    *a ^= t << shift;
    *b ^= t;
}

// Transposes the 8x8 byte matrix whose row i is r[i] (byte j at bits 8j): afterwards
// byte i of r[j] is the former byte j of r[i]. The swap is symmetric, so this works
// in both directions. Written out so that r stays in registers.
static inline void transpose8x8(uint64_t r[8])
{
    const uint64_t m32 = 0x00000000FFFFFFFFull, m16 = 0x0000FFFF0000FFFFull;
    const uint64_t m8 = 0x00FF00FF00FF00FFull;
    swap_masked(&r[0], &r[4], 32, m32); // 4x4 blocks: top right <-> bottom left
    swap_masked(&r[1], &r[5], 32, m32);
    swap_masked(&r[2], &r[6], 32, m32);
    swap_masked(&r[3], &r[7], 32, m32);
    swap_masked(&r[0], &r[2], 16, m16); // 2x2 blocks within them
    swap_masked(&r[1], &r[3], 16, m16);
    swap_masked(&r[4], &r[6], 16, m16);
    swap_masked(&r[5], &r[7], 16, m16);
    swap_masked(&r[0], &r[1], 8, m8); // single bytes
    swap_masked(&r[2], &r[3], 8, m8);
    swap_masked(&r[4], &r[5], 8, m8);
    swap_masked(&r[6], &r[7], 8, m8);
}

void sta_byte_planes_split(const uint8_t *in, size_t count, size_t rec, uint8_t *out)
{
    size_t whole = count - count % 8, wide = rec - rec % 8;
    for (size_t i = 0; i < whole; i += 8) {
        const uint8_t *group = in + i * rec;
        for (size_t k = 0; k < wide; k += 8) {
            uint64_t r[8];
            for (int j = 0; j < 8; j++) {
                r[j] = load64(group + (size_t)j * rec + k);
            }
            transpose8x8(r);
            for (int j = 0; j < 8; j++) {
                store64(out + (k + (size_t)j) * count + i, r[j]);
            }
        }
        for (size_t k = wide; k < rec; k++) {
            for (size_t j = 0; j < 8; j++) {
                out[k * count + i + j] = group[j * rec + k];
            }
        }
    }
    for (size_t k = 0; k < rec; k++) {
        for (size_t i = whole; i < count; i++) {
            out[k * count + i] = in[i * rec + k];
        }
    }
}

void sta_byte_planes_join(const uint8_t *in, size_t count, size_t rec, uint8_t *out)
{
    size_t whole = count - count % 8, wide = rec - rec % 8;
    for (size_t i = 0; i < whole; i += 8) {
        uint8_t *group = out + i * rec;
        for (size_t k = 0; k < wide; k += 8) {
            uint64_t r[8];
            for (int j = 0; j < 8; j++) {
                r[j] = load64(in + (k + (size_t)j) * count + i);
            }
            transpose8x8(r);
            for (int j = 0; j < 8; j++) {
                store64(group + (size_t)j * rec + k, r[j]);
            }
        }
        for (size_t k = wide; k < rec; k++) {
            for (size_t j = 0; j < 8; j++) {
                group[j * rec + k] = in[k * count + i + j];
            }
        }
    }
    for (size_t k = 0; k < rec; k++) {
        for (size_t i = whole; i < count; i++) {
            out[i * rec + k] = in[k * count + i];
        }
    }
}
