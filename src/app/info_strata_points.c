/* SPDX-License-Identifier: MIT
 * Points of a .strata file as CSV, in file order. */
#include "app/info_strata_points.h"

#include "app/info_print.h"
#include "format/strata_reader.h"

sta_status sta_info_strata_points(FILE *out, const char *path, uint64_t start, uint64_t count,
                                  sta_error *err)
{
    sta_strata_reader *reader = NULL;
    sta_strata_decoder *decoder = NULL;
    sta_status status = sta_strata_open(path, NULL, &reader, err);
    if (status == STA_OK) {
        status = sta_strata_decoder_create(&decoder, err);
    }
    if (status != STA_OK) {
        sta_strata_close(reader);
        return status;
    }
    const sta_strata_info *info = sta_strata_reader_info(reader);
    const uint32_t attributes = sta_strata_attributes_to_sta_attr(info->layout.attributes);
    sta_info_print_points_header(out, attributes);
    uint64_t first = 0; // file index of the current node's first point
    for (uint32_t n = 0; n < info->node_count && count > 0 && status == STA_OK; n++) {
        const sta_strata_node *node = sta_strata_reader_node(reader, n);
        if (first + node->point_count <= start) {
            first += node->point_count;
            continue;
        }
        sta_strata_points points;
        status = sta_strata_decode_node(reader, n, decoder, &points, err);
        for (size_t i = start > first ? (size_t)(start - first) : 0;
             status == STA_OK && i < points.count && count > 0; i++, count--) {
            sta_info_print_point_row(out, &info->geometry.grid, attributes, &points.points[i]);
        }
        first += node->point_count;
    }
    sta_strata_decoder_destroy(decoder);
    sta_strata_close(reader);
    return status;
}
