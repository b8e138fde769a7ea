/* SPDX-License-Identifier: MIT
 * The streamer: LOD cut, loader requests, residency decisions, bad nodes. */
#include "stream/streamer.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "core/alloc.h"
#include "core/log.h"
#include "stream/gpu_points.h"
#include "stream/gpu_splats.h"
#include "stream/loader.h"
#include "stream/residency.h"
#include "stream/strata_source.h"

typedef struct s0_sample {
    double spacing;
    uint64_t weight;
} s0_sample;

struct sta_streamer {
    sta_streamer_options options;                       /* defaults resolved */
    sta_camera extra_views[STA_SELECT_MAX_EXTRA_VIEWS]; /* sta_streamer_set_extra_views */
    size_t extra_view_count;
    sta_strata_reader *reader; /* owned; NULL over another source */
    sta_strata_source strata_source;
    const sta_node_source *source; /* &strata_source.source or borrowed */
    sta_lod_tree tree;             /* owned copy */
    float intensity_scale;
    sta_loader *loader;
    sta_residency residency;
    sta_selection selection;
    uint8_t *bad; /* 1 for nodes refused by the loader */
    uint32_t bad_count;
    /* Per-frame lists (room for every node each): */
    uint32_t *requests; /* selected, neither resident nor bad */
    uint32_t *evict;
    sta_loaded_node *loaded; /* taken from the loader this frame, owned until next frame */
    sta_stream_upload *upload;
    size_t loaded_count;
    uint32_t *draw;
    size_t draw_count;    /* entries of draw from the last update */
    size_t pending_evict; /* evict[0 .. pending_evict) go out with the next frame */
    uint32_t *new_bad;
    uint8_t *selected;     /* scratch for the s0 estimate, one byte per node */
    s0_sample *s0_samples; /* scratch for the s0 estimate, one per node */
};

void sta_streamer_options_defaults(sta_streamer_options *o)
{
    o->budget_points = o->budget_points ? o->budget_points : STA_DEFAULT_BUDGET_POINTS;
    o->gpu_bytes_cap = o->gpu_bytes_cap ? o->gpu_bytes_cap : STA_DEFAULT_GPU_BYTES_CAP;
    o->upload_bytes_per_frame =
        o->upload_bytes_per_frame ? o->upload_bytes_per_frame : (uint64_t)64 << 20;
    if (o->loader_threads <= 0) {
        long cores = sysconf(_SC_NPROCESSORS_ONLN);
        o->loader_threads = cores > 1 ? (int)cores - 1 : 1;
    }
    sta_select_params select = { .min_spacing_px = o->min_spacing_px };
    sta_select_params_defaults(&select);
    o->min_spacing_px = select.min_spacing_px;
}

// 16-bit colour files store 0..65535; 8-bit writers use 0..255. The root is a uniform
// subsample of the scene, so its largest value tells which.
static int detect_colour_shift(const sta_strata_reader *reader, float *out_intensity_scale)
{
    sta_strata_decoder *decoder = NULL;
    sta_error err = { 0 };
    int shift = 8;
    *out_intensity_scale = 1.0f / 65535.0f;
    if (sta_strata_decoder_create(&decoder, &err) != STA_OK) {
        return shift;
    }
    sta_strata_points points;
    if (sta_strata_decode_node(reader, 0, decoder, &points, &err) == STA_OK && points.count) {
        uint16_t colour_max = 0, intensity_max = 0;
        for (size_t i = 0; i < points.count; i++) {
            const sta_point *p = &points.points[i];
            uint16_t m = p->red > p->green ? p->red : p->green;
            m = m > p->blue ? m : p->blue;
            colour_max = m > colour_max ? m : colour_max;
            intensity_max = p->intensity > intensity_max ? p->intensity : intensity_max;
        }
        shift = colour_max > 255 ? 8 : 0;
        *out_intensity_scale = 1.0f / (float)(intensity_max > 0 ? intensity_max : 1);
    }
    sta_strata_decoder_destroy(decoder);
    return shift;
}

bool sta_streamer_has_splats(const sta_streamer *s)
{
    return s->source && s->source->has_splats;
}

// GPU bytes per point: the splat section, when there is one, counts against the cap.
static uint32_t bytes_per_point(const sta_streamer *s)
{
    return STA_GPU_POINT_SIZE + (sta_streamer_has_splats(s) ? STA_GPU_SPLAT_SIZE : 0);
}

// Everything but the source and the tree, which the two constructors provide.
static sta_status start(sta_streamer *s, const sta_streamer_options *options, sta_error *err)
{
    if (options) {
        s->options = *options;
    }
    sta_streamer_options_defaults(&s->options);
    uint32_t n = s->tree.count ? s->tree.count : 1;
    s->bad = sta_calloc(n, 1);
    s->requests = sta_alloc_array(n, sizeof(*s->requests));
    s->evict = sta_alloc_array(n, sizeof(*s->evict));
    s->loaded = sta_alloc_array(n, sizeof(*s->loaded));
    s->upload = sta_alloc_array(n, sizeof(*s->upload));
    s->draw = sta_alloc_array(n, sizeof(*s->draw));
    s->new_bad = sta_alloc_array(n, sizeof(*s->new_bad));
    s->selected = sta_alloc_array(n, 1);
    s->s0_samples = sta_alloc_array(n, sizeof(*s->s0_samples));
    if (!s->bad || !s->requests || !s->evict || !s->loaded || !s->upload || !s->draw ||
        !s->new_bad || !s->selected || !s->s0_samples) {
        return sta_fail(err, STA_ERR_NOMEM, "%s: out of memory for %u nodes", sta_streamer_name(s),
                        s->tree.count);
    }
    sta_status status =
        sta_residency_init(&s->residency, s->tree.count, s->options.gpu_bytes_cap, err);
    if (status != STA_OK) {
        return status;
    }
    s->residency.point_bytes = bytes_per_point(s);
    if (s->reader && sta_clip_filters_points(&s->options.clip)) {
        s->strata_source.clip = &s->options.clip; // before any worker starts
    }
    if (s->reader) {
        s->strata_source.mirrors = s->options.mirrors;
    }
    sta_loader_options lo = { .threads = s->options.loader_threads,
                              .point_bytes = bytes_per_point(s) };
    return sta_loader_create(s->source, &lo, &s->loader, err);
}

sta_status sta_streamer_open(const char *path, const sta_streamer_options *options,
                             sta_streamer **out_streamer, sta_error *err)
{
    *out_streamer = NULL;
    sta_streamer *s = sta_calloc(1, sizeof(*s));
    if (!s) {
        return sta_fail(err, STA_ERR_NOMEM, "%s: out of memory", path);
    }
    s->intensity_scale = 1.0f / 65535.0f;
    sta_status status = sta_strata_open(path, NULL, &s->reader, err);
    if (status == STA_OK) {
        status = sta_lod_tree_init(&s->tree, s->reader, err);
    }
    if (status == STA_OK) {
        int shift = detect_colour_shift(s->reader, &s->intensity_scale);
        sta_strata_source_init(&s->strata_source, s->reader, shift);
        s->source = &s->strata_source.source;
        status = start(s, options, err);
    }
    if (status != STA_OK) {
        sta_streamer_close(s);
        return status;
    }
    *out_streamer = s;
    return STA_OK;
}

sta_status sta_streamer_create(const sta_lod_tree *tree, const sta_node_source *source,
                               const sta_streamer_options *options, sta_streamer **out_streamer,
                               sta_error *err)
{
    *out_streamer = NULL;
    if (source->node_count != tree->count) {
        return sta_fail(err, STA_ERR_ARG, "node source has %u nodes, the tree %u",
                        source->node_count, tree->count);
    }
    sta_streamer *s = sta_calloc(1, sizeof(*s));
    if (!s) {
        return sta_fail(err, STA_ERR_NOMEM, "out of memory for the streamer");
    }
    s->intensity_scale = 1.0f / 65535.0f;
    s->source = source;
    s->tree.nodes = sta_alloc_array(tree->count ? tree->count : 1, sizeof(*s->tree.nodes));
    sta_status status = STA_OK;
    if (!s->tree.nodes) {
        status = sta_fail(err, STA_ERR_NOMEM, "out of memory for %u nodes", tree->count);
    } else {
        memcpy(s->tree.nodes, tree->nodes, tree->count * sizeof(*tree->nodes));
        s->tree.count = tree->count;
        status = start(s, options, err);
    }
    if (status != STA_OK) {
        sta_streamer_close(s);
        return status;
    }
    *out_streamer = s;
    return STA_OK;
}

static void release_loaded(sta_streamer *s)
{
    for (size_t i = 0; i < s->loaded_count; i++) {
        sta_loaded_node_release(&s->loaded[i]);
    }
    s->loaded_count = 0;
}

void sta_streamer_close(sta_streamer *s)
{
    if (!s) {
        return;
    }
    sta_loader_destroy(s->loader); // before the reader it reads from
    if (s->loaded) {
        release_loaded(s);
    }
    sta_residency_release(&s->residency);
    sta_selection_release(&s->selection);
    sta_lod_tree_release(&s->tree);
    sta_strata_close(s->reader);
    sta_free(s->bad);
    sta_free(s->requests);
    sta_free(s->evict);
    sta_free(s->loaded);
    sta_free(s->upload);
    sta_free(s->draw);
    sta_free(s->new_bad);
    sta_free(s->selected);
    sta_free(s->s0_samples);
    sta_free(s);
}

// Takes finished nodes from the loader and admits them up to the per-frame upload bytes.
static void take_finished(sta_streamer *s, sta_stream_frame *f)
{
    uint64_t uploaded = 0;
    sta_loaded_node done;
    while (uploaded < s->options.upload_bytes_per_frame && sta_loader_take(s->loader, &done)) {
        if (done.status != STA_OK) {
            if (!s->bad[done.node]) {
                s->bad[done.node] = 1;
                s->bad_count++;
                s->new_bad[f->new_bad_count++] = done.node;
                sta_log_warn("%s: skipping a node that cannot be shown: %s", sta_streamer_name(s),
                             done.message);
            }
            sta_loaded_node_release(&done);
        } else if (sta_residency_admit(&s->residency, done.node, (uint32_t)done.count, s->evict,
                                       &f->evict_count)) {
            uploaded += done.count * s->residency.point_bytes;
            s->upload[f->upload_count] =
                (sta_stream_upload){ done.node, (uint32_t)done.count, done.gpu };
            f->upload_count++;
            s->loaded[s->loaded_count++] = done; // keeps the bytes until the next frame
        } else {
            sta_loaded_node_release(&done);
        }
    }
}

void sta_streamer_set_extra_views(sta_streamer *s, const sta_camera *views, size_t count)
{
    s->extra_view_count = count < STA_SELECT_MAX_EXTRA_VIEWS ? count : STA_SELECT_MAX_EXTRA_VIEWS;
    for (size_t i = 0; i < s->extra_view_count; i++) {
        s->extra_views[i] = views[i];
    }
}

sta_status sta_streamer_update(sta_streamer *s, const sta_camera *camera, sta_stream_frame *f,
                               sta_error *err)
{
    memset(f, 0, sizeof(*f));
    release_loaded(s);
    f->evict_count = s->pending_evict; // a clip change evicted everything
    s->pending_evict = 0;
    sta_residency_begin_frame(&s->residency);
    // The budget can never ask for more than the GPU holds.
    uint64_t cache_points = s->options.gpu_bytes_cap / s->residency.point_bytes;
    sta_select_params params = { s->options.budget_points < cache_points ? s->options.budget_points
                                                                         : cache_points,
                                 s->options.min_spacing_px, &s->options.clip, s->extra_views,
                                 s->extra_view_count };
    sta_status status = sta_select(&s->tree, camera, &params, &s->selection, err);
    if (status != STA_OK) {
        return status;
    }
    // Keep what this frame wants from being evicted by its own uploads.
    for (size_t i = 0; i < s->selection.count; i++) {
        uint32_t node = s->selection.nodes[i];
        if (sta_residency_is_resident(&s->residency, node)) {
            sta_residency_touch(&s->residency, node);
        }
    }
    take_finished(s, f);
    size_t wanted = 0;
    for (size_t i = 0; i < s->selection.count; i++) {
        uint32_t node = s->selection.nodes[i];
        if (sta_residency_is_resident(&s->residency, node)) {
            s->draw[f->draw_count++] = node;
            f->points_drawn += s->residency.entries[node].count;
        } else if (!s->bad[node]) {
            s->requests[wanted++] = node;
        }
    }
    status = sta_loader_request(s->loader, s->requests, wanted, err);
    if (status != STA_OK) {
        return status;
    }
    f->evict = s->evict;
    f->upload = s->upload;
    f->draw = s->draw;
    s->draw_count = f->draw_count;
    f->new_bad = s->new_bad;
    f->points_selected = s->selection.point_count;
    f->nodes_selected = (uint32_t)s->selection.count;
    f->nodes_resident = s->residency.resident_count;
    f->resident_bytes = s->residency.bytes_used;
    f->loader_backlog = sta_loader_backlog(s->loader);
    f->bad_nodes = s->bad_count;
    f->evictions = s->residency.evictions;
    f->complete = wanted == 0 && f->loader_backlog == 0;
    return STA_OK;
}

const sta_streamer_options *sta_streamer_options_used(const sta_streamer *s)
{
    return &s->options;
}

const sta_lod_tree *sta_streamer_tree(const sta_streamer *s)
{
    return &s->tree;
}

const uint32_t *sta_streamer_last_draw(const sta_streamer *s, size_t *out_count)
{
    *out_count = s->draw_count;
    return s->draw;
}

const sta_clip *sta_streamer_clip(const sta_streamer *s)
{
    return &s->options.clip;
}

sta_status sta_streamer_set_clip(sta_streamer *s, const sta_clip *clip, sta_error *err)
{
    // The workers read the clip: stop them, drop what they made under the old one.
    sta_loader_destroy(s->loader);
    s->loader = NULL;
    release_loaded(s);
    s->options.clip = *clip;
    s->strata_source.clip = s->reader && sta_clip_filters_points(clip) ? &s->options.clip : NULL;
    // Resident nodes hold the old clip's points: all go, and are loaded again as wanted.
    sta_residency_evict_all(&s->residency, s->evict, &s->pending_evict);
    sta_loader_options lo = { .threads = s->options.loader_threads,
                              .point_bytes = bytes_per_point(s) };
    return sta_loader_create(s->source, &lo, &s->loader, err);
}

const sta_strata_reader *sta_streamer_reader(const sta_streamer *s)
{
    return s->reader;
}

const char *sta_streamer_name(const sta_streamer *s)
{
    return s->reader ? sta_strata_reader_info(s->reader)->path : "nodes";
}

float sta_streamer_intensity_scale(const sta_streamer *s)
{
    return s->intensity_scale;
}

static int compare_doubles(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : (x > y ? 1 : 0);
}

void sta_streamer_robust_bounds(const sta_streamer *s, double out_min[3], double out_max[3])
{
    if (!s->reader) {
        memcpy(out_min, s->tree.nodes[0].min, 3 * sizeof(double));
        memcpy(out_max, s->tree.nodes[0].max, 3 * sizeof(double));
        return;
    }
    const sta_strata_info *info = sta_strata_reader_info(s->reader);
    memcpy(out_min, info->bounds_min, 3 * sizeof(double));
    memcpy(out_max, info->bounds_max, 3 * sizeof(double));
    sta_strata_decoder *decoder = NULL;
    sta_error err = { 0 };
    if (sta_strata_decoder_create(&decoder, &err) != STA_OK) {
        return;
    }
    sta_strata_points points;
    double *values = NULL;
    if (sta_strata_decode_node(s->reader, 0, decoder, &points, &err) == STA_OK &&
        points.count >= 100 && (values = sta_alloc_array(points.count, sizeof(double)))) {
        const sta_grid *grid = &info->geometry.grid;
        for (int a = 0; a < 3; a++) {
            for (size_t i = 0; i < points.count; i++) {
                const int32_t xyz[3] = { points.points[i].X, points.points[i].Y,
                                         points.points[i].Z };
                values[i] = sta_grid_apply(grid, a, xyz[a]);
            }
            qsort(values, points.count, sizeof(double), compare_doubles);
            out_min[a] = values[points.count / 100];
            out_max[a] = values[points.count - 1 - points.count / 100];
        }
    }
    sta_free(values);
    sta_strata_decoder_destroy(decoder);
}

// Bouchiba's s0, the typical distance between neighbouring points: for each selected
// node none of whose children is selected (where refinement stops), points are taken
// to lie on a surface crossing the node, so their spacing is about edge / sqrt(n), n
// counting the node's points plus the ancestors' share in its box (1/4 per level up:
// n * 4/3). s0 is the point-weighted median of these estimates.

static int compare_s0(const void *a, const void *b)
{
    double x = ((const s0_sample *)a)->spacing, y = ((const s0_sample *)b)->spacing;
    return x < y ? -1 : (x > y ? 1 : 0);
}

double sta_streamer_surface_spacing(sta_streamer *s)
{
    const sta_selection *sel = &s->selection;
    if (sel->count == 0) {
        return 0.0;
    }
    memset(s->selected, 0, s->tree.count);
    for (size_t i = 0; i < sel->count; i++) {
        s->selected[sel->nodes[i]] = 1;
    }
    size_t n = 0;
    uint64_t total = 0;
    for (size_t i = 0; i < sel->count; i++) {
        const sta_lod_node *node = &s->tree.nodes[sel->nodes[i]];
        bool refined = false;
        uint32_t child = node->first_child;
        for (int slot = 0; slot < 8; slot++) {
            if (node->child_mask & (1u << slot)) {
                refined = refined || (child < s->tree.count && s->selected[child]);
                child++;
            }
        }
        if (refined || node->point_count == 0) {
            continue;
        }
        double edge = fmax(node->max[0] - node->min[0],
                           fmax(node->max[1] - node->min[1], node->max[2] - node->min[2]));
        s->s0_samples[n].spacing = edge / sqrt((double)node->point_count * 4.0 / 3.0);
        s->s0_samples[n].weight = node->point_count;
        total += node->point_count;
        n++;
    }
    if (n == 0) {
        return 0.0;
    }
    qsort(s->s0_samples, n, sizeof(s0_sample), compare_s0);
    uint64_t seen = 0;
    for (size_t i = 0; i < n; i++) {
        seen += s->s0_samples[i].weight;
        if (2 * seen >= total) {
            return s->s0_samples[i].spacing;
        }
    }
    return s->s0_samples[n - 1].spacing;
}
