/* SPDX-License-Identifier: MIT
 * Tree statistics of a .strata file. */
#include "app/info_strata.h"

#include <inttypes.h>
#include <string.h>

#include "core/json_out.h"
#include "format/strata_reader.h"
#include "stream/gpu_points.h"

#include "core/alloc.h"
#include "core/clock.h"

bool sta_info_is_strata(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f) {
        return false;
    }
    char magic[STA_STRATA_MAGIC_SIZE];
    size_t n = fread(magic, 1, sizeof(magic), f);
    fclose(f);
    return n == sizeof(magic) && memcmp(magic, STA_STRATA_MAGIC, sizeof(magic)) == 0;
}

typedef struct level_stats {
    uint64_t nodes;
    uint64_t points;
    uint64_t overflow_nodes;
    uint64_t stored_bytes;
    uint64_t raw_bytes;
    double spacing;
} level_stats;

static bool draw_progress(void *user, uint32_t done, uint32_t count)
{
    (void)user;
    if (done % 64 == 0 || done == count) {
        fprintf(stderr, "\rverifying %u / %u nodes", done, count);
        if (done == count) {
            fprintf(stderr, "\r%40s\r", "");
        }
    }
    return true;
}

// The LAS source block (format 1.2): what strata-export writes back.
static void print_las_source(FILE *out, const sta_strata_las_source *source)
{
    if (!source) {
        fprintf(out, "las source:     none (export writes default header fields, no CRS)\n");
        return;
    }
    fprintf(out, "las source:     LAS %u.%u, point format %u, global encoding 0x%04x, \"%s\"\n",
            source->version_major, source->version_minor, source->point_format,
            source->global_encoding, source->generating_software);
    for (uint32_t i = 0; i < source->record_count; i++) {
        const sta_strata_las_record *r = &source->records[i];
        fprintf(out, "  %s %s/%u %" PRIu64 " bytes \"%s\"\n", r->extended ? "EVLR" : "VLR ",
                r->user_id, r->record_id, r->size, r->description);
    }
}

static void print_text(FILE *out, const sta_strata_info *info, const level_stats *levels,
                       int level_count, uint64_t raw, uint64_t stored)
{
    char a[40], b[40], c[40];
    fprintf(out, "file:           %s\n", info->path);
    fprintf(out, "format:         .strata %u.%u, written by %s\n", info->version_major,
            info->version_minor, info->generator);
    fprintf(out, "points:         %" PRIu64 "\n", info->point_count);
    fprintf(out, "nodes:          %" PRIu32 " in %d levels, %u cells per node axis\n",
            info->node_count, level_count, info->geometry.grid_cells);
    fprintf(out, "scale:          %s %s %s\n",
            sta_format_double(info->geometry.grid.scale[0], a, 40),
            sta_format_double(info->geometry.grid.scale[1], b, 40),
            sta_format_double(info->geometry.grid.scale[2], c, 40));
    fprintf(out, "offset:         %s %s %s\n",
            sta_format_double(info->geometry.grid.offset[0], a, 40),
            sta_format_double(info->geometry.grid.offset[1], b, 40),
            sta_format_double(info->geometry.grid.offset[2], c, 40));
    fprintf(out, "bounds min:     %s %s %s\n", sta_format_double(info->bounds_min[0], a, 40),
            sta_format_double(info->bounds_min[1], b, 40),
            sta_format_double(info->bounds_min[2], c, 40));
    fprintf(out, "bounds max:     %s %s %s\n", sta_format_double(info->bounds_max[0], a, 40),
            sta_format_double(info->bounds_max[1], b, 40),
            sta_format_double(info->bounds_max[2], c, 40));
    fprintf(out, "up axis:        %s\n", info->up_axis == STA_STRATA_UP_Y ? "+Y" : "+Z");
    fprintf(out, "attributes:    ");
    uint32_t attributes = sta_strata_attributes_to_sta_attr(info->layout.attributes);
    for (uint32_t bit = 1; bit != 0; bit <<= 1) {
        const char *name = sta_attr_name(bit);
        if ((attributes & bit) && name) {
            fprintf(out, " %s", name);
        }
    }
    for (uint32_t i = 0; i < info->layout.extra_dim_count; i++) {
        fprintf(out, " extra:%s", info->layout.extra_dims[i].name);
    }
    fprintf(out, "\nrecord:         %u bytes per point\n", info->layout.record_size);
    fprintf(out, "payloads:       %.2f MiB stored, %.2f MiB raw (compression %.2fx)\n",
            (double)stored / 1048576.0, (double)raw / 1048576.0,
            stored ? (double)raw / (double)stored : 1.0);
    fprintf(out, "level      nodes       points   leaf buckets   spacing (m)   avg points/node\n");
    for (int l = 0; l < level_count; l++) {
        const level_stats *s = &levels[l];
        fprintf(out, "%5d %10" PRIu64 " %12" PRIu64 " %14" PRIu64 " %13.6g %17.0f\n", l, s->nodes,
                s->points, s->overflow_nodes, s->spacing,
                s->nodes ? (double)s->points / (double)s->nodes : 0.0);
    }
}

static void json_triple(sta_json_out *j, const char *key, const double v[3])
{
    sta_json_key(j, key);
    sta_json_begin_array(j);
    for (int i = 0; i < 3; i++) {
        sta_json_double(j, v[i]);
    }
    sta_json_end_array(j);
}

static void print_json(FILE *out, const sta_strata_info *info, const level_stats *levels,
                       int level_count, uint64_t raw, uint64_t stored, bool verified)
{
    sta_json_out j;
    sta_json_init(&j, out, true);
    sta_json_begin_object(&j);
    sta_json_key(&j, "file");
    sta_json_string(&j, info->path);
    sta_json_key(&j, "kind");
    sta_json_string(&j, "strata");
    char version[16];
    snprintf(version, sizeof(version), "%u.%u", info->version_major, info->version_minor);
    sta_json_key(&j, "version");
    sta_json_string(&j, version);
    sta_json_key(&j, "point_count");
    sta_json_uint(&j, info->point_count);
    sta_json_key(&j, "node_count");
    sta_json_uint(&j, info->node_count);
    sta_json_key(&j, "grid_cells");
    sta_json_uint(&j, info->geometry.grid_cells);
    json_triple(&j, "scale", info->geometry.grid.scale);
    json_triple(&j, "offset", info->geometry.grid.offset);
    json_triple(&j, "bounds_min", info->bounds_min);
    json_triple(&j, "bounds_max", info->bounds_max);
    sta_json_key(&j, "up_axis");
    sta_json_string(&j, info->up_axis == STA_STRATA_UP_Y ? "+Y" : "+Z");
    sta_json_key(&j, "record_size");
    sta_json_uint(&j, info->layout.record_size);
    sta_json_key(&j, "raw_bytes");
    sta_json_uint(&j, raw);
    sta_json_key(&j, "stored_bytes");
    sta_json_uint(&j, stored);
    sta_json_key(&j, "verified");
    sta_json_bool(&j, verified);
    sta_json_key(&j, "levels");
    sta_json_begin_array(&j);
    for (int l = 0; l < level_count; l++) {
        sta_json_begin_object(&j);
        sta_json_key(&j, "level");
        sta_json_int(&j, l);
        sta_json_key(&j, "nodes");
        sta_json_uint(&j, levels[l].nodes);
        sta_json_key(&j, "points");
        sta_json_uint(&j, levels[l].points);
        sta_json_key(&j, "leaf_buckets");
        sta_json_uint(&j, levels[l].overflow_nodes);
        sta_json_key(&j, "spacing");
        sta_json_double(&j, levels[l].spacing);
        sta_json_end_object(&j);
    }
    sta_json_end_array(&j);
    sta_json_end_object(&j);
    sta_json_finish(&j);
}

sta_status sta_info_strata(FILE *out, const char *path, bool json, bool verify, bool progress,
                           sta_error *err)
{
    sta_strata_reader *reader = NULL;
    sta_status status = sta_strata_open(path, NULL, &reader, err);
    if (status != STA_OK) {
        return status;
    }
    const sta_strata_info *info = sta_strata_reader_info(reader);
    if (verify) {
        status = sta_strata_verify(reader, progress ? draw_progress : NULL, NULL, err);
        if (status != STA_OK) {
            sta_strata_close(reader);
            return status;
        }
    }
    level_stats levels[STA_STRATA_MAX_ROOT_LOG2 + 1];
    memset(levels, 0, sizeof(levels));
    int level_count = 0;
    uint64_t raw = 0, stored = 0;
    for (uint32_t i = 0; i < info->node_count; i++) {
        const sta_strata_node *n = sta_strata_reader_node(reader, i);
        level_stats *s = &levels[n->key.level];
        s->nodes++;
        s->points += n->point_count;
        s->overflow_nodes += (n->flags & STA_STRATA_NODE_OVERFLOW) ? 1 : 0;
        s->stored_bytes += n->payload.stored_size;
        s->raw_bytes += n->payload.raw_size;
        s->spacing = n->spacing;
        raw += n->payload.raw_size;
        stored += n->payload.stored_size;
        level_count = n->key.level + 1 > level_count ? n->key.level + 1 : level_count;
    }
    if (json) {
        print_json(out, info, levels, level_count, raw, stored, verify);
    } else {
        print_text(out, info, levels, level_count, raw, stored);
        print_las_source(out, sta_strata_reader_las_source(reader));
        if (verify) {
            fprintf(out, "verify:         ok (every checksum, point inside its node, one point "
                         "per cell)\n");
        }
    }
    sta_strata_close(reader);
    return STA_OK;
}

sta_status sta_info_strata_decode_speed(FILE *out, const char *path, sta_error *err)
{
    sta_strata_reader *reader = NULL;
    sta_strata_decoder *decoder = NULL;
    uint8_t *gpu = NULL;
    size_t gpu_capacity = 0;
    sta_status status = sta_strata_open(path, NULL, &reader, err);
    if (status == STA_OK) {
        status = sta_strata_decoder_create(&decoder, err);
    }
    const sta_strata_info *info = status == STA_OK ? sta_strata_reader_info(reader) : NULL;
    uint64_t raw_bytes = 0, stored_bytes = 0;
    double load_s = 0.0, convert_s = 0.0;
    for (int pass = 0; pass < 2 && status == STA_OK; pass++) {
        double t0 = sta_clock_s();
        for (uint32_t i = 0; i < info->node_count && status == STA_OK; i++) {
            const sta_strata_node *n = sta_strata_reader_node(reader, i);
            if (pass == 0) {
                const uint8_t *raw;
                status = sta_strata_load_node(reader, i, decoder, &raw, err);
                raw_bytes += n->payload.raw_size;
                stored_bytes += n->payload.stored_size;
                continue;
            }
            sta_strata_points points;
            status = sta_strata_decode_node(reader, i, decoder, &points, err);
            if (status == STA_OK && points.count > gpu_capacity) {
                sta_free(gpu);
                gpu = sta_alloc_array(points.count, STA_GPU_POINT_SIZE);
                gpu_capacity = gpu ? points.count : 0;
                status = gpu ? STA_OK : sta_fail(err, STA_ERR_NOMEM, "out of memory");
            }
            if (status == STA_OK && points.count > 0) {
                sta_gpu_node_frame frame;
                sta_gpu_node_frame_init(&frame, &info->geometry, n->key);
                sta_gpu_points_encode(&frame, points.points, points.count, 8, gpu);
            }
        }
        *(pass == 0 ? &load_s : &convert_s) = sta_clock_s() - t0;
    }
    if (status == STA_OK) {
        double points = (double)info->point_count;
        fprintf(out, "%s: %llu points, %u nodes, %.1f MiB stored, %.1f MiB raw\n", path,
                (unsigned long long)info->point_count, info->node_count,
                (double)stored_bytes / 1048576.0, (double)raw_bytes / 1048576.0);
        fprintf(out, "  checksum + zstd only:           %7.2f M points/s, %7.1f MB/s raw out\n",
                points / load_s * 1e-6, (double)raw_bytes / load_s * 1e-6);
        fprintf(out, "  + decode + GPU layout (loader): %7.2f M points/s (one thread)\n",
                points / convert_s * 1e-6);
    }
    sta_free(gpu);
    sta_strata_decoder_destroy(decoder);
    sta_strata_close(reader);
    return status;
}
