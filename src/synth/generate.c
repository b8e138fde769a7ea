/* SPDX-License-Identifier: MIT
 * The generator: drives a point source in batches into the LAS writer, then writes
 * the truth sidecar.
 *
 * Design: one thread; memory is one batch of 64 Ki points, the writer's buffer and
 * the scene's caches, whatever the point count.
 */
#include <ctype.h>
#include <stdio.h>
#include <string.h>

#include "core/alloc.h"
#include "io/las_write.h"
#include "synth/synth_internal.h"

#define BATCH_POINTS 65536u

/* Stream keys for the sampling streams (distinct from the layout's). */
#define KEY_SCAN   0x5343414E4E455231ull
#define KEY_SAMPLE 0x53414D504C455231ull

sta_status sta_synth_source_init(synth_source *src, sta_synth_scene *scene,
                                 const sta_synth_georef *georef, bool legacy_classes,
                                 sta_error *err)
{
    memset(src, 0, sizeof(*src));
    src->scene = scene;
    src->georef = georef;
    src->legacy_classes = legacy_classes;
    if (scene->street) {
        sta_rng_seed(&src->rng, sta_hash2(scene->params.seed, KEY_SCAN));
        return sta_street_source_init(src, err);
    }
    if (scene->room) {
        sta_rng_seed(&src->rng, sta_hash2(scene->params.seed, KEY_SCAN));
        return STA_OK;
    }
    sta_rng_seed(&src->rng, sta_hash2(scene->params.seed, KEY_SAMPLE));
    src->primitive = 0;
    src->primitive_left = scene->analytic.counts[0];
    return STA_OK;
}

void sta_synth_source_release(synth_source *src)
{
    sta_free(src->ray_cos);
    sta_free(src->ray_sin);
    src->ray_cos = NULL;
    src->ray_sin = NULL;
}

void sta_synth_source_fill(synth_source *src, sta_point *out, size_t count)
{
    if (src->scene->street) {
        sta_street_source_fill(src, out, count);
    } else if (src->scene->room) {
        sta_room_source_fill(src, out, count);
    } else {
        sta_analytic_source_fill(src, out, count);
    }
}

/* las_path with ".las" (any case) replaced by `suffix`, or `suffix` appended. */
static sta_status sidecar_path(const char *las_path, const char *suffix, char **out_path,
                               sta_error *err)
{
    *out_path = NULL;
    size_t n = strlen(las_path);
    size_t stem = n;
    if (n >= 4 && las_path[n - 4] == '.' && tolower((unsigned char)las_path[n - 3]) == 'l' &&
        tolower((unsigned char)las_path[n - 2]) == 'a' &&
        tolower((unsigned char)las_path[n - 1]) == 's') {
        stem = n - 4;
    }
    size_t suffix_size = strlen(suffix) + 1;
    char *path = sta_malloc(stem + suffix_size);
    if (!path) {
        return sta_fail(err, STA_ERR_NOMEM, "%s: out of memory", las_path);
    }
    memcpy(path, las_path, stem);
    memcpy(path + stem, suffix, suffix_size);
    *out_path = path;
    return STA_OK;
}

sta_status sta_synth_truth_path(const char *las_path, char **out_path, sta_error *err)
{
    return sidecar_path(las_path, ".truth.json", out_path, err);
}

sta_status sta_synth_mirrors_path(const char *las_path, char **out_path, sta_error *err)
{
    return sidecar_path(las_path, ".mirrors.json", out_path, err);
}

/* The mirror scene's mirror file, in world coordinates (local + georef origin). */
static sta_status write_mirror_file(const sta_synth_scene *scene, const sta_synth_georef *georef,
                                    const char *las_path, sta_error *err)
{
    const sta_mirror_set *local = sta_synth_scene_mirrors(scene);
    if (!local) {
        return STA_OK;
    }
    char *path = NULL;
    sta_mirror_set world = { 0 };
    sta_status s = sta_synth_mirrors_path(las_path, &path, err);
    s = s == STA_OK ? sta_mirror_set_translated(local, georef->origin, &world, err) : s;
    s = s == STA_OK ? sta_mirror_set_save(path, &world, err) : s;
    sta_mirror_set_release(&world);
    sta_free(path);
    return s;
}

sta_status sta_synth_generate(const sta_synth_params *params, const char *las_path,
                              sta_synth_progress_fn progress, void *user, sta_error *err)
{
    return sta_synth_generate_reported(params, las_path, progress, user, NULL, err);
}

sta_status sta_synth_generate_reported(const sta_synth_params *params, const char *las_path,
                                       sta_synth_progress_fn progress, void *user,
                                       sta_synth_report *out_report, sta_error *err)
{
    if (out_report) {
        memset(out_report, 0, sizeof(*out_report));
    }
    sta_synth_scene *scene = NULL;
    sta_las_writer *writer = NULL;
    sta_point *batch = NULL;
    char *truth_path = NULL;
    synth_source src;
    memset(&src, 0, sizeof(src));
    sta_status status = sta_synth_scene_create(params, &scene, err);
    if (status != STA_OK) {
        return status;
    }
    if (out_report && params->kind == STA_SYNTH_MESH) {
        out_report->mesh_y_up = scene->analytic.mesh_y_up;
        snprintf(out_report->mesh_up_why, sizeof(out_report->mesh_up_why), "%s",
                 scene->analytic.mesh_up_why);
    }
    const sta_synth_params *p = sta_synth_scene_params(scene);
    sta_synth_georef georef;
    sta_synth_georef_init(p->origin, &georef);
    bool legacy = p->point_format == 3;
    status = sta_synth_truth_path(las_path, &truth_path, err);
    if (status != STA_OK) {
        goto out;
    }
    status = sta_synth_source_init(&src, scene, &georef, legacy, err);
    if (status != STA_OK) {
        goto out;
    }
    batch = sta_alloc_array(BATCH_POINTS, sizeof(*batch));
    if (!batch) {
        status =
            sta_fail(err, STA_ERR_NOMEM, "out of memory for a batch of %u points", BATCH_POINTS);
        goto out;
    }
    char software[33];
    snprintf(software, sizeof(software), "strata-synth %s v%d", sta_synth_kind_name(p->kind),
             STA_SYNTH_STREET_VERSION);
    sta_las_write_options options = {
        .version_minor = legacy ? 2 : 4,
        .point_format = p->point_format,
        .grid = georef.grid,
        .system_identifier = "strata-synth",
        .generating_software = software,
        .wkt = georef.wkt,
        .gps_time_adjusted = p->kind == STA_SYNTH_STREET,
    };
    status = sta_las_writer_open(las_path, &options, &writer, err);
    if (status != STA_OK) {
        goto out;
    }
    uint64_t done = 0;
    while (done < p->point_count) {
        uint64_t left = p->point_count - done;
        size_t n = left < BATCH_POINTS ? (size_t)left : BATCH_POINTS;
        sta_synth_source_fill(&src, batch, n);
        status = sta_las_writer_write(writer, batch, n, err);
        if (status != STA_OK) {
            goto out;
        }
        done += n;
        if (progress && !progress(user, done, p->point_count)) {
            status = sta_fail(err, STA_ERR_CANCELLED, "%s: stopped after %llu points", las_path,
                              (unsigned long long)done);
            goto out;
        }
    }
    status = sta_las_writer_close(writer, err);
    writer = NULL;
    if (status != STA_OK) {
        goto out;
    }
    status = sta_synth_truth_write(truth_path, &src, err);
    if (status == STA_OK) {
        status = write_mirror_file(scene, &georef, las_path, err);
        if (status != STA_OK) {
            remove(truth_path);
        }
    }
    if (status != STA_OK) {
        remove(las_path); // no LAS without its truth
    }
out:
    sta_las_writer_abort(writer);
    sta_free(batch);
    sta_free(truth_path);
    sta_synth_source_release(&src);
    sta_synth_scene_destroy(scene);
    return status;
}
