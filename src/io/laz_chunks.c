/* SPDX-License-Identifier: MIT
 * LAZ point data: the chunk table, walking the chunks and decoding records.
 *
 * Structure (chunked compressors 2 and 3): at offset_to_point_data an int64 gives the
 * file offset of the chunk table (-1: the writer could not seek back, the offset is
 * then in the last 8 bytes of the file); the chunks follow it back to back. Each chunk
 * starts with its first record raw, then the arithmetic-coded rest (point10) or the
 * layers (point14). The chunk table is u32 version (0), u32 chunk count, then an
 * arithmetic-coded list of (point count, for variable chunks) and byte size per chunk,
 * each predicted from the previous chunk's. Compressor 1 has one chunk, no table.
 *
 * Decisions:
 * - A chunk table that is missing, has another version, decodes to impossible sizes
 *   (zero, past the table, fewer points than the header) is not trusted: a warning
 *   is printed and the chunks are found sequentially (a chunk ends where its decoder
 *   stopped reading). Variable point10 chunks cannot be walked that way
 *   (STA_ERR_FORMAT at open).
 * - A decoder that reads any byte past its chunk (valid streams end exactly there) means the chunk
 * is damaged or truncated: STA_ERR_FORMAT naming the file, chunk, byte range and point. This check
 * runs after every point, so a lying point count costs at most a few thousand points of work per
 * missing byte, never a hang.
 * - Seeking decodes from the start of the chunk that holds the point (sequential
 *   mode: from the current position, or from the first chunk when going back).
 */
#include <stdio.h>
#include <string.h>

#include "core/alloc.h"
#include "core/bytes.h"
#include "core/log.h"
#include "io/laz_internal.h"

enum {
    OVERRUN_SLACK = 0,     // valid streams end exactly at their chunk end (writer pads)
    CHUNK_TABLE_HEADER = 8 // u32 version, u32 chunk count
};

struct sta_laz {
    const char *path;    // for messages
    const uint8_t *data; // whole file (borrowed)
    size_t size;
    sta_laz_vlr vlr;
    bool layered;          // point14 family
    uint64_t point_count;  // points to decode
    size_t record_length;  // raw record bytes
    uint64_t chunk_size;   // points per chunk (fixed), or UINT64_MAX (variable)
    uint64_t chunks_start; // offset of the first chunk
    uint64_t chunks_end;   // end of the chunk data (table offset, or file size)
    bool tabled;           // chunk table trusted
    uint64_t chunk_count;  // tabled chunks
    uint64_t *starts;      // chunk_count + 1 byte offsets (tabled)
    uint64_t *firsts;      // chunk_count + 1 first point indices (tabled)
    sta_laz_p10 *p10;      // item decoders of the family in use
    sta_laz_p14 *p14;
    uint8_t *scratch; // one record (seeking) and the first raw record
    // Position.
    bool live;              // a chunk is being decoded
    uint64_t cur;           // index of the next point the decoder yields
    uint64_t target;        // index the next sta_laz_decode must yield
    uint64_t chunk;         // current chunk number
    uint64_t chunk_start;   // its byte offset
    uint64_t chunk_limit;   // end of its bytes
    uint64_t chunk_points;  // its point count
    uint64_t chunk_done;    // points of it decoded
    const uint8_t *first;   // its raw first record (in the file)
    const uint8_t *p14_end; // point14: end of its layers
    sta_laz_dec dec;        // point10 decoder
};

bool sta_laz_has_chunk_table(const sta_laz *laz)
{
    return laz->tabled;
}

// Decodes the chunk table; false (with `why` filled) when it cannot be trusted.
static bool read_chunk_table(sta_laz *laz, uint64_t point_data, char *why, size_t why_size,
                             bool *out_nomem)
{
    const uint8_t *d = laz->data;
    uint64_t size = laz->size;
    *out_nomem = false;
    int64_t table_at = sta_load_i64le(d + point_data);
    if (table_at == -1 && size >= 8) {
        table_at = sta_load_i64le(d + size - 8);
    }
    if (table_at < (int64_t)laz->chunks_start || (uint64_t)table_at > size - CHUNK_TABLE_HEADER) {
        snprintf(why, why_size, "chunk table offset %lld is outside the point data (%llu..%llu)",
                 (long long)table_at, (unsigned long long)laz->chunks_start,
                 (unsigned long long)size);
        return false;
    }
    uint64_t at = (uint64_t)table_at;
    uint32_t version = sta_load_u32le(d + at);
    uint64_t count = sta_load_u32le(d + at + 4);
    if (version != 0) {
        snprintf(why, why_size, "chunk table version %u is unknown", version);
        return false;
    }
    // Each chunk holds at least its raw first record.
    if (count > (at - laz->chunks_start) / laz->record_length) {
        snprintf(why, why_size, "chunk table lists %llu chunks, %llu bytes cannot hold them",
                 (unsigned long long)count, (unsigned long long)(at - laz->chunks_start));
        return false;
    }
    laz->starts = sta_alloc_array(count + 1, sizeof(*laz->starts));
    laz->firsts = sta_alloc_array(count + 1, sizeof(*laz->firsts));
    sta_laz_ic ic;
    if (!laz->starts || !laz->firsts || !sta_laz_ic_init(&ic, 32, 2)) {
        if (laz->starts && laz->firsts) {
            sta_laz_ic_release(&ic);
        }
        *out_nomem = true;
        return false;
    }
    sta_laz_dec dec;
    sta_laz_dec_init(&dec, d + at + CHUNK_TABLE_HEADER, d + size);
    bool variable = laz->chunk_size == UINT64_MAX;
    laz->starts[0] = laz->chunks_start;
    laz->firsts[0] = 0;
    int32_t last_count = 0;
    int32_t last_size = 0;
    bool ok = true;
    for (uint64_t i = 1; i <= count && ok; i++) {
        if (variable) {
            last_count = sta_laz_ic_decode(&ic, &dec, last_count, 0);
        }
        last_size = sta_laz_ic_decode(&ic, &dec, last_size, 1);
        uint64_t points = variable ? (uint32_t)last_count : laz->chunk_size;
        laz->starts[i] = laz->starts[i - 1] + (uint64_t)(uint32_t)last_size;
        laz->firsts[i] = laz->firsts[i - 1] + points;
        if (last_size <= 0 || laz->starts[i] > at || (variable && last_count <= 0)) {
            snprintf(why, why_size,
                     "chunk table entry %llu decodes to %d points in %d bytes, past the table "
                     "at byte %llu",
                     (unsigned long long)(i - 1), variable ? last_count : (int)laz->chunk_size,
                     last_size, (unsigned long long)at);
            ok = false;
        }
    }
    sta_laz_ic_release(&ic);
    if (ok && dec.overrun > OVERRUN_SLACK) {
        snprintf(why, why_size, "chunk table at byte %llu is truncated", (unsigned long long)at);
        ok = false;
    }
    uint64_t total = laz->firsts[count];
    if (ok && (total < laz->point_count ||
               (!variable && count > 0 && laz->firsts[count - 1] >= laz->point_count))) {
        snprintf(why, why_size, "chunk table's %llu chunks hold %llu points, the header says %llu",
                 (unsigned long long)count, (unsigned long long)total,
                 (unsigned long long)laz->point_count);
        ok = false;
    }
    if (!ok) {
        return false;
    }
    laz->chunk_count = count;
    laz->chunks_end = at;
    return true;
}

static sta_status setup_chunks(sta_laz *laz, uint64_t point_data, sta_error *err)
{
    if (laz->vlr.compressor == STA_LAZ_COMPRESSOR_POINTWISE) {
        // One chunk of every point right at the point data, no table.
        laz->starts = sta_alloc_array(2, sizeof(*laz->starts));
        laz->firsts = sta_alloc_array(2, sizeof(*laz->firsts));
        if (!laz->starts || !laz->firsts) {
            return sta_fail(err, STA_ERR_NOMEM, "%s: out of memory", laz->path);
        }
        laz->chunks_start = point_data;
        laz->chunks_end = laz->size;
        laz->chunk_size = UINT64_MAX;
        laz->starts[0] = point_data;
        laz->starts[1] = laz->size;
        laz->firsts[0] = 0;
        laz->firsts[1] = laz->point_count;
        laz->chunk_count = 1;
        laz->tabled = true;
        return STA_OK;
    }
    laz->chunk_size = laz->vlr.chunk_size == UINT32_MAX ? UINT64_MAX : laz->vlr.chunk_size;
    if (laz->size - point_data < 8) {
        if (laz->point_count == 0) {
            laz->tabled = true;
            return STA_OK;
        }
        return sta_fail(err, STA_ERR_FORMAT,
                        "%s: LAZ point data at byte %llu is shorter than its 8-byte chunk table "
                        "offset",
                        laz->path, (unsigned long long)point_data);
    }
    laz->chunks_start = point_data + 8;
    laz->chunks_end = laz->size;
    char why[200];
    bool nomem = false;
    laz->tabled = read_chunk_table(laz, point_data, why, sizeof(why), &nomem);
    if (nomem) {
        return sta_fail(err, STA_ERR_NOMEM, "%s: out of memory for the LAZ chunk table", laz->path);
    }
    if (laz->tabled || laz->point_count == 0) {
        laz->tabled = true;
        return STA_OK;
    }
    laz->chunks_end = laz->size;
    laz->chunk_count = 0;
    if (laz->chunk_size == UINT64_MAX && !laz->layered) {
        return sta_fail(err, STA_ERR_FORMAT,
                        "%s: LAZ %s and the chunks have variable point counts, so they cannot be "
                        "found without it",
                        laz->path, why);
    }
    sta_log_warn("%s: LAZ %s; decoding the chunks sequentially (seeking is slow)", laz->path, why);
    return STA_OK;
}

sta_status sta_laz_open(const char *path, const uint8_t *data, size_t size, uint64_t point_data,
                        const sta_laz_vlr *vlr, uint64_t point_count, size_t record_length,
                        sta_laz **out_laz, sta_error *err)
{
    *out_laz = NULL;
    sta_laz *laz = sta_calloc(1, sizeof(*laz));
    if (!laz) {
        return sta_fail(err, STA_ERR_NOMEM, "%s: out of memory", path);
    }
    laz->path = path;
    laz->data = data;
    laz->size = size;
    laz->vlr = *vlr;
    laz->layered = vlr->compressor == STA_LAZ_COMPRESSOR_LAYERED_CHUNKED;
    laz->point_count = point_count;
    laz->record_length = record_length;
    sta_status status = setup_chunks(laz, point_data, err);
    if (status != STA_OK) {
        goto out_close;
    }
    laz->scratch = sta_malloc(record_length);
    if (laz->layered) {
        laz->p14 = sta_laz_p14_create(vlr);
    } else {
        laz->p10 = sta_laz_p10_create(vlr);
    }
    if (!laz->scratch || (!laz->p14 && !laz->p10)) {
        status = sta_fail(err, STA_ERR_NOMEM, "%s: out of memory for the LAZ decoder", path);
        goto out_close;
    }
    *out_laz = laz;
    return STA_OK;

out_close:
    sta_laz_close(laz);
    return status;
}

void sta_laz_close(sta_laz *laz)
{
    if (!laz) {
        return;
    }
    sta_laz_p10_destroy(laz->p10);
    sta_laz_p14_destroy(laz->p14);
    sta_free(laz->starts);
    sta_free(laz->firsts);
    sta_free(laz->scratch);
    sta_free(laz);
}

// Starts chunk `chunk` at byte `start` whose first point is `first_index`.
static sta_status begin_chunk(sta_laz *laz, uint64_t chunk, uint64_t start, uint64_t first_index,
                              sta_error *err)
{
    laz->live = false;
    uint64_t limit = laz->tabled ? laz->starts[chunk + 1] : laz->chunks_end;
    if (start > limit || limit - start < laz->record_length) {
        return sta_fail(err, STA_ERR_FORMAT,
                        "%s: LAZ chunk %llu (point %llu) at byte %llu has %llu bytes, fewer than "
                        "its raw first record of %zu bytes; the file is truncated or corrupt",
                        laz->path, (unsigned long long)chunk, (unsigned long long)first_index,
                        (unsigned long long)start,
                        (unsigned long long)(start > limit ? 0 : limit - start),
                        laz->record_length);
    }
    uint64_t left = laz->point_count - first_index;
    uint64_t points;
    if (laz->tabled) {
        points = laz->firsts[chunk + 1] - laz->firsts[chunk];
    } else {
        points = laz->chunk_size;
    }
    const uint8_t *first = laz->data + start;
    const uint8_t *body = first + laz->record_length;
    if (laz->layered) {
        uint32_t stored = 0;
        const uint8_t *end = NULL;
        if (!sta_laz_p14_begin(laz->p14, first, body, laz->data + limit, &stored, &end)) {
            return sta_fail(err, STA_ERR_FORMAT,
                            "%s: LAZ chunk %llu (point %llu) at byte %llu: its layer sizes run "
                            "past the chunk's %llu bytes; the file is truncated or corrupt",
                            laz->path, (unsigned long long)chunk, (unsigned long long)first_index,
                            (unsigned long long)start, (unsigned long long)(limit - start));
        }
        if (!laz->tabled && laz->chunk_size == UINT64_MAX) {
            points = stored;
        }
        laz->p14_end = end;
    } else {
        sta_laz_p10_begin(laz->p10, first);
        sta_laz_dec_init(&laz->dec, body, laz->data + limit);
    }
    if (points == 0) {
        return sta_fail(err, STA_ERR_FORMAT, "%s: LAZ chunk %llu (point %llu) holds no points",
                        laz->path, (unsigned long long)chunk, (unsigned long long)first_index);
    }
    laz->chunk = chunk;
    laz->chunk_start = start;
    laz->chunk_limit = limit;
    laz->chunk_points = points < left ? points : left;
    laz->chunk_done = 0;
    laz->first = first;
    laz->cur = first_index;
    laz->live = true;
    return STA_OK;
}

// Where the chunk after the current one starts.
static uint64_t next_chunk_start(const sta_laz *laz)
{
    if (laz->tabled) {
        return laz->starts[laz->chunk + 1];
    }
    if (laz->layered) {
        return (uint64_t)(laz->p14_end - laz->data);
    }
    return (uint64_t)(laz->dec.p - laz->data);
}

static sta_status decode_one(sta_laz *laz, uint8_t *out, sta_error *err)
{
    if (laz->chunk_done == laz->chunk_points) {
        uint64_t next = laz->chunk + 1;
        if (laz->tabled && next >= laz->chunk_count) {
            return sta_fail(err, STA_ERR_FORMAT,
                            "%s: LAZ point %llu lies past the %llu chunks of the chunk table",
                            laz->path, (unsigned long long)laz->cur,
                            (unsigned long long)laz->chunk_count);
        }
        sta_status status = begin_chunk(laz, next, next_chunk_start(laz), laz->cur, err);
        if (status != STA_OK) {
            return status;
        }
    }
    bool ok = true;
    bool overrun = false;
    if (laz->chunk_done == 0) {
        memcpy(out, laz->first, laz->record_length);
    } else if (laz->layered) {
        ok = sta_laz_p14_decode(laz->p14, out);
        overrun = !ok;
        ok = true;
    } else {
        ok = sta_laz_p10_decode(laz->p10, &laz->dec, out);
        overrun = laz->dec.overrun > OVERRUN_SLACK;
    }
    if (!ok) {
        laz->live = false;
        return sta_fail(err, STA_ERR_NOMEM, "%s: out of memory decoding LAZ chunk %llu", laz->path,
                        (unsigned long long)laz->chunk);
    }
    if (overrun) {
        laz->live = false;
        return sta_fail(err, STA_ERR_FORMAT,
                        "%s: LAZ chunk %llu (bytes %llu..%llu) ends before its point %llu (point "
                        "%llu of the file); the file is truncated or corrupt",
                        laz->path, (unsigned long long)laz->chunk,
                        (unsigned long long)laz->chunk_start, (unsigned long long)laz->chunk_limit,
                        (unsigned long long)laz->chunk_done, (unsigned long long)laz->cur);
    }
    laz->chunk_done++;
    laz->cur++;
    return STA_OK;
}

// Chunk holding point `index` (tabled).
static uint64_t chunk_of(const sta_laz *laz, uint64_t index)
{
    if (laz->chunk_size != UINT64_MAX) {
        return index / laz->chunk_size;
    }
    uint64_t lo = 0;
    uint64_t hi = laz->chunk_count; // firsts[lo] <= index < firsts[hi]
    while (hi - lo > 1) {
        uint64_t mid = lo + (hi - lo) / 2;
        if (laz->firsts[mid] <= index) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    return lo;
}

// Makes the decoder's next point laz->target.
static sta_status reposition(sta_laz *laz, sta_error *err)
{
    uint64_t target = laz->target;
    bool ahead_in_chunk = laz->live && laz->cur <= target &&
                          target - (laz->cur - laz->chunk_done) < laz->chunk_points;
    if (!ahead_in_chunk) {
        sta_status status;
        if (laz->tabled) {
            uint64_t chunk = chunk_of(laz, target);
            status = begin_chunk(laz, chunk, laz->starts[chunk], laz->firsts[chunk], err);
        } else if (!laz->live || laz->cur > target) {
            status = begin_chunk(laz, 0, laz->chunks_start, 0, err);
        } else {
            status = STA_OK; // sequential: go on from here
        }
        if (status != STA_OK) {
            return status;
        }
    }
    while (laz->cur < target) {
        sta_status status = decode_one(laz, laz->scratch, err);
        if (status != STA_OK) {
            return status;
        }
    }
    return STA_OK;
}

sta_status sta_laz_decode(sta_laz *laz, uint8_t *out, size_t count, sta_error *err)
{
    if (count > laz->point_count || laz->target > laz->point_count - count) {
        return sta_fail(err, STA_ERR_ARG, "%s: LAZ read of %zu points from %llu past the end",
                        laz->path, count, (unsigned long long)laz->target);
    }
    if (count == 0) {
        return STA_OK;
    }
    if (!laz->live || laz->cur != laz->target) {
        sta_status status = reposition(laz, err);
        if (status != STA_OK) {
            return status;
        }
    }
    for (size_t i = 0; i < count; i++) {
        sta_status status = decode_one(laz, out + i * laz->record_length, err);
        if (status != STA_OK) {
            return status;
        }
    }
    laz->target += count;
    return STA_OK;
}

sta_status sta_laz_seek(sta_laz *laz, uint64_t index, sta_error *err)
{
    if (index > laz->point_count) {
        return sta_fail(err, STA_ERR_ARG, "%s: seek to point %llu past the %llu points", laz->path,
                        (unsigned long long)index, (unsigned long long)laz->point_count);
    }
    laz->target = index; // decoded lazily by the next sta_laz_decode
    return STA_OK;
}
