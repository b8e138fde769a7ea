/* SPDX-License-Identifier: MIT
 * The screen-space pipeline. */
#include "render/pipeline.h"

#include <string.h>

#include "core/clock.h"
#include "render/bindings.h"
#include "render/gl.h"
#include "render/gl_image.h"

static const char *const mode_names[STA_PIPELINE_MODE_COUNT] = { "raw",     "hpr",    "fill",
                                                                 "normals", "shaded", "edl",
                                                                 "splats" };
static const char *const normal_names[STA_NORMAL_METHOD_COUNT] = { "pyramid", "ld", "pd", "pc",
                                                                   "ti" };
static const char *const pass_names[STA_PASS_COUNT] = { "unproject", "hpr",    "pullpush",
                                                        "normals",   "smooth", "shade",
                                                        "volumetric" };

int sta_pipeline_mode_from_name(const char *name)
{
    for (int i = 0; i < STA_PIPELINE_MODE_COUNT; i++) {
        if (strcmp(name, mode_names[i]) == 0) {
            return i;
        }
    }
    return -1;
}

int sta_normal_method_from_name(const char *name)
{
    for (int i = 0; i < STA_NORMAL_METHOD_COUNT; i++) {
        if (strcmp(name, normal_names[i]) == 0) {
            return i;
        }
    }
    return -1;
}

const char *sta_pipeline_mode_name(int mode)
{
    return mode >= 0 && mode < STA_PIPELINE_MODE_COUNT ? mode_names[mode] : "?";
}

const char *sta_normal_method_name(int method)
{
    return method >= 0 && method < STA_NORMAL_METHOD_COUNT ? normal_names[method] : "?";
}

const char *sta_pass_name(int pass)
{
    return pass >= 0 && pass < STA_PASS_COUNT ? pass_names[pass] : "?";
}

sta_status sta_pipeline_init(sta_pipeline *p, sta_error *err)
{
    memset(p, 0, sizeof(*p));
    sta_status s = sta_unproject_pass_init(&p->unproject, err);
    if (s == STA_OK) {
        s = sta_hpr_pass_init(&p->hpr, err);
    }
    if (s == STA_OK) {
        s = sta_pullpush_pass_init(&p->pullpush, err);
    }
    if (s == STA_OK) {
        s = sta_normals_pyramid_pass_init(&p->normals_pyramid, err);
    }
    // One staging buffer for the passes that stage their stores (render/gl_staged.h): they
    // run one after the other.
    p->unproject.shared_staging = &p->staging;
    p->hpr.shared_staging = &p->staging;
    p->pullpush.shared_staging = &p->staging;
    p->normals_pyramid.shared_staging = &p->staging;
    if (s == STA_OK) {
        s = sta_normals_screen_pass_init(&p->normals_screen, err);
    }
    if (s == STA_OK) {
        s = sta_shade_pass_init(&p->shade, err);
    }
    if (s == STA_OK) {
        s = sta_volumetric_pass_init(&p->volumetric, err);
    }
    const char *display[] = { "display.comp" };
    const char *colour[] = { "colour_to_float.comp" };
    if (s == STA_OK) {
        s = sta_gl_program_create(display, 1, NULL, &p->display_program, err);
    }
    if (s == STA_OK) {
        s = sta_gl_program_create(colour, 1, NULL, &p->colour_program, err);
    }
    if (s != STA_OK) {
        sta_pipeline_release(p);
        return s;
    }
    p->display_size = glGetUniformLocation(p->display_program, "u_size");
    p->display_mode = glGetUniformLocation(p->display_program, "u_mode");
    p->colour_size = glGetUniformLocation(p->colour_program, "u_size");
    return STA_OK;
}

static void release_textures(sta_pipeline *p)
{
    GLuint textures[] = { p->position,      p->colour, p->label,   p->pyramid, p->filled_position,
                          p->filled_colour, p->normal, p->normal2, p->classes };
    for (size_t i = 0; i < sizeof(textures) / sizeof(textures[0]); i++) {
        if (textures[i]) {
            glDeleteTextures(1, &textures[i]);
        }
    }
    p->position = p->colour = p->label = p->pyramid = 0;
    p->filled_position = p->filled_colour = p->normal = p->normal2 = p->classes = 0;
    p->width_px = p->height_px = 0;
}

void sta_pipeline_release(sta_pipeline *p)
{
    release_textures(p);
    sta_unproject_pass_release(&p->unproject);
    sta_hpr_pass_release(&p->hpr);
    sta_pullpush_pass_release(&p->pullpush);
    sta_normals_pyramid_pass_release(&p->normals_pyramid);
    sta_gl_staging_release(&p->staging);
    sta_normals_screen_pass_release(&p->normals_screen);
    sta_shade_pass_release(&p->shade);
    sta_volumetric_pass_release(&p->volumetric);
    if (p->display_program) {
        glDeleteProgram(p->display_program);
    }
    if (p->colour_program) {
        glDeleteProgram(p->colour_program);
    }
    memset(p, 0, sizeof(*p));
}

static sta_status resize(sta_pipeline *p, int w, int h, sta_error *err)
{
    if (p->width_px == w && p->height_px == h) {
        return STA_OK;
    }
    release_textures(p);
    GLuint *four[] = { &p->position, &p->colour, &p->filled_position, &p->normal, &p->normal2 };
    sta_status s = STA_OK;
    for (size_t i = 0; i < sizeof(four) / sizeof(four[0]) && s == STA_OK; i++) {
        s = sta_gl_texture_create(w, h, 4, 1, four[i], err);
    }
    if (s == STA_OK) {
        s = sta_gl_texture_create_rgba8(w, h, &p->filled_colour, err);
    }
    if (s == STA_OK) {
        s = sta_gl_label_texture_create(w, h, &p->label, err);
    }
    if (s == STA_OK) {
        glCreateTextures(GL_TEXTURE_2D, 1, &p->classes);
        glTextureStorage2D(p->classes, 1, GL_R8UI, w, h);
    }
    if (s == STA_OK) {
        s = sta_hpr_pyramid_texture_create(w, h, &p->pyramid, err);
    }
    if (s != STA_OK) {
        release_textures(p);
        return s;
    }
    p->width_px = w;
    p->height_px = h;
    return STA_OK;
}

sta_status sta_pipeline_raster_textures(sta_pipeline *p, int width_px, int height_px,
                                        GLuint *out_position, GLuint *out_classes, sta_error *err)
{
    *out_position = *out_classes = 0;
    sta_status s = resize(p, width_px, height_px, err);
    if (s == STA_OK) {
        *out_position = p->position;
        *out_classes = p->classes;
    }
    return s;
}

double sta_timing_clock_ms(int clock)
{
    return clock == STA_TIMING_CPU ? sta_clock_process_cpu_ms() : sta_clock_ms();
}

// Per-pass time: with timing on, the GPU is drained before and after each pass and the
// clock read (wall time, or the process's CPU time: sta_timing_clock). GL timestamp
// queries would be cheaper on a real GPU but on llvmpipe they record when commands are
// queued, not when they run; a drained pipeline gives honest numbers on both (and
// timing is only on for --stats and benchmarks).
static void mark(sta_pipeline *p, sta_pipeline_timing *t, int pass, int end)
{
    if (t) {
        glFinish();
        p->marks[2 * pass + end] = sta_timing_clock_ms(p->timing_clock);
    }
}

static void display(sta_pipeline *p, int mode, int w, int h, GLuint out)
{
    glUseProgram(p->display_program);
    glUniform2f(p->display_size, (float)w, (float)h);
    glUniform1i(p->display_mode, mode);
    glBindImageTexture(STA_DISPLAY_IMAGE_POSITION, mode == 1 ? p->filled_position : p->position, 0,
                       GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
    glBindImageTexture(STA_DISPLAY_IMAGE_COLOUR, p->colour, 0, GL_FALSE, 0, GL_READ_ONLY,
                       GL_RGBA32F);
    glBindImageTexture(STA_DISPLAY_IMAGE_FILLED_COLOUR, p->filled_colour, 0, GL_FALSE, 0,
                       GL_READ_ONLY, GL_RGBA8);
    glBindImageTexture(STA_DISPLAY_IMAGE_LABEL, p->label, 0, GL_FALSE, 0, GL_READ_ONLY,
                       STA_GL_LABEL_FORMAT);
    glBindImageTexture(STA_DISPLAY_IMAGE_NORMAL, p->normal, 0, GL_FALSE, 0, GL_READ_ONLY,
                       GL_RGBA32F);
    glBindImageTexture(STA_DISPLAY_IMAGE_OUT, out, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA8);
    sta_gl_dispatch_2d(w, h);
}

// deferred: NULL, or where the half-resolution pyramidal normals leave their last step
// to the shade pass (then *deferred_used is set; the normal image is not written).
static sta_status run_normals(sta_pipeline *p, const sta_pipeline_options *o,
                              const sta_view_params *view, sta_pipeline_timing *t,
                              sta_normals_upsample_inputs *deferred, bool *deferred_used,
                              sta_error *err)
{
    mark(p, t, STA_PASS_NORMALS, 0);
    sta_status s;
    *deferred_used = false;
    if (o->normals == STA_NORMAL_PYRAMID) {
        sta_normals_pyramid_params params = { .half_resolution = !o->normals_every_pixel };
        sta_normals_pyramid_params_defaults(&params);
        if (deferred && params.half_resolution && !o->smooth) {
            *deferred_used = true;
            s = sta_normals_pyramid_pass_run_deferred(&p->normals_pyramid, view, &params,
                                                      sta_pullpush_pass_pyramid(&p->pullpush),
                                                      p->filled_position, deferred, err);
        } else {
            s = sta_normals_pyramid_pass_run(&p->normals_pyramid, view, &params,
                                             sta_pullpush_pass_pyramid(&p->pullpush),
                                             p->filled_position, p->normal, err);
        }
    } else {
        static const int methods[STA_NORMAL_METHOD_COUNT] = { 0, STA_NORMALS_SCREEN_LD,
                                                              STA_NORMALS_SCREEN_PD,
                                                              STA_NORMALS_SCREEN_PC,
                                                              STA_NORMALS_SCREEN_TI };
        sta_normals_screen_params params = { methods[o->normals], o->samples,
                                             o->normal_max_distance_m };
        s = sta_normals_screen_pass_run(&p->normals_screen, view, &params, p->filled_position,
                                        p->normal, err);
    }
    mark(p, t, STA_PASS_NORMALS, 1);
    if (s == STA_OK && o->smooth) {
        mark(p, t, STA_PASS_SMOOTH, 0);
        sta_normals_screen_params params = { 0, o->samples, o->normal_max_distance_m };
        s = sta_normals_smooth_pass_run(&p->normals_screen, view, &params, p->filled_position,
                                        p->normal, p->normal2, err);
        GLuint swap = p->normal;
        p->normal = p->normal2;
        p->normal2 = swap;
        mark(p, t, STA_PASS_SMOOTH, 1);
    }
    return s;
}

sta_status sta_pipeline_set_points(sta_pipeline *p, GLuint id_texture, const sta_gpu_cache *cache,
                                   sta_error *err)
{
    memset(&p->points_source, 0, sizeof(p->points_source));
    if (!cache || !id_texture) {
        return STA_OK;
    }
    return sta_volumetric_points_from_cache(&p->volumetric, cache, id_texture, &p->points_source,
                                            err);
}

bool sta_pipeline_volumetric_set(const sta_pipeline_options *o,
                                 uint32_t set[STA_VOLUMETRIC_CLASS_WORDS])
{
    memset(set, 0, STA_VOLUMETRIC_CLASS_WORDS * sizeof(set[0]));
    if (o->mode != STA_PIPELINE_FILL && o->mode != STA_PIPELINE_NORMALS &&
        o->mode != STA_PIPELINE_SHADED) {
        return false;
    }
    uint32_t any = 0;
    for (int i = 0; i < STA_VOLUMETRIC_CLASS_WORDS; i++) {
        set[i] = o->no_fill_set ? o->no_fill_classes[i] : 0;
        any |= set[i];
    }
    if (!o->no_fill_set) {
        set[0] = STA_PIPELINE_NO_FILL_DEFAULT;
        any = set[0];
    }
    return any != 0;
}

// The volumetric class set of `o`, or false when it is empty, the mode marks nothing or
// there is nothing to look classes up in (the resolve marked them: no lookup needed).
static bool volumetric_classes(const sta_pipeline *p, const sta_pipeline_options *o,
                               bool positions_marked, uint32_t set[STA_VOLUMETRIC_CLASS_WORDS])
{
    bool any = sta_pipeline_volumetric_set(o, set);
    return any && (positions_marked || (p->points_source.id_texture && p->points_source.arena));
}

static void read_timing(sta_pipeline *p, sta_pipeline_timing *t, const bool *ran)
{
    t->total_ms = 0.0;
    for (int pass = 0; pass < STA_PASS_COUNT; pass++) {
        t->ms[pass] = 0.0;
        if (!ran[pass]) {
            continue;
        }
        double begin = p->marks[2 * pass], end = p->marks[2 * pass + 1];
        t->ms[pass] = end > begin ? end - begin : 0.0;
        t->total_ms += t->ms[pass];
    }
}

sta_status sta_pipeline_run(sta_pipeline *p, const sta_pipeline_options *o,
                            const sta_view_params *view, GLuint depth, GLuint colour_rgba8,
                            sta_pipeline_timing *t, sta_error *err)
{
    bool ran[STA_PASS_COUNT] = { false };
    bool positions_ready = p->positions_ready;
    bool classes_ready = positions_ready || p->classes_ready;
    bool positions_marked = positions_ready && p->positions_marked;
    p->positions_ready = p->classes_ready = p->positions_marked = false;
    if (t) {
        memset(t, 0, sizeof(*t));
    }
    if (o->mode == STA_PIPELINE_RAW || o->mode == STA_PIPELINE_SPLATS) {
        return STA_OK; // splats are shaded in their own pass (render/pass_splats.h)
    }
    const int w = view->width_px, h = view->height_px;
    sta_status s = resize(p, w, h, err);
    if (s != STA_OK) {
        return s;
    }
    // Volumetric classes (fill, normals and shaded modes): marked in the positions before HPR
    // (w = STA_POSITION_W_MARKED: no seeds for the fill), drawn back as points after shading.
    uint32_t classes[STA_VOLUMETRIC_CLASS_WORDS];
    bool volumetric = volumetric_classes(p, o, positions_marked, classes);
    // Where the geometry pass wrote a class image, the mark runs inside the unproject pass
    // (issue 15, tenth round: one full-screen pass fewer).
    bool mark_in_unproject = volumetric && !positions_ready && classes_ready;
    // Inputs: positions from depth (unless the compute rasteriser wrote them); colour as float only
    // for the passes that read it as an image (EDL, the HPR display); pull-push and the volumetric
    // overlay sample the geometry pass's RGBA8 colour (the same values).
    mark(p, t, STA_PASS_UNPROJECT, 0);
    if (!positions_ready) {
        sta_unproject_mark fused = { p->classes, classes, 0 };
        if (mark_in_unproject) {
            s = sta_volumetric_pass_tile_flags(&p->volumetric, w, h, &fused.tile_flags, err);
            if (s != STA_OK) {
                return s;
            }
        }
        s = sta_unproject_pass_run_marked(&p->unproject, view, depth,
                                          mark_in_unproject ? &fused : NULL, p->position, err);
        if (s != STA_OK) {
            return s;
        }
    }
    if (o->mode == STA_PIPELINE_EDL || o->mode == STA_PIPELINE_HPR) {
        glUseProgram(p->colour_program);
        glUniform2f(p->colour_size, (float)w, (float)h);
        glBindTextureUnit(STA_COLOUR_TO_FLOAT_SAMPLER_COLOUR8, colour_rgba8);
        glBindImageTexture(STA_COLOUR_TO_FLOAT_IMAGE_COLOUR, p->colour, 0, GL_FALSE, 0,
                           GL_WRITE_ONLY, GL_RGBA32F);
        sta_gl_dispatch_2d(w, h);
    }
    mark(p, t, STA_PASS_UNPROJECT, 1);
    ran[STA_PASS_UNPROJECT] = true;
    // The overlay reads the marked points' colours from the geometry pass's colour (it runs
    // before the shade pass or the fill display overwrites it) and draws them into the
    // RGBA8 filled colour with alpha 1, which both show unlit (screen_space.h).
    sta_volumetric_frame vframe = { w, h, p->position, colour_rgba8 };
    if (volumetric && !mark_in_unproject && !positions_marked) {
        mark(p, t, STA_PASS_VOLUMETRIC, 0);
        s = sta_volumetric_pass_mark(&p->volumetric, &p->points_source, classes,
                                     classes_ready ? p->classes : 0, &vframe, err);
        mark(p, t, STA_PASS_VOLUMETRIC, 1);
        ran[STA_PASS_VOLUMETRIC] = true;
        if (s != STA_OK) {
            return s;
        }
    }

    if (o->mode == STA_PIPELINE_EDL) {
        mark(p, t, STA_PASS_SHADE, 0);
        sta_edl_params edl = { .background = { o->background[0], o->background[1],
                                               o->background[2] } };
        sta_edl_pass_run(&p->shade, &edl, w, h, p->position, p->colour, colour_rgba8);
        mark(p, t, STA_PASS_SHADE, 1);
        ran[STA_PASS_SHADE] = true;
        goto done;
    }

    mark(p, t, STA_PASS_HPR, 0);
    sta_hpr_params hpr = { .threshold = o->hpr_threshold,
                           .sparse = !o->hpr_every_pixel,
                           .block_gaps = o->hpr_block_gaps,
                           // Positions from depth hold no see-through returns (only the
                           // compute rasteriser's resolve writes them): HPR without the rule.
                           .no_see_through = !positions_ready };
    if (o->hpr_exhaustive) {
        s = sta_hpr_pass_run_exhaustive(&p->hpr, view, &hpr,
                                        o->hpr_radius_px > 0 ? o->hpr_radius_px
                                                             : STA_PIPELINE_DEFAULT_HPR_RADIUS_PX,
                                        p->position, p->label, err);
    } else {
        s = sta_hpr_pass_run_pyramid(&p->hpr, view, &hpr, p->position, p->pyramid, p->label, err);
    }
    mark(p, t, STA_PASS_HPR, 1);
    ran[STA_PASS_HPR] = true;
    if (s != STA_OK) {
        return s;
    }
    if (o->mode == STA_PIPELINE_HPR) {
        display(p, 0, w, h, colour_rgba8);
        goto done;
    }

    mark(p, t, STA_PASS_PULLPUSH, 0);
    s = sta_pullpush_pass_run(&p->pullpush, view, p->position, colour_rgba8, p->label,
                              p->filled_position, p->filled_colour, err);
    mark(p, t, STA_PASS_PULLPUSH, 1);
    ran[STA_PASS_PULLPUSH] = true;
    if (s != STA_OK) {
        return s;
    }
    if (o->mode == STA_PIPELINE_FILL) {
        goto overlay;
    }

    // Shaded: the half-resolution normals are upsampled inside the shade pass.
    sta_normals_upsample_inputs upsample;
    bool upsampled_in_shade = false;
    bool defer = o->mode == STA_PIPELINE_SHADED && !o->keep_normal_image;
    s = run_normals(p, o, view, t, defer ? &upsample : NULL, &upsampled_in_shade, err);
    ran[STA_PASS_NORMALS] = true;
    ran[STA_PASS_SMOOTH] = o->smooth;
    if (s != STA_OK) {
        return s;
    }
    if (o->mode == STA_PIPELINE_NORMALS) {
        display(p, 2, w, h, colour_rgba8);
        goto done;
    }
    mark(p, t, STA_PASS_SHADE, 0);
    sta_shade_params shade = { .background = { o->background[0], o->background[1],
                                               o->background[2] } };
    // The normals' upsample runs inside the shade pass (a full-screen pass fewer), the
    // marked volumetric points are drawn before it into the filled colour, on the tiles
    // they reach (issue 15, fourteenth round); both count as shading.
    if (volumetric) {
        s = sta_volumetric_pass_overlay(&p->volumetric, &vframe, mark_in_unproject,
                                        p->filled_colour, err);
    }
    sta_shade_pass_run(&p->shade, &shade, w, h, p->filled_position, p->filled_colour, p->normal,
                       upsampled_in_shade ? &upsample : NULL, colour_rgba8);
    mark(p, t, STA_PASS_SHADE, 1);
    ran[STA_PASS_SHADE] = true;
    if (s != STA_OK) {
        return s;
    }
    goto done;
overlay:
    if (volumetric) {
        double before = ran[STA_PASS_VOLUMETRIC] ? p->marks[2 * STA_PASS_VOLUMETRIC + 1] -
                                                       p->marks[2 * STA_PASS_VOLUMETRIC]
                                                 : 0.0;
        ran[STA_PASS_VOLUMETRIC] = true;
        mark(p, t, STA_PASS_VOLUMETRIC, 0);
        s = sta_volumetric_pass_overlay(&p->volumetric, &vframe, mark_in_unproject,
                                        p->filled_colour, err);
        mark(p, t, STA_PASS_VOLUMETRIC, 1);
        if (s != STA_OK) {
            return s;
        }
        if (t) {
            p->marks[2 * STA_PASS_VOLUMETRIC] -= before; // mark and overlay together
        }
    }
    display(p, 1, w, h, colour_rgba8);
done:
    if (t) {
        read_timing(p, t, ran);
    }
    return sta_gl_check("screen-space pipeline", err);
}
