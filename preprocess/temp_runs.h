/* SPDX-License-Identifier: MIT
 * The converter's temporary records as compressed runs: each chunk's records are a
 * list of blocks (byte-shuffled, zstd level -5) appended to one temporary file.
 *
 * Design: writers append blocks from any thread (offsets reserved under `lock`, the
 * write outside it). A block carries an order key; reading a chunk sorts its blocks
 * by that key, so the records come back in the order the caller defined (input
 * order), whichever thread wrote first. A chunk that has been read for the last time
 * is discarded: its blocks' bytes are punched out of the file (fallocate), so the
 * file's allocated size follows the records still waiting, and `peak_bytes` is the
 * most that was ever allocated. Blocks start on `alignment` boundaries (4 KiB: punching
 * frees whole file-system blocks).
 */
#ifndef STA_PREPROCESS_TEMP_RUNS_H
#define STA_PREPROCESS_TEMP_RUNS_H

#include <pthread.h>
#include <stdatomic.h>
#include <stddef.h>
#include <stdint.h>

#include "core/status.h"

/* Raw bytes a block holds at most (callers flush buffers of at most this size). */
#define STA_TEMP_RUNS_MAX_BLOCK_BYTES ((size_t)1 << 20)

/* Raw bytes a block should hold at least: smaller blocks compress poorly and waste
 * most of their aligned 4 KiB on disk. */
#define STA_TEMP_RUNS_MIN_BLOCK_BYTES ((size_t)32 << 10)

/* Block alignment for runs whose blocks are punched out as they are read. */
#define STA_TEMP_RUNS_PAGE_ALIGNMENT 4096u

typedef struct sta_run_block {
    uint64_t offset;      /* in the file, 4 KiB aligned */
    uint64_t order;       /* read order within its list */
    uint32_t stored_size; /* compressed bytes */
    uint32_t count;       /* records */
} sta_run_block;

typedef struct sta_run_list {
    sta_run_block *blocks;
    size_t block_count;
    size_t block_capacity;
    uint64_t record_count;
} sta_run_list;

/* Disk held by several stores together (their peaks need not coincide). */
typedef struct sta_temp_usage {
    _Atomic uint64_t live_bytes; /* atomic */
    _Atomic uint64_t peak_bytes; /* atomic: most live_bytes ever */
} sta_temp_usage;

typedef struct sta_temp_runs {
    int fd;               /* borrowed: the temporary file, read-write */
    const char *path;     /* borrowed, for messages */
    size_t record_size;   /* bytes per record */
    uint32_t alignment;   /* of block offsets, bytes */
    pthread_mutex_t lock; /* guards every field below */
    sta_run_list *lists;  /* one per chunk */
    size_t list_count;
    size_t list_capacity;
    uint64_t end;          /* next free offset */
    uint64_t live_bytes;   /* allocated and not discarded */
    uint64_t peak_bytes;   /* most live_bytes ever */
    sta_temp_usage *usage; /* borrowed, may be NULL: also counts this store's bytes */
} sta_temp_runs;

/* Per-thread compression state and buffers; zero-initialize, release when done. */
typedef struct sta_run_codec {
    void *cctx; /* ZSTD_CCtx */
    void *dctx; /* ZSTD_DCtx */
    uint8_t *shuffled;
    size_t shuffled_capacity;
    uint8_t *packed;
    size_t packed_capacity;
} sta_run_codec;

/* Starts an empty store of `list_count` lists over `fd` (borrowed). `alignment`:
 * block offsets' alignment in bytes (0 means 1). */
sta_status sta_temp_runs_init(sta_temp_runs *runs, int fd, const char *path, size_t record_size,
                              size_t list_count, uint32_t alignment, sta_error *err);

void sta_temp_runs_release(sta_temp_runs *runs);

/* Adds `count` empty lists; the first one's index goes to *out_first. Thread-safe
 * against appends; not while another thread reads a block. */
sta_status sta_temp_runs_add_lists(sta_temp_runs *runs, size_t count, size_t *out_first,
                                   sta_error *err);

/* Compresses `count` records (at most STA_TEMP_RUNS_MAX_BLOCK_BYTES) and appends them
 * to list `list` as one block read back in `order`. Thread-safe (one codec per thread). */
sta_status sta_temp_runs_append(sta_temp_runs *runs, sta_run_codec *codec, size_t list,
                                uint64_t order, const uint8_t *records, size_t count,
                                sta_error *err);

/* Sorts list `list`'s blocks into read order. Call after the last append to it. */
void sta_temp_runs_sort(sta_temp_runs *runs, size_t list);

/* Decompresses block `block` of (sorted) list `list` into `out` (room for the block's
 * count records). */
sta_status sta_temp_runs_read_block(sta_temp_runs *runs, sta_run_codec *codec, size_t list,
                                    size_t block, uint8_t *out, sta_error *err);

/* Reads all of list `list` in order into `out` (room for its record_count records). */
sta_status sta_temp_runs_read(sta_temp_runs *runs, sta_run_codec *codec, size_t list, uint8_t *out,
                              sta_error *err);

/* Punches block `block` of list `list` out of the file once it has been read for the
 * last time (the entry stays, with no stored bytes). */
void sta_temp_runs_discard_block(sta_temp_runs *runs, size_t list, size_t block);

/* Frees list `list`'s blocks and punches their bytes out of the file. Thread-safe
 * across different lists. */
void sta_temp_runs_discard(sta_temp_runs *runs, size_t list);

void sta_run_codec_release(sta_run_codec *codec);

#endif
