/* SPDX-License-Identifier: MIT
 * CPU twin of the geometry pass's rasterisers (render/pass_geometry.h): the nearest
 * point per pixel, its depth and its id, with the GPU's float arithmetic and pixel rule,
 * so that small cases compare exactly. No GL.
 *
 * The rule (shaders/raster_common.glsl): relative = origin + q * step; clip =
 * projection * (view * (relative, 1)), summed column by column in float; a point is
 * drawn when -w <= x, y <= w and 0 <= z <= w (w > 0); ndc = clip * (1 / w); window =
 * ndc * size / 2 + size / 2 as one fused multiply-add (llvmpipe's viewport transform),
 * snapped to 1 / 2^subpixel_bits pixel (round half up); the
 * point lands in pixel ceil(snapped) - 1 on each axis. The largest reverse-Z depth wins;
 * at equal depth the first point in draw order (nodes in the given order, then points).
 *
 * Wider points (render/point_size.h; sta_raster_ref_footprint): the same clip test on
 * the point's centre and the same snapped window position s (in 1 / 2^bits pixel);
 * the centre pixel c = ceil(s) - 1 as above (it may lie outside the target now); the
 * radius R in pixels, fixed or from the node's spacing (spacing * spacing_to_px / w,
 * clamped to [min, max]); r = (int)(R * 2^bits). The point covers c and every pixel p
 * with |p - c| <= (int)R + 1 per axis, inside the target, whose centre lies within r of
 * s: dx^2 + dy^2 <= r^2 with d = p * 2^bits + 2^(bits-1) - s in integers. Its depth
 * there is a paraboloid towards the camera: depth * (1 / (1 - R * depth_per_px * t)),
 * t = 1 - min(d^2 * (1 / r^2), 1) (t = 0 when r = 0), that is the eye distance made
 * shorter by the radius in metres at the centre and by nothing at the rim.
 *
 * The compute rasteriser's one-pixel rule (`node_rows`; sta_raster_ref_node_rows) is
 * cheaper and differs from GL_POINTS' in the last bits: per node, the product of the
 * viewport, projection, view and the node's dequantisation (relative = origin + q *
 * step) is formed once in double from the float inputs and rounded to three float rows
 * X, Y, W with the viewport and the snapping folded in (X = 2^bits * size / 2 *
 * (clip.x + clip.w) + clip.w / 2), and the clip plane to a fourth; clip.z is one number
 * Z, the projection's (reverse-Z, infinite far: sta_camera_projection; a projection
 * whose clip.z varies with the position is not supported). A point's q (float) gives
 * each row as ((r0 q.x + r1 q.y) + r2 q.z) + r3 in float; it is drawn when its plane
 * value is not negative, w > 0, depth = Z * (1 / W) lies in [0, 1] and sx = X * (1 / W)
 * in [1, 2^bits * width + 1) (sy alike): pixel ((int)sx - 1) >> bits on each axis.
 */
#ifndef STA_RENDER_REF_RASTER_REF_H
#define STA_RENDER_REF_RASTER_REF_H

#include <stddef.h>
#include <stdint.h>

/* How wide a point is; all zero: one pixel. */
typedef struct sta_raster_ref_footprint {
    int wide;                           /* 0: one pixel; 1: the disk described above */
    int adaptive;                       /* radius from the node's spacing, else radius_px */
    float radius_px;                    /* fixed radius, pixels */
    float spacing_to_px;                /* adaptive: radius = spacing * spacing_to_px * (1 / w) */
    float min_radius_px, max_radius_px; /* adaptive clamp */
    float depth_per_px; /* eye-distance offset per pixel of radius, relative: 2 / (height P11) */
} sta_raster_ref_footprint;

/* One drawn node. */
typedef struct sta_raster_ref_node {
    float origin[3];       /* node corner minus camera position, metres */
    float step[3];         /* metres per quantisation step */
    const uint8_t *points; /* count records of 16 bytes (stream/gpu_points.h layout) */
    uint32_t count;
    uint32_t slot; /* node id reported per pixel */
    float spacing; /* metres between the node's points (adaptive footprint) */
} sta_raster_ref_node;

typedef struct sta_raster_ref_view {
    float view[16];       /* column-major, world directions -> camera space */
    float projection[16]; /* column-major, reverse-Z */
    int width_px, height_px;
    int subpixel_bits;   /* the driver's GL_SUBPIXEL_BITS */
    uint8_t hide_flags;  /* points whose flags byte (14) has any of these are not drawn */
    float clip_plane[4]; /* camera-relative; points with a negative distance are not drawn */
    sta_raster_ref_footprint footprint;
    int node_rows; /* 1: one-pixel points by the compute rasteriser's per-node rows */
} sta_raster_ref_view;

/* The compute rasteriser's per-node rows (the rule above). */
typedef struct sta_raster_ref_rows {
    float x[4], y[4], w[4]; /* snapped window x, y (times w), w */
    float plane[4];         /* clip plane distance */
    float z;                /* clip.z: the same for every point (infinite reverse-Z) */
    float unused[3];        /* (the GPU table's vec4) */
} sta_raster_ref_rows;

/* Rasterises the nodes. Outputs per pixel, rows from the bottom (GL order): `depth`
 * (0 where empty) and `ids` (2 per pixel: node slot, point index; 0xFFFFFFFF both
 * where empty). */
void sta_raster_ref_draw(const sta_raster_ref_view *view, const sta_raster_ref_node *nodes,
                         size_t node_count, float *depth, uint32_t *ids);

/* The rows of the node at `origin` with quantisation `step` (the rule above). */
void sta_raster_ref_node_rows(const sta_raster_ref_view *view, const float origin[3],
                              const float step[3], sta_raster_ref_rows *out);

/* Pixel (GL order: x + y * width) and depth of the point at quantised position `q` by
 * the node's rows, or -1 when the point is not drawn (its plane value included). */
long sta_raster_ref_project_rows(const sta_raster_ref_view *view, const sta_raster_ref_rows *rows,
                                 const float q[3], float *out_depth);

/* Pixel (GL order: x + y * width) and depth of one camera-relative position, or -1 when
 * the point is not drawn. */
long sta_raster_ref_project(const sta_raster_ref_view *view, const float relative[3],
                            float *out_depth);

#endif
