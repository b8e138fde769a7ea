/* SPDX-License-Identifier: MIT
 * The street's mobile-mapping scanner: a profiler on a vehicle that drives the
 * centreline's right lane, casting pulses through the scene's own ray caster.
 *
 * Each pulse may give several returns: leaves and wires are partial targets (the
 * pulse goes on behind them with part of its energy) and window glass returns a pulse
 * only now and then, so the rooms behind show through. Pulse times rise strictly;
 * returns of one pulse share its time.
 */
#include <math.h>
#include <string.h>

#include "core/alloc.h"
#include "synth/synth_internal.h"

#define PI          3.14159265358979323846
#define MAX_RETURNS 5
#define GOLDEN      0.6180339887498949

/* Share of pulses expected to hit something (the sky takes the rest); used only to
 * aim the run length, the point count is exact anyway. */
#define HIT_SHARE 0.6

void sta_street_scan_config_init(street_scan_config *scan, const street_config *cfg,
                                 uint64_t point_count)
{
    memset(scan, 0, sizeof(*scan));
    scan->speed_mps = 10.0;
    scan->profile_hz = 200.0;
    scan->tilt_rad = 10.0 * PI / 180.0;
    scan->height_m = 2.5;
    scan->lane_u_m = -0.5 * cfg->lane_width_m;
    scan->start_s_m = 5.0;
    scan->gps_time_start = 388102418.0; // 2024-01-01T00:00:00Z, adjusted standard GPS time
    scan->min_range_m = 0.5;
    scan->max_range_m = 120.0;
    // At full resolution (3600 pulses per profile, 5 cm apart) about 40 000 points fall
    // on each metre of run; fewer points keep at least 100 m and thin the profiles.
    double n = (double)point_count;
    scan->nominal_length_m = fmax(100.0, n / 40000.0);
    double per_profile = n * (scan->speed_mps / scan->profile_hz) / scan->nominal_length_m;
    double rays = fmin(fmax(round(per_profile / HIT_SHARE), 90.0), 3600.0);
    scan->rays_per_profile = (int)rays;
}

sta_status sta_street_source_init(synth_source *src, sta_error *err)
{
    int m = src->scene->scan.rays_per_profile;
    src->ray_cos = sta_alloc_array((size_t)m, sizeof(double));
    src->ray_sin = sta_alloc_array((size_t)m, sizeof(double));
    if (!src->ray_cos || !src->ray_sin) {
        return sta_fail(err, STA_ERR_NOMEM, "out of memory for %d scanner rays", m);
    }
    for (int i = 0; i < m; i++) {
        double angle = 2.0 * PI * (double)i / (double)m;
        src->ray_cos[i] = cos(angle);
        src->ray_sin[i] = sin(angle);
    }
    src->inv_rays = 1.0 / (double)m;
    src->inv_profile_hz = 1.0 / src->scene->scan.profile_hz;
    src->tilt_cos = cos(src->scene->scan.tilt_rad);
    src->tilt_sin = sin(src->scene->scan.tilt_rad);
    return STA_OK;
}

/* Reflectance (0..1) and base colour (8-bit) per material. */
typedef struct look {
    double reflectance;
    double rgb[3];
} look;

static const look looks[STA_SYNTH_MAT_COUNT] = {
    [STA_SYNTH_MAT_NONE] = { 0.3, { 128, 128, 128 } },
    [STA_SYNTH_MAT_ROAD] = { 0.15, { 70, 70, 74 } },
    [STA_SYNTH_MAT_MARKING] = { 0.75, { 235, 235, 230 } },
    [STA_SYNTH_MAT_CURB] = { 0.4, { 150, 150, 145 } },
    [STA_SYNTH_MAT_SIDEWALK] = { 0.35, { 175, 170, 160 } },
    [STA_SYNTH_MAT_WALL] = { 0.5, { 200, 190, 170 } },
    [STA_SYNTH_MAT_GLASS] = { 0.06, { 60, 80, 95 } },
    [STA_SYNTH_MAT_DOOR] = { 0.3, { 110, 70, 40 } },
    [STA_SYNTH_MAT_INTERIOR] = { 0.45, { 225, 215, 195 } },
    [STA_SYNTH_MAT_POLE] = { 0.4, { 95, 100, 100 } },
    [STA_SYNTH_MAT_WIRE] = { 0.2, { 40, 40, 40 } },
    [STA_SYNTH_MAT_TRUNK] = { 0.3, { 95, 70, 50 } },
    [STA_SYNTH_MAT_FOLIAGE] = { 0.45, { 70, 125, 50 } },
    [STA_SYNTH_MAT_CAR] = { 0.55, { 150, 150, 150 } },
    [STA_SYNTH_MAT_TYRE] = { 0.1, { 30, 30, 30 } },
    [STA_SYNTH_MAT_SURFACE] = { 0.5, { 180, 180, 180 } },
};

/* Facade and car colours, chosen per object. */
static const double facade_palette[6][3] = { { 225, 205, 170 }, { 200, 200, 195 },
                                             { 215, 170, 140 }, { 180, 195, 205 },
                                             { 235, 225, 200 }, { 170, 120, 100 } };
static const double car_palette[6][3] = { { 190, 30, 30 }, { 30, 60, 150 },   { 220, 220, 220 },
                                          { 25, 25, 30 },  { 120, 125, 130 }, { 40, 110, 60 } };

/* Objects: block, kind and side bits of the id, without the part index. */
static uint64_t object_of(uint64_t id, unsigned material)
{
    if (material == STA_SYNTH_MAT_CAR || material == STA_SYNTH_MAT_TYRE) {
        return id & ~(uint64_t)7; // the car, not its part
    }
    return id;
}

static uint16_t channel16(double value)
{
    double v = value < 0.0 ? 0.0 : (value > 255.0 ? 255.0 : value);
    return (uint16_t)((unsigned)(v + 0.5) * 257u);
}

static void colour_of(const sta_synth_hit *h, sta_rng *rng, sta_point *p)
{
    const double *base = looks[h->material].rgb;
    uint64_t key = sta_hash2(object_of(h->primitive_id, h->material), 0xC0105u);
    if (h->material == STA_SYNTH_MAT_WALL) {
        base = facade_palette[key % 6];
    } else if (h->material == STA_SYNTH_MAT_CAR) {
        base = car_palette[key % 6];
    }
    // Per object tint (+-10 %), per point grain (+-4 %).
    double tint = 0.9 + 0.2 * (double)((key >> 16) & 0xFFFF) / 65535.0;
    double grain = 1.0 + 0.04 * (2.0 * sta_rng_uniform(rng) - 1.0);
    p->red = channel16(base[0] * tint * grain);
    p->green = channel16(base[1] * tint * grain);
    p->blue = channel16(base[2] * tint * grain);
}

static uint8_t legacy_class(uint8_t c)
{
    switch (c) {
    case 11:
        return 2; // road surface -> ground
    case 2:
    case 5:
    case 6:
        return c;
    default:
        return 1; // wire, pole, vehicle -> unclassified
    }
}

/* Writes return `index` of the last pulse as point *p. */
static void emit_return(synth_source *src, int index, sta_point *p)
{
    const street_pulse *pl = &src->pulse;
    const sta_synth_hit *h = &src->returns[index].hit;
    double range = h->t + src->scene->noise_m * sta_rng_gauss(&src->rng);
    double cos_i =
        fabs(h->normal[0] * pl->d[0] + h->normal[1] * pl->d[1] + h->normal[2] * pl->d[2]);
    double falloff = 1.0 / (1.0 + (h->t / 40.0) * (h->t / 40.0));
    double level =
        looks[h->material].reflectance * (0.2 + 0.8 * cos_i) * falloff * src->returns[index].energy;
    // Speckle: triangular noise of 5 % standard deviation (cheaper than a Gaussian).
    level *= 1.0 + 0.1225 * (sta_rng_uniform(&src->rng) + sta_rng_uniform(&src->rng) - 1.0);
    level = level < 0.0 ? 0.0 : (level > 1.0 ? 1.0 : level);
    *p = (sta_point){
        .X = sta_synth_georef_step(src->georef, 0, pl->o[0] + range * pl->d[0]),
        .Y = sta_synth_georef_step(src->georef, 1, pl->o[1] + range * pl->d[1]),
        .Z = sta_synth_georef_step(src->georef, 2, pl->o[2] + range * pl->d[2]),
        .intensity = (uint16_t)(level * 65000.0 + 1.5),
        .return_number = (uint8_t)(index + 1),
        .number_of_returns = (uint8_t)src->return_count,
        .classification = src->legacy_classes ? legacy_class(h->classification) : h->classification,
        .user_data = h->material,
        .scan_angle = pl->scan_angle,
        .scan_direction_flag = 1,
        .point_source_id = 1,
        .gps_time = pl->gps_time,
    };
    colour_of(h, &src->rng, p);
}

static void add_return(synth_source *src, const sta_synth_hit *h, double energy)
{
    street_return *r = &src->returns[src->return_count++];
    r->hit = *h;
    r->energy = energy;
}

/* Casts the last pulse and keeps its returns (0..MAX_RETURNS). */
static void cast_pulse(synth_source *src)
{
    sta_synth_scene *scene = src->scene;
    const street_scan_config *scan = &scene->scan;
    const street_pulse *pl = &src->pulse;
    double t_lo = scan->min_range_m, energy = 1.0;
    unsigned flags = STA_SYNTH_RAY_GLASS;
    src->return_count = 0;
    src->return_next = 0;
    while (src->return_count < MAX_RETURNS) {
        sta_synth_hit h;
        if (!sta_street_trace_walk(scene->street, pl->block, pl->o, pl->d, t_lo, scan->max_range_m,
                                   flags, &h)) {
            break;
        }
        if (h.material == STA_SYNTH_MAT_GLASS) {
            // Glass answers one pulse in eight; the rest go on into the room.
            if (sta_rng_uniform(&src->rng) < 0.125) {
                add_return(src, &h, energy);
            }
            energy *= 0.85;
            flags = 0; // trace again from t_lo: glass is now transparent
            continue;
        }
        add_return(src, &h, energy);
        double go_on = h.material == STA_SYNTH_MAT_FOLIAGE ? 0.55
                       : h.material == STA_SYNTH_MAT_WIRE  ? 0.85
                                                           : 0.0;
        if (sta_rng_uniform(&src->rng) >= go_on) {
            break;
        }
        energy *= h.material == STA_SYNTH_MAT_FOLIAGE ? 0.5 : 0.8;
        t_lo = h.t + 0.3; // returns closer than 0.3 m merge in a real receiver
    }
}

/* Sets up the next pulse and advances the profile/ray counters. */
static void next_pulse(synth_source *src)
{
    street_pulse *pl = &src->pulse;
    const sta_synth_scene *scene = src->scene;
    const street_scan_config *scan = &scene->scan;
    const street_config *cfg = &scene->street->cfg;
    const int m = scan->rays_per_profile;
    if (src->ray == 0) {
        // Each profile starts at a different fraction of the angular step (golden
        // ratio), so successive profiles do not sample the same angles.
        src->phase = (double)src->profile * GOLDEN;
        src->phase -= floor(src->phase);
        src->phase_cos = cos(2.0 * PI * src->phase / (double)m);
        src->phase_sin = sin(2.0 * PI * src->phase / (double)m);
    }
    double fraction = ((double)src->ray + src->phase) * src->inv_rays; // of a revolution
    double tau = ((double)src->profile + fraction) * src->inv_profile_hz;
    pl->gps_time = scan->gps_time_start + tau;
    double s = scan->start_s_m + scan->speed_mps * tau;
    pl->block = sta_street_block_of(s);
    if (!src->has_frame || src->frame_block != pl->block) {
        src->frame = *sta_street_cached_frame(scene->street, pl->block);
        src->frame_block = pl->block;
        src->has_frame = true;
    }
    const street_frame *f = &src->frame;
    double s_local = s - (double)pl->block * STREET_BLOCK_M;
    double u = scan->lane_u_m;
    pl->o[0] = f->origin[0] + s_local * f->cos_h - u * f->sin_h;
    pl->o[1] = f->origin[1] + s_local * f->sin_h + u * f->cos_h;
    pl->o[2] = -cfg->cross_slope * fabs(u) + scan->height_m;
    // Angle from nadir: table angle rotated by the profile's phase.
    double pc = src->phase_cos, ps = src->phase_sin;
    double c = src->ray_cos[src->ray] * pc - src->ray_sin[src->ray] * ps;
    double sn = src->ray_sin[src->ray] * pc + src->ray_cos[src->ray] * ps;
    // Profile plane (0, sin, -cos) in (s, u, w), leaning forward by the tilt.
    double ds = -c * src->tilt_sin, du = sn, dw = -c * src->tilt_cos;
    pl->d[0] = ds * f->cos_h - du * f->sin_h;
    pl->d[1] = ds * f->sin_h + du * f->cos_h;
    pl->d[2] = dw;
    double degrees = fraction * 360.0;
    if (degrees >= 180.0) {
        degrees -= 360.0;
    }
    double units = fmin(fmax(round(degrees / 0.006), -30000.0), 30000.0);
    pl->scan_angle = (int16_t)units;
    src->last_s_m = s;
    src->last_gps_time = pl->gps_time;
    src->pulse_count++;
    if (++src->ray == m) {
        src->ray = 0;
        src->profile++;
    }
}

void sta_street_source_fill(synth_source *src, sta_point *out, size_t count)
{
    size_t done = 0;
    while (done < count) {
        if (src->return_next < src->return_count) {
            emit_return(src, src->return_next++, &out[done++]);
            continue;
        }
        next_pulse(src);
        cast_pulse(src);
    }
    src->emitted += count;
}
