/* SPDX-License-Identifier: MIT
 * Scene rendering: the streamer's decisions carried out on the GPU, then the passes. */
#include "render/scene.h"

#include <string.h>

#include "core/alloc.h"
#include "core/clock.h"
#include "core/log.h"
#include "mirror/mirror_camera.h"
#include "render/bindings.h"
#include "render/gl.h"
#include "render/gpu_cache.h"
#include "render/pass_geometry.h"
#include "stream/gpu_points.h"

struct sta_scene {
    sta_streamer *streamer;
    sta_gpu_node_frame *frames; /* per node dequantisation */
    sta_gpu_cache cache;
    sta_pass_geometry geometry; /* built at the first render */
    bool has_geometry;
    sta_geometry_options raster; /* rasteriser of the geometry pass */
    int colour_mode;
    unsigned hide_flags;       /* STA_GPU_FLAG_* not drawn */
    sta_ground_texture ground; /* built the first time the height mode is drawn */
    sta_pipeline pipeline;     /* initialised on first use */
    bool has_pipeline;
    sta_pipeline_options pipeline_options;
    bool timing;        /* drain and time each pass */
    int timing_clock;   /* sta_timing_clock */
    sta_pass_katz katz; /* live Katz mode */
    double ramp[3];     /* elevation ramp min, max (metres), largest intensity; 0: from the scene */
    sta_point_size point_size;     /* raw and EDL modes; zero: one pixel */
    const sta_mirror_set *mirrors; /* drawn by reflection when reflect_mirrors */
    bool reflect_mirrors;
    sta_pass_mirror mirror_pass; /* built at the first frame with a mirror */
    bool has_mirror_pass;
    sta_pass_splats splats; /* the splats mode's pass, built at its first frame */
    sta_splat_options splat_options;
    bool warned_no_splats; /* the splats mode on a scene without normals, said once */
};

sta_status sta_scene_open(const char *path, const sta_scene_options *options, sta_scene **out_scene,
                          sta_error *err)
{
    *out_scene = NULL;
    sta_scene *s = sta_calloc(1, sizeof(*s));
    if (s) {
        s->hide_flags = STA_SCENE_DEFAULT_HIDE_FLAGS;
    }
    if (!s) {
        return sta_fail(err, STA_ERR_NOMEM, "out of memory");
    }
    sta_status status = sta_streamer_open(path, options, &s->streamer, err);
    const sta_strata_info *info = NULL;
    if (status == STA_OK) {
        info = sta_scene_info(s);
        s->frames = sta_alloc_array(info->node_count, sizeof(*s->frames));
        if (!s->frames) {
            status = sta_fail(err, STA_ERR_NOMEM, "%s: out of memory", path);
        }
    }
    if (status == STA_OK) {
        const sta_strata_reader *reader = sta_streamer_reader(s->streamer);
        for (uint32_t i = 0; i < info->node_count; i++) {
            sta_gpu_node_frame_init(&s->frames[i], &info->geometry,
                                    sta_strata_reader_node(reader, i)->key);
        }
        status = sta_gpu_cache_init(&s->cache, info->node_count, err);
        if (sta_streamer_has_splats(s->streamer)) {
            sta_gpu_cache_enable_splats(&s->cache);
        }
    }
    if (status == STA_OK) {
        double centre[3];
        for (int a = 0; a < 3; a++) {
            centre[a] = 0.5 * (info->bounds_min[a] + info->bounds_max[a]);
        }
        sta_pass_katz_init(&s->katz, info->node_count, centre, NULL);
    }
    if (status != STA_OK) {
        sta_scene_close(s);
        return status;
    }
    *out_scene = s;
    return STA_OK;
}

void sta_scene_close(sta_scene *s)
{
    if (!s) {
        return;
    }
    sta_pass_katz_release(&s->katz);
    if (s->has_mirror_pass) {
        sta_pass_mirror_release(&s->mirror_pass);
    }
    sta_pass_geometry_release(&s->geometry);
    sta_pass_splats_release(&s->splats);
    if (s->has_pipeline) {
        sta_pipeline_release(&s->pipeline);
    }
    sta_gpu_cache_release(&s->cache);
    sta_ground_texture_release(&s->ground);
    sta_streamer_close(s->streamer);
    sta_free(s->frames);
    sta_free(s);
}

const sta_streamer *sta_scene_streamer(const sta_scene *s)
{
    return s->streamer;
}

sta_status sta_scene_set_clip(sta_scene *s, const sta_clip *clip, sta_error *err)
{
    return sta_streamer_set_clip(s->streamer, clip, err);
}

const sta_strata_info *sta_scene_info(const sta_scene *s)
{
    return sta_strata_reader_info(sta_streamer_reader(s->streamer));
}

void sta_scene_robust_bounds(const sta_scene *s, double out_min[3], double out_max[3])
{
    sta_streamer_robust_bounds(s->streamer, out_min, out_max);
}

void sta_scene_set_pipeline(sta_scene *s, const sta_pipeline_options *options)
{
    s->pipeline_options = *options;
}

void sta_scene_set_point_size(sta_scene *s, const sta_point_size *size)
{
    if (size) {
        s->point_size = *size;
    } else {
        sta_point_size_defaults(&s->point_size);
    }
}

void sta_scene_set_raster(sta_scene *s, const sta_geometry_options *options)
{
    s->raster = *options;
    if (s->has_geometry) {
        sta_pass_geometry_release(&s->geometry);
        s->has_geometry = false;
    }
}

const sta_geometry_choice *sta_scene_raster_choice(const sta_scene *s)
{
    return s->has_geometry ? &s->geometry.choice : NULL;
}

const char *sta_scene_splat_method(const sta_scene *s)
{
    return s->splats.program ? sta_splat_method_name(s->splats.method) : NULL;
}

void sta_scene_set_splats(sta_scene *s, const sta_splat_options *options)
{
    if (options->method != s->splat_options.method) {
        sta_pass_splats_release(&s->splats); // zeroed: rebuilt at the next splat frame
    }
    s->splat_options = *options;
}

const sta_gpu_cache *sta_scene_gpu_cache(const sta_scene *s)
{
    return &s->cache;
}

bool sta_scene_has_splats(const sta_scene *s)
{
    return sta_streamer_has_splats(s->streamer);
}

// The splats mode: splats where the scene has them; else the documented fallback, the
// shaded pipeline, said once.
static bool draws_splats(sta_scene *s, sta_pipeline_options *pipeline)
{
    if (pipeline->mode != STA_PIPELINE_SPLATS) {
        return false;
    }
    if (sta_scene_has_splats(s)) {
        return true;
    }
    if (!s->warned_no_splats) {
        sta_log_warn("%s has no normals and radii (convert it with strata-convert --normals): "
                     "splats fall back to the shaded pipeline",
                     sta_streamer_name(s->streamer));
        s->warned_no_splats = true;
    }
    pipeline->mode = STA_PIPELINE_SHADED;
    return false;
}

void sta_scene_set_timing(sta_scene *s, bool on)
{
    s->timing = on;
}

void sta_scene_set_timing_clock(sta_scene *s, int clock)
{
    s->timing_clock = clock;
}

int sta_scene_pipeline_mode(const sta_scene *s)
{
    return s->pipeline_options.mode;
}

const sta_pipeline *sta_scene_pipeline(const sta_scene *s)
{
    return s->has_pipeline ? &s->pipeline : NULL;
}

void sta_scene_set_katz(sta_scene *s, const sta_katz_view_options *options)
{
    sta_pass_katz_set_options(&s->katz, options);
}

const sta_pass_katz *sta_scene_katz(const sta_scene *s)
{
    return &s->katz;
}

void sta_scene_set_hide_flags(sta_scene *s, unsigned flags)
{
    s->hide_flags = flags;
}

void sta_scene_set_mirrors(sta_scene *s, const sta_mirror_set *mirrors, bool reflect)
{
    s->mirrors = mirrors;
    s->reflect_mirrors = reflect && mirrors && mirrors->count > 0;
}

// Whether every vertex of the outline lies outside one plane of the frustum (then the
// mirror cannot show on screen).
static bool mirror_outside(const sta_mirror *m, const sta_frustum *frustum)
{
    for (int p = 0; p < 6; p++) {
        const double *plane = frustum->planes[p];
        size_t outside = 0;
        for (size_t i = 0; i < m->vertex_count; i++) {
            const double *v = m->vertices[i];
            outside += plane[0] * v[0] + plane[1] * v[1] + plane[2] * v[2] + plane[3] < 0.0;
        }
        if (outside == m->vertex_count) {
            return true;
        }
    }
    return false;
}

// The mirrors drawn this frame (in view, seen from the front, vertical) and their
// reflected cameras; returns how many.
static size_t mirror_views(const sta_scene *s, const sta_camera *camera,
                           const sta_mirror *out_mirrors[STA_SELECT_MAX_EXTRA_VIEWS],
                           sta_camera out_views[STA_SELECT_MAX_EXTRA_VIEWS])
{
    size_t n = 0;
    sta_frustum frustum;
    sta_camera_frustum(camera, 1e300, &frustum);
    for (size_t k = 0; s->reflect_mirrors && k < s->mirrors->count; k++) {
        const sta_mirror *m = &s->mirrors->mirrors[k];
        if (n < STA_SELECT_MAX_EXTRA_VIEWS && !mirror_outside(m, &frustum) &&
            sta_mirror_reflect_camera(m, camera, &out_views[n])) {
            out_mirrors[n++] = m;
        }
    }
    return n;
}

void sta_scene_set_colour_mode(sta_scene *s, int mode)
{
    s->colour_mode = mode >= 0 && mode < STA_COLOUR_MODE_COUNT ? mode : STA_COLOUR_RGB;
}

void sta_scene_set_ramps(sta_scene *s, double elevation_min, double elevation_max,
                         double intensity_max)
{
    bool elevation = elevation_max > elevation_min;
    s->ramp[0] = elevation ? elevation_min : 0.0;
    s->ramp[1] = elevation ? elevation_max : 0.0;
    s->ramp[2] = intensity_max > 0.0 ? intensity_max : 0.0;
}

// The ground model from the top of the tree (stream/ground.h), as a texture. Once per
// scene: the model does not depend on the camera.
static sta_status build_ground(sta_scene *s, sta_error *err)
{
    sta_ground ground;
    sta_status status = sta_ground_build(sta_streamer_reader(s->streamer),
                                         sta_streamer_tree(s->streamer), &ground, err);
    if (status == STA_OK) {
        status = sta_ground_texture_upload(&s->ground, &ground, err);
        sta_log_info("%s: ground for the height colours from %zu points (%s), %dx%d cells of "
                     "%.2f m, ramp 0-%.1f m",
                     sta_scene_info(s)->path, ground.sampled,
                     ground.from_class ? "class 2" : "lowest points, opened", ground.width,
                     ground.height, ground.cell_m, ground.height_span_m);
    }
    sta_ground_release(&ground);
    return status;
}

static sta_status ensure_pipeline(sta_scene *s, sta_error *err)
{
    if (!s->has_pipeline) {
        sta_status status = sta_pipeline_init(&s->pipeline, err);
        if (status != STA_OK) {
            return status;
        }
        s->has_pipeline = true;
    }
    return STA_OK;
}

// Before the geometry pass of a frame the screen-space pipeline runs on: the compute
// rasteriser's resolve writes the pipeline's camera-space positions itself (the same
// bits as the unproject pass, which the pipeline then skips: one full-screen pass fewer)
// and the classes the volumetric mark would otherwise look up through the point ids.
// GL_POINTS writes the classes alone (the mark's id lookups cost more than the write).
static sta_status geometry_positions(sta_scene *s, const sta_camera *camera,
                                     const sta_pipeline_options *pipeline, sta_error *err)
{
    s->pipeline.positions_ready = s->pipeline.classes_ready = false;
    s->pipeline.positions_marked = false;
    if (pipeline->mode == STA_PIPELINE_RAW || pipeline->mode == STA_PIPELINE_SPLATS ||
        pipeline->mode == STA_PIPELINE_EDL) {
        return STA_OK;
    }
    sta_status status = ensure_pipeline(s, err);
    GLuint position = 0, classes = 0;
    if (status == STA_OK) {
        status = sta_pipeline_raster_textures(&s->pipeline, camera->width_px, camera->height_px,
                                              &position, &classes, err);
    }
    if (status == STA_OK && s->geometry.choice.raster != STA_RASTER_COMPUTE) {
        s->pipeline.classes_ready = sta_pass_geometry_set_class_out(&s->geometry, classes);
        return STA_OK;
    }
    if (status == STA_OK) {
        sta_view_params view = { camera->width_px, camera->height_px, (float)camera->fov_y,
                                 (float)camera->near_m, 0.0f };
        // The resolve marks the volumetric classes too (the mark pass is then skipped).
        uint32_t set[STA_VOLUMETRIC_CLASS_WORDS];
        bool mark = sta_pipeline_volumetric_set(pipeline, set);
        s->pipeline.positions_ready = sta_pass_geometry_set_position_out(
            &s->geometry, position, classes, &view, mark ? set : NULL);
        s->pipeline.positions_marked = s->pipeline.positions_ready && mark;
    }
    return status;
}

sta_status sta_scene_render(sta_scene *s, const sta_camera *camera, sta_render_target *target,
                            sta_frame_stats *stats, sta_error *err)
{
    memset(stats, 0, sizeof(*stats));
    sta_status status = sta_render_target_resize(target, camera->width_px, camera->height_px, err);
    if (status != STA_OK) {
        return status;
    }
    const sta_mirror *mirrors[STA_SELECT_MAX_EXTRA_VIEWS];
    sta_camera reflected[STA_SELECT_MAX_EXTRA_VIEWS];
    size_t mirror_count = mirror_views(s, camera, mirrors, reflected);
    sta_streamer_set_extra_views(s->streamer, reflected, mirror_count);
    sta_stream_frame frame;
    status = sta_streamer_update(s->streamer, camera, &frame, err);
    if (status != STA_OK) {
        return status;
    }
    status = sta_gpu_cache_apply(&s->cache, &frame, err);
    if (status == STA_OK && !s->has_geometry) {
        status = sta_pass_geometry_init(&s->geometry, &s->raster, err);
        s->has_geometry = status == STA_OK;
    }
    if (status == STA_OK) {
        status = sta_pass_katz_apply(&s->katz, &frame, err);
    }
    if (status != STA_OK) {
        return status;
    }

    double geometry_start = 0, geometry_cpu_start = 0;
    if (s->timing) {
        glFinish();
        geometry_start = sta_timing_clock_ms(s->timing_clock);
        geometry_cpu_start = sta_clock_process_cpu_ms();
    }
    const sta_strata_info *info = sta_scene_info(s);
    if (s->colour_mode == STA_COLOUR_HEIGHT && !s->ground.texture) {
        status = build_ground(s, err);
        if (status != STA_OK) {
            return status;
        }
    }
    sta_geometry_colours colours = { s->colour_mode,
                                     info->bounds_min[2],
                                     info->bounds_max[2] - info->bounds_min[2],
                                     sta_streamer_intensity_scale(s->streamer),
                                     &s->ground,
                                     s->hide_flags,
                                     { 0 } };
    if (s->ramp[1] > s->ramp[0]) { // --elevation-range
        colours.elevation_min = s->ramp[0];
        colours.elevation_span = s->ramp[1] - s->ramp[0];
    }
    if (s->ramp[2] > 0.0) { // --intensity-max
        colours.intensity_scale = (float)(1.0 / s->ramp[2]);
    }
    stats->s0_m = s->pipeline_options.s0_m > 0 ? s->pipeline_options.s0_m
                                               : (float)sta_streamer_surface_spacing(s->streamer);
    sta_pipeline_options pipeline = s->pipeline_options;
    bool splats = draws_splats(s, &pipeline) && !s->katz.options.enabled;
    if (splats && !s->splats.program) {
        status = sta_pass_splats_init(&s->splats, s->splat_options.method, err);
    }
    if (status != STA_OK) {
        return status;
    }
    if (splats) {
        status =
            sta_pass_splats_draw(&s->splats, &s->splat_options, camera, &colours, &s->cache,
                                 s->frames, frame.draw, frame.draw_count, stats->s0_m, target, err);
        if (status != STA_OK) {
            return status;
        }
    } else if (s->katz.options.enabled) {
        status = sta_pass_katz_frame(&s->katz, camera, &colours, s->frames, &frame, &s->cache,
                                     stats->s0_m, target, &stats->katz, err);
        if (status != STA_OK) {
            return status;
        }
    } else {
        // Wide points only where the picture is the points themselves: the screen-space
        // reconstruction (HPR, pull-push, normals) assumes one pixel per point.
        int mode = s->pipeline_options.mode;
        bool sized = mode == STA_PIPELINE_RAW || mode == STA_PIPELINE_EDL;
        sta_pass_geometry_set_point_size(&s->geometry, sized ? &s->point_size : NULL);
        status = geometry_positions(s, camera, &pipeline, err);
        if (status == STA_OK) {
            status = sta_pass_geometry_draw(&s->geometry, camera, &colours, &s->cache, s->frames,
                                            frame.draw, frame.draw_count, target, err);
        }
        sta_pass_geometry_set_position_out(&s->geometry, 0, 0, NULL, NULL); // this draw only
        sta_pass_geometry_set_class_out(&s->geometry, 0);
        if (status != STA_OK) {
            return status;
        }
    }
    if (s->timing) {
        glFinish();
        stats->geometry_ms = sta_timing_clock_ms(s->timing_clock) - geometry_start;
        stats->geometry_cpu_ms = sta_clock_process_cpu_ms() - geometry_cpu_start;
    }
    if (pipeline.mode != STA_PIPELINE_RAW && pipeline.mode != STA_PIPELINE_SPLATS) {
        status = ensure_pipeline(s, err);
        if (status != STA_OK) {
            return status;
        }
        sta_view_params screen = { camera->width_px, camera->height_px, (float)camera->fov_y,
                                   (float)camera->near_m, stats->s0_m > 0 ? stats->s0_m : 0.01f };
        status = sta_pipeline_set_points(&s->pipeline, target->id, &s->cache, err);
        if (status != STA_OK) {
            return status;
        }
        s->pipeline.timing_clock = s->timing_clock;
        stats->raster_positions = s->pipeline.positions_ready;
        status = sta_pipeline_run(&s->pipeline, &pipeline, &screen, target->depth, target->colour,
                                  s->timing ? &stats->timing : NULL, err);
        if (status != STA_OK) {
            return status;
        }
    }
    if (mirror_count > 0 && !s->has_mirror_pass) {
        status = sta_pass_mirror_init(&s->mirror_pass, err);
        if (status != STA_OK) {
            return status;
        }
        s->has_mirror_pass = true;
    }
    // The filled surface hides mirrors behind it where the pipeline made one this frame.
    bool fills = pipeline.mode == STA_PIPELINE_FILL || pipeline.mode == STA_PIPELINE_NORMALS ||
                 pipeline.mode == STA_PIPELINE_SHADED;
    GLuint filled = fills && s->has_pipeline ? s->pipeline.filled_position : 0;
    for (size_t i = 0; i < mirror_count; i++) {
        status = sta_pass_mirror_draw(&s->mirror_pass, mirrors[i], camera, &reflected[i], &colours,
                                      &s->geometry, &s->cache, s->frames, frame.draw,
                                      frame.draw_count, filled, target, err);
        if (status != STA_OK) {
            return status;
        }
    }
    stats->points_selected = frame.points_selected;
    stats->points_drawn = frame.points_drawn;
    stats->nodes_selected = frame.nodes_selected;
    stats->nodes_drawn = (uint32_t)frame.draw_count;
    stats->nodes_resident = frame.nodes_resident;
    stats->uploads = (uint32_t)frame.upload_count;
    stats->gpu_bytes = frame.resident_bytes;
    stats->loader_backlog = frame.loader_backlog;
    stats->bad_nodes = frame.bad_nodes;
    stats->evictions = frame.evictions;
    stats->complete = frame.complete && (!s->katz.options.enabled || stats->katz.current);
    return sta_gl_check("drawing the scene", err);
}
