/* SPDX-License-Identifier: MIT
 * Byte planes of fixed-size records: all first bytes, then all second bytes, ... (the
 * shuffle before zstd of the converter's temporary runs, preprocess/temp_runs.c, and
 * of each column of a .strata payload, format/strata_codec.c).
 */
#ifndef STA_CORE_BYTE_PLANES_H
#define STA_CORE_BYTE_PLANES_H

#include <stddef.h>
#include <stdint.h>

// out[k * count + i] = in[i * rec + k] for every record i < count and byte k < rec.
void sta_byte_planes_split(const uint8_t *in, size_t count, size_t rec, uint8_t *out);

// The inverse: out[i * rec + k] = in[k * count + i].
void sta_byte_planes_join(const uint8_t *in, size_t count, size_t rec, uint8_t *out);

#endif
