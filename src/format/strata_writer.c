/* SPDX-License-Identifier: MIT
 * Writing .strata files: streaming, thread-safe payload appends, table and header
 * last, atomic appearance under the final name.
 *
 * Design: payload bytes go to the temporary file at offsets reserved under `lock`
 * (next_offset advances by the aligned stored size); the pwrite itself runs outside
 * the lock, so threads compress and write in parallel. Alignment gaps are never
 * written: they read as zero. Lock order: only `lock`.
 *
 * Crash safety: the temporary file is created without a name (O_TMPFILE) in the
 * output's folder and only linked under its temporary name at finish, just before
 * the rename, so a process killed with SIGKILL leaves nothing. Where the file system
 * has no O_TMPFILE it is named from the start ("<path>.tmp.<pid>.<n>"), and create
 * removes such files whose process no longer exists.
 */
#define _GNU_SOURCE // O_TMPFILE
#include "format/strata_writer.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <inttypes.h>
#include <pthread.h>
#include <signal.h>
#include <stdatomic.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <zstd.h>

#include "core/alloc.h"
#include "core/bytes.h"
#include "core/file_io.h"
#include "format/strata_internal.h"

struct sta_strata_encoder {
    ZSTD_CCtx *cctx;          // owned by this encoder's thread
    uint8_t *raw;             // encoded columns (add_points)
    size_t raw_capacity;      // bytes
    uint8_t *packed;          // zstd output
    size_t packed_capacity;   // bytes
    uint8_t *shuffled;        // byte-shuffled columns, zstd input
    size_t shuffled_capacity; // bytes
};

struct sta_strata_writer {
    char *path;                   // final name
    char *temp_path;              // where bytes go until finish
    char *folder;                 // folder of `path`, fsynced after the rename
    int fd;                       // temp file, -1 once closed
    bool is_named;                // temp_path names the temp file (else O_TMPFILE)
    sta_strata_geometry geometry; // validated, grid_cells resolved
    sta_strata_layout layout;     // extra_dims point at `dims`
    sta_strata_extra_dim *dims;   // owned copy
    int zstd_level;               // 0 store
    char generator[33];           // NUL-terminated
    uint8_t up_axis;              // STA_STRATA_UP_*
    uint8_t *source_block;        // serialised LAS source block, or NULL (owned)
    uint64_t source_size;         // bytes of source_block
    uint64_t data_offset;         // first payload byte
    bool finished;                // finish succeeded (caller's thread only)
    pthread_mutex_t lock;         // guards the fields below
    uint64_t next_offset;         // lock: next free aligned offset
    uint64_t payload_count;       // lock: non-empty payloads written
    bool failed;                  // lock: a write failed; finish refuses
    bool has_points;              // lock: grid_min/max valid
    int32_t grid_min[3];          // lock: tight bounds of all points written
    int32_t grid_max[3];          // lock
};

static atomic_uint temp_counter;

sta_status sta_strata_encoder_create(sta_strata_encoder **out_encoder, sta_error *err)
{
    *out_encoder = NULL;
    sta_strata_encoder *e = sta_calloc(1, sizeof(*e));
    if (!e) {
        return sta_fail(err, STA_ERR_NOMEM, "strata encoder: out of memory");
    }
    e->cctx = ZSTD_createCCtx();
    if (!e->cctx) {
        sta_free(e);
        return sta_fail(err, STA_ERR_NOMEM, "strata encoder: out of memory for zstd");
    }
    *out_encoder = e;
    return STA_OK;
}

void sta_strata_encoder_destroy(sta_strata_encoder *encoder)
{
    if (!encoder) {
        return;
    }
    ZSTD_freeCCtx(encoder->cctx);
    sta_free(encoder->raw);
    sta_free(encoder->packed);
    sta_free(encoder->shuffled);
    sta_free(encoder);
}

// Grows *buf to hold `need` bytes (contents not kept); false when memory is short.
static bool reserve(uint8_t **buf, size_t *capacity, size_t need)
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

// Grows a batch's buffer to at least `need` bytes (doubling), keeping its contents.
static bool reserve_batch(sta_strata_batch *batch, size_t need)
{
    if (need <= batch->capacity) {
        return true;
    }
    size_t capacity = batch->capacity ? batch->capacity : 1 << 16;
    while (capacity < need) {
        capacity = capacity > SIZE_MAX / 2 ? need : capacity * 2;
    }
    uint8_t *grown = sta_realloc_array(batch->bytes, capacity, 1);
    if (!grown) {
        return false;
    }
    batch->bytes = grown;
    batch->capacity = capacity;
    return true;
}

static sta_status check_options(const sta_strata_writer_options *o, const char *path,
                                sta_error *err)
{
    const sta_strata_geometry *g = &o->geometry;
    for (int a = 0; a < 3; a++) {
        if (!(g->grid.scale[a] > 0.0) || g->grid.scale[a] > 1e300 ||
            !(g->grid.offset[a] > -1e300 && g->grid.offset[a] < 1e300)) {
            return sta_fail(err, STA_ERR_ARG, "%s: axis %d has scale %g and offset %g", path, a,
                            g->grid.scale[a], g->grid.offset[a]);
        }
        int64_t size = g->root_size_log2[a] <= STA_STRATA_MAX_ROOT_LOG2
                           ? (int64_t)1 << g->root_size_log2[a]
                           : 0;
        if (size == 0 || g->root_corner[a] < INT32_MIN ||
            g->root_corner[a] > (int64_t)INT32_MAX + 1 - size) {
            return sta_fail(err, STA_ERR_ARG,
                            "%s: root box axis %d at %" PRId64 " of 2^%u units leaves the int32 "
                            "grid",
                            path, a, g->root_corner[a], g->root_size_log2[a]);
        }
    }
    if (g->grid_cells > STA_STRATA_MAX_CELLS) {
        return sta_fail(err, STA_ERR_ARG, "%s: grid_cells %" PRIu32 " exceeds %u", path,
                        g->grid_cells, STA_STRATA_MAX_CELLS);
    }
    if (o->zstd_level < 0 || o->zstd_level > ZSTD_maxCLevel()) {
        return sta_fail(err, STA_ERR_ARG, "%s: zstd level %d is not in 0..%d", path, o->zstd_level,
                        ZSTD_maxCLevel());
    }
    return STA_OK;
}

// The folder holding `path` ("." when it names none); NULL when memory is short.
static char *folder_of(const char *path)
{
    char *folder = sta_malloc(strlen(path) + 2);
    if (!folder) {
        return NULL;
    }
    strcpy(folder, path);
    char *slash = strrchr(folder, '/');
    if (slash == folder) {
        slash[1] = '\0';
    } else if (slash) {
        *slash = '\0';
    } else {
        strcpy(folder, ".");
    }
    return folder;
}

// Removes "<base>.tmp.<pid>.<n>" files in `folder` left by a process that no longer
// exists (killed before it could clean up, on a file system without O_TMPFILE).
static void sweep_stale_temporaries(const char *path, const char *folder)
{
    const char *slash = strrchr(path, '/');
    const char *base = slash ? slash + 1 : path;
    size_t base_length = strlen(base);
    DIR *dir = opendir(folder);
    if (!dir) {
        return;
    }
    struct dirent *entry;
    while ((entry = readdir(dir)) != NULL) {
        const char *name = entry->d_name;
        if (strncmp(name, base, base_length) != 0 || strncmp(name + base_length, ".tmp.", 5)) {
            continue;
        }
        char *end = NULL;
        long pid = strtol(name + base_length + 5, &end, 10);
        if (pid <= 0 || *end != '.' || pid == (long)getpid() ||
            !(kill((pid_t)pid, 0) != 0 && errno == ESRCH)) {
            continue;
        }
        char *stale = sta_malloc(strlen(folder) + strlen(name) + 2);
        if (stale) {
            sprintf(stale, "%s/%s", folder, name);
            unlink(stale);
            sta_free(stale);
        }
    }
    closedir(dir);
}

sta_status sta_strata_writer_create(const char *path, const sta_strata_writer_options *options,
                                    sta_strata_writer **out_writer, sta_error *err)
{
    *out_writer = NULL;
    sta_status s = check_options(options, path, err);
    if (s != STA_OK) {
        return s;
    }
    sta_strata_writer *w = sta_calloc(1, sizeof(*w));
    if (!w) {
        return sta_fail(err, STA_ERR_NOMEM, "%s: out of memory", path);
    }
    w->fd = -1;
    w->geometry = options->geometry;
    if (w->geometry.grid_cells == 0) {
        w->geometry.grid_cells = STA_STRATA_DEFAULT_CELLS;
    }
    w->zstd_level = options->zstd_level;
    snprintf(w->generator, sizeof(w->generator), "%s",
             options->generator ? options->generator : "strata");
    w->up_axis = options->up_axis == STA_STRATA_UP_Y ? STA_STRATA_UP_Y : STA_STRATA_UP_Z;
    uint32_t dim_count = options->layout.extra_dim_count;
    if (dim_count > 0 && dim_count <= STA_STRATA_MAX_EXTRA_DIMS && options->layout.extra_dims) {
        w->dims = sta_alloc_array(dim_count, sizeof(*w->dims));
        if (!w->dims) {
            s = sta_fail(err, STA_ERR_NOMEM, "%s: out of memory", path);
            goto out_free;
        }
        memcpy(w->dims, options->layout.extra_dims, dim_count * sizeof(*w->dims));
    }
    s = sta_strata_layout_init(&w->layout, options->layout.attributes, w->dims, dim_count, err);
    if (s != STA_OK) {
        sta_error_prefix(err, "%s", path);
        goto out_free;
    }
    if (options->las_source) {
        w->source_size = sta_strata_las_source_size(options->las_source);
        w->source_block = w->source_size <= SIZE_MAX ? sta_malloc((size_t)w->source_size) : NULL;
        if (!w->source_block) {
            s = sta_fail(err, STA_ERR_NOMEM, "%s: out of memory for the LAS source", path);
            goto out_free;
        }
        sta_strata_las_source_store(options->las_source, w->source_block);
    }
    w->data_offset =
        sta_strata_align(STA_STRATA_HEADER_SIZE + (uint64_t)dim_count * STA_STRATA_EXTRA_DIM_SIZE,
                         STA_STRATA_ALIGNMENT);
    w->next_offset = w->data_offset;
    w->path = sta_strdup(path);
    w->folder = folder_of(path);
    size_t temp_size = strlen(path) + 48;
    w->temp_path = sta_malloc(temp_size);
    if (!w->path || !w->folder || !w->temp_path) {
        s = sta_fail(err, STA_ERR_NOMEM, "%s: out of memory", path);
        goto out_free;
    }
    sweep_stale_temporaries(path, w->folder);
    snprintf(w->temp_path, temp_size, "%s.tmp.%ld.%u", path, (long)getpid(),
             atomic_fetch_add(&temp_counter, 1u));
    w->fd = open(w->folder, O_TMPFILE | O_WRONLY | O_CLOEXEC, 0666);
    for (int attempt = 0; attempt < 100 && w->fd < 0; attempt++) {
        // No O_TMPFILE here (or it failed): a named file, removed by a later sweep if
        // this process dies.
        snprintf(w->temp_path, temp_size, "%s.tmp.%ld.%u", path, (long)getpid(),
                 atomic_fetch_add(&temp_counter, 1u));
        w->fd = open(w->temp_path, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        w->is_named = w->fd >= 0;
        if (w->fd < 0 && errno != EEXIST) {
            break;
        }
    }
    if (w->fd < 0) {
        s = sta_fail(err, STA_ERR_IO, "%s: cannot create %s: %s", path, w->temp_path,
                     strerror(errno));
        goto out_free;
    }
    if (pthread_mutex_init(&w->lock, NULL) != 0) {
        close(w->fd);
        if (w->is_named) {
            unlink(w->temp_path);
        }
        s = sta_fail(err, STA_ERR_NOMEM, "%s: cannot create a mutex", path);
        goto out_free;
    }
    *out_writer = w;
    return STA_OK;

out_free:
    sta_free(w->temp_path);
    sta_free(w->folder);
    sta_free(w->path);
    sta_free(w->dims);
    sta_free(w->source_block);
    sta_free(w);
    return s;
}

// "node (level 3, 5/2/7)" for messages about a node not yet in a table.
static const char *key_label(char *buf, size_t size, sta_strata_key key)
{
    snprintf(buf, size, "node (level %u, %" PRIu32 "/%" PRIu32 "/%" PRIu32 ")", key.level, key.x,
             key.y, key.z);
    return buf;
}

// A key must name a cell of its level within the root's depth limit.
static sta_status check_key(const sta_strata_writer *w, sta_strata_key key, sta_error *err)
{
    char label[96];
    unsigned cap = sta_strata_level_cap(&w->geometry);
    uint64_t cells = (uint64_t)1 << (key.level <= 32 ? key.level : 0);
    if (key.level > cap || key.x >= cells || key.y >= cells || key.z >= cells) {
        return sta_fail(err, STA_ERR_ARG, "%s: %s is not a node of a tree with depth limit %u",
                        w->path, key_label(label, sizeof(label), key), cap);
    }
    return STA_OK;
}

// Checks every position of the columns against the node box; gives the tight bounds.
static sta_status check_positions(const sta_strata_writer *w, sta_strata_key key,
                                  const uint8_t *raw, size_t count, int32_t out_min[3],
                                  int32_t out_max[3], sta_error *err)
{
    char label[96];
    int64_t corner[3], size[3];
    sta_status s = check_key(w, key, err);
    if (s != STA_OK) {
        return s;
    }
    sta_strata_node_grid_bounds(&w->geometry, key, corner, size);
    for (int a = 0; a < 3; a++) {
        const uint8_t *column = raw + (size_t)a * 4 * count;
        uint32_t lo = UINT32_MAX, hi = 0;
        for (size_t i = 0; i < count; i++) {
            uint32_t rel = sta_load_u32le(column + i * 4);
            if (rel >= (uint64_t)size[a]) {
                int64_t p[3];
                for (int b = 0; b < 3; b++) {
                    p[b] = corner[b] + sta_load_u32le(raw + ((size_t)b * count + i) * 4);
                }
                key_label(label, sizeof(label), key);
                return sta_fail(
                    err, STA_ERR_ARG,
                    "%s: %s: point %zu at grid (%" PRId64 ", %" PRId64 ", %" PRId64
                    ") lies outside the node's box [%" PRId64 ", %" PRId64 ") on axis %d",
                    w->path, label, i, p[0], p[1], p[2], corner[a], corner[a] + size[a], a);
            }
            lo = rel < lo ? rel : lo;
            hi = rel > hi ? rel : hi;
        }
        out_min[a] = (int32_t)(corner[a] + lo);
        out_max[a] = (int32_t)(corner[a] + hi);
    }
    return STA_OK;
}

// Checks and compresses one node's columns: *out_stored points at the bytes to store
// (the caller's columns or the encoder's buffer), *out_payload gets everything but
// the offset, lo/hi the node's tight bounds.
static sta_status pack(sta_strata_writer *w, sta_strata_encoder *enc, sta_strata_key key,
                       const void *columns, size_t count, const uint8_t **out_stored,
                       sta_strata_payload *out_payload, int32_t lo[3], int32_t hi[3],
                       sta_error *err)
{
    if (count > SIZE_MAX / w->layout.record_size) {
        return sta_fail(err, STA_ERR_ARG, "%s: %zu points do not fit in memory", w->path, count);
    }
    const uint8_t *raw = columns;
    size_t raw_size = count * w->layout.record_size;
    sta_status s = check_positions(w, key, raw, count, lo, hi, err);
    if (s != STA_OK) {
        return s;
    }
    const uint8_t *stored = raw;
    size_t stored_size = raw_size;
    uint8_t compression = STA_STRATA_COMPRESSION_NONE;
    if (w->zstd_level > 0) {
        size_t bound = ZSTD_compressBound(raw_size);
        if (ZSTD_isError(bound) || !reserve(&enc->packed, &enc->packed_capacity, bound)) {
            return sta_fail(err, STA_ERR_NOMEM, "%s: out of memory compressing %zu bytes", w->path,
                            raw_size);
        }
        if (!reserve(&enc->shuffled, &enc->shuffled_capacity, raw_size)) {
            return sta_fail(err, STA_ERR_NOMEM, "%s: out of memory compressing %zu bytes", w->path,
                            raw_size);
        }
        // Byte planes of each column compress better and faster than whole values.
        sta_strata_shuffle(&w->layout, count, raw, enc->shuffled);
        ZSTD_CCtx_setParameter(enc->cctx, ZSTD_c_compressionLevel, w->zstd_level);
        size_t n = ZSTD_compress2(enc->cctx, enc->packed, bound, enc->shuffled, raw_size);
        if (ZSTD_isError(n)) {
            return sta_fail(err, STA_ERR_NOMEM, "%s: zstd failed on %zu bytes: %s", w->path,
                            raw_size, ZSTD_getErrorName(n));
        }
        if (n < raw_size) {
            stored = enc->packed;
            stored_size = n;
            compression = STA_STRATA_COMPRESSION_ZSTD_SHUFFLE;
        }
    }
    *out_stored = stored;
    out_payload->stored_size = stored_size;
    out_payload->raw_size = raw_size;
    out_payload->checksum = sta_strata_checksum(stored, stored_size);
    out_payload->compression = compression;
    return STA_OK;
}

// Reserves `size` bytes (aligned) for `payloads` payloads with bounds lo/hi, writes
// `bytes` there and returns the offset in *out_offset.
static sta_status append(sta_strata_writer *w, const uint8_t *bytes, uint64_t size,
                         uint64_t payloads, const int32_t lo[3], const int32_t hi[3],
                         uint64_t *out_offset, sta_error *err)
{
    pthread_mutex_lock(&w->lock);
    bool failed = w->failed;
    uint64_t offset = w->next_offset;
    if (!failed) {
        w->next_offset = sta_strata_align(offset + size, STA_STRATA_ALIGNMENT);
        w->payload_count += payloads;
        for (int a = 0; a < 3; a++) {
            w->grid_min[a] = !w->has_points || lo[a] < w->grid_min[a] ? lo[a] : w->grid_min[a];
            w->grid_max[a] = !w->has_points || hi[a] > w->grid_max[a] ? hi[a] : w->grid_max[a];
        }
        w->has_points = true;
    }
    pthread_mutex_unlock(&w->lock);
    if (failed) {
        return sta_fail(err, STA_ERR_IO, "%s: an earlier write failed", w->path);
    }
    sta_status s = sta_pwrite_all(w->fd, bytes, (size_t)size, offset, w->temp_path, err);
    if (s != STA_OK) {
        pthread_mutex_lock(&w->lock);
        w->failed = true;
        pthread_mutex_unlock(&w->lock);
        return s;
    }
    *out_offset = offset;
    return STA_OK;
}

sta_status sta_strata_writer_add_node(sta_strata_writer *w, sta_strata_encoder *enc,
                                      sta_strata_key key, const void *columns, size_t count,
                                      sta_strata_payload *out_payload, sta_error *err)
{
    memset(out_payload, 0, sizeof(*out_payload));
    out_payload->checksum = sta_strata_checksum(NULL, 0);
    if (count == 0) {
        return STA_OK;
    }
    const uint8_t *stored = NULL;
    int32_t lo[3], hi[3];
    sta_status s = pack(w, enc, key, columns, count, &stored, out_payload, lo, hi, err);
    if (s != STA_OK) {
        return s;
    }
    return append(w, stored, out_payload->stored_size, 1, lo, hi, &out_payload->offset, err);
}

sta_status sta_strata_writer_pack_node(sta_strata_writer *w, sta_strata_encoder *enc,
                                       sta_strata_key key, const void *columns, size_t count,
                                       sta_strata_batch *batch, sta_strata_payload *out_payload,
                                       sta_error *err)
{
    memset(out_payload, 0, sizeof(*out_payload));
    out_payload->checksum = sta_strata_checksum(NULL, 0);
    if (count == 0) {
        return STA_OK;
    }
    const uint8_t *stored = NULL;
    int32_t lo[3], hi[3];
    sta_status s = pack(w, enc, key, columns, count, &stored, out_payload, lo, hi, err);
    if (s != STA_OK) {
        return s;
    }
    // Aligned inside the batch, so aligned in the file once the batch starts aligned.
    uint64_t at = sta_strata_align(batch->size, STA_STRATA_ALIGNMENT);
    uint64_t end = at + out_payload->stored_size;
    if (end > SIZE_MAX || !reserve_batch(batch, (size_t)end)) {
        return sta_fail(err, STA_ERR_NOMEM, "%s: out of memory for a batch of %" PRIu64 " bytes",
                        w->path, end);
    }
    memset(batch->bytes + batch->size, 0, (size_t)(at - batch->size));
    memcpy(batch->bytes + at, stored, out_payload->stored_size);
    batch->size = (size_t)end;
    batch->payload_count++;
    for (int a = 0; a < 3; a++) {
        batch->lo[a] = !batch->has_points || lo[a] < batch->lo[a] ? lo[a] : batch->lo[a];
        batch->hi[a] = !batch->has_points || hi[a] > batch->hi[a] ? hi[a] : batch->hi[a];
    }
    batch->has_points = true;
    out_payload->offset = at;
    return STA_OK;
}

sta_status sta_strata_writer_add_batch(sta_strata_writer *w, const sta_strata_batch *batch,
                                       uint64_t *out_offset, sta_error *err)
{
    *out_offset = 0;
    if (batch->payload_count == 0) {
        return STA_OK;
    }
    return append(w, batch->bytes, batch->size, batch->payload_count, batch->lo, batch->hi,
                  out_offset, err);
}

void sta_strata_batch_release(sta_strata_batch *batch)
{
    sta_free(batch->bytes);
    memset(batch, 0, sizeof(*batch));
}

sta_status sta_strata_writer_add_points(sta_strata_writer *w, sta_strata_encoder *enc,
                                        sta_strata_key key, const sta_point *points,
                                        const uint8_t *extra, size_t count,
                                        sta_strata_payload *out_payload, sta_error *err)
{
    memset(out_payload, 0, sizeof(*out_payload));
    if (count > SIZE_MAX / w->layout.record_size) {
        return sta_fail(err, STA_ERR_ARG, "%s: %zu points do not fit in memory", w->path, count);
    }
    if (count > 0 && w->layout.extra_size > 0 && !extra) {
        return sta_fail(err, STA_ERR_ARG, "%s: the layout has extra bytes but none were given",
                        w->path);
    }
    if (!reserve(&enc->raw, &enc->raw_capacity, count * w->layout.record_size)) {
        return sta_fail(err, STA_ERR_NOMEM, "%s: out of memory encoding %zu points", w->path,
                        count);
    }
    sta_status s = check_key(w, key, err);
    if (s != STA_OK) {
        return s;
    }
    int64_t corner[3], size[3];
    sta_strata_node_grid_bounds(&w->geometry, key, corner, size);
    s = sta_strata_encode_points(&w->layout, points, extra, count, corner, enc->raw, err);
    if (s != STA_OK) {
        char label[96];
        sta_error_prefix(err, "%s: %s", w->path, key_label(label, sizeof(label), key));
        return s;
    }
    return sta_strata_writer_add_node(w, enc, key, enc->raw, count, out_payload, err);
}

// Fsyncs the folder so that the rename is durable.
static sta_status sync_folder(const sta_strata_writer *w, sta_error *err)
{
    sta_status s = STA_OK;
    int fd = open(w->folder, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0 || fsync(fd) != 0) {
        s = sta_fail(err, STA_ERR_IO, "%s: cannot sync folder %s: %s", w->path, w->folder,
                     strerror(errno));
    }
    if (fd >= 0) {
        close(fd);
    }
    return s;
}

// Fills the header description of the finished file.
static void describe(const sta_strata_writer *w, const sta_strata_node *nodes, uint32_t count,
                     sta_strata_info *info)
{
    memset(info, 0, sizeof(*info));
    info->path = w->path;
    info->version_major = STA_STRATA_VERSION_MAJOR;
    info->version_minor = STA_STRATA_VERSION_MINOR; // 1.2: up axis, LAS source (may be none)
    info->header_size = STA_STRATA_HEADER_SIZE;
    info->geometry = w->geometry;
    info->layout = w->layout;
    info->node_count = count;
    info->node_entry_size = STA_STRATA_NODE_ENTRY_SIZE;
    info->payload_alignment = STA_STRATA_ALIGNMENT;
    info->data_offset = w->data_offset;
    info->table_offset = w->next_offset;
    if (w->source_block) { // after the last payload, before the table
        info->source_offset = w->next_offset;
        info->source_size = w->source_size;
        info->source_checksum = sta_strata_checksum(w->source_block, (size_t)w->source_size);
        info->table_offset =
            sta_strata_align(info->source_offset + w->source_size, STA_STRATA_ALIGNMENT);
    }
    info->file_size = info->table_offset + (uint64_t)count * STA_STRATA_NODE_ENTRY_SIZE;
    snprintf(info->generator, sizeof(info->generator), "%s", w->generator);
    info->up_axis = w->up_axis;
    for (uint32_t i = 0; i < count; i++) {
        info->point_count += nodes[i].point_count; // overflow is caught by the table check
        if (nodes[i].key.level > info->max_level) {
            info->max_level = nodes[i].key.level;
        }
    }
    if (w->has_points) {
        for (int a = 0; a < 3; a++) {
            info->grid_min[a] = w->grid_min[a];
            info->grid_max[a] = w->grid_max[a];
            info->bounds_min[a] = sta_grid_apply(&w->geometry.grid, a, w->grid_min[a]);
            info->bounds_max[a] = sta_grid_apply(&w->geometry.grid, a, w->grid_max[a]);
        }
    }
}

sta_status sta_strata_writer_finish(sta_strata_writer *w, const sta_strata_node *nodes,
                                    size_t node_count, sta_error *err)
{
    if (w->finished || w->fd < 0) {
        return sta_fail(err, STA_ERR_ARG, "%s: writer already finished", w->path);
    }
    if (w->failed) {
        return sta_fail(err, STA_ERR_IO, "%s: an earlier write failed", w->path);
    }
    if (node_count == 0 || node_count > UINT32_MAX) {
        return sta_fail(err, STA_ERR_ARG, "%s: %zu nodes (need 1 to 2^32-1)", w->path, node_count);
    }
    uint32_t count = (uint32_t)node_count;
    sta_status s = STA_OK;
    uint8_t *table = NULL, *head = NULL;
    sta_strata_node *copy = sta_alloc_array(count, sizeof(*copy));
    size_t table_size = (size_t)count * STA_STRATA_NODE_ENTRY_SIZE;
    size_t dims_size = (size_t)w->layout.extra_dim_count * STA_STRATA_EXTRA_DIM_SIZE;
    table = sta_malloc(table_size);
    head = sta_malloc(STA_STRATA_HEADER_SIZE + dims_size);
    if (!copy || !table || !head) {
        s = sta_fail(err, STA_ERR_NOMEM, "%s: out of memory for a table of %" PRIu32 " nodes",
                     w->path, count);
        goto out_free;
    }
    uint64_t written = 0;
    for (uint32_t i = 0; i < count; i++) {
        copy[i] = nodes[i];
        unsigned level = nodes[i].key.level <= 32 ? nodes[i].key.level : 0;
        copy[i].spacing = sta_strata_node_spacing(&w->geometry, level);
        written += nodes[i].payload.stored_size > 0;
    }
    sta_strata_info info;
    describe(w, copy, count, &info);
    s = sta_strata_table_check(&info, copy, w->path, err);
    if (s != STA_OK) {
        if (s == STA_ERR_FORMAT) { // the caller's table, not a file, is wrong
            s = STA_ERR_ARG;
            if (err) {
                err->code = s;
            }
        }
        goto out_free;
    }
    if (written != w->payload_count) {
        s = sta_fail(err, STA_ERR_ARG,
                     "%s: the table references %" PRIu64 " payloads but %" PRIu64 " were written",
                     w->path, written, w->payload_count);
        goto out_free;
    }
    for (uint32_t i = 0; i < count; i++) {
        sta_strata_node_store(&copy[i], table + (size_t)i * STA_STRATA_NODE_ENTRY_SIZE);
    }
    info.table_checksum = sta_strata_checksum(table, table_size);
    sta_strata_extra_dims_store(w->dims, w->layout.extra_dim_count, head + STA_STRATA_HEADER_SIZE);
    info.extra_dims_checksum = sta_strata_checksum(head + STA_STRATA_HEADER_SIZE, dims_size);
    sta_strata_header_store(&info, head);

    s = sta_pwrite_all(w->fd, table, table_size, info.table_offset, w->temp_path, err);
    if (s == STA_OK && w->source_block) {
        s = sta_pwrite_all(w->fd, w->source_block, (size_t)w->source_size, info.source_offset,
                           w->temp_path, err);
    }
    if (s == STA_OK) {
        s = sta_pwrite_all(w->fd, head, STA_STRATA_HEADER_SIZE + dims_size, 0, w->temp_path, err);
    }
    if (s == STA_OK && fsync(w->fd) != 0) {
        s = sta_fail(err, STA_ERR_IO, "%s: cannot sync: %s", w->temp_path, strerror(errno));
    }
    if (s != STA_OK) {
        goto out_free;
    }
    if (!w->is_named) {
        // Give the unnamed file its temporary name, then rename it like a named one.
        char proc_path[64];
        snprintf(proc_path, sizeof(proc_path), "/proc/self/fd/%d", w->fd);
        if (linkat(AT_FDCWD, proc_path, AT_FDCWD, w->temp_path, AT_SYMLINK_FOLLOW) != 0) {
            s = sta_fail(err, STA_ERR_IO, "%s: cannot link the temporary file as %s: %s", w->path,
                         w->temp_path, strerror(errno));
            goto out_free;
        }
        w->is_named = true;
    }
    int fd = w->fd;
    w->fd = -1;
    if (close(fd) != 0) {
        s = sta_fail(err, STA_ERR_IO, "%s: cannot close: %s", w->temp_path, strerror(errno));
        goto out_free;
    }
    if (rename(w->temp_path, w->path) != 0) {
        s = sta_fail(err, STA_ERR_IO, "%s: cannot rename %s to it: %s", w->path, w->temp_path,
                     strerror(errno));
        goto out_free;
    }
    w->finished = true;
    s = sync_folder(w, err);

out_free:
    sta_free(head);
    sta_free(table);
    sta_free(copy);
    return s;
}

const char *sta_strata_writer_temp_path(const sta_strata_writer *w)
{
    return w->temp_path;
}

bool sta_strata_writer_is_unnamed(const sta_strata_writer *w)
{
    return !w->is_named;
}

void sta_strata_writer_destroy(sta_strata_writer *w)
{
    if (!w) {
        return;
    }
    if (w->fd >= 0) {
        close(w->fd);
    }
    if (!w->finished && w->is_named) {
        unlink(w->temp_path);
    }
    pthread_mutex_destroy(&w->lock);
    sta_free(w->temp_path);
    sta_free(w->folder);
    sta_free(w->path);
    sta_free(w->dims);
    sta_free(w->source_block);
    sta_free(w);
}
