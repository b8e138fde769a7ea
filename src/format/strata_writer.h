/* SPDX-License-Identifier: MIT
 * Writing a .strata file: payloads are appended one by one (from any number of
 * threads), then the node table and the header are written and the file appears
 * under its final name.
 *
 * Design: the file is written under a temporary name in the target's folder
 * ("<path>.tmp.<pid>.<n>"). sta_strata_writer_add_* encodes, compresses and checks
 * in the calling thread with that thread's sta_strata_encoder, reserves the byte
 * range under the writer's mutex and writes it with pwrite outside the lock.
 * sta_strata_writer_finish writes the table and the header, fsyncs and renames.
 * Destroying an unfinished writer removes the temporary file.
 *
 * Typical use by the converter:
 *   sta_strata_writer_create(path, &options, &w, err);
 *   // per worker thread: sta_strata_encoder_create(&enc, err);
 *   //   for each finished node: sta_strata_writer_add_points(w, enc, key, points, extra,
 *   //                                                        count, &node.payload, err);
 *   // table in breadth-first order, children contiguous, payloads from add_*:
 *   sta_strata_writer_finish(w, nodes, node_count, err);
 *   sta_strata_writer_destroy(w);
 */
#ifndef STA_FORMAT_STRATA_WRITER_H
#define STA_FORMAT_STRATA_WRITER_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "core/status.h"
#include "format/strata.h"

/* Per-thread compression state (one ZSTD_CCtx and scratch buffers). */
typedef struct sta_strata_encoder sta_strata_encoder;

/* Creates an encoder for one thread. Errors: STA_ERR_NOMEM. */
sta_status sta_strata_encoder_create(sta_strata_encoder **out_encoder, sta_error *err);

/* Frees an encoder; NULL is a no-op. */
void sta_strata_encoder_destroy(sta_strata_encoder *encoder);

typedef struct sta_strata_writer sta_strata_writer;

#define STA_STRATA_DEFAULT_ZSTD_LEVEL 3

/* How to write. Geometry fields have no defaults except grid_cells (0 means 128). */
typedef struct sta_strata_writer_options {
    sta_strata_geometry geometry; /* grid, root box (inside the int32 grid), cells */
    sta_strata_layout layout;     /* from sta_strata_layout_init; extra dims are copied */
    int zstd_level;               /* 0 stores payloads uncompressed; 1..19 zstd level
                                     (STA_STRATA_DEFAULT_ZSTD_LEVEL is a good choice) */
    const char *generator;        /* software name for the header; NULL means "strata" */
    int up_axis;                  /* STA_STRATA_UP_Z (0) or STA_STRATA_UP_Y */
    const sta_strata_las_source *las_source; /* LAS header fields and CRS records to keep
                                                (copied at create), or NULL: none */
} sta_strata_writer_options;

/* Creates the temporary file beside `path` and checks the options (scale, root box,
 * grid cells, level). `path` is where the file appears after finish. On success
 * *out_writer is owned by the caller (sta_strata_writer_destroy).
 * Errors: STA_ERR_ARG for bad options, STA_ERR_IO naming the file. */
sta_status sta_strata_writer_create(const char *path, const sta_strata_writer_options *options,
                                    sta_strata_writer **out_writer, sta_error *err);

/* Appends the payload of node `key` from `count` points already in the column
 * layout (`columns`: count * record_size bytes, see sta_strata_encode_points).
 * Checks that every position lies inside the node's box, compresses with `encoder`
 * (falling back to storing when zstd does not shrink it), writes it and fills
 * *out_payload for the node's table entry. An empty node (count 0) writes nothing.
 * Thread-safe: any number of threads may call add_* at once, each with its own
 * encoder. Errors: STA_ERR_ARG naming the node and point outside the box,
 * STA_ERR_NOMEM, STA_ERR_IO (the writer then refuses to finish). */
sta_status sta_strata_writer_add_node(sta_strata_writer *writer, sta_strata_encoder *encoder,
                                      sta_strata_key key, const void *columns, size_t count,
                                      sta_strata_payload *out_payload, sta_error *err);

/* Payloads packed in memory to be appended together, so that the file's layout can
 * follow an order of the caller's choosing (the converter's output does not depend
 * on which thread finished first). Zero-initialize; release with
 * sta_strata_batch_release. */
typedef struct sta_strata_batch {
    uint8_t *bytes;         /* owned; payloads at aligned offsets from 0 */
    size_t size;            /* bytes used */
    size_t capacity;        /* bytes allocated */
    uint64_t payload_count; /* non-empty payloads packed */
    bool has_points;        /* lo/hi valid */
    int32_t lo[3];          /* tight bounds of the packed points */
    int32_t hi[3];
} sta_strata_batch;

/* As sta_strata_writer_add_node, but the stored bytes go to the end of `batch`
 * (owned by the calling thread) instead of the file: out_payload->offset is relative
 * to the batch's start until sta_strata_writer_add_batch gives the batch its place.
 * Thread-safe like add_node (different batches and encoders). */
sta_status sta_strata_writer_pack_node(sta_strata_writer *writer, sta_strata_encoder *encoder,
                                       sta_strata_key key, const void *columns, size_t count,
                                       sta_strata_batch *batch, sta_strata_payload *out_payload,
                                       sta_error *err);

/* Writes `batch` at the next aligned offset of the file (*out_offset: add it to the
 * offsets pack_node returned; 0 for an empty batch). Thread-safe. */
sta_status sta_strata_writer_add_batch(sta_strata_writer *writer, const sta_strata_batch *batch,
                                       uint64_t *out_offset, sta_error *err);

/* Frees a batch's buffer and zeroes it. */
void sta_strata_batch_release(sta_strata_batch *batch);

/* As sta_strata_writer_add_node from an array of points (absolute grid integers)
 * and their extra bytes (layout extra_size bytes per point, NULL when 0). */
sta_status sta_strata_writer_add_points(sta_strata_writer *writer, sta_strata_encoder *encoder,
                                        sta_strata_key key, const sta_point *points,
                                        const uint8_t *extra, size_t count,
                                        sta_strata_payload *out_payload, sta_error *err);

/* Writes the node table (`node_count` entries: node 0 the root, children contiguous
 * and after their parent; payloads as returned by add_*; spacing is computed
 * here), then the header, fsyncs, and renames the temporary file to the final path.
 * The table gets the same checks as a reader's (tree shape, keys, payload ranges)
 * and must reference each payload written exactly once. Call once, after every
 * add_* has returned. Errors: STA_ERR_ARG (table), STA_ERR_IO, STA_ERR_NOMEM;
 * the temporary file stays until destroy. */
sta_status sta_strata_writer_finish(sta_strata_writer *writer, const sta_strata_node *nodes,
                                    size_t node_count, sta_error *err);

/* The temporary file's path (valid until destroy), for tests and messages. While
 * sta_strata_writer_is_unnamed, nothing exists there yet: the file has no name
 * (O_TMPFILE) until finish links it there and renames it. */
const char *sta_strata_writer_temp_path(const sta_strata_writer *writer);

/* True while the temporary file has no name in the folder (O_TMPFILE), so a killed
 * process leaves nothing behind; false where the file system cannot do that. */
bool sta_strata_writer_is_unnamed(const sta_strata_writer *writer);

/* Frees the writer; if finish has not succeeded, closes and removes the temporary
 * file (abort). NULL is a no-op. */
void sta_strata_writer_destroy(sta_strata_writer *writer);

#endif
