/* SPDX-License-Identifier: MIT
 * The LAS source block of a .strata file (1.2): encode and parse (docs/FORMAT.md §4a). */
#include <inttypes.h>
#include <string.h>

#include "core/alloc.h"
#include "core/bytes.h"
#include "format/layout.h"
#include "format/strata.h"

#define RECORD_FLAG_EVLR 1u

uint64_t sta_strata_las_source_size(const sta_strata_las_source *source)
{
    uint64_t size = STA_STRATA_LAS_SOURCE_SIZE;
    for (uint32_t i = 0; i < source->record_count; i++) {
        size += STA_STRATA_LAS_RECORD_SIZE + source->records[i].size;
    }
    return size;
}

static void put_text(uint8_t *dst, size_t size, const char *text)
{
    memcpy(dst, text, strnlen(text, size));
}

static void copy_text(char *dst, const uint8_t *src, size_t size)
{
    size_t n = strnlen((const char *)src, size);
    memcpy(dst, src, n);
    dst[n] = '\0';
}

void sta_strata_las_source_store(const sta_strata_las_source *s, uint8_t *out)
{
    memset(out, 0, STA_STRATA_LAS_SOURCE_SIZE);
    out[0] = s->version_major;
    out[1] = s->version_minor;
    out[2] = s->point_format;
    sta_store_u16le(out + 4, s->global_encoding);
    sta_store_u16le(out + 6, s->file_source_id);
    sta_store_u16le(out + 8, s->creation_day);
    sta_store_u16le(out + 10, s->creation_year);
    put_text(out + 12, 32, s->system_identifier);
    put_text(out + 44, 32, s->generating_software);
    sta_store_u32le(out + 76, s->record_count);
    uint8_t *p = out + STA_STRATA_LAS_SOURCE_SIZE;
    for (uint32_t i = 0; i < s->record_count; i++) {
        const sta_strata_las_record *r = &s->records[i];
        memset(p, 0, STA_STRATA_LAS_RECORD_SIZE);
        put_text(p, 16, r->user_id);
        sta_store_u16le(p + 16, r->record_id);
        sta_store_u16le(p + 18, r->extended ? RECORD_FLAG_EVLR : 0u);
        sta_store_u64le(p + 24, r->size);
        put_text(p + 32, 32, r->description);
        p += STA_STRATA_LAS_RECORD_SIZE;
        if (r->size > 0) {
            memcpy(p, r->data, (size_t)r->size);
        }
        p += r->size;
    }
}

sta_status sta_strata_las_source_parse(const uint8_t *data, uint64_t size, const char *name,
                                       sta_strata_las_source *out,
                                       sta_strata_las_record **out_records, sta_error *err)
{
    memset(out, 0, sizeof(*out));
    *out_records = NULL;
    if (size < STA_STRATA_LAS_SOURCE_SIZE) {
        return sta_fail(err, STA_ERR_FORMAT,
                        "%s: LAS source block of %" PRIu64 " bytes (at least %u)", name, size,
                        STA_STRATA_LAS_SOURCE_SIZE);
    }
    out->version_major = data[0];
    out->version_minor = data[1];
    out->point_format = data[2];
    out->global_encoding = sta_load_u16le(data + 4);
    out->file_source_id = sta_load_u16le(data + 6);
    out->creation_day = sta_load_u16le(data + 8);
    out->creation_year = sta_load_u16le(data + 10);
    copy_text(out->system_identifier, data + 12, 32);
    copy_text(out->generating_software, data + 44, 32);
    uint32_t count = sta_load_u32le(data + 76);
    if (out->point_format > 10) {
        return sta_fail(err, STA_ERR_FORMAT, "%s: LAS source: point format %u (0..10)", name,
                        out->point_format);
    }
    // Each record needs its 64-byte header: bounds the count before allocating.
    if (count > (size - STA_STRATA_LAS_SOURCE_SIZE) / STA_STRATA_LAS_RECORD_SIZE) {
        return sta_fail(err, STA_ERR_FORMAT,
                        "%s: LAS source: %" PRIu32 " records do not fit %" PRIu64 " bytes", name,
                        count, size);
    }
    sta_strata_las_record *records = count ? sta_calloc(count, sizeof(*records)) : NULL;
    if (count && !records) {
        return sta_fail(err, STA_ERR_NOMEM, "%s: out of memory", name);
    }
    uint64_t at = STA_STRATA_LAS_SOURCE_SIZE;
    for (uint32_t i = 0; i < count; i++) {
        sta_strata_las_record *r = &records[i];
        if (size - at < STA_STRATA_LAS_RECORD_SIZE) {
            sta_free(records);
            return sta_fail(err, STA_ERR_FORMAT, "%s: LAS source: record %" PRIu32 " is cut", name,
                            i);
        }
        const uint8_t *p = data + at;
        copy_text(r->user_id, p, 16);
        r->record_id = sta_load_u16le(p + 16);
        r->extended = sta_load_u16le(p + 18) & RECORD_FLAG_EVLR;
        r->size = sta_load_u64le(p + 24);
        copy_text(r->description, p + 32, 32);
        at += STA_STRATA_LAS_RECORD_SIZE;
        if (r->size > size - at) {
            sta_status s = sta_fail(err, STA_ERR_FORMAT,
                                    "%s: LAS source: record %" PRIu32 " (%s/%u) of %" PRIu64
                                    " bytes passes the block's end",
                                    name, i, r->user_id, r->record_id, r->size);
            sta_free(records); // after the message, which reads the record
            return s;
        }
        r->data = data + at;
        at += r->size;
    }
    if (at != size) {
        sta_free(records);
        return sta_fail(err, STA_ERR_FORMAT,
                        "%s: LAS source: %" PRIu64 " bytes after the last record", name, size - at);
    }
    out->records = records;
    out->record_count = count;
    *out_records = records;
    return STA_OK;
}
