/* SPDX-License-Identifier: MIT
 * Private helpers shared by the .strata writer, reader and verifier: serialising and
 * parsing the header, the extra-dimension descriptors and the node table, and the
 * structural checks of the table that writer and reader both run.
 */
#ifndef STA_FORMAT_STRATA_INTERNAL_H
#define STA_FORMAT_STRATA_INTERNAL_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "format/strata.h"

/* XXH3-64 (seed 0) of `size` bytes: the one checksum of the format. */
uint64_t sta_strata_checksum(const void *data, size_t size);

/* Rounds `value` up to a multiple of the power of two `alignment`. */
static inline uint64_t sta_strata_align(uint64_t value, uint64_t alignment)
{
    return (value + alignment - 1) & ~(alignment - 1);
}

/* Writes info's header fields into `out` (info->header_size bytes, zeroed first)
 * and seals it: header_checksum is computed last over the bytes with the field 0. */
void sta_strata_header_store(const sta_strata_info *info, uint8_t *out);

/* Checksum of a header of `size` bytes, taken with its checksum field as zero. */
uint64_t sta_strata_header_checksum(const uint8_t *header, size_t size);

/* Writes the descriptors into `out` (count * 128 bytes). */
void sta_strata_extra_dims_store(const sta_strata_extra_dim *dims, uint32_t count, uint8_t *out);

/* Parses and validates the header and descriptors of a file of `size` bytes.
 * On success fills *out (layout.extra_dims points at *out_dims, which the caller
 * frees with sta_free). `ignore_checksums` skips checksum comparisons only. */
sta_status sta_strata_header_parse(const uint8_t *data, size_t size, const char *name,
                                   bool ignore_checksums, sta_strata_info *out,
                                   sta_strata_extra_dim **out_dims, sta_error *err);

/* Serialises one node-table entry (80 bytes; reserved bytes zero). */
void sta_strata_node_store(const sta_strata_node *node, uint8_t *out);

/* Parses one node-table entry (the first 80 bytes of it). */
void sta_strata_node_load(const uint8_t *in, sta_strata_node *out);

/* Checks the tree and payload ranges of `nodes` (info->node_count entries) against
 * the header fields of `info`: keys, child links (each child after its parent and
 * claimed once, so no cycles), levels, sizes, compression codes, payload ranges
 * inside [data_offset, table_offset) and disjoint, point counts summing to the
 * header's. `name` prefixes messages. Errors: STA_ERR_FORMAT (or _UNSUPPORTED for
 * an unknown compression code), STA_ERR_NOMEM. */
sta_status sta_strata_table_check(const sta_strata_info *info, const sta_strata_node *nodes,
                                  const char *name, sta_error *err);

#endif
