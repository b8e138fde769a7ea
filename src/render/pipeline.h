/* SPDX-License-Identifier: MIT
 * The screen-space pipeline after the geometry pass (DESIGN.md §5):
 * unproject -> HPR (pyramidal, or exhaustive as a baseline) -> pull-push -> normals
 * (pyramidal, or the screen-space LD/PD/PC/TI variants, optional smoothing) ->
 * deferred shading; or eye-dome lighting straight from the unprojected points. Every
 * stage can be shown on its own (`mode`), and every pass can be timed.
 * Main thread (GL) only.
 */
#ifndef STA_RENDER_PIPELINE_H
#define STA_RENDER_PIPELINE_H

#include <epoxy/gl.h>
#include <stdbool.h>

#include "core/status.h"
#include "render/pass_hpr.h"
#include "render/pass_normals_pyramid.h"
#include "render/pass_normals_screen.h"
#include "render/pass_pullpush.h"
#include "render/pass_shade.h"
#include "render/pass_unproject.h"
#include "render/pass_volumetric.h"
#include "render/ref/screen_space.h"

typedef enum sta_pipeline_mode {
    STA_PIPELINE_RAW = 0, /* the geometry pass as it is */
    STA_PIPELINE_HPR,     /* HPR labels: visible points, hidden red, holes green */
    STA_PIPELINE_FILL,    /* pull-push filled colour */
    STA_PIPELINE_NORMALS, /* estimated normals as colours */
    STA_PIPELINE_SHADED,  /* deferred Blinn-Phong on the filled surface */
    STA_PIPELINE_EDL,     /* eye-dome lighting on the raw points */
    STA_PIPELINE_SPLATS,  /* oriented round splats instead of points (render/pass_splats.h,
                             drawn and shaded by sta_scene; sta_pipeline_run does nothing);
                             a scene without normals falls back to shaded */
    STA_PIPELINE_MODE_COUNT
} sta_pipeline_mode;

typedef enum sta_normal_method {
    STA_NORMAL_PYRAMID = 0, /* Bouchiba's pyramidal estimator on the pull-push levels */
    STA_NORMAL_LD,          /* Schiffner: local derivatives */
    STA_NORMAL_PD,          /* plane fit, diagonal samples */
    STA_NORMAL_PC,          /* plane fit, counter-clockwise samples */
    STA_NORMAL_TI,          /* covariance tensor */
    STA_NORMAL_METHOD_COUNT
} sta_normal_method;

/* Passes timed in sta_pipeline_timing. */
typedef enum sta_pass_id {
    STA_PASS_UNPROJECT = 0,
    STA_PASS_HPR,
    STA_PASS_PULLPUSH,
    STA_PASS_NORMALS,
    STA_PASS_SMOOTH,
    STA_PASS_SHADE,
    STA_PASS_VOLUMETRIC, /* volumetric classes: mark and overlay together */
    STA_PASS_COUNT
} sta_pass_id;

/* Radius of the exhaustive HPR baseline when none is given, pixels. */
#define STA_PIPELINE_DEFAULT_HPR_RADIUS_PX 8

typedef struct sta_pipeline_options {
    int mode;                    /* sta_pipeline_mode */
    int normals;                 /* sta_normal_method */
    int samples;                 /* LD/PD/PC/TI scheme: 5, 9, 17, 25 (0: 9) */
    bool smooth;                 /* run the normal smoothing pass */
    bool hpr_exhaustive;         /* the fixed-radius baseline instead of the pyramid */
    bool hpr_every_pixel;        /* the pyramid on every pixel instead of the sparse operator
                                    (the default; sta_hpr_params.sparse, docs/HPR.md) */
    bool hpr_block_gaps;         /* empty pixels' hole / background decision by the pyramid's
                                    blocks (sta_hpr_params.block_gaps; default: per pixel) */
    bool normals_every_pixel;    /* pyramidal normals gathered on every pixel instead of on
                                    a quarter of them and upsampled (the default;
                                    sta_normals_pyramid_params.half_resolution) */
    bool keep_normal_image;      /* shaded: the normals' upsample writes the normal image
                                    (strata-bench reads it) instead of running inside the
                                    shade pass (the default: a full-screen pass fewer) */
    int hpr_radius_px;           /* exhaustive radius (0: STA_PIPELINE_DEFAULT_HPR_RADIUS_PX) */
    float hpr_threshold;         /* 0: 0.1 */
    float s0_m;                  /* sampling scale; 0: the scene's estimate */
    float normal_max_distance_m; /* screen-space normals; 0: 5 s0 */
    float background[3];
    /* Volumetric classes, drawn as points with no surface fill (shaded and fill modes):
     * bit c % 32 of word c / 32 is class c. With no_fill_set false (zero), the default
     * STA_PIPELINE_NO_FILL_DEFAULT; set with all bits clear: none. */
    bool no_fill_set;
    uint32_t no_fill_classes[STA_VOLUMETRIC_CLASS_WORDS];
} sta_pipeline_options;

/* The default volumetric classes, word 0: LAS vegetation (3 low, 4 medium, 5 high) and
 * wires (13 guard, 14 conductor; issue 15, fifteenth round: a wire is a line, not a
 * surface, so it is drawn as points and occludes only within HPR's marked reach, and the
 * facade behind it is not hidden in a band along it). A scene without classification
 * has none of them, so nothing changes there. */
#define STA_PIPELINE_NO_FILL_DEFAULT ((1u << 3) | (1u << 4) | (1u << 5) | (1u << 13) | (1u << 14))

/* The clock of per-pass times: wall time, or the CPU time of all the process's threads
 * (sta_clock_process_cpu_ms: the work of a pass on llvmpipe, steady on a busy machine;
 * meaningless where the GPU is a separate device). */
typedef enum sta_timing_clock {
    STA_TIMING_WALL,
    STA_TIMING_CPU
} sta_timing_clock;

/* The time of `clock` in milliseconds (differences only). */
double sta_timing_clock_ms(int clock);

typedef struct sta_pipeline_timing {
    double ms[STA_PASS_COUNT]; /* GPU time per pass (0 when not run) */
    double total_ms;
} sta_pipeline_timing;

typedef struct sta_pipeline {
    sta_unproject_pass unproject;
    sta_hpr_pass hpr;
    sta_pullpush_pass pullpush;
    sta_normals_pyramid_pass normals_pyramid;
    sta_normals_screen_pass normals_screen;
    sta_shade_pass shade;
    sta_volumetric_pass volumetric;
    sta_volumetric_points points_source; /* sta_pipeline_set_points; id_texture 0: none */
    sta_gl_staging staging; /* shared by the passes that stage their stores (gl_staged.h) */
    GLuint display_program, colour_program;
    GLint display_size, display_mode, colour_size;
    int width_px, height_px; /* texture size */
    GLuint position, colour, label, pyramid, filled_position, filled_colour, normal, normal2;
    GLuint classes;                   /* R8UI point classes (from the compute rasteriser) */
    double marks[2 * STA_PASS_COUNT]; /* pass start/end, ms (timing on) */
    int timing_clock;                 /* sta_timing_clock of the marks (0: wall) */
    /* Set by the caller for one run: `position` and `classes` already hold this frame's
     * camera-space positions and point classes (the compute rasteriser's resolve wrote
     * them, see sta_pipeline_raster_textures), so the unproject pass is skipped and the
     * volumetric mark reads the classes; cleared by the run. */
    bool positions_ready;
    /* Set by the caller for one run: `classes` already holds this frame's point classes
     * (the GL_POINTS geometry pass wrote them: sta_pass_geometry_set_class_out), so the
     * volumetric mark reads them instead of looking them up; cleared by the run. */
    bool classes_ready;
    /* Set by the caller for one run, with positions_ready: the resolve also marked the
     * volumetric classes of sta_pipeline_volumetric_set in the positions, so the mark
     * pass is skipped; cleared by the run. */
    bool positions_marked;
} sta_pipeline;

/* The volumetric class set `options` asks for in a mode that marks them (fill, normals,
 * shaded) into `set` (STA_VOLUMETRIC_CLASS_WORDS words); false when it is empty or the
 * mode marks nothing. */
bool sta_pipeline_volumetric_set(const sta_pipeline_options *options,
                                 uint32_t set[STA_VOLUMETRIC_CLASS_WORDS]);

sta_status sta_pipeline_init(sta_pipeline *pipeline, sta_error *err);
void sta_pipeline_release(sta_pipeline *pipeline);

/* Where the drawn points' classes come from for this frame (the point-id texture of
 * the geometry pass's target and the GPU cache); without it (or with an empty arena)
 * no class is drawn as points. The cache is read now, not kept. */
sta_status sta_pipeline_set_points(sta_pipeline *pipeline, GLuint id_texture,
                                   const sta_gpu_cache *cache, sta_error *err);

/* Runs the passes `options->mode` needs on the geometry pass's depth (reverse-Z
 * float) and colour (RGBA8) textures and writes the result into `colour_rgba8` (it is
 * read first, then overwritten). With `timing` (may be NULL) every pass is timed by
 * draining the GPU around it (wall clock), which slows the frame a little. */
/* The textures the next run of a width x height view reads its camera-space positions
 * (RGBA32F) and point classes (R8UI) from ((re)allocated for that size), for a geometry
 * pass that writes them itself (then set positions_ready). */
sta_status sta_pipeline_raster_textures(sta_pipeline *pipeline, int width_px, int height_px,
                                        GLuint *out_position, GLuint *out_classes, sta_error *err);

sta_status sta_pipeline_run(sta_pipeline *pipeline, const sta_pipeline_options *options,
                            const sta_view_params *view, GLuint depth, GLuint colour_rgba8,
                            sta_pipeline_timing *timing, sta_error *err);

/* Names for command lines: "raw", "hpr", "fill", "normals", "shaded", "edl", "splats" and
 * "pyramid", "ld", "pd", "pc", "ti"; -1 when unknown. */
int sta_pipeline_mode_from_name(const char *name);
int sta_normal_method_from_name(const char *name);
const char *sta_pipeline_mode_name(int mode);
const char *sta_normal_method_name(int method);
const char *sta_pass_name(int pass);

#endif
