/* SPDX-License-Identifier: MIT
 * LAS 1.2 / 1.4 writer: header, WKT VLR, point records 0-10, atomic rename.
 *
 * Design: see las_write.h. One writer belongs to one thread. The header is written
 * once at open (with zero counts, so the point data offset is right) and rewritten
 * by close with pwrite at offset 0.
 */
#include "io/las_write.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdatomic.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "core/alloc.h"
#include "core/bytes.h"

#define BUFFER_SIZE      (4u << 20)
#define HEADER_SIZE_12   227u
#define HEADER_SIZE_14   375u
#define VLR_HEADER_SIZE  54u
#define EVLR_HEADER_SIZE 60u

/* A VLR or EVLR to write, copied from the options. */
typedef struct owned_vlr {
    char user_id[17];
    char description[33];
    uint16_t record_id;
    bool extended; /* written after the points (LAS 1.4) */
    uint8_t *data; /* size bytes, owned */
    uint64_t size;
} owned_vlr;

struct sta_las_writer {
    char *path;                /* final path (owned) */
    char *tmp_path;            /* temporary path (owned) */
    int fd;                    /* open on tmp_path, or -1 */
    int version_minor;         /* 2 or 4 */
    int point_format;          /* 0..10 */
    uint16_t record_length;    /* bytes per record */
    uint16_t header_size;      /* 227 or 375 */
    uint32_t offset_to_points; /* header + VLRs */
    uint16_t global_encoding;  /* as written */
    sta_las_write_options opt; /* copy; string pointers below replace the caller's */
    char system_identifier[33];
    char generating_software[33];
    char *wkt;       /* owned copy or NULL */
    owned_vlr *vlrs; /* vlr_count copies of the options' records */
    size_t vlr_count;
    uint32_t vlrs_in_header; /* VLRs before the points (WKT included) */
    uint32_t evlr_count;     /* EVLRs after the points */
    uint64_t evlr_start;     /* file offset of the first EVLR, 0 when none */
    size_t extra_size;       /* bytes appended to each record */
    uint8_t *buffer;         /* BUFFER_SIZE bytes */
    size_t used;             /* bytes pending in buffer */
    uint64_t count;          /* points written */
    uint64_t by_return[15];  /* points with return_number 1..15 */
    int32_t min[3], max[3];  /* integer bounds of the written points */
    bool failed;             /* a write failed; only abort or a failing close remain */
};

static const uint16_t record_sizes[11] = { 20, 28, 26, 34, 57, 63, 30, 36, 38, 59, 67 };

static bool format_has_gps(int f)
{
    return f == 1 || f >= 3;
}

static bool format_has_rgb(int f)
{
    return f == 2 || f == 3 || f == 5 || f == 7 || f == 8 || f == 10;
}

static bool format_has_wave(int f)
{
    return f == 4 || f == 5 || f == 9 || f == 10;
}

static sta_status write_all(sta_las_writer *w, const uint8_t *data, size_t size, sta_error *err)
{
    while (size > 0) {
        ssize_t n = write(w->fd, data, size);
        if (n < 0) {
            if (errno == EINTR) {
                continue;
            }
            return sta_fail(err, STA_ERR_IO, "%s: write failed: %s", w->path, strerror(errno));
        }
        data += n;
        size -= (size_t)n;
    }
    return STA_OK;
}

static sta_status pwrite_all(sta_las_writer *w, const uint8_t *data, size_t size, off_t offset,
                             sta_error *err)
{
    while (size > 0) {
        ssize_t n = pwrite(w->fd, data, size, offset);
        if (n < 0) {
            if (errno == EINTR) {
                continue;
            }
            return sta_fail(err, STA_ERR_IO, "%s: header write failed: %s", w->path,
                            strerror(errno));
        }
        data += n;
        size -= (size_t)n;
        offset += n;
    }
    return STA_OK;
}

static void put_text(uint8_t *dst, size_t size, const char *text)
{
    memset(dst, 0, size);
    size_t n = strlen(text);
    memcpy(dst, text, n < size ? n : size);
}

/* Fills the public header (header_size bytes) from the writer's current state. */
static void build_header(const sta_las_writer *w, uint8_t *h)
{
    memset(h, 0, HEADER_SIZE_14);
    memcpy(h, "LASF", 4);
    sta_store_u16le(h + 4, w->opt.file_source_id);
    sta_store_u16le(h + 6, w->global_encoding);
    h[24] = 1;
    h[25] = (uint8_t)w->version_minor;
    put_text(h + 26, 32, w->system_identifier);
    put_text(h + 58, 32, w->generating_software);
    sta_store_u16le(h + 90, w->opt.creation_day);
    sta_store_u16le(h + 92, w->opt.creation_year);
    sta_store_u16le(h + 94, w->header_size);
    sta_store_u32le(h + 96, w->offset_to_points);
    sta_store_u32le(h + 100, w->vlrs_in_header);
    h[104] = (uint8_t)w->point_format;
    sta_store_u16le(h + 105, w->record_length);
    // Legacy counts: only where the format and the count allow them (LAS 1.4 R15 2.4).
    bool legacy = w->point_format < 6 && w->count <= UINT32_MAX;
    sta_store_u32le(h + 107, legacy ? (uint32_t)w->count : 0u);
    for (int r = 0; r < 5; r++) {
        uint64_t n = w->by_return[r];
        sta_store_u32le(h + 111 + 4 * r, legacy && n <= UINT32_MAX ? (uint32_t)n : 0u);
    }
    for (int a = 0; a < 3; a++) {
        sta_store_f64le(h + 131 + 8 * a, w->opt.grid.scale[a]);
        sta_store_f64le(h + 155 + 8 * a, w->opt.grid.offset[a]);
        double lo = 0.0, hi = 0.0;
        if (w->count > 0) {
            lo = sta_grid_apply(&w->opt.grid, a, w->min[a]);
            hi = sta_grid_apply(&w->opt.grid, a, w->max[a]);
        }
        sta_store_f64le(h + 179 + 16 * a, hi);
        sta_store_f64le(h + 187 + 16 * a, lo);
    }
    if (w->version_minor >= 4) {
        // 227: start of waveform data (0), 235: start of first EVLR, 243: EVLR count.
        sta_store_u64le(h + 235, w->evlr_start);
        sta_store_u32le(h + 243, w->evlr_count);
        sta_store_u64le(h + 247, w->count);
        for (int r = 0; r < 15; r++) {
            sta_store_u64le(h + 255 + 8 * r, w->by_return[r]);
        }
    }
}

static sta_status check_options(const char *path, const sta_las_write_options *o, sta_error *err)
{
    int minor = o->version_minor == 0 ? 4 : o->version_minor;
    if (minor != 2 && minor != 4) {
        return sta_fail(err, STA_ERR_ARG,
                        "%s: LAS version 1.%d not supported for writing (1.2, 1.4)", path, minor);
    }
    int max_format = minor == 2 ? 3 : 10;
    if (o->point_format < 0 || o->point_format > max_format) {
        return sta_fail(err, STA_ERR_ARG, "%s: point format %d not allowed in LAS 1.%d (0..%d)",
                        path, o->point_format, minor, max_format);
    }
    for (int a = 0; a < 3; a++) {
        if (!(o->grid.scale[a] > 0.0) || !isfinite(o->grid.scale[a]) ||
            !isfinite(o->grid.offset[a])) {
            return sta_fail(err, STA_ERR_ARG, "%s: grid axis %d: scale %g offset %g invalid", path,
                            a, o->grid.scale[a], o->grid.offset[a]);
        }
    }
    if (o->system_identifier && strlen(o->system_identifier) > 32) {
        return sta_fail(err, STA_ERR_ARG, "%s: system identifier longer than 32 bytes", path);
    }
    if (o->generating_software && strlen(o->generating_software) > 32) {
        return sta_fail(err, STA_ERR_ARG, "%s: generating software longer than 32 bytes", path);
    }
    if (o->wkt && strlen(o->wkt) + 1 > UINT16_MAX) {
        return sta_fail(err, STA_ERR_ARG, "%s: WKT of %zu bytes does not fit a VLR (65534 max)",
                        path, strlen(o->wkt));
    }
    if (o->extra_size > (size_t)(UINT16_MAX - record_sizes[o->point_format])) {
        return sta_fail(err, STA_ERR_ARG, "%s: %zu extra bytes do not fit a LAS record", path,
                        o->extra_size);
    }
    for (size_t i = 0; i < o->vlr_count; i++) {
        const sta_las_vlr_record *v = &o->vlrs[i];
        bool evlr = v->extended && minor >= 4;
        if (!v->user_id || strlen(v->user_id) > 16 ||
            (v->description && strlen(v->description) > 32) || (v->size > 0 && !v->data) ||
            (!evlr && v->size > UINT16_MAX)) {
            return sta_fail(err, STA_ERR_ARG,
                            "%s: VLR %zu (%s/%u, %llu bytes) cannot be written in LAS 1.%d", path,
                            i, v->user_id ? v->user_id : "?", v->record_id,
                            (unsigned long long)v->size, minor);
        }
    }
    return STA_OK;
}

static sta_status create_temporary(sta_las_writer *w, sta_error *err)
{
    static atomic_uint counter;
    size_t size = strlen(w->path) + 48;
    w->tmp_path = sta_malloc(size);
    if (!w->tmp_path) {
        return sta_fail(err, STA_ERR_NOMEM, "%s: out of memory", w->path);
    }
    for (int attempt = 0; attempt < 100; attempt++) {
        unsigned n = atomic_fetch_add(&counter, 1u);
        snprintf(w->tmp_path, size, "%s.tmp-%ld-%u", w->path, (long)getpid(), n);
        w->fd = open(w->tmp_path, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (w->fd >= 0) {
            return STA_OK;
        }
        if (errno != EEXIST) {
            break;
        }
    }
    return sta_fail(err, STA_ERR_IO, "%s: cannot create temporary file %s: %s", w->path,
                    w->tmp_path, strerror(errno));
}

// Writes one VLR (54-byte header) or EVLR (60-byte header) and its payload.
static sta_status write_vlr(sta_las_writer *w, const owned_vlr *v, bool evlr, sta_error *err)
{
    uint8_t head[EVLR_HEADER_SIZE];
    memset(head, 0, sizeof(head));
    put_text(head + 2, 16, v->user_id);
    sta_store_u16le(head + 18, v->record_id);
    size_t at = 20;
    if (evlr) {
        sta_store_u64le(head + at, v->size);
        at += 8;
    } else {
        sta_store_u16le(head + at, (uint16_t)v->size);
        at += 2;
    }
    put_text(head + at, 32, v->description);
    sta_status status = write_all(w, head, at + 32, err);
    if (status == STA_OK && v->size > 0) {
        status = write_all(w, v->data, (size_t)v->size, err);
    }
    return status;
}

static sta_status write_preamble(sta_las_writer *w, sta_error *err)
{
    uint8_t header[HEADER_SIZE_14];
    build_header(w, header);
    sta_status status = write_all(w, header, w->header_size, err);
    for (size_t i = 0; i < w->vlr_count && status == STA_OK; i++) {
        if (!w->vlrs[i].extended) {
            status = write_vlr(w, &w->vlrs[i], false, err);
        }
    }
    if (status != STA_OK || !w->wkt) {
        return status;
    }
    uint8_t vlr[VLR_HEADER_SIZE];
    memset(vlr, 0, sizeof(vlr));
    size_t length = strlen(w->wkt) + 1;
    put_text(vlr + 2, 16, "LASF_Projection");
    sta_store_u16le(vlr + 18, 2112);
    sta_store_u16le(vlr + 20, (uint16_t)length);
    put_text(vlr + 22, 32, "OGC WKT coordinate system");
    status = write_all(w, vlr, sizeof(vlr), err);
    if (status == STA_OK) {
        status = write_all(w, (const uint8_t *)w->wkt, length, err);
    }
    return status;
}

static void destroy(sta_las_writer *w, bool remove_temporary)
{
    if (w->fd >= 0) {
        close(w->fd);
    }
    if (remove_temporary && w->tmp_path) {
        unlink(w->tmp_path);
    }
    sta_free(w->path);
    sta_free(w->tmp_path);
    sta_free(w->wkt);
    for (size_t i = 0; i < w->vlr_count; i++) {
        sta_free(w->vlrs[i].data);
    }
    sta_free(w->vlrs);
    sta_free(w->buffer);
    sta_free(w);
}

// Copies the options' VLRs and accounts for those that go before the points.
static sta_status copy_vlrs(sta_las_writer *w, const sta_las_write_options *options, sta_error *err)
{
    if (options->vlr_count == 0) {
        return STA_OK;
    }
    w->vlrs = sta_calloc(options->vlr_count, sizeof(*w->vlrs));
    if (!w->vlrs) {
        return sta_fail(err, STA_ERR_NOMEM, "%s: out of memory", w->path);
    }
    w->vlr_count = options->vlr_count;
    for (size_t i = 0; i < options->vlr_count; i++) {
        const sta_las_vlr_record *v = &options->vlrs[i];
        owned_vlr *o = &w->vlrs[i];
        snprintf(o->user_id, sizeof(o->user_id), "%s", v->user_id);
        snprintf(o->description, sizeof(o->description), "%s",
                 v->description ? v->description : "");
        o->record_id = v->record_id;
        o->size = v->size;
        o->extended = v->extended && w->version_minor >= 4;
        o->data = v->size > 0 ? sta_malloc((size_t)v->size) : NULL;
        if (v->size > 0 && !o->data) {
            return sta_fail(err, STA_ERR_NOMEM, "%s: out of memory", w->path);
        }
        if (v->size > 0) {
            memcpy(o->data, v->data, (size_t)v->size);
        }
        if (o->extended) {
            w->evlr_count++;
        } else {
            w->offset_to_points += VLR_HEADER_SIZE + (uint32_t)v->size;
            w->vlrs_in_header++;
        }
    }
    return STA_OK;
}

sta_status sta_las_writer_open(const char *path, const sta_las_write_options *options,
                               sta_las_writer **out_writer, sta_error *err)
{
    *out_writer = NULL;
    sta_status status = check_options(path, options, err);
    if (status != STA_OK) {
        return status;
    }
    sta_las_writer *w = sta_calloc(1, sizeof(*w));
    if (!w) {
        return sta_fail(err, STA_ERR_NOMEM, "%s: out of memory", path);
    }
    w->fd = -1;
    w->opt = *options;
    w->opt.system_identifier = NULL;
    w->opt.generating_software = NULL;
    w->opt.wkt = NULL;
    w->version_minor = options->version_minor == 0 ? 4 : options->version_minor;
    w->point_format = options->point_format;
    w->extra_size = options->extra_size;
    w->record_length = (uint16_t)(record_sizes[w->point_format] + options->extra_size);
    w->header_size = w->version_minor == 4 ? HEADER_SIZE_14 : HEADER_SIZE_12;
    snprintf(w->system_identifier, sizeof(w->system_identifier), "%s",
             options->system_identifier ? options->system_identifier : "OTHER");
    snprintf(w->generating_software, sizeof(w->generating_software), "%s",
             options->generating_software ? options->generating_software : "strata");
    w->path = sta_strdup(path);
    w->buffer = sta_malloc(BUFFER_SIZE);
    if (options->wkt) {
        w->wkt = sta_strdup(options->wkt);
    }
    if (!w->path || !w->buffer || (options->wkt && !w->wkt)) {
        destroy(w, false);
        return sta_fail(err, STA_ERR_NOMEM, "%s: out of memory", path);
    }
    w->offset_to_points = w->header_size;
    if (w->wkt) {
        w->offset_to_points += VLR_HEADER_SIZE + (uint32_t)strlen(w->wkt) + 1;
        w->vlrs_in_header = 1;
    }
    status = copy_vlrs(w, options, err);
    if (status != STA_OK) {
        destroy(w, false);
        return status;
    }
    w->global_encoding = options->gps_time_adjusted ? 1u : 0u;
    if ((w->wkt || options->wkt_crs) && w->version_minor >= 4) {
        w->global_encoding |= 1u << 4;
    }
    for (int a = 0; a < 3; a++) {
        w->min[a] = INT32_MAX;
        w->max[a] = INT32_MIN;
    }
    status = create_temporary(w, err);
    if (status == STA_OK) {
        status = write_preamble(w, err);
    }
    if (status != STA_OK) {
        destroy(w, true);
        return status;
    }
    *out_writer = w;
    return STA_OK;
}

static sta_status check_point(const sta_las_writer *w, const sta_point *p, uint64_t index,
                              sta_error *err)
{
    bool legacy = w->point_format < 6;
    unsigned max_return = legacy ? 7u : 15u;
    if (p->return_number > max_return || p->number_of_returns > max_return) {
        return sta_fail(err, STA_ERR_ARG,
                        "%s: point %llu: return %u of %u does not fit point format %d (max %u)",
                        w->path, (unsigned long long)index, p->return_number, p->number_of_returns,
                        w->point_format, max_return);
    }
    if (legacy && p->classification > 31) {
        return sta_fail(err, STA_ERR_ARG,
                        "%s: point %llu: classification %u does not fit point format %d (0..31)",
                        w->path, (unsigned long long)index, p->classification, w->point_format);
    }
    if (!legacy && p->scanner_channel > 3) {
        return sta_fail(err, STA_ERR_ARG, "%s: point %llu: scanner channel %u (0..3)", w->path,
                        (unsigned long long)index, p->scanner_channel);
    }
    return STA_OK;
}

static int8_t legacy_scan_angle(int16_t angle)
{
    double degrees = round((double)angle * 0.006);
    if (degrees < -128.0) {
        degrees = -128.0;
    }
    if (degrees > 127.0) {
        degrees = 127.0;
    }
    return (int8_t)degrees;
}

static void encode_wave(uint8_t *r, const sta_point *p)
{
    r[0] = p->wave_descriptor_index;
    sta_store_u64le(r + 1, p->wave_byte_offset);
    sta_store_u32le(r + 9, p->wave_packet_size);
    sta_store_f32le(r + 13, p->wave_return_location);
    sta_store_f32le(r + 17, p->wave_xt);
    sta_store_f32le(r + 21, p->wave_yt);
    sta_store_f32le(r + 25, p->wave_zt);
}

static void encode_rgb(uint8_t *r, const sta_point *p)
{
    sta_store_u16le(r, p->red);
    sta_store_u16le(r + 2, p->green);
    sta_store_u16le(r + 4, p->blue);
}

/* Encodes one record of format 0-5 into r (record_length bytes). */
static void encode_legacy(int f, uint8_t *r, const sta_point *p)
{
    sta_store_i32le(r, p->X);
    sta_store_i32le(r + 4, p->Y);
    sta_store_i32le(r + 8, p->Z);
    sta_store_u16le(r + 12, p->intensity);
    r[14] = (uint8_t)((p->return_number & 7u) | ((p->number_of_returns & 7u) << 3) |
                      ((p->scan_direction_flag & 1u) << 6) | ((p->edge_of_flight_line & 1u) << 7));
    r[15] = (uint8_t)((p->classification & 31u) | ((p->classification_flags & 7u) << 5));
    r[16] = (uint8_t)legacy_scan_angle(p->scan_angle);
    r[17] = p->user_data;
    sta_store_u16le(r + 18, p->point_source_id);
    size_t at = 20;
    if (format_has_gps(f)) {
        sta_store_f64le(r + at, p->gps_time);
        at += 8;
    }
    if (format_has_rgb(f)) {
        encode_rgb(r + at, p);
        at += 6;
    }
    if (format_has_wave(f)) {
        encode_wave(r + at, p);
    }
}

/* Encodes one record of format 6-10 into r. */
static void encode_extended(int f, uint8_t *r, const sta_point *p)
{
    sta_store_i32le(r, p->X);
    sta_store_i32le(r + 4, p->Y);
    sta_store_i32le(r + 8, p->Z);
    sta_store_u16le(r + 12, p->intensity);
    r[14] = (uint8_t)((p->return_number & 15u) | ((p->number_of_returns & 15u) << 4));
    r[15] = (uint8_t)((p->classification_flags & 15u) | ((p->scanner_channel & 3u) << 4) |
                      ((p->scan_direction_flag & 1u) << 6) | ((p->edge_of_flight_line & 1u) << 7));
    r[16] = p->classification;
    r[17] = p->user_data;
    sta_store_i16le(r + 18, p->scan_angle);
    sta_store_u16le(r + 20, p->point_source_id);
    sta_store_f64le(r + 22, p->gps_time);
    size_t at = 30;
    if (format_has_rgb(f)) {
        encode_rgb(r + at, p);
        at += 6;
    }
    if (f == 8 || f == 10) {
        sta_store_u16le(r + at, p->nir);
        at += 2;
    }
    if (format_has_wave(f)) {
        encode_wave(r + at, p);
    }
}

static sta_status flush(sta_las_writer *w, sta_error *err)
{
    sta_status status = write_all(w, w->buffer, w->used, err);
    w->used = 0;
    return status;
}

sta_status sta_las_writer_write(sta_las_writer *w, const sta_point *points, size_t count,
                                sta_error *err)
{
    return sta_las_writer_write_extra(w, points, NULL, count, err);
}

sta_status sta_las_writer_write_extra(sta_las_writer *w, const sta_point *points,
                                      const uint8_t *extra, size_t count, sta_error *err)
{
    if (w->failed) {
        return sta_fail(err, STA_ERR_ARG, "%s: write after a failed write", w->path);
    }
    if (w->version_minor < 4 && count > UINT32_MAX - w->count) {
        w->failed = true;
        return sta_fail(err, STA_ERR_ARG, "%s: more than %u points do not fit LAS 1.2", w->path,
                        UINT32_MAX);
    }
    const int f = w->point_format;
    const size_t size = w->record_length;
    for (size_t i = 0; i < count; i++) {
        const sta_point *p = &points[i];
        sta_status status = check_point(w, p, w->count, err);
        if (status == STA_OK && w->used + size > BUFFER_SIZE) {
            status = flush(w, err);
        }
        if (status != STA_OK) {
            w->failed = true;
            return status;
        }
        uint8_t *r = w->buffer + w->used;
        if (f < 6) {
            encode_legacy(f, r, p);
        } else {
            encode_extended(f, r, p);
        }
        if (w->extra_size > 0) {
            uint8_t *tail = r + record_sizes[f];
            if (extra) {
                memcpy(tail, extra + i * w->extra_size, w->extra_size);
            } else {
                memset(tail, 0, w->extra_size);
            }
        }
        w->used += size;
        const int32_t xyz[3] = { p->X, p->Y, p->Z };
        for (int a = 0; a < 3; a++) {
            if (xyz[a] < w->min[a]) {
                w->min[a] = xyz[a];
            }
            if (xyz[a] > w->max[a]) {
                w->max[a] = xyz[a];
            }
        }
        if (p->return_number >= 1) {
            w->by_return[p->return_number - 1]++;
        }
        w->count++;
    }
    return STA_OK;
}

uint64_t sta_las_writer_point_count(const sta_las_writer *writer)
{
    return writer->count;
}

sta_status sta_las_writer_close(sta_las_writer *w, sta_error *err)
{
    if (!w) {
        return STA_OK;
    }
    sta_status status = STA_OK;
    if (w->failed) {
        status = sta_fail(err, STA_ERR_ARG, "%s: not written: an earlier write failed", w->path);
        goto out_remove;
    }
    status = flush(w, err);
    if (status != STA_OK) {
        goto out_remove;
    }
    if (w->evlr_count > 0) {
        w->evlr_start = (uint64_t)w->offset_to_points + w->count * w->record_length;
    }
    for (size_t i = 0; i < w->vlr_count && status == STA_OK; i++) {
        if (w->vlrs[i].extended) {
            status = write_vlr(w, &w->vlrs[i], true, err);
        }
    }
    if (status != STA_OK) {
        goto out_remove;
    }
    uint8_t header[HEADER_SIZE_14];
    build_header(w, header);
    status = pwrite_all(w, header, w->header_size, 0, err);
    if (status != STA_OK) {
        goto out_remove;
    }
    int fd = w->fd;
    w->fd = -1;
    if (close(fd) != 0) {
        status = sta_fail(err, STA_ERR_IO, "%s: close failed: %s", w->path, strerror(errno));
        goto out_remove;
    }
    if (rename(w->tmp_path, w->path) != 0) {
        status = sta_fail(err, STA_ERR_IO, "%s: cannot rename %s to it: %s", w->path, w->tmp_path,
                          strerror(errno));
        goto out_remove;
    }
    destroy(w, false);
    return STA_OK;
out_remove:
    destroy(w, true);
    return status;
}

void sta_las_writer_abort(sta_las_writer *writer)
{
    if (writer) {
        destroy(writer, true);
    }
}
