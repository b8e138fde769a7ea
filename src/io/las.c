/* SPDX-License-Identifier: MIT
 * Placeholder: replaced by the real reader. */
#include "io/las.h"

sta_status sta_las_open_map(const sta_file_map *map, const sta_read_options *options,
                            void **out_impl, const sta_cloud_ops **out_ops, sta_error *err)
{
    (void)options;
    *out_impl = NULL;
    *out_ops = NULL;
    return sta_fail(err, STA_ERR_UNSUPPORTED, "%s: reader not written yet", map->path);
}
unsigned sta_las_format_record_size(int point_format) { (void)point_format; return 0; }
