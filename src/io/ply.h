/* SPDX-License-Identifier: MIT
 * PLY reader: ASCII and binary (little and big endian); vertices become points.
 * Use it through io/cloud.h; this header is for cloud.c and the PLY tests.
 *
 * PLY stores float or double coordinates, not integers. The reader scans the vertex
 * bounds once and chooses a grid (offset = bounds centre, scale = extent / 2^30 rounded
 * down to a power of two) finer than the input's own precision, so every coordinate is
 * kept to well below float resolution.
 */
#ifndef STA_IO_PLY_H
#define STA_IO_PLY_H

#include "io/cloud_impl.h"

/* A triangle mesh from a PLY file: vertex positions and faces (polygons are fanned
 * into triangles). Zero-initialise; release with sta_mesh_release. */
typedef struct sta_mesh {
    double *positions; /* 3 doubles per vertex (x, y, z as stored) */
    size_t vertex_count;
    uint32_t *triangles; /* 3 vertex indices per triangle, each < vertex_count */
    size_t triangle_count;
} sta_mesh;

/* Loads vertices and faces of `path` (ASCII or binary PLY) for mesh sampling.
 * A file without faces gives triangle_count 0. Bad indices are an error. */
sta_status sta_ply_load_mesh(const char *path, sta_mesh *out_mesh, sta_error *err);

/* As sta_ply_load_mesh, over `size` bytes the caller owns (fuzzing, tests); `name` is
 * used in messages. The faces are the list property "vertex_indices" (or
 * "vertex_index") of element "face"; a polygon of n >= 3 vertices gives n - 2
 * triangles (a fan from its first vertex), a face of fewer than 3 gives none. Every
 * index must be < vertex_count; coordinates must be finite. On failure *out_mesh is
 * left zeroed. */
sta_status sta_ply_load_mesh_memory(const uint8_t *data, size_t size, const char *name,
                                    sta_mesh *out_mesh, sta_error *err);

/* Frees a mesh; a zeroed one is a no-op. */
void sta_mesh_release(sta_mesh *mesh);

sta_status sta_ply_open_map(const sta_file_map *map, const sta_read_options *options,
                            void **out_impl, const sta_cloud_ops **out_ops, sta_error *err);

#endif
