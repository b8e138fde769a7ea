/* SPDX-License-Identifier: MIT
 * Scene rendering: the streamer's decisions carried out on the GPU, then the passes. */
#include "render/scene.h"

#include <string.h>

#include "core/alloc.h"
#include "core/clock.h"
#include "core/log.h"
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
    sta_ground_texture ground; /* built the first time the height mode is drawn */
    sta_pipeline pipeline;     /* initialised on first use */
    bool has_pipeline;
    sta_pipeline_options pipeline_options;
    bool timing;        /* drain and time each pass */
    sta_pass_katz katz; /* live Katz mode */
    double ramp[3];     /* elevation ramp min, max (metres), largest intensity; 0: from the scene */
    sta_point_size point_size; /* raw and EDL modes; zero: one pixel */
};

sta_status sta_scene_open(const char *path, const sta_scene_options *options, sta_scene **out_scene,
                          sta_error *err)
{
    *out_scene = NULL;
    sta_scene *s = sta_calloc(1, sizeof(*s));
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
    sta_pass_geometry_release(&s->geometry);
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

void sta_scene_set_timing(sta_scene *s, bool on)
{
    s->timing = on;
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

sta_status sta_scene_render(sta_scene *s, const sta_camera *camera, sta_render_target *target,
                            sta_frame_stats *stats, sta_error *err)
{
    memset(stats, 0, sizeof(*stats));
    sta_status status = sta_render_target_resize(target, camera->width_px, camera->height_px, err);
    if (status != STA_OK) {
        return status;
    }
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

    double geometry_start = 0;
    if (s->timing) {
        glFinish();
        geometry_start = sta_clock_ms();
    }
    const sta_strata_info *info = sta_scene_info(s);
    if (s->colour_mode == STA_COLOUR_HEIGHT && !s->ground.texture) {
        status = build_ground(s, err);
        if (status != STA_OK) {
            return status;
        }
    }
    sta_geometry_colours colours = { s->colour_mode, info->bounds_min[2],
                                     info->bounds_max[2] - info->bounds_min[2],
                                     sta_streamer_intensity_scale(s->streamer), &s->ground };
    if (s->ramp[1] > s->ramp[0]) { // --elevation-range
        colours.elevation_min = s->ramp[0];
        colours.elevation_span = s->ramp[1] - s->ramp[0];
    }
    if (s->ramp[2] > 0.0) { // --intensity-max
        colours.intensity_scale = (float)(1.0 / s->ramp[2]);
    }
    stats->s0_m = s->pipeline_options.s0_m > 0 ? s->pipeline_options.s0_m
                                               : (float)sta_streamer_surface_spacing(s->streamer);
    if (s->katz.options.enabled) {
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
        status = sta_pass_geometry_draw(&s->geometry, camera, &colours, &s->cache, s->frames,
                                        frame.draw, frame.draw_count, target, err);
        if (status != STA_OK) {
            return status;
        }
    }
    if (s->timing) {
        glFinish();
        stats->geometry_ms = sta_clock_ms() - geometry_start;
    }
    if (s->pipeline_options.mode != STA_PIPELINE_RAW) {
        if (!s->has_pipeline) {
            status = sta_pipeline_init(&s->pipeline, err);
            if (status != STA_OK) {
                return status;
            }
            s->has_pipeline = true;
        }
        sta_view_params screen = { camera->width_px, camera->height_px, (float)camera->fov_y,
                                   (float)camera->near_m, stats->s0_m > 0 ? stats->s0_m : 0.01f };
        status = sta_pipeline_set_points(&s->pipeline, target->id, &s->cache, err);
        if (status != STA_OK) {
            return status;
        }
        status = sta_pipeline_run(&s->pipeline, &s->pipeline_options, &screen, target->depth,
                                  target->colour, s->timing ? &stats->timing : NULL, err);
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
