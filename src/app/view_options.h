/* SPDX-License-Identifier: MIT
 * strata-view's command line.
 */
#ifndef STA_APP_VIEW_OPTIONS_H
#define STA_APP_VIEW_OPTIONS_H

#include "render/pass_katz.h"
#include <stdbool.h>
#include <stdint.h>

#include "core/camera.h"
#include "render/point_size.h"
#include "stream/clip.h"

typedef struct sta_view_args {
    const char *scene; /* .strata path */
    bool headless;
    int width_px, height_px;   /* --size */
    const char *out_png;       /* --out */
    const char *out_exr;       /* --exr */
    int max_frames;            /* --frames (0: until fully loaded) */
    double timeout_s;          /* headless: give up waiting after this */
    uint64_t budget_points;    /* --budget */
    uint64_t gpu_mem_mib;      /* --gpu-mem */
    double min_spacing_px;     /* --min-spacing */
    int colour_mode;           /* --colour */
    bool has_camera;           /* --camera given (world coordinates) */
    bool camera_relative;      /* --look given (relative to the scene centre) */
    double camera[6];          /* x, y, z, yaw deg, pitch deg, fov deg */
    const char *path_file;     /* --path: play a camera path */
    const char *record_file;   /* --record: write a camera path (window) */
    double path_speed_mps;     /* --path-speed: constant speed playback (0: key times) */
    double orbit_pitch_deg[2]; /* --orbit-pitch: camera elevation above the orbit centre */
    const char *frame_pattern; /* --frames-out: numbered PNGs when playing a path */
    bool stats;                /* --stats: one line per frame */
    int stats_clock;           /* --stats-clock (sta_timing_clock) */
    int pipeline;              /* --pipeline (sta_pipeline_mode) */
    int normals;               /* --normals (sta_normal_method) */
    int samples;               /* --samples 5|9|17|25 */
    bool smooth;               /* --smooth */
    bool hpr_exhaustive;       /* --hpr exhaustive */
    bool hpr_every_pixel;      /* --hpr pyramid (default --hpr sparse) */
    bool hpr_block_gaps;       /* --hpr-gaps blocks (default smooth) */
    bool normals_every_pixel;  /* --normals-every-pixel */
    int hpr_radius_px;         /* --hpr-radius */
    double hpr_threshold;      /* --hpr-threshold */
    double s0_m;               /* --s0 */
    bool no_fill_set;          /* --no-fill-classes given */
    uint32_t no_fill[8];       /* --no-fill-classes: bit c % 32 of word c / 32 */
    int repeat;                /* --repeat: time N more frames once loaded */
    /* --hpr katz, --katz-*: the live Katz mode */
    sta_katz_view_options katz;
    sta_clip clip;             /* --clip, --classes, --returns (the streamer's selection) */
    bool has_pick;             /* --pick given */
    double pick_px[2];         /* --pick X,Y: pixel to pick after the last frame */
    const char *measure_file;  /* --measure: measurements (JSON) to load and show */
    const char *measure_csv;   /* --measure-csv: export the measurements as CSV */
    bool hud;                  /* --hud: burn the readout into headless frames */
    bool no_readout;           /* --no-readout: no readout over the window's frames */
    double elevation_range[2]; /* --elevation-range MIN,MAX (max <= min: the scene's) */
    double intensity_max;      /* --intensity-max (0: the scene's) */
    int raster;                /* --raster (sta_raster_method) */
    bool raster_32bit;         /* --raster-32bit: the two-pass compute path always */
    sta_point_size point_size; /* --point-size, --point-size-min/max (raw and EDL modes) */
    const char *mirrors_file;  /* --mirrors: classify ghosts at load (files without MIRROR) */
    bool show_ghosts;          /* --show-ghosts: draw mirror ghosts (hidden by default) */
    bool no_reflections;       /* --no-reflections: --mirrors without the mirror pass */
    double splat_scale;        /* --splat-scale: factor on the splat radii ([ and ] keys) */
    int splat_method;          /* --splat-method (sta_splat_method) */
} sta_view_args;

/* Sets the defaults, then parses argv (core/cli.h; argv's pointers are reordered); prints
 * the help or an error itself. Returns 0 to continue, -1 when --help was printed (exit 0),
 * 2 for bad usage. */
int sta_view_parse_args(int argc, char **argv, sta_view_args *out);

/* Parses "rgb|intensity|elevation|class|returns"; -1 when unknown. */
int sta_view_colour_mode(const char *name);

#endif
