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

sta_status sta_ply_open_map(const sta_file_map *map, const sta_read_options *options,
                            void **out_impl, const sta_cloud_ops **out_ops, sta_error *err);

#endif
