/* SPDX-License-Identifier: MIT
 * strata-export's work: read nodes, select, write LAS. Design: see export.h. */
#include "export/export.h"

#include <errno.h>
#include <inttypes.h>
#include <stdio.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

#include "core/alloc.h"
#include "core/log.h"
#include "export/export_extra.h"
#include "format/strata_reader.h"
#include "io/las_write.h"

/* Points handed to the writer at a time. */
#define EXPORT_BATCH_POINTS 65536u

/* Everything one export holds, released in one place. */
typedef struct export_job {
    const sta_export_options *options;
    sta_strata_reader *reader;
    sta_strata_decoder *decoder;
    sta_las_writer *writer;
    sta_point *points; /* EXPORT_BATCH_POINTS */
    uint8_t *extra;    /* EXPORT_BATCH_POINTS * extra_size, or NULL */
    size_t extra_size;
    size_t pending; /* points waiting in the batch */
    uint8_t *extra_vlr;
    size_t extra_vlr_size;
    sta_las_vlr_record *vlrs; /* the scene's CRS records, then the Extra Bytes record */
} export_job;

int sta_export_point_format(uint32_t sta_attr_mask)
{
    bool gps = sta_attr_mask & STA_ATTR_GPS_TIME;
    bool rgb = sta_attr_mask & STA_ATTR_RGB;
    bool nir = sta_attr_mask & STA_ATTR_NIR;
    bool wave = sta_attr_mask & STA_ATTR_WAVE_PACKET;
    if (sta_attr_mask & (STA_ATTR_SCANNER_CHANNEL | STA_ATTR_NIR)) {
        // Formats 6-10 (GPS time always): 6, 7 +RGB, 8 +RGB+NIR, 9 +wave, 10 +RGB+NIR+wave.
        if (wave) {
            return rgb || nir ? 10 : 9;
        }
        return nir ? 8 : (rgb ? 7 : 6);
    }
    if (wave) {
        return rgb ? 5 : 4;
    }
    return (gps ? 1 : 0) + (rgb ? 2 : 0);
}

static bool ends_with(const char *s, const char *tail)
{
    size_t n = strlen(s), m = strlen(tail);
    return n >= m && strcasecmp(s + n - m, tail) == 0;
}

static sta_status flush_batch(export_job *job, sta_error *err)
{
    sta_status status = STA_OK;
    if (job->pending > 0) {
        status =
            sta_las_writer_write_extra(job->writer, job->points, job->extra, job->pending, err);
    }
    job->pending = 0;
    return status;
}

static void draw_progress(const export_job *job, uint32_t node, uint32_t node_count)
{
    if (!job->options->progress) {
        return;
    }
    fprintf(stderr, "\rexport: %3u%% of nodes, %" PRIu64 " points written",
            (unsigned)(100.0 * node / (node_count ? node_count : 1)),
            sta_las_writer_point_count(job->writer) + job->pending);
    if (node == node_count) {
        fputc('\n', stderr);
    }
}

// Filters one decoded node into the batch; false once max_points is reached.
static sta_status take_points(export_job *job, const sta_strata_info *info,
                              const sta_strata_points *node, uint32_t attributes, bool *out_full,
                              sta_error *err)
{
    const sta_export_options *o = job->options;
    const bool filter = sta_clip_filters_points(&o->clip);
    for (size_t i = 0; i < node->count; i++) {
        const sta_point *p = &node->points[i];
        if (filter && !sta_clip_keeps_point(&o->clip, &info->geometry.grid, attributes, p)) {
            continue;
        }
        uint64_t written = sta_las_writer_point_count(job->writer) + job->pending;
        if (o->max_points > 0 && written >= o->max_points) {
            *out_full = true;
            return STA_OK;
        }
        job->points[job->pending] = *p;
        if (job->extra_size > 0) {
            memcpy(job->extra + job->pending * job->extra_size, node->extra + i * job->extra_size,
                   job->extra_size);
        }
        if (++job->pending == EXPORT_BATCH_POINTS) {
            sta_status status = flush_batch(job, err);
            if (status != STA_OK) {
                return status;
            }
        }
    }
    return STA_OK;
}

static sta_status run_nodes(export_job *job, sta_export_report *report, sta_error *err)
{
    const sta_strata_info *info = sta_strata_reader_info(job->reader);
    const uint32_t attributes = sta_strata_attributes_to_sta_attr(info->layout.attributes);
    bool full = false;
    sta_status status = STA_OK;
    for (uint32_t n = 0; n < info->node_count && !full && status == STA_OK; n++) {
        const sta_strata_node *node = sta_strata_reader_node(job->reader, n);
        double min[3], max[3];
        sta_strata_node_real_bounds(&info->geometry, node->key, min, max);
        if (node->point_count == 0 ||
            !sta_clip_keeps_node(&job->options->clip, node->key.level, node->spacing, min, max)) {
            report->nodes_culled += node->point_count > 0;
            continue;
        }
        sta_strata_points points;
        status = sta_strata_decode_node(job->reader, n, job->decoder, &points, err);
        if (status == STA_OK) {
            report->nodes_read++;
            report->points_read += points.count;
            status = take_points(job, info, &points, attributes, &full, err);
        }
        if ((n & 63u) == 0) {
            draw_progress(job, n, info->node_count);
        }
    }
    if (status == STA_OK) {
        status = flush_batch(job, err);
    }
    if (status == STA_OK) {
        draw_progress(job, info->node_count, info->node_count);
    }
    return status;
}

/* The writer's header fields and VLRs from the scene's LAS source block (absent in
 * files before 1.2): identifiers, date, GPS time encoding, CRS records; then the
 * Extra Bytes record. A CRS EVLR too large for a LAS 1.2 VLR is an error. */
static sta_status source_options(export_job *job, const sta_strata_las_source *source,
                                 int version_minor, sta_las_write_options *w, sta_error *err)
{
    uint32_t count = source ? source->record_count : 0;
    job->vlrs = sta_calloc((size_t)count + 1, sizeof(*job->vlrs));
    if (!job->vlrs) {
        return sta_fail(err, STA_ERR_NOMEM, "%s: out of memory", job->options->output);
    }
    size_t n = 0;
    if (source) {
        w->system_identifier = source->system_identifier;
        w->generating_software = source->generating_software;
        w->file_source_id = source->file_source_id;
        w->creation_day = source->creation_day;
        w->creation_year = source->creation_year;
        w->gps_time_adjusted = source->global_encoding & 1u;
        w->wkt_crs = source->global_encoding & (1u << 4); // LAS 1.4: the CRS is WKT
        for (uint32_t i = 0; i < count; i++) {
            const sta_strata_las_record *r = &source->records[i];
            if (version_minor < 4 && r->size > UINT16_MAX) {
                return sta_fail(err, STA_ERR_ARG,
                                "%s: the CRS record %s/%u of %llu bytes needs LAS 1.4 (an EVLR)",
                                job->options->output, r->user_id, r->record_id,
                                (unsigned long long)r->size);
            }
            job->vlrs[n++] = (sta_las_vlr_record){ .user_id = r->user_id,
                                                   .record_id = r->record_id,
                                                   .description = r->description,
                                                   .data = r->data,
                                                   .size = r->size,
                                                   .extended = r->extended };
        }
    }
    if (job->extra_vlr_size > 0) {
        job->vlrs[n++] = (sta_las_vlr_record){ .user_id = "LASF_Spec",
                                               .record_id = 4,
                                               .description = "Extra Bytes",
                                               .data = job->extra_vlr,
                                               .size = job->extra_vlr_size };
    }
    w->vlrs = job->vlrs;
    w->vlr_count = n;
    return STA_OK;
}

static sta_status open_writer(export_job *job, sta_export_report *report, sta_error *err)
{
    const sta_export_options *o = job->options;
    const sta_strata_info *info = sta_strata_reader_info(job->reader);
    const uint32_t attributes = sta_strata_attributes_to_sta_attr(info->layout.attributes);
    report->point_format = sta_export_point_format(attributes);
    report->version_minor =
        o->version_minor ? o->version_minor : (report->point_format <= 3 ? 2 : 4);
    if (report->version_minor == 2 && report->point_format > 3) {
        return sta_fail(err, STA_ERR_ARG,
                        "%s: the scene's points need LAS point format %d, which LAS 1.2 lacks "
                        "(use LAS 1.4)",
                        o->output, report->point_format);
    }
    job->extra_size = info->layout.extra_size;
    report->extra_size = info->layout.extra_size;
    sta_status status =
        sta_export_extra_bytes_vlr(info->layout.extra_dims, info->layout.extra_dim_count,
                                   &job->extra_vlr, &job->extra_vlr_size, err);
    if (status != STA_OK) {
        return status;
    }
    sta_las_write_options w = {
        .version_minor = report->version_minor,
        .point_format = report->point_format,
        .grid = info->geometry.grid,
        .generating_software = "strata-export",
        .extra_size = job->extra_size,
    };
    const sta_strata_las_source *source = sta_strata_reader_las_source(job->reader);
    status = source_options(job, source, report->version_minor, &w, err);
    if (status != STA_OK) {
        return status;
    }
    job->points = sta_alloc_array(EXPORT_BATCH_POINTS, sizeof(*job->points));
    job->extra = job->extra_size ? sta_alloc_array(EXPORT_BATCH_POINTS, job->extra_size) : NULL;
    if (!job->points || (job->extra_size && !job->extra)) {
        return sta_fail(err, STA_ERR_NOMEM, "%s: out of memory", o->output);
    }
    return sta_las_writer_open(o->output, &w, &job->writer, err);
}

static sta_status check_options(const sta_export_options *o, sta_error *err)
{
    if (!o->input || !o->output) {
        return sta_fail(err, STA_ERR_ARG, "export: an input scene and an output path are needed");
    }
    if (ends_with(o->output, ".laz")) {
        return sta_fail(err, STA_ERR_UNSUPPORTED,
                        "%s: LAZ output is not supported: write .las and compress it with "
                        "laszip or PDAL (docs/EXPORT.md)",
                        o->output);
    }
    if (o->version_minor != 0 && o->version_minor != 2 && o->version_minor != 4) {
        return sta_fail(err, STA_ERR_ARG, "%s: LAS version 1.%d (1.2 or 1.4)", o->output,
                        o->version_minor);
    }
    if (o->clip.polygon && o->clip.polygon_count < 3) {
        return sta_fail(err, STA_ERR_ARG, "export: a polygon needs 3 vertices or more");
    }
    struct stat st;
    if (!o->force && stat(o->output, &st) == 0) {
        return sta_fail(err, STA_ERR_ARG, "%s: exists (use --force to overwrite it)", o->output);
    }
    return STA_OK;
}

sta_status sta_export(const sta_export_options *options, sta_export_report *report, sta_error *err)
{
    sta_export_report local;
    report = report ? report : &local;
    memset(report, 0, sizeof(*report));
    export_job job = { .options = options };
    sta_status status = check_options(options, err);
    if (status == STA_OK) {
        status = sta_strata_open(options->input, NULL, &job.reader, err);
    }
    if (status == STA_OK) {
        status = sta_strata_decoder_create(&job.decoder, err);
    }
    if (status == STA_OK) {
        status = open_writer(&job, report, err);
    }
    if (status == STA_OK) {
        status = run_nodes(&job, report, err);
    }
    if (status == STA_OK) {
        report->points_written = sta_las_writer_point_count(job.writer);
        status = sta_las_writer_close(job.writer, err);
    } else {
        sta_las_writer_abort(job.writer);
    }
    sta_free(job.points);
    sta_free(job.extra);
    sta_free(job.extra_vlr);
    sta_free(job.vlrs);
    sta_strata_decoder_destroy(job.decoder);
    sta_strata_close(job.reader);
    return status;
}
