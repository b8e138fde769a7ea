/* SPDX-License-Identifier: MIT
 * strata-synth: writes a synthetic scene as LAS plus a truth sidecar.
 *
 *   strata-synth SCENE -o OUT.las [--points N] [--seed S] [--format 3|7]
 *                [--origin zero|utm|ecef] [--mesh FILE.ply] [--noise M] [--quiet]
 *
 * Exit status: 0 success, 1 failure, 2 bad arguments.
 */
#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/alloc.h"
#include "core/clock.h"
#include "core/log.h"
#include "synth/synth.h"

static const char usage_text[] =
    "usage: strata-synth SCENE -o OUT.las [options]\n"
    "\n"
    "Writes a synthetic point cloud as LAS and its truth as OUT.truth.json.\n"
    "\n"
    "Scenes:\n"
    "  street   mobile-mapping run through a procedural street (scanner, multiple returns)\n"
    "  sphere   points uniformly on a sphere of radius 10 m\n"
    "  planes   five stacked 10 m squares at depth gaps of 1 cm, 10 cm, 1 m, 10 m\n"
    "  nested   a sphere (radius 3 m) inside a closed box (10 m), hidden from outside\n"
    "  mesh     uniform samples on the triangles of a PLY (--mesh FILE.ply)\n"
    "\n"
    "Options:\n"
    "  -o, --output FILE       output LAS file (required)\n"
    "  --points N              number of points, > 0; suffix k, M or G (default 1M)\n"
    "  --seed S                random seed, 0 .. 2^64-1 (default 1)\n"
    "  --format 3|7            3: LAS 1.2 format 3; 7: LAS 1.4 format 7 (default)\n"
    "  --origin zero|utm|ecef  where the scene sits (default utm)\n"
    "  --mesh FILE.ply         triangle mesh for the mesh scene\n"
    "  --noise M               Gaussian noise sigma in metres (street 0.015, others 0)\n"
    "  --quiet                 no progress or summary on stderr\n"
    "  -h, --help              this text\n";

typedef struct cli {
    sta_synth_params params;
    const char *output;
    bool quiet;
} cli;

static int usage_error(const char *fmt, ...) __attribute__((format(printf, 1, 2)));

static int usage_error(const char *fmt, ...)
{
    va_list args;
    va_start(args, fmt);
    fprintf(stderr, "strata-synth: ");
    vfprintf(stderr, fmt, args);
    fprintf(stderr, "\n(try strata-synth --help)\n");
    va_end(args);
    return 2;
}

/* Unsigned decimal with an optional k/M/G suffix; false when not a number or too big. */
static bool parse_count(const char *text, uint64_t *out)
{
    if (!text[0] || text[0] < '0' || text[0] > '9') {
        return false;
    }
    errno = 0;
    char *end = NULL;
    unsigned long long v = strtoull(text, &end, 10);
    if (errno != 0) {
        return false;
    }
    uint64_t factor = 1;
    if (*end == 'k' || *end == 'K') {
        factor = 1000u;
        end++;
    } else if (*end == 'M') {
        factor = 1000000u;
        end++;
    } else if (*end == 'G') {
        factor = 1000000000u;
        end++;
    }
    if (*end != '\0' || (v != 0 && factor > UINT64_MAX / v)) {
        return false;
    }
    *out = (uint64_t)v * factor;
    return true;
}

static bool parse_double(const char *text, double *out)
{
    errno = 0;
    char *end = NULL;
    double v = strtod(text, &end);
    if (errno != 0 || end == text || *end != '\0') {
        return false;
    }
    *out = v;
    return true;
}

/* Splits "--name=value" or takes the next argument; NULL when missing. */
static const char *option_value(int argc, char **argv, int *i, const char *arg)
{
    const char *eq = strchr(arg, '=');
    if (eq) {
        return eq + 1;
    }
    if (*i + 1 >= argc) {
        return NULL;
    }
    return argv[++*i];
}

static bool option_is(const char *arg, const char *name)
{
    size_t n = strlen(name);
    return strncmp(arg, name, n) == 0 && (arg[n] == '\0' || arg[n] == '=');
}

static int set_option(cli *c, const char *arg, const char *value)
{
    sta_synth_params *p = &c->params;
    if (!value) {
        return usage_error("%s needs a value", arg);
    }
    if (option_is(arg, "-o") || option_is(arg, "--output")) {
        c->output = value;
    } else if (option_is(arg, "--points")) {
        if (!parse_count(value, &p->point_count) || p->point_count == 0) {
            return usage_error("--points: '%s' is not a positive whole number", value);
        }
    } else if (option_is(arg, "--seed")) {
        if (!parse_count(value, &p->seed)) {
            return usage_error("--seed: '%s' is not a whole number 0 .. 2^64-1", value);
        }
    } else if (option_is(arg, "--format")) {
        if (strcmp(value, "3") == 0 || strcmp(value, "7") == 0) {
            p->point_format = value[0] - '0';
        } else {
            return usage_error("--format: '%s' is not 3 or 7", value);
        }
    } else if (option_is(arg, "--origin")) {
        if (strcmp(value, "utm") == 0) {
            p->origin = STA_SYNTH_ORIGIN_UTM;
        } else if (strcmp(value, "zero") == 0) {
            p->origin = STA_SYNTH_ORIGIN_ZERO;
        } else if (strcmp(value, "ecef") == 0) {
            p->origin = STA_SYNTH_ORIGIN_ECEF;
        } else {
            return usage_error("--origin: '%s' is not zero, utm or ecef", value);
        }
    } else if (option_is(arg, "--mesh")) {
        p->mesh_path = value;
    } else if (option_is(arg, "--noise")) {
        if (!parse_double(value, &p->noise_m) || !(p->noise_m >= 0.0 && p->noise_m <= 10.0)) {
            return usage_error("--noise: '%s' is not a distance 0 .. 10 m", value);
        }
        p->has_noise = true;
    } else {
        return usage_error("unknown option '%s'", arg);
    }
    return 0;
}

/* Returns -1 to go on, else the exit status. */
static int parse(int argc, char **argv, cli *c)
{
    const char *scene = NULL;
    c->params.point_count = 1000000u;
    c->params.seed = 1u;
    for (int i = 1; i < argc; i++) {
        const char *arg = argv[i];
        if (strcmp(arg, "-h") == 0 || strcmp(arg, "--help") == 0) {
            fputs(usage_text, stdout);
            return 0;
        }
        if (strcmp(arg, "--quiet") == 0 || strcmp(arg, "-q") == 0) {
            c->quiet = true;
        } else if (arg[0] == '-' && arg[1] != '\0') {
            bool has_value = strchr(arg, '=') != NULL;
            const char *value = option_value(argc, argv, &i, arg);
            char name[64];
            snprintf(name, sizeof(name), "%.*s", has_value ? (int)(strchr(arg, '=') - arg) : 63,
                     arg);
            int status = set_option(c, name, value);
            if (status != 0) {
                return status;
            }
        } else if (!scene) {
            scene = arg;
        } else {
            return usage_error("unexpected argument '%s'", arg);
        }
    }
    if (!scene) {
        return usage_error("no scene given (street, sphere, planes, nested, mesh)");
    }
    if (!sta_synth_kind_from_name(scene, &c->params.kind)) {
        return usage_error("unknown scene '%s' (street, sphere, planes, nested, mesh)", scene);
    }
    if (!c->output) {
        return usage_error("no output given (-o OUT.las)");
    }
    if (c->params.kind == STA_SYNTH_MESH && !c->params.mesh_path) {
        return usage_error("the mesh scene needs --mesh FILE.ply");
    }
    if (c->params.kind != STA_SYNTH_MESH && c->params.mesh_path) {
        return usage_error("--mesh is only for the mesh scene, not '%s'", scene);
    }
    return -1;
}

typedef struct progress_state {
    double start_s;
    double last_s;
    bool drawn;
} progress_state;

static bool show_progress(void *user, uint64_t done, uint64_t total)
{
    progress_state *ps = user;
    double t = sta_clock_s();
    if (done < total && t - ps->last_s < 0.25) {
        return true;
    }
    ps->last_s = t;
    double elapsed = t - ps->start_s;
    double rate = elapsed > 0.0 ? (double)done / elapsed : 0.0;
    double eta = rate > 0.0 ? (double)(total - done) / rate : 0.0;
    fprintf(stderr, "\r%5.1f%%  %llu / %llu points  %.2f M points/s  ETA %.0f s   ",
            100.0 * (double)done / (double)total, (unsigned long long)done,
            (unsigned long long)total, rate / 1e6, eta);
    ps->drawn = true;
    return true;
}

int main(int argc, char **argv)
{
    cli c;
    memset(&c, 0, sizeof(c));
    int status = parse(argc, argv, &c);
    if (status >= 0) {
        return status;
    }
    progress_state ps = { .start_s = sta_clock_s() };
    bool draw = !c.quiet && sta_log_is_terminal();
    sta_error err = { 0 };
    sta_status s = sta_synth_generate(&c.params, c.output, draw ? show_progress : NULL, &ps, &err);
    if (ps.drawn) {
        fputc('\n', stderr);
    }
    if (s != STA_OK) {
        fprintf(stderr, "strata-synth: %s\n", err.message);
        return 1;
    }
    if (!c.quiet) {
        double elapsed = sta_clock_s() - ps.start_s;
        char *truth = NULL;
        sta_synth_truth_path(c.output, &truth, NULL);
        fprintf(
            stderr,
            "strata-synth: wrote %llu points of '%s' to %s and %s in %.2f s (%.2f M points/s)\n",
            (unsigned long long)c.params.point_count, sta_synth_kind_name(c.params.kind), c.output,
            truth ? truth : "its truth sidecar", elapsed,
            elapsed > 0.0 ? (double)c.params.point_count / elapsed / 1e6 : 0.0);
        sta_free(truth);
    }
    return 0;
}
