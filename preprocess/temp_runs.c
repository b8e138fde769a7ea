/* SPDX-License-Identifier: MIT
 * Compressed temporary runs (see temp_runs.h). Records are byte-shuffled (all first
 * bytes, then all second bytes, ...: byte_planes.c) before zstd: coordinates and attributes of
 * nearby points share their high bytes, which then form long runs.
 */
#define _GNU_SOURCE // fallocate, FALLOC_FL_PUNCH_HOLE
#include "temp_runs.h"

#include <errno.h>
#include <fcntl.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>
#include <zstd.h>

#include "core/alloc.h"
#include "core/array.h"
#include "core/byte_planes.h"
#include "core/file_io.h"

enum {
    /* A fast (negative) level: the runs are written and read once. On the 20 M street
     * -5 against 1: 176 against 149 MiB of runs (0.27x against 0.23x the LAS size),
     * about 5 % less CPU for the whole conversion (docs/BENCHMARKS.md). */
    ZSTD_LEVEL = -5,
};

static uint64_t align_up(const sta_temp_runs *runs, uint64_t v)
{
    return (v + runs->alignment - 1) / runs->alignment * runs->alignment;
}

static void usage_add(sta_temp_usage *usage, uint64_t bytes)
{
    if (!usage) {
        return;
    }
    uint64_t live = atomic_fetch_add(&usage->live_bytes, bytes) + bytes;
    uint64_t peak = atomic_load(&usage->peak_bytes);
    while (live > peak && !atomic_compare_exchange_weak(&usage->peak_bytes, &peak, live)) {
    }
}

static bool grow(uint8_t **buf, size_t *capacity, size_t need)
{
    if (need <= *capacity) {
        return true;
    }
    uint8_t *grown = sta_malloc(need);
    if (!grown) {
        return false;
    }
    sta_free(*buf);
    *buf = grown;
    *capacity = need;
    return true;
}

sta_status sta_temp_runs_init(sta_temp_runs *runs, int fd, const char *path, size_t record_size,
                              size_t list_count, uint32_t alignment, sta_error *err)
{
    memset(runs, 0, sizeof(*runs));
    runs->alignment = alignment ? alignment : 1;
    runs->fd = fd;
    runs->path = path;
    runs->record_size = record_size;
    pthread_mutex_init(&runs->lock, NULL);
    size_t first = 0;
    return sta_temp_runs_add_lists(runs, list_count, &first, err);
}

void sta_temp_runs_release(sta_temp_runs *runs)
{
    if (!runs->record_size) {
        return;
    }
    for (size_t i = 0; i < runs->list_count; i++) {
        sta_free(runs->lists[i].blocks);
    }
    sta_free(runs->lists);
    pthread_mutex_destroy(&runs->lock);
    memset(runs, 0, sizeof(*runs));
}

sta_status sta_temp_runs_add_lists(sta_temp_runs *runs, size_t count, size_t *out_first,
                                   sta_error *err)
{
    sta_status status = STA_OK;
    pthread_mutex_lock(&runs->lock); // appends to other lists may run meanwhile
    *out_first = runs->list_count;
    if (sta_array_reserve((void **)&runs->lists, &runs->list_capacity, runs->list_count + count,
                          sizeof(*runs->lists), 64, NULL) != STA_OK) {
        status = sta_fail(err, STA_ERR_NOMEM, "out of memory for %zu temporary runs",
                          runs->list_count + count);
    } else if (count > 0) {
        memset(runs->lists + runs->list_count, 0, count * sizeof(*runs->lists));
        runs->list_count += count;
    }
    pthread_mutex_unlock(&runs->lock);
    return status;
}

/* The shuffle goes through the records in tiles of SHUFFLE_TILE: a tile (about 2 KiB)
 * stays in L1 while each of its byte planes is gathered, where walking the whole
 * block once per byte of the record went out to L2/L3 `rec` times. */
enum {
    SHUFFLE_TILE = 64
};

sta_status sta_temp_runs_append(sta_temp_runs *runs, sta_run_codec *codec, size_t list,
                                uint64_t order, const uint8_t *records, size_t count,
                                sta_error *err)
{
    if (count == 0) {
        return STA_OK;
    }
    size_t raw = count * runs->record_size;
    size_t bound = ZSTD_compressBound(raw);
    if (!codec->cctx) {
        codec->cctx = ZSTD_createCCtx();
    }
    if (!codec->cctx || !grow(&codec->shuffled, &codec->shuffled_capacity, raw) ||
        !grow(&codec->packed, &codec->packed_capacity, bound)) {
        return sta_fail(err, STA_ERR_NOMEM, "out of memory compressing temporary records");
    }
    sta_byte_planes_split(records, count, runs->record_size, codec->shuffled);
    size_t stored =
        ZSTD_compressCCtx(codec->cctx, codec->packed, bound, codec->shuffled, raw, ZSTD_LEVEL);
    if (ZSTD_isError(stored)) {
        return sta_fail(err, STA_ERR_NOMEM, "%s: zstd failed: %s", runs->path,
                        ZSTD_getErrorName(stored));
    }
    sta_status status = STA_OK;
    pthread_mutex_lock(&runs->lock);
    sta_run_list *l = &runs->lists[list];
    uint64_t offset = runs->end;
    if (sta_array_reserve((void **)&l->blocks, &l->block_capacity, l->block_count + 1,
                          sizeof(*l->blocks), 16, NULL) != STA_OK) {
        status = sta_fail(err, STA_ERR_NOMEM, "out of memory for temporary blocks");
    } else {
        l->blocks[l->block_count++] =
            (sta_run_block){ offset, order, (uint32_t)stored, (uint32_t)count };
        l->record_count += count;
        runs->end = align_up(runs, offset + stored);
        runs->live_bytes += runs->end - offset;
        usage_add(runs->usage, runs->end - offset);
        runs->peak_bytes =
            runs->live_bytes > runs->peak_bytes ? runs->live_bytes : runs->peak_bytes;
    }
    pthread_mutex_unlock(&runs->lock);
    if (status == STA_OK) {
        status = sta_pwrite_all(runs->fd, codec->packed, stored, offset, runs->path, err);
    }
    return status;
}

static int compare_blocks(const void *a, const void *b)
{
    uint64_t x = ((const sta_run_block *)a)->order, y = ((const sta_run_block *)b)->order;
    return x < y ? -1 : x > y ? 1 : 0;
}

void sta_temp_runs_sort(sta_temp_runs *runs, size_t list)
{
    sta_run_list *l = &runs->lists[list];
    if (l->block_count > 1) { // an empty list has no block array (qsort wants one)
        qsort(l->blocks, l->block_count, sizeof(*l->blocks), compare_blocks);
    }
}

sta_status sta_temp_runs_read_block(sta_temp_runs *runs, sta_run_codec *codec, size_t list,
                                    size_t block, uint8_t *out, sta_error *err)
{
    const sta_run_block *b = &runs->lists[list].blocks[block];
    size_t raw = (size_t)b->count * runs->record_size;
    if (!codec->dctx) {
        codec->dctx = ZSTD_createDCtx();
    }
    if (!codec->dctx || !grow(&codec->packed, &codec->packed_capacity, b->stored_size) ||
        !grow(&codec->shuffled, &codec->shuffled_capacity, raw)) {
        return sta_fail(err, STA_ERR_NOMEM, "out of memory reading temporary records");
    }
    sta_status status =
        sta_pread_all(runs->fd, codec->packed, b->stored_size, b->offset, runs->path, err);
    if (status != STA_OK) {
        return status;
    }
    size_t n =
        ZSTD_decompressDCtx(codec->dctx, codec->shuffled, raw, codec->packed, b->stored_size);
    if (ZSTD_isError(n) || n != raw) {
        return sta_fail(err, STA_ERR_IO, "%s: temporary block at byte %llu is damaged (%s)",
                        runs->path, (unsigned long long)b->offset,
                        ZSTD_isError(n) ? ZSTD_getErrorName(n) : "wrong size");
    }
    sta_byte_planes_join(codec->shuffled, b->count, runs->record_size, out);
    return STA_OK;
}

sta_status sta_temp_runs_read(sta_temp_runs *runs, sta_run_codec *codec, size_t list, uint8_t *out,
                              sta_error *err)
{
    sta_temp_runs_sort(runs, list);
    const sta_run_list *l = &runs->lists[list];
    sta_status status = STA_OK;
    for (size_t i = 0; i < l->block_count && status == STA_OK; i++) {
        status = sta_temp_runs_read_block(runs, codec, list, i, out, err);
        out += (size_t)l->blocks[i].count * runs->record_size;
    }
    return status;
}

void sta_temp_runs_discard_block(sta_temp_runs *runs, size_t list, size_t block)
{
    pthread_mutex_lock(&runs->lock);
    sta_run_block *b = &runs->lists[list].blocks[block];
    uint64_t offset = b->offset, size = align_up(runs, b->stored_size);
    runs->live_bytes -= size;
    if (runs->usage) {
        atomic_fetch_sub(&runs->usage->live_bytes, size);
    }
    b->stored_size = 0; // punched: counted once
    pthread_mutex_unlock(&runs->lock);
    // Not under the lock: the punch is I/O. Failure only costs disk until the end.
    if (size > 0) {
        fallocate(runs->fd, FALLOC_FL_PUNCH_HOLE | FALLOC_FL_KEEP_SIZE, (off_t)offset, (off_t)size);
    }
}

void sta_temp_runs_discard(sta_temp_runs *runs, size_t list)
{
    for (size_t i = 0; i < runs->lists[list].block_count; i++) {
        sta_temp_runs_discard_block(runs, list, i);
    }
    pthread_mutex_lock(&runs->lock);
    sta_run_list *l = &runs->lists[list];
    sta_run_block *blocks = l->blocks;
    memset(l, 0, sizeof(*l));
    pthread_mutex_unlock(&runs->lock);
    sta_free(blocks);
}

void sta_run_codec_release(sta_run_codec *codec)
{
    ZSTD_freeCCtx(codec->cctx);
    ZSTD_freeDCtx(codec->dctx);
    sta_free(codec->shuffled);
    sta_free(codec->packed);
    memset(codec, 0, sizeof(*codec));
}
