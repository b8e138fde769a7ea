/* SPDX-License-Identifier: MIT
 * Small JSON files. */
#include "render/json_file.h"

#include "core/file_map.h"

sta_status sta_json_file_load(const char *path, cJSON **out_root, sta_error *err)
{
    *out_root = NULL;
    sta_file_map map = { 0 };
    sta_status status = sta_file_map_open(path, &map, err);
    if (status != STA_OK) {
        return status;
    }
    *out_root = cJSON_ParseWithLength((const char *)map.data, map.size);
    sta_file_map_close(&map);
    if (!*out_root) {
        return sta_fail(err, STA_ERR_FORMAT, "%s: not valid JSON", path);
    }
    return STA_OK;
}
