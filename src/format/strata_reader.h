/* SPDX-License-Identifier: MIT
 * Reading a .strata file: open (map + validate header and table), walk the node
 * table, decode node payloads, verify a whole file.
 *
 * Design: sta_strata_open maps the file read-only and checks everything that does
 * not need the payloads (header and table checksums, the tree's shape, every
 * payload range); after that the reader is immutable, so any number of threads may
 * call sta_strata_reader_node and sta_strata_decode_node at once, each with its own
 * sta_strata_decoder. A payload's checksum is checked each time it is decoded.
 */
#ifndef STA_FORMAT_STRATA_READER_H
#define STA_FORMAT_STRATA_READER_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "core/status.h"
#include "format/strata.h"

typedef struct sta_strata_reader sta_strata_reader;

/* Open options. Zero means default. */
typedef struct sta_strata_open_options {
    bool ignore_checksums;       /* skip checksum comparisons (fuzzing, forensics only;
                                    every structural check still runs) */
    uint64_t max_node_raw_bytes; /* decoding refuses larger payloads; 0 = 4 GiB */
} sta_strata_open_options;

/* Maps `path` and validates it. `options` may be NULL. On success *out_reader is
 * owned by the caller (sta_strata_close). Errors name the file and, for the table,
 * the node: STA_ERR_IO, STA_ERR_FORMAT (truncated, corrupted or inconsistent),
 * STA_ERR_UNSUPPORTED (another major version, unknown feature flag or compression),
 * STA_ERR_NOMEM. */
sta_status sta_strata_open(const char *path, const sta_strata_open_options *options,
                           sta_strata_reader **out_reader, sta_error *err);

/* As sta_strata_open over bytes the caller keeps alive until close; `name` is used
 * in messages. */
sta_status sta_strata_open_memory(const uint8_t *data, size_t size, const char *name,
                                  const sta_strata_open_options *options,
                                  sta_strata_reader **out_reader, sta_error *err);

/* Unmaps and frees; NULL is a no-op. */
void sta_strata_close(sta_strata_reader *reader);

/* The header (layout, geometry, bounds, counts); valid until close. */
const sta_strata_info *sta_strata_reader_info(const sta_strata_reader *reader);

/* The LAS source block (header fields and CRS records of the LAS input), or NULL when
 * the file has none (files before 1.2, or not converted from LAS); valid until close. */
const sta_strata_las_source *sta_strata_reader_las_source(const sta_strata_reader *reader);

/* Table entry `index` (< info->node_count, else NULL); valid until close. Node 0 is
 * the root; a node's children are first_child .. first_child + popcount(mask) - 1. */
const sta_strata_node *sta_strata_reader_node(const sta_strata_reader *reader, uint32_t index);

/* The bytes of the file (mapped or the caller's); valid until close. */
const uint8_t *sta_strata_reader_data(const sta_strata_reader *reader, size_t *out_size);

/* Per-thread decoding state: a ZSTD_DCtx and buffers reused from call to call. */
typedef struct sta_strata_decoder sta_strata_decoder;

/* Creates a decoder. Errors: STA_ERR_NOMEM. */
sta_status sta_strata_decoder_create(sta_strata_decoder **out_decoder, sta_error *err);

/* Frees a decoder; NULL is a no-op. */
void sta_strata_decoder_destroy(sta_strata_decoder *decoder);

/* Checks node `index`'s payload checksum and decompresses it: *out_raw points at
 * raw_size bytes in the column layout (sta_strata_column_offset), owned by the
 * decoder or the map and valid until the decoder's next call or close.
 * Errors: STA_ERR_ARG (index), STA_ERR_FORMAT naming the file and node (checksum,
 * zstd stream, size), STA_ERR_UNSUPPORTED (larger than max_node_raw_bytes),
 * STA_ERR_NOMEM. */
sta_status sta_strata_load_node(const sta_strata_reader *reader, uint32_t index,
                                sta_strata_decoder *decoder, const uint8_t **out_raw,
                                sta_error *err);

/* Points of one node, owned by the decoder (valid until its next call). */
typedef struct sta_strata_points {
    const sta_point *points; /* count points, absolute grid integers; absent fields 0 */
    const uint8_t *extra;    /* count * extra_size bytes (row-wise), NULL when none */
    size_t count;            /* = the node's point_count */
    size_t extra_size;       /* bytes per point of extra dimensions */
} sta_strata_points;

/* As sta_strata_load_node, then decodes into points with absolute coordinates
 * (corner + stored offset). Same errors. */
sta_status sta_strata_decode_node(const sta_strata_reader *reader, uint32_t index,
                                  sta_strata_decoder *decoder, sta_strata_points *out_points,
                                  sta_error *err);

/* Called after each verified node; return false to stop (STA_ERR_CANCELLED). */
typedef bool (*sta_strata_progress_fn)(void *user, uint32_t nodes_done, uint32_t node_count);

/* Decodes every node and checks: each payload checksum; every point inside its
 * node's box; no two points of a node in the same cell of its grid (grid_cells per
 * axis, cell = sta_strata_cell_of) except in OVERFLOW nodes; the header's tight
 * bounds equal the points' bounds; each node's spacing. Stops at the first
 * violation with a message naming the node (index and key) and the point(s).
 * `progress` may be NULL. Errors: STA_ERR_FORMAT, STA_ERR_NOMEM, STA_ERR_CANCELLED. */
sta_status sta_strata_verify(const sta_strata_reader *reader, sta_strata_progress_fn progress,
                             void *user, sta_error *err);

#endif
