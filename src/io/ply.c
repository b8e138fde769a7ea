/* SPDX-License-Identifier: MIT
 * Placeholder: replaced by the real reader. */
#include "io/ply.h"

sta_status sta_ply_open_map(const sta_file_map *map, const sta_read_options *options,
                            void **out_impl, const sta_cloud_ops **out_ops, sta_error *err)
{
    (void)options;
    *out_impl = NULL;
    *out_ops = NULL;
    return sta_fail(err, STA_ERR_UNSUPPORTED, "%s: reader not written yet", map->path);
}
