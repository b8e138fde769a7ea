/* SPDX-License-Identifier: MIT
 * Internal: the procedural street behind the "street" scene.
 *
 * Design: the street centreline is a chain of straight 40 m blocks whose heading
 * follows h(b) = heading0 + amplitude * sin(2 pi b / 24); one period (24 blocks) is
 * tabulated at creation and repeated with a shift, so any block's frame is a pure
 * function of (seed, b). Blocks meet at mitre planes (bisectors of the two
 * headings), which partition the ground exactly; everything that is constant across
 * the street (road, curb, sidewalk, facade line) is therefore continuous over the
 * joints. Block contents (buildings, poles, wires, trees, cars) come from streams
 * seeded with (seed, block, side) and stay inside their block, except the wires
 * that run from pole to pole, which each neighbouring block carries in its own frame.
 *
 * Block frame: s along the street (0..40 m), u to the left, w up; the road's crown
 * line is u = 0, w = 0. Side content is stored "canonically" with v = sigma * u
 * (sigma +1 left, -1 right) so one code path serves both sides.
 *
 * A sta_street caches 32 block contents and 64 frames (direct-mapped by index); it is
 * not thread-safe.
 */
#ifndef STA_SYNTH_STREET_H
#define STA_SYNTH_STREET_H

#include <stdbool.h>
#include <stdint.h>

#include "core/status.h"
#include "synth/synth.h"

#define STREET_BLOCK_M       40.0 /* block length along the centreline */
#define STREET_PERIOD        24   /* blocks per heading period */
#define STREET_GROUND_M      60.0 /* ground extends this far from the centreline */
#define STREET_MAX_BUILDINGS 4    /* per side and block */
#define STREET_MAX_TREES     2    /* per side and block */
#define STREET_MAX_CARS      4    /* per side and block */
#define STREET_MAX_CLUSTERS  110  /* leaf clusters per crown */
#define STREET_CLUSTER_MAX_R 0.4  /* largest leaf cluster radius */
#define STREET_WIRE_SEGMENTS 10   /* straight pieces of one catenary */
#define STREET_BINS          40   /* 1 m bins along s for culling */
#define STREET_CACHE_BLOCKS  32   /* cached block contents */
#define STREET_CACHE_FRAMES  64   /* cached block frames */

/* Street-wide values drawn from the seed (generator version 1). */
typedef struct street_config {
    uint64_t seed;
    double heading0_rad;                 /* mean direction of the street, from east */
    double amplitude_rad;                /* heading swing over one period */
    double lane_width_m;                 /* one driving lane */
    double parking_width_m;              /* parking lane beside the curb */
    double road_half_m;                  /* crown line to curb face: lane + parking */
    double sidewalk_m;                   /* curb face to the nominal facade line */
    double curb_height_m;                /* step from road edge to sidewalk */
    double cross_slope;                  /* road fall per metre from the crown (tent) */
    double sidewalk_z_m;                 /* sidewalk height (w) */
    double facade_m;                     /* nominal facade line, v */
    double centre[STREET_PERIOD + 1][2]; /* block start points over one period */
    double heading[STREET_PERIOD];       /* block headings over one period */
} street_config;

/* A block's placement: local xy = origin + s * (c, s_) + u * (-s_, c). */
typedef struct street_frame {
    double origin[2];     /* start of the block on the centreline */
    double cos_h;         /* cos(heading) */
    double sin_h;         /* sin(heading) */
    double start_n[2];    /* world normal of the start mitre plane (points forward) */
    double end_n[2];      /* world normal of the end mitre plane (points forward) */
    double end_origin[2]; /* start of the next block */
} street_frame;

typedef struct street_box {
    double lo[3], hi[3]; /* (s, v, w) canonical or (s, u, w) block coordinates */
} street_box;

typedef struct street_building {
    street_box box;                    /* s0..s1, facade v0..v0 + depth, sidewalk..roof */
    double floor_m;                    /* storey height */
    int floors;                        /* storeys with openings */
    int columns;                       /* window columns */
    double column_first;               /* s of the first column's start */
    double pitch_m;                    /* column spacing */
    double window_w, window_h, sill_m; /* upper-floor windows */
    double recess_m;                   /* depth of the openings */
    int door_column;                   /* ground-floor column holding the door */
    bool shop;                         /* ground floor has shop windows */
    uint16_t index;                    /* within the side (for ids and colour) */
} street_building;

typedef struct street_tree {
    double s, v;               /* trunk axis */
    double trunk_r;            /* trunk radius */
    double centre[3];          /* crown centre (s, v, w) */
    double radius_h, radius_v; /* crown semi-axes */
    street_box bounds;         /* of the clusters and the trunk */
    int cluster_count;
    double clusters[STREET_MAX_CLUSTERS][4]; /* s, v, w, radius; sorted by s */
} street_tree;

typedef struct street_car {
    street_box bounds;   /* whole car */
    street_box parts[6]; /* body, cabin, 4 wheels */
} street_car;

typedef struct street_wire {
    double points[STREET_WIRE_SEGMENTS + 1][3]; /* block coordinates (s, u, w) */
    street_box bounds;                          /* inflated by the radius */
    double radius_m;
    uint64_t id; /* primitive id (owner block's) */
} street_wire;

typedef struct street_side {
    street_building buildings[STREET_MAX_BUILDINGS];
    int building_count;
    street_tree trees[STREET_MAX_TREES];
    int tree_count;
    street_car cars[STREET_MAX_CARS];
    int car_count;
    double pole_s, pole_v, pole_r, pole_top; /* one pole per side */
    double v_min;                            /* no side content below this v */
    uint16_t bins[STREET_BINS]; /* objects overlapping each 1 m of s: bits 0-3 buildings,
                                   4-5 trees, 6-9 cars, 10 pole */
} street_side;

typedef struct street_block {
    int64_t index; /* block number; valid only when `valid` */
    bool valid;
    street_frame frame;
    street_side sides[2]; /* [0] left (sigma +1), [1] right (sigma -1) */
    street_wire wires[5]; /* cross span, left/right to next pole, left/right from previous */
    int wire_count;
    uint8_t wire_bins[STREET_BINS]; /* wires overlapping each 1 m of s (bit = wire) */
    double top_m;                   /* nothing of the block lies above this w */
} street_block;

typedef struct street_frame_slot {
    int64_t index; /* block number; valid only when `valid` */
    bool valid;
    street_frame frame;
} street_frame_slot;

typedef struct sta_street {
    street_config cfg;
    int64_t first_block, last_block;               /* blocks the public ray cast covers */
    street_block cache[STREET_CACHE_BLOCKS];       /* direct-mapped by index */
    street_frame_slot frames[STREET_CACHE_FRAMES]; /* direct-mapped by index */
} sta_street;

/* Draws the street-wide values of version 1 from `seed`. */
void sta_street_config_init(street_config *cfg, uint64_t seed);

/* The frame of block `b` (pure function of cfg and b). */
void sta_street_frame(const street_config *cfg, int64_t b, street_frame *out_frame);

/* Creates a street whose public ray cast covers [-1, length_m + 40] along the run. */
sta_status sta_street_create(uint64_t seed, double length_m, sta_street **out_street,
                             sta_error *err);

void sta_street_destroy(sta_street *street);

/* Block `b`, generated on first use and cached (the pointer is valid until the next
 * call that may generate another block). */
const street_block *sta_street_block(sta_street *street, int64_t b);

/* The frame of block `b` through the frame cache (valid until the next call). */
const street_frame *sta_street_cached_frame(sta_street *street, int64_t b);

/* Start point of block b on the centreline, without trigonometry. */
void sta_street_block_start(const street_config *cfg, int64_t b, double out_xy[2]);

/* Nearest hit for t in (t_lo, t_hi) among blocks b_lo..b_hi; ray in local coordinates
 * (unit dir). */
bool sta_street_trace(sta_street *street, int64_t b_lo, int64_t b_hi, const double origin[3],
                      const double dir[3], double t_lo, double t_hi, unsigned flags,
                      sta_synth_hit *hit);

/* As sta_street_trace, following the ray from block to block starting near block
 * b_hint (the scanner's path): visits only the blocks the ray crosses. */
bool sta_street_trace_walk(sta_street *street, int64_t b_hint, const double origin[3],
                           const double dir[3], double t_lo, double t_hi, unsigned flags,
                           sta_synth_hit *hit);

/* Block of run position s (arc length along the centreline). */
int64_t sta_street_block_of(double s_m);

/* Local position of centreline arc length s_m offset by u_m (left) and at height w_m. */
void sta_street_point(const street_config *cfg, double s_m, double u_m, double w_m,
                      double out_xyz[3]);

/* LAS 1.4 class of a street material. */
uint8_t sta_street_class(sta_synth_material material);

#endif
