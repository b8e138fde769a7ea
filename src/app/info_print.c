/* SPDX-License-Identifier: MIT
 * strata-info's output formats. */
#include "app/info_print.h"

#include <inttypes.h>
#include <string.h>

#include "core/json_out.h"

static const char *kind_name(sta_cloud_kind kind)
{
    return kind == STA_CLOUD_LAS ? "LAS" : kind == STA_CLOUD_PLY ? "PLY" : "unknown";
}

static void print_attribute_names(FILE *out, uint32_t attributes, const char *separator)
{
    const char *sep = "";
    for (uint32_t bit = 1; bit != 0; bit <<= 1) {
        const char *name = sta_attr_name(bit);
        if ((attributes & bit) && name) {
            fprintf(out, "%s%s", sep, name);
            sep = separator;
        }
    }
}

static void print_triple(FILE *out, const double v[3])
{
    char a[40], b[40], c[40];
    fprintf(out, "%s %s %s", sta_format_double(v[0], a, sizeof(a)),
            sta_format_double(v[1], b, sizeof(b)), sta_format_double(v[2], c, sizeof(c)));
}

void sta_info_print_text(FILE *out, const sta_cloud_info *info, const sta_cloud_stats *stats)
{
    fprintf(out, "file:              %s\n", info->path);
    if (info->kind == STA_CLOUD_LAS) {
        fprintf(out, "format:            LAS %d.%d, point format %d, record %u bytes\n",
                info->version_major, info->version_minor, info->point_format,
                (unsigned)info->record_length);
        fprintf(out, "software:          %s / %s, created %u/%u\n", info->generating_software,
                info->system_identifier, (unsigned)info->creation_year,
                (unsigned)info->creation_day);
        fprintf(out, "header size:       %u, point data at %" PRIu32 "\n",
                (unsigned)info->header_size, info->offset_to_point_data);
    } else {
        fprintf(out, "format:            %s\n", kind_name(info->kind));
    }
    fprintf(out, "points:            %" PRIu64, info->point_count);
    if (info->header_point_count != info->point_count) {
        fprintf(out, " (header says %" PRIu64 ")", info->header_point_count);
    }
    fputc('\n', out);
    if (info->skipped_point_count) {
        fprintf(out, "salvaged:          %" PRIu64 " incomplete points skipped\n",
                info->skipped_point_count);
    }
    fprintf(out, "attributes:        ");
    print_attribute_names(out, info->attributes, ", ");
    fputc('\n', out);
    fprintf(out, "scale:             ");
    print_triple(out, info->grid.scale);
    fprintf(out, "\noffset:            ");
    print_triple(out, info->grid.offset);
    fprintf(out, "\nheader bounds min: ");
    print_triple(out, info->header_min);
    fprintf(out, "\nheader bounds max: ");
    print_triple(out, info->header_max);
    fprintf(out, "\nactual bounds min: ");
    print_triple(out, stats->min);
    fprintf(out, "\nactual bounds max: ");
    print_triple(out, stats->max);
    fputc('\n', out);
    if (info->attributes & STA_ATTR_GPS_TIME) {
        char a[40], b[40];
        fprintf(out, "gps time:          %s .. %s", sta_format_double(stats->gps_min, a, 40),
                sta_format_double(stats->gps_max, b, 40));
        if (stats->gps_nan_count) {
            fprintf(out, " (%" PRIu64 " not finite)", stats->gps_nan_count);
        }
        fputc('\n', out);
    }
    if (stats->colour_bits) {
        fprintf(out, "colour:            %d-bit (largest value %u)\n", stats->colour_bits,
                (unsigned)stats->rgb_max);
    }
    fprintf(out, "classes:          ");
    for (int c = 0; c < 256; c++) {
        if (stats->by_class[c]) {
            fprintf(out, " %d:%" PRIu64, c, stats->by_class[c]);
        }
    }
    fputc('\n', out);
    if (info->crs_wkt) {
        fprintf(out, "crs (wkt):         %.80s%s\n", info->crs_wkt,
                strlen(info->crs_wkt) > 80 ? "..." : "");
    } else if (info->has_geotiff_crs) {
        fprintf(out, "crs:               GeoTIFF keys\n");
    }
    if (info->has_waveform_packets) {
        fprintf(out, "waveform packets:  present (%s)\n",
                info->has_internal_waveform ? "internal" : "external");
    }
    fprintf(out, "vlrs:              %zu\n", info->vlr_count);
    for (size_t i = 0; i < info->vlr_count; i++) {
        const sta_vlr_info *v = &info->vlrs[i];
        fprintf(out, "  %s %s/%u %" PRIu64 " bytes \"%s\"\n", v->is_extended ? "EVLR" : "VLR ",
                v->user_id, (unsigned)v->record_id, v->length, v->description);
    }
    if (info->extra_dim_count) {
        fprintf(out, "extra dimensions:  %zu (%zu bytes per point)\n", info->extra_dim_count,
                info->extra_size);
        for (size_t i = 0; i < info->extra_dim_count; i++) {
            const sta_extra_dim *d = &info->extra_dims[i];
            fprintf(out, "  %s: %s, %zu bytes at +%zu\n", d->name,
                    sta_extra_type_name(d->data_type), d->size_bytes, d->offset_bytes);
        }
    }
}

static void json_triple(sta_json_out *json, const char *key, const double v[3])
{
    sta_json_key(json, key);
    sta_json_begin_array(json);
    for (int i = 0; i < 3; i++) {
        sta_json_double(json, v[i]);
    }
    sta_json_end_array(json);
}

static void json_vlrs(sta_json_out *json, const sta_cloud_info *info)
{
    sta_json_key(json, "vlrs");
    sta_json_begin_array(json);
    for (size_t i = 0; i < info->vlr_count; i++) {
        const sta_vlr_info *v = &info->vlrs[i];
        sta_json_begin_object(json);
        sta_json_key(json, "user_id");
        sta_json_string(json, v->user_id);
        sta_json_key(json, "record_id");
        sta_json_uint(json, v->record_id);
        sta_json_key(json, "length");
        sta_json_uint(json, v->length);
        sta_json_key(json, "description");
        sta_json_string(json, v->description);
        sta_json_key(json, "extended");
        sta_json_bool(json, v->is_extended);
        sta_json_end_object(json);
    }
    sta_json_end_array(json);
}

static void json_extra_dims(sta_json_out *json, const sta_cloud_info *info)
{
    sta_json_key(json, "extra_dimensions");
    sta_json_begin_array(json);
    for (size_t i = 0; i < info->extra_dim_count; i++) {
        const sta_extra_dim *d = &info->extra_dims[i];
        sta_json_begin_object(json);
        sta_json_key(json, "name");
        sta_json_string(json, d->name);
        sta_json_key(json, "type");
        sta_json_string(json, sta_extra_type_name(d->data_type));
        sta_json_key(json, "data_type");
        sta_json_uint(json, d->data_type);
        sta_json_key(json, "options");
        sta_json_uint(json, d->options);
        sta_json_key(json, "offset");
        sta_json_uint(json, d->offset_bytes);
        sta_json_key(json, "size");
        sta_json_uint(json, d->size_bytes);
        json_triple(json, "scale", d->scale);
        json_triple(json, "value_offset", d->offset);
        if (d->options & 1) {
            json_triple(json, "no_data", d->no_data);
        }
        sta_json_end_object(json);
    }
    sta_json_end_array(json);
}

void sta_info_print_json(FILE *out, const sta_cloud_info *info, const sta_cloud_stats *stats)
{
    sta_json_out json;
    sta_json_init(&json, out, true);
    sta_json_begin_object(&json);
    sta_json_key(&json, "file");
    sta_json_string(&json, info->path);
    sta_json_key(&json, "kind");
    sta_json_string(&json, kind_name(info->kind));
    char version[16];
    snprintf(version, sizeof(version), "%d.%d", info->version_major, info->version_minor);
    sta_json_key(&json, "version");
    sta_json_string(&json, version);
    sta_json_key(&json, "point_format");
    sta_json_int(&json, info->point_format);
    sta_json_key(&json, "point_count");
    sta_json_uint(&json, info->point_count);
    sta_json_key(&json, "header_point_count");
    sta_json_uint(&json, info->header_point_count);
    sta_json_key(&json, "skipped_point_count");
    sta_json_uint(&json, info->skipped_point_count);
    sta_json_key(&json, "record_length");
    sta_json_uint(&json, info->record_length);
    sta_json_key(&json, "header_size");
    sta_json_uint(&json, info->header_size);
    sta_json_key(&json, "offset_to_point_data");
    sta_json_uint(&json, info->offset_to_point_data);
    sta_json_key(&json, "global_encoding");
    sta_json_uint(&json, info->global_encoding);
    sta_json_key(&json, "system_identifier");
    sta_json_string(&json, info->system_identifier);
    sta_json_key(&json, "generating_software");
    sta_json_string(&json, info->generating_software);
    json_triple(&json, "scale", info->grid.scale);
    json_triple(&json, "offset", info->grid.offset);
    json_triple(&json, "header_min", info->header_min);
    json_triple(&json, "header_max", info->header_max);
    json_triple(&json, "actual_min", stats->min);
    json_triple(&json, "actual_max", stats->max);
    sta_json_key(&json, "attributes");
    sta_json_begin_array(&json);
    for (uint32_t bit = 1; bit != 0; bit <<= 1) {
        const char *name = sta_attr_name(bit);
        if ((info->attributes & bit) && name) {
            sta_json_string(&json, name);
        }
    }
    sta_json_end_array(&json);
    sta_json_key(&json, "colour_bits");
    sta_json_int(&json, stats->colour_bits);
    if (info->attributes & STA_ATTR_GPS_TIME) {
        sta_json_key(&json, "gps_time_range");
        sta_json_begin_array(&json);
        sta_json_double(&json, stats->gps_min);
        sta_json_double(&json, stats->gps_max);
        sta_json_end_array(&json);
        sta_json_key(&json, "gps_time_not_finite");
        sta_json_uint(&json, stats->gps_nan_count);
    }
    sta_json_key(&json, "points_by_return");
    sta_json_begin_array(&json);
    for (int r = 0; r < 16; r++) {
        sta_json_uint(&json, stats->by_return[r]);
    }
    sta_json_end_array(&json);
    sta_json_key(&json, "classes");
    sta_json_begin_object(&json);
    for (int c = 0; c < 256; c++) {
        if (stats->by_class[c]) {
            char key[8];
            snprintf(key, sizeof(key), "%d", c);
            sta_json_key(&json, key);
            sta_json_uint(&json, stats->by_class[c]);
        }
    }
    sta_json_end_object(&json);
    sta_json_key(&json, "crs_wkt");
    if (info->crs_wkt) {
        sta_json_string(&json, info->crs_wkt);
    } else {
        sta_json_null(&json);
    }
    sta_json_key(&json, "has_geotiff_crs");
    sta_json_bool(&json, info->has_geotiff_crs);
    sta_json_key(&json, "has_waveform_packets");
    sta_json_bool(&json, info->has_waveform_packets);
    json_vlrs(&json, info);
    json_extra_dims(&json, info);
    sta_json_end_object(&json);
    sta_json_finish(&json);
}

static void csv_double(FILE *out, double value)
{
    char text[40];
    fputs(sta_format_double(value, text, sizeof(text)), out);
}

void sta_info_print_points_header(FILE *out, uint32_t attr)
{
    fputs("x,y,z,intensity,return_number,number_of_returns,classification,gps_time,red,green,"
          "blue",
          out);
    fputs(attr & STA_ATTR_SPLAT ? ",nx,ny,nz,radius\n" : "\n", out);
}

void sta_info_print_point_row(FILE *out, const sta_grid *grid, uint32_t attr, const sta_point *p)
{
    csv_double(out, sta_grid_apply(grid, 0, p->X));
    fputc(',', out);
    csv_double(out, sta_grid_apply(grid, 1, p->Y));
    fputc(',', out);
    csv_double(out, sta_grid_apply(grid, 2, p->Z));
    fputc(',', out);
    if (attr & STA_ATTR_INTENSITY) {
        fprintf(out, "%u", (unsigned)p->intensity);
    }
    fputc(',', out);
    if (attr & STA_ATTR_RETURNS) {
        fprintf(out, "%u,%u", (unsigned)p->return_number, (unsigned)p->number_of_returns);
    } else {
        fputc(',', out);
    }
    fputc(',', out);
    if (attr & STA_ATTR_CLASSIFICATION) {
        fprintf(out, "%u", (unsigned)p->classification);
    }
    fputc(',', out);
    if (attr & STA_ATTR_GPS_TIME) {
        csv_double(out, p->gps_time);
    }
    fputc(',', out);
    if (attr & STA_ATTR_RGB) {
        fprintf(out, "%u,%u,%u", (unsigned)p->red, (unsigned)p->green, (unsigned)p->blue);
    } else {
        fputs(",,", out);
    }
    if (attr & STA_ATTR_SPLAT) { // strata-convert --normals: the decoded normal and radius
        fprintf(out, ",%.5f,%.5f,%.5f,%.5g", (double)p->normal[0], (double)p->normal[1],
                (double)p->normal[2], (double)p->radius);
    }
    fputc('\n', out);
}

sta_status sta_info_print_points(FILE *out, sta_cloud_reader *reader, uint64_t start,
                                 uint64_t count, sta_error *err)
{
    const sta_cloud_info *info = sta_cloud_reader_info(reader);
    sta_info_print_points_header(out, info->attributes);
    if (start >= info->point_count || count == 0) {
        return STA_OK;
    }
    sta_status status = sta_cloud_seek(reader, start, err);
    if (status != STA_OK) {
        return status;
    }
    sta_point_batch batch;
    size_t capacity = count < 65536 ? (size_t)count : 65536;
    status = sta_point_batch_init(&batch, capacity, info->extra_size, err);
    if (status != STA_OK) {
        return status;
    }
    uint64_t left = count;
    while (left > 0 && status == STA_OK) {
        status = sta_cloud_read(reader, &batch, err);
        if (status != STA_OK || batch.count == 0) {
            break;
        }
        for (size_t i = 0; i < batch.count && left > 0; i++, left--) {
            sta_info_print_point_row(out, &info->grid, info->attributes, &batch.points[i]);
        }
    }
    sta_point_batch_release(&batch);
    return status;
}
