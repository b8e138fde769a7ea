/* SPDX-License-Identifier: MIT
 * Collecting a LAS input's header fields and CRS records for the .strata file. */
#include "las_source.h"

#include <errno.h>
#include <fcntl.h>
#include <string.h>
#include <unistd.h>

#include "core/alloc.h"
#include "core/log.h"

/* Only the coordinate reference system's records are kept (LAS 1.4 R15 2.5). */
static bool is_crs_record(const sta_vlr_info *v)
{
    return strcmp(v->user_id, "LASF_Projection") == 0;
}

static sta_status read_at(int fd, const char *path, uint8_t *out, uint64_t size, uint64_t offset,
                          sta_error *err)
{
    while (size > 0) {
        ssize_t n = pread(fd, out, (size_t)size, (off_t)offset);
        if (n <= 0) {
            if (n < 0 && errno == EINTR) {
                continue;
            }
            return sta_fail(err, STA_ERR_IO, "%s: cannot read a VLR at %llu: %s", path,
                            (unsigned long long)offset, n < 0 ? strerror(errno) : "end of file");
        }
        out += n;
        size -= (uint64_t)n;
        offset += (uint64_t)n;
    }
    return STA_OK;
}

sta_status sta_las_source_collect(const sta_input_set *inputs, sta_las_source_keep *out,
                                  sta_error *err)
{
    memset(out, 0, sizeof(*out));
    if (inputs->count == 0) {
        return STA_OK;
    }
    const sta_cloud_info *info = sta_cloud_reader_info(inputs->readers[0]);
    if (info->kind != STA_CLOUD_LAS) {
        return STA_OK;
    }
    for (size_t i = 1; i < inputs->count; i++) {
        const sta_cloud_info *other = sta_cloud_reader_info(inputs->readers[i]);
        if (other->kind != STA_CLOUD_LAS || other->point_format != info->point_format) {
            sta_log_warn("%s: its point format differs from %s's: the LAS header fields and CRS "
                         "records kept are the first input's",
                         inputs->paths[i], inputs->paths[0]);
            break;
        }
    }
    sta_strata_las_source *s = &out->source;
    s->version_major = (uint8_t)info->version_major;
    s->version_minor = (uint8_t)info->version_minor;
    s->point_format = (uint8_t)info->point_format;
    s->global_encoding = info->global_encoding;
    s->file_source_id = info->file_source_id;
    s->creation_day = info->creation_day;
    s->creation_year = info->creation_year;
    memcpy(s->system_identifier, info->system_identifier, sizeof(s->system_identifier));
    memcpy(s->generating_software, info->generating_software, sizeof(s->generating_software));
    uint64_t total = 0;
    uint32_t count = 0;
    for (size_t i = 0; i < info->vlr_count; i++) {
        if (is_crs_record(&info->vlrs[i])) {
            total += info->vlrs[i].length;
            count++;
        }
    }
    out->present = true;
    if (count == 0) {
        return STA_OK;
    }
    out->records = sta_calloc(count, sizeof(*out->records));
    out->data = total > 0 && total <= SIZE_MAX ? sta_malloc((size_t)total) : NULL;
    if (!out->records || (total > 0 && !out->data)) {
        sta_las_source_release(out);
        return sta_fail(err, STA_ERR_NOMEM, "%s: out of memory for %llu bytes of CRS records",
                        inputs->paths[0], (unsigned long long)total);
    }
    int fd = open(inputs->paths[0], O_RDONLY | O_CLOEXEC);
    if (fd < 0) {
        sta_status status =
            sta_fail(err, STA_ERR_IO, "%s: cannot open: %s", inputs->paths[0], strerror(errno));
        sta_las_source_release(out);
        return status;
    }
    uint64_t at = 0;
    uint32_t k = 0;
    sta_status status = STA_OK;
    for (size_t i = 0; i < info->vlr_count && status == STA_OK; i++) {
        const sta_vlr_info *v = &info->vlrs[i];
        if (!is_crs_record(v)) {
            continue;
        }
        sta_strata_las_record *r = &out->records[k++];
        memcpy(r->user_id, v->user_id, sizeof(r->user_id));
        memcpy(r->description, v->description, sizeof(r->description));
        r->record_id = v->record_id;
        r->extended = v->is_extended;
        r->size = v->length;
        r->data = out->data + at;
        status = read_at(fd, inputs->paths[0], out->data + at, v->length, v->data_offset, err);
        at += v->length;
    }
    close(fd);
    if (status != STA_OK) {
        sta_las_source_release(out);
        return status;
    }
    s->records = out->records;
    s->record_count = count;
    return STA_OK;
}

void sta_las_source_release(sta_las_source_keep *keep)
{
    sta_free(keep->records);
    sta_free(keep->data);
    memset(keep, 0, sizeof(*keep));
}
