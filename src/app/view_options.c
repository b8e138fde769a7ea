/* SPDX-License-Identifier: MIT
 * strata-view's command line. */
#include "app/view_options.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "render/bindings.h"
#include "render/pipeline.h"

static void print_usage(FILE *out)
{
    fputs("usage: strata-view [options] SCENE.strata\n"
          "\n"
          "Opens a .strata scene in a window and streams it to the GPU within a point budget.\n"
          "With --headless it renders through EGL (no display needed) to a PNG / EXR.\n"
          "\n"
          "options:\n"
          "  --headless             render offscreen; needs --out and/or --exr\n"
          "  --out FILE.png         write the colour image (headless)\n"
          "  --exr FILE.exr         write colour and depth as float channels (headless)\n"
          "  --size WxH             image or window size (default 1280x720)\n"
          "  --camera X,Y,Z,YAW,PITCH[,FOV]\n"
          "                         camera in world coordinates; angles in degrees, yaw 0\n"
          "                         looks along +X, 90 along +Y; fov vertical (default 60)\n"
          "  --look DX,DY,DZ,YAW,PITCH[,FOV]\n"
          "                         the same, relative to the centre of the scene's bounds\n"
          "                         (default: the whole scene, seen from the south-west)\n"
          "  --frames N             stop after N frames (headless default: until every\n"
          "                         wanted node is loaded)\n"
          "  --budget POINTS        points drawn per frame at most (default 30000000)\n"
          "  --gpu-mem MIB          GPU memory for resident nodes (default 1024)\n"
          "  --colour MODE          rgb, intensity, elevation, class or returns (default:\n"
          "                         rgb when the scene has colour, else elevation)\n"
          "  --path FILE.json       play a recorded camera path (window or headless)\n"
          "  --frames-out PATTERN   headless path playback: write frame i to\n"
          "                         PATTERN with %d replaced (e.g. frames/%05d.png)\n"
          "  --record FILE.json     window: record the camera path (key P adds a keyframe)\n"
          "  --stats                print one line of frame statistics per frame, with the\n"
          "                         GPU time of every pass\n"
          "\n"
          "screen-space pipeline (after the one-pixel-per-point geometry pass):\n"
          "  --pipeline MODE        raw (points only), hpr (hidden point removal labels),\n"
          "                         fill (pull-push), normals, shaded (default) or edl\n"
          "  --normals METHOD       pyramid (default), ld, pd, pc or ti\n"
          "  --samples N            sampling scheme of pd/pc/ti: 5, 9 (default), 17 or 25\n"
          "  --smooth               smooth the normals (one extra pass)\n"
          "  --hpr pyramid|exhaustive  pyramidal HPR (default) or the fixed-radius baseline\n"
          "  --hpr-radius PX        radius of the exhaustive operator (default 8)\n"
          "  --hpr-threshold T      visibility threshold (default 0.1)\n"
          "  --s0 METRES            sampling scale (default: from the hierarchy's spacing)\n"
          "  -h, --help             this text\n"
          "\n"
          "window keys and mouse:\n"
          "  left drag      orbit around the picked point      right drag / shift  pan\n"
          "  wheel          zoom towards the cursor             double-click  focus a point\n"
          "  W A S D Q E    fly (hold shift: faster)            F       toggle fly / orbit\n"
          "  1..5           colour: rgb, intensity, elevation, class, returns\n"
          "  M / N          next pipeline mode / next normal method\n"
          "  H              pyramidal / exhaustive HPR     G    normal smoothing on/off\n"
          "  R              reset to the whole scene            P       add path keyframe\n"
          "  Esc            quit\n",
          out);
}

int sta_view_colour_mode(const char *name)
{
    static const char *names[] = { "rgb", "intensity", "elevation", "class", "returns" };
    for (int i = 0; i < STA_COLOUR_MODE_COUNT; i++) {
        if (strcmp(name, names[i]) == 0) {
            return i;
        }
    }
    return -1;
}

static int parse_doubles(const char *text, double *out, int min_count, int max_count)
{
    int n = 0;
    const char *p = text;
    while (*p && n < max_count) {
        char *end = NULL;
        errno = 0;
        double v = strtod(p, &end);
        if (end == p || errno) {
            return -1;
        }
        out[n++] = v;
        p = end;
        if (*p == ',') {
            p++;
        } else if (*p) {
            return -1;
        }
    }
    return n >= min_count && *p == '\0' ? n : -1;
}

static int parse_count(const char *option, const char *text, uint64_t lo, uint64_t hi,
                       uint64_t *out)
{
    char *end = NULL;
    errno = 0;
    unsigned long long v = text && text[0] != '-' ? strtoull(text, &end, 10) : 0;
    if (!text || errno || end == text || *end || v < lo || v > hi) {
        fprintf(stderr, "strata-view: %s needs a whole number from %llu to %llu, got '%s'\n",
                option, (unsigned long long)lo, (unsigned long long)hi, text ? text : "");
        return 0;
    }
    *out = v;
    return 1;
}

int sta_view_parse_args(int argc, char **argv, sta_view_args *a)
{
    memset(a, 0, sizeof(*a));
    a->width_px = 1280;
    a->height_px = 720;
    a->colour_mode = -1;
    a->timeout_s = 300.0;
    a->camera[5] = 60.0;
    a->pipeline = STA_PIPELINE_SHADED;
    for (int i = 1; i < argc; i++) {
        const char *o = argv[i];
        const char *v = i + 1 < argc ? argv[i + 1] : NULL;
        // "--name=value" is "--name value" (handy for negative numbers).
        char name[64];
        const char *eq = strchr(o, '=');
        bool joined = o[0] == '-' && o[1] == '-' && eq && (size_t)(eq - o) < sizeof(name);
        if (joined) {
            memcpy(name, o, (size_t)(eq - o));
            name[eq - o] = '\0';
            o = name;
            v = eq + 1;
        }
        uint64_t n = 0;
        if (strcmp(o, "-h") == 0 || strcmp(o, "--help") == 0) {
            print_usage(stdout);
            return -1;
        } else if (joined && (strcmp(o, "--headless") == 0 || strcmp(o, "--stats") == 0 ||
                              strcmp(o, "--smooth") == 0)) {
            fprintf(stderr, "strata-view: %s takes no value\n", o);
            return 2;
        } else if (strcmp(o, "--headless") == 0) {
            a->headless = true;
        } else if (strcmp(o, "--stats") == 0) {
            a->stats = true;
        } else if (strcmp(o, "--smooth") == 0) {
            a->smooth = true;
        } else if (o[0] == '-' && o[1] == '-' && !v) {
            fprintf(stderr, "strata-view: %s needs a value (or is unknown; see --help)\n", o);
            return 2;
        } else if (strcmp(o, "--out") == 0) {
            a->out_png = v;
            i += !joined;
        } else if (strcmp(o, "--exr") == 0) {
            a->out_exr = v;
            i += !joined;
        } else if (strcmp(o, "--path") == 0) {
            a->path_file = v;
            i += !joined;
        } else if (strcmp(o, "--record") == 0) {
            a->record_file = v;
            i += !joined;
        } else if (strcmp(o, "--frames-out") == 0) {
            // Exactly one %d-style conversion: the pattern reaches snprintf.
            const char *pc = strchr(v, '%');
            const char *d = pc ? pc + 1 : NULL;
            while (d && *d >= '0' && *d <= '9') {
                d++;
            }
            if (!pc || *d != 'd' || strchr(pc + 1, '%')) {
                fprintf(stderr, "strata-view: --frames-out needs one %%d (e.g. f/%%05d.png)\n");
                return 2;
            }
            a->frame_pattern = v;
            i += !joined;
        } else if (strcmp(o, "--size") == 0) {
            int w = 0, h = 0;
            char tail = 0;
            if (sscanf(v, "%dx%d%c", &w, &h, &tail) != 2 || w < 1 || h < 1 || w > 16384 ||
                h > 16384) {
                fprintf(stderr, "strata-view: --size needs WxH (e.g. 1920x1080), got '%s'\n", v);
                return 2;
            }
            a->width_px = w;
            a->height_px = h;
            i += !joined; // the value was the next argument
        } else if (strcmp(o, "--camera") == 0 || strcmp(o, "--look") == 0) {
            if (parse_doubles(v, a->camera, 5, 6) < 0) {
                fprintf(stderr, "strata-view: %s needs X,Y,Z,YAW,PITCH[,FOV], got '%s'\n", o, v);
                return 2;
            }
            a->has_camera = true;
            a->camera_relative = strcmp(o, "--look") == 0;
            i += !joined; // the value was the next argument
        } else if (strcmp(o, "--frames") == 0) {
            if (!parse_count(o, v, 1, 1000000, &n)) {
                return 2;
            }
            a->max_frames = (int)n;
            i += !joined; // the value was the next argument
        } else if (strcmp(o, "--repeat") == 0) {
            if (!parse_count(o, v, 1, 256, &n)) {
                return 2;
            }
            a->repeat = (int)n;
            i += !joined; // the value was the next argument
        } else if (strcmp(o, "--budget") == 0) {
            if (!parse_count(o, v, 1000, 2000000000ull, &n)) {
                return 2;
            }
            a->budget_points = n;
            i += !joined; // the value was the next argument
        } else if (strcmp(o, "--gpu-mem") == 0) {
            if (!parse_count(o, v, 16, 1 << 20, &n)) {
                return 2;
            }
            a->gpu_mem_mib = n;
            i += !joined; // the value was the next argument
        } else if (strcmp(o, "--pipeline") == 0) {
            a->pipeline = sta_pipeline_mode_from_name(v);
            if (a->pipeline < 0) {
                fprintf(stderr,
                        "strata-view: --pipeline takes raw, hpr, fill, normals, shaded "
                        "or edl, got '%s'\n",
                        v);
                return 2;
            }
            i += !joined; // the value was the next argument
        } else if (strcmp(o, "--normals") == 0) {
            a->normals = sta_normal_method_from_name(v);
            if (a->normals < 0) {
                fprintf(stderr,
                        "strata-view: --normals takes pyramid, ld, pd, pc or ti, got "
                        "'%s'\n",
                        v);
                return 2;
            }
            i += !joined; // the value was the next argument
        } else if (strcmp(o, "--samples") == 0) {
            if (!parse_count(o, v, 5, 25, &n) || (n != 5 && n != 9 && n != 17 && n != 25)) {
                fprintf(stderr, "strata-view: --samples takes 5, 9, 17 or 25\n");
                return 2;
            }
            a->samples = (int)n;
            i += !joined; // the value was the next argument
        } else if (strcmp(o, "--hpr") == 0) {
            if (strcmp(v, "pyramid") != 0 && strcmp(v, "exhaustive") != 0) {
                fprintf(stderr, "strata-view: --hpr takes pyramid or exhaustive, got '%s'\n", v);
                return 2;
            }
            a->hpr_exhaustive = strcmp(v, "exhaustive") == 0;
            i += !joined; // the value was the next argument
        } else if (strcmp(o, "--hpr-radius") == 0) {
            if (!parse_count(o, v, 1, 64, &n)) {
                return 2;
            }
            a->hpr_radius_px = (int)n;
            i += !joined; // the value was the next argument
        } else if (strcmp(o, "--hpr-threshold") == 0 || strcmp(o, "--s0") == 0) {
            char *end = NULL;
            double d = strtod(v, &end);
            if (end == v || *end || !(d > 0) || d > 1e6) {
                fprintf(stderr, "strata-view: %s needs a positive number, got '%s'\n", o, v);
                return 2;
            }
            if (strcmp(o, "--s0") == 0) {
                a->s0_m = d;
            } else {
                a->hpr_threshold = d;
            }
            i += !joined; // the value was the next argument
        } else if (strcmp(o, "--colour") == 0 || strcmp(o, "--color") == 0) {
            a->colour_mode = sta_view_colour_mode(v);
            if (a->colour_mode < 0) {
                fprintf(stderr,
                        "strata-view: --colour takes rgb, intensity, elevation, class "
                        "or returns, got '%s'\n",
                        v);
                return 2;
            }
            i += !joined; // the value was the next argument
        } else if (o[0] == '-' && o[1] != '\0') {
            fprintf(stderr, "strata-view: unknown option %s (see --help)\n", o);
            return 2;
        } else if (!a->scene) {
            a->scene = o;
        } else {
            fprintf(stderr, "strata-view: one scene at a time (got %s and %s)\n", a->scene, o);
            return 2;
        }
    }
    if (!a->scene) {
        fprintf(stderr, "strata-view: no scene given (see --help)\n");
        return 2;
    }
    if (a->headless && !a->out_png && !a->out_exr && !a->frame_pattern && !a->stats) {
        fprintf(stderr, "strata-view: --headless needs --out, --exr, --frames-out or --stats\n");
        return 2;
    }
    return 0;
}
