/* SPDX-License-Identifier: MIT
 * Wavefront OBJ meshes, for mesh sampling (strata-synth mesh): vertex positions and
 * faces. The converter does not read OBJ (its point inputs are LAS and PLY).
 */
#ifndef STA_IO_OBJ_H
#define STA_IO_OBJ_H

#include <stddef.h>
#include <stdint.h>

#include "io/ply.h"

/* Loads the vertices (`v x y z`, a fourth w or r g b ignored) and faces (`f` with
 * `i`, `i/t`, `i//n` or `i/t/n` references, 1-based, negative counting back from the
 * last vertex read) of `size` bytes the caller owns (fuzzing, tests); `name` is used
 * in messages. A polygon of n >= 3 vertices gives n - 2 triangles (a fan from its
 * first vertex), as the PLY loader does; a face of fewer gives none. Every other
 * statement (normals, texture coordinates, groups, materials, lines) is skipped.
 * Errors name the file and the line: a coordinate that is missing, not a number or not
 * finite; a vertex reference of 0, not a number, or outside the vertices (positive
 * references are checked against all of the file's vertices, so a face may come
 * before them); a line continued with a backslash (not supported). Counts are bounded
 * by the bytes, so a huge file fails on memory, not on overflow. On failure *out_mesh
 * is left zeroed. */
sta_status sta_obj_load_mesh_memory(const uint8_t *data, size_t size, const char *name,
                                    sta_mesh *out_mesh, sta_error *err);

/* A mesh from `path` (mapped) by its content: PLY when it starts with "ply", otherwise OBJ when
 * its first statement is one (v, vn, vt, f, o, g, s, usemtl, mtllib or a comment);
 * anything else is STA_ERR_FORMAT naming the file ("neither a PLY nor an OBJ mesh"). */
sta_status sta_mesh_load(const char *path, sta_mesh *out_mesh, sta_error *err);

#endif
