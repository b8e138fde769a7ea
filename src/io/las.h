/* SPDX-License-Identifier: MIT
 * LAS 1.0-1.4 reader, point data record formats 0-10.
 * Use it through io/cloud.h; this header is for cloud.c and the LAS tests.
 */
#ifndef STA_IO_LAS_H
#define STA_IO_LAS_H

#include "io/cloud_impl.h"

/* Parses and validates the LAS header, VLRs and EVLRs in `map` (borrowed, outlives
 * the reader). Refuses LAZ with STA_ERR_UNSUPPORTED. */
sta_status sta_las_open_map(const sta_file_map *map, const sta_read_options *options,
                            void **out_impl, const sta_cloud_ops **out_ops, sta_error *err);

/* Bytes of a point record of `point_format` (0..10) without extra bytes; 0 if unknown. */
unsigned sta_las_format_record_size(int point_format);

#endif
