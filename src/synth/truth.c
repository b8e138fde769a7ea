/* SPDX-License-Identifier: MIT
 * The truth sidecar: a small JSON file naming everything needed to rebuild the
 * scene's geometry (docs/SYNTH.md gives the schema).
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "core/alloc.h"
#include "core/json_out.h"
#include "synth/synth_internal.h"

#define PI 3.14159265358979323846

/* Shortest decimal that reads back as the same double. */
static void put_number(FILE *f, double v)
{
    char text[40];
    snprintf(text, sizeof(text), "%.15g", v);
    if (strtod(text, NULL) != v) {
        snprintf(text, sizeof(text), "%.17g", v);
    }
    fputs(text, f);
}

static void put_vec(FILE *f, const double *v, int n)
{
    fputc('[', f);
    for (int i = 0; i < n; i++) {
        if (i > 0) {
            fputs(", ", f);
        }
        put_number(f, v[i]);
    }
    fputc(']', f);
}

static void put_string(FILE *f, const char *s)
{
    fputc('"', f);
    for (const unsigned char *c = (const unsigned char *)s; *c; c++) {
        if (*c == '"' || *c == '\\') {
            fprintf(f, "\\%c", *c);
        } else if (*c < 0x20) {
            fprintf(f, "\\u%04x", *c);
        } else {
            fputc(*c, f);
        }
    }
    fputc('"', f);
}

static void put_key_number(FILE *f, const char *indent, const char *key, double v, bool comma)
{
    fprintf(f, "%s\"%s\": ", indent, key);
    put_number(f, v);
    fputs(comma ? ",\n" : "\n", f);
}

static const char *const material_names[STA_SYNTH_MAT_COUNT] = {
    "none",     "road", "marking", "curb",  "sidewalk", "wall", "glass", "door",
    "interior", "pole", "wire",    "trunk", "foliage",  "car",  "tyre",  "surface"
};

static void put_street(FILE *f, const synth_source *src)
{
    const sta_synth_scene *scene = src->scene;
    const street_config *c = &scene->street->cfg;
    const street_scan_config *s = &scene->scan;
    const char *in = "    ";
    fputs("  \"street\": {\n", f);
    fprintf(f, "%s\"generator_version\": %d,\n", in, STA_SYNTH_STREET_VERSION);
    put_key_number(f, in, "block_length_m", STREET_BLOCK_M, true);
    fprintf(f, "%s\"period_blocks\": %d,\n", in, STREET_PERIOD);
    put_key_number(f, in, "heading0_rad", c->heading0_rad, true);
    put_key_number(f, in, "amplitude_rad", c->amplitude_rad, true);
    put_key_number(f, in, "lane_width_m", c->lane_width_m, true);
    put_key_number(f, in, "parking_width_m", c->parking_width_m, true);
    put_key_number(f, in, "road_half_width_m", c->road_half_m, true);
    put_key_number(f, in, "sidewalk_width_m", c->sidewalk_m, true);
    put_key_number(f, in, "curb_height_m", c->curb_height_m, true);
    put_key_number(f, in, "cross_slope", c->cross_slope, true);
    put_key_number(f, in, "sidewalk_z_m", c->sidewalk_z_m, true);
    put_key_number(f, in, "facade_line_m", c->facade_m, true);
    put_key_number(f, in, "ground_extent_m", STREET_GROUND_M, false);
    fputs("  },\n  \"scanner\": {\n", f);
    put_key_number(f, in, "speed_mps", s->speed_mps, true);
    put_key_number(f, in, "profile_hz", s->profile_hz, true);
    fprintf(f, "%s\"rays_per_profile\": %d,\n", in, s->rays_per_profile);
    put_key_number(f, in, "tilt_deg", s->tilt_rad * 180.0 / PI, true);
    put_key_number(f, in, "height_m", s->height_m, true);
    put_key_number(f, in, "lane_u_m", s->lane_u_m, true);
    put_key_number(f, in, "start_s_m", s->start_s_m, true);
    put_key_number(f, in, "min_range_m", s->min_range_m, true);
    put_key_number(f, in, "max_range_m", s->max_range_m, true);
    put_key_number(f, in, "gps_time_start", s->gps_time_start, true);
    put_key_number(f, in, "gps_time_end", src->last_gps_time, true);
    put_key_number(f, in, "nominal_length_m", s->nominal_length_m, true);
    put_key_number(f, in, "end_s_m", src->last_s_m, true);
    put_key_number(f, in, "run_length_m", src->last_s_m - s->start_s_m, true);
    put_key_number(f, in, "raycast_length_m", scene->params.street_length_m, true);
    fprintf(f, "%s\"pulses\": %llu,\n", in, (unsigned long long)src->pulse_count);
    uint64_t rays = (uint64_t)s->rays_per_profile;
    fprintf(f, "%s\"profiles\": %llu,\n", in,
            (unsigned long long)((src->pulse_count + rays - 1u) / rays));
    fprintf(f, "%s\"first_block\": %lld,\n", in, (long long)sta_street_block_of(s->start_s_m));
    fprintf(f, "%s\"last_block\": %lld,\n", in, (long long)sta_street_block_of(src->last_s_m));
    fprintf(f, "%s\"run_id\": 1\n", in);
    fputs("  },\n", f);
}

static void put_rects(FILE *f, const synth_analytic *an, bool comma_after)
{
    for (int i = 0; i < an->rect_count; i++) {
        const synth_rect *r = &an->rects[i];
        double corners[4][3];
        for (int k = 0; k < 3; k++) {
            corners[0][k] = r->corner[k];
            corners[1][k] = r->corner[k] + r->edge_a[k];
            corners[2][k] = r->corner[k] + r->edge_a[k] + r->edge_b[k];
            corners[3][k] = r->corner[k] + r->edge_b[k];
        }
        fprintf(f, "    {\"id\": %d, \"type\": \"rectangle\", \"corners\": [", i);
        for (int c = 0; c < 4; c++) {
            put_vec(f, corners[c], 3);
            fputs(c < 3 ? ", " : "], \"normal\": ", f);
        }
        put_vec(f, r->normal, 3);
        fprintf(f, ", \"point_count\": %llu}%s\n", (unsigned long long)an->counts[i],
                (i + 1 < an->rect_count || comma_after) ? "," : "");
    }
}

// The mesh path as the sidecar stores it: relative to the sidecar's folder (readers
// resolve it from there, whatever their working directory), or as given when either
// path cannot be resolved.
static void sidecar_mesh_path(const char *sidecar, const char *mesh, char *out, size_t size)
{
    snprintf(out, size, "%s", mesh);
    char *dir = sta_malloc(strlen(sidecar) + 2);
    if (!dir) {
        return;
    }
    const char *slash = strrchr(sidecar, '/');
    snprintf(dir, strlen(sidecar) + 2, "%.*s", slash ? (int)(slash - sidecar) + 1 : 1,
             slash ? sidecar : ".");
    char *dir_real = realpath(dir, NULL), *mesh_real = realpath(mesh, NULL);
    sta_free(dir);
    if (dir_real && mesh_real) {
        // d = the sidecar's folder with a trailing '/'; keep the common leading folders,
        // then one "../" per folder of d left over.
        char d[4096];
        snprintf(d, sizeof(d), "%s%s", dir_real, strcmp(dir_real, "/") == 0 ? "" : "/");
        size_t common = 0;
        for (size_t i = 0; d[i] && d[i] == mesh_real[i]; i++) {
            if (d[i] == '/') {
                common = i + 1;
            }
        }
        size_t used = 0;
        out[0] = '\0';
        for (const char *c = d + common; *c; c++) {
            if (*c == '/' && used + 4 < size) {
                used += (size_t)snprintf(out + used, size - used, "../");
            }
        }
        snprintf(out + used, size - used, "%s", mesh_real + common);
    }
    free(dir_real);
    free(mesh_real);
}

static void put_analytic(FILE *f, const sta_synth_scene *scene, const char *sidecar)
{
    const synth_analytic *an = &scene->analytic;
    if (scene->params.kind == STA_SYNTH_MESH) {
        fputs("  \"mesh\": {\n    \"path\": ", f);
        char mesh[4096];
        sidecar_mesh_path(sidecar, scene->params.mesh_path, mesh, sizeof(mesh));
        put_string(f, mesh);
        fputs(",\n    \"transform\": \"local = R (mesh - centre) * scale; R = identity when up "
              "is z, (x, y, z) -> (x, -z, y) when up is y\",\n",
              f);
        fprintf(f, "    \"up\": \"%s\",\n", an->mesh_y_up ? "y" : "z");
        fputs("    \"centre\": ", f);
        put_vec(f, an->mesh_centre, 3);
        fputs(",\n", f);
        put_key_number(f, "    ", "scale", an->mesh_scale, true);
        fprintf(f, "    \"vertex_count\": %zu,\n    \"triangle_count\": %zu,\n",
                an->mesh.vertex_count, an->mesh.triangle_count);
        put_key_number(f, "    ", "area_m2", an->mesh_area_m2, false);
        fputs("  },\n", f);
        return;
    }
    if (scene->params.kind == STA_SYNTH_NESTED) {
        fputs("  \"box\": {\"min\": [-5, -5, -5], \"max\": [5, 5, 5]},\n", f);
    }
    fputs("  \"primitives\": [\n", f);
    put_rects(f, an, an->has_sphere);
    if (an->has_sphere) {
        fprintf(f, "    {\"id\": %u, \"type\": \"sphere\", \"centre\": ", an->sphere_id);
        put_vec(f, an->sphere_centre, 3);
        fputs(", \"radius_m\": ", f);
        put_number(f, an->sphere_radius_m);
        fprintf(f, ", \"point_count\": %llu}\n", (unsigned long long)an->counts[an->rect_count]);
    }
    fputs("  ],\n", f);
}

/* The mirror scene: stations, ghost labels and counts, the mirrors in world
 * coordinates as the mirror file holds them. */
static void put_room(FILE *f, const synth_source *src, const char *sidecar)
{
    const synth_room *room = src->scene->room;
    const sta_synth_georef *g = src->georef;
    fputs("  \"mirror\": {\n    \"stations_local\": [", f);
    for (int i = 0; i < ROOM_STATIONS; i++) {
        fputs(i ? ", " : "", f);
        put_vec(f, room->stations[i], 3);
    }
    fprintf(f, "],\n    \"rays_per_station\": %llu,\n", (unsigned long long)room->rays_per_station);
    put_key_number(f, "    ", "ray_period_s", ROOM_RAY_PERIOD_S, true);
    put_key_number(f, "    ", "gps_time_start", ROOM_GPS_START, true);
    fprintf(f, "    \"pulses\": %llu,\n    \"max_bounces\": %d,\n",
            (unsigned long long)src->room_ray, ROOM_MAX_BOUNCES);
    fputs("    \"ghost_label\": \"user_data: 0 real point, k > 0 ghost seen through mirror k-1 "
          "(the first on its path)\",\n",
          f);
    fprintf(f, "    \"real_count\": %llu,\n    \"ghost_counts\": [",
            (unsigned long long)room->ghost_counts[0]);
    for (size_t k = 0; k < room->mirrors.count; k++) {
        fprintf(f, "%s%llu", k ? ", " : "", (unsigned long long)room->ghost_counts[k + 1]);
    }
    (void)sidecar;
    fputs("],\n    \"mirrors\": ", f);
    sta_mirror_set world = { 0 };
    if (sta_mirror_set_translated(&room->mirrors, g->origin, &world, NULL) == STA_OK) {
        sta_json_out json;
        sta_json_init(&json, f, false);
        sta_mirror_set_write_json(&json, &world);
    } else {
        fputs("null", f);
    }
    sta_mirror_set_release(&world);
    fputs("\n  },\n", f);
}

static void put_classes(FILE *f, bool street, bool legacy)
{
    fputs("  \"classes\": {", f);
    if (!street) {
        fputs("\"1\": \"surface\"},\n", f);
        return;
    }
    if (legacy) {
        fputs("\"1\": \"pole, wire, car\", \"2\": \"road, curb, sidewalk\", \"5\": \"tree\", "
              "\"6\": \"building\"},\n",
              f);
    } else {
        fputs("\"2\": \"curb, sidewalk\", \"5\": \"tree\", \"6\": \"building\", \"11\": \"road\", "
              "\"14\": \"wire\", \"15\": \"pole\", \"64\": \"car\"},\n",
              f);
    }
    fputs("  \"user_data\": {", f);
    for (int m = 1; m < STA_SYNTH_MAT_COUNT; m++) {
        fprintf(f, "\"%d\": \"%s\"%s", m, material_names[m],
                m + 1 < STA_SYNTH_MAT_COUNT ? ", " : "");
    }
    fputs("},\n", f);
}

static void put_document(FILE *f, const synth_source *src, const char *sidecar)
{
    const sta_synth_scene *scene = src->scene;
    const sta_synth_params *p = &scene->params;
    const sta_synth_georef *g = src->georef;
    bool street = p->kind == STA_SYNTH_STREET;
    static const char *const origin_names[] = { "utm", "zero", "ecef" };
    fputs("{\n  \"format\": \"strata-synth-truth\",\n  \"format_version\": 1,\n", f);
    fprintf(f, "  \"scene\": \"%s\",\n", sta_synth_kind_name(p->kind));
    fprintf(f, "  \"seed\": %llu,\n", (unsigned long long)p->seed);
    fprintf(f, "  \"point_count\": %llu,\n", (unsigned long long)p->point_count);
    fprintf(f, "  \"las\": {\"version\": \"1.%d\", \"point_format\": %d},\n",
            p->point_format == 3 ? 2 : 4, p->point_format);
    put_key_number(f, "  ", "noise_sigma_m", scene->noise_m, true);
    fprintf(f, "  \"georef\": {\n    \"origin_kind\": \"%s\",\n    \"crs\": \"%s\",\n",
            origin_names[p->origin], g->crs);
    fputs("    \"origin\": ", f);
    put_vec(f, g->origin, 3);
    fputs(",\n    \"scale\": ", f);
    put_vec(f, g->grid.scale, 3);
    fputs(",\n    \"offset\": ", f);
    put_vec(f, g->grid.offset, 3);
    fprintf(f, ",\n    \"origin_steps\": [%lld, %lld, %lld],\n", (long long)g->origin_steps[0],
            (long long)g->origin_steps[1], (long long)g->origin_steps[2]);
    fputs(
        "    \"rule\": \"X = round(local_x / scale) + origin_steps; real = X * scale + offset\",\n",
        f);
    fprintf(f, "    \"axes\": \"%s\"\n  },\n",
            p->origin == STA_SYNTH_ORIGIN_ECEF ? "local axes parallel to ECEF X, Y, Z"
                                               : "x east, y north, z up");
    if (scene->room) {
        fputs("  \"classes\": {\"1\": \"furniture, mirror back\", \"2\": \"floor\", "
              "\"6\": \"walls, ceiling\"},\n",
              f);
    } else {
        put_classes(f, street, p->point_format == 3);
    }
    if (street) {
        put_street(f, src);
    } else if (scene->room) {
        put_room(f, src, sidecar);
    } else {
        put_analytic(f, scene, sidecar);
    }
    fputs("  \"normals\": \"", f);
    fputs(street || scene->room
              ? "from sta_synth_scene_raycast (hit.normal)"
              : "analytic: sphere (p - centre) / radius, rectangle normal, mesh triangle "
                "winding; colour of each point encodes it as rgb = (n + 1) / 2",
          f);
    fputs("\"\n}\n", f);
}

sta_status sta_synth_truth_write(const char *path, const synth_source *src, sta_error *err)
{
    size_t size = strlen(path) + 32;
    char *tmp = sta_malloc(size);
    if (!tmp) {
        return sta_fail(err, STA_ERR_NOMEM, "%s: out of memory", path);
    }
    snprintf(tmp, size, "%s.tmp-%ld", path, (long)getpid());
    sta_status status = STA_OK;
    FILE *f = fopen(tmp, "w");
    if (!f) {
        status = sta_fail(err, STA_ERR_IO, "%s: cannot create %s: %s", path, tmp, strerror(errno));
        goto out_free;
    }
    put_document(f, src, path);
    bool failed = ferror(f) != 0;
    if (fclose(f) != 0 || failed) {
        status = sta_fail(err, STA_ERR_IO, "%s: write failed: %s", path, strerror(errno));
        remove(tmp);
        goto out_free;
    }
    if (rename(tmp, path) != 0) {
        status =
            sta_fail(err, STA_ERR_IO, "%s: cannot rename %s to it: %s", path, tmp, strerror(errno));
        remove(tmp);
    }
out_free:
    sta_free(tmp);
    return status;
}
