/* SPDX-License-Identifier: MIT
 * Reading a small JSON file (camera paths, measurements) through cJSON.
 */
#ifndef STA_RENDER_JSON_FILE_H
#define STA_RENDER_JSON_FILE_H

#include <cjson/cJSON.h>

#include "core/status.h"

/* Parses the JSON file at `path`; *out_root is freed by the caller with cJSON_Delete.
 * Errors: those of opening the file, STA_ERR_FORMAT "<path>: not valid JSON". */
sta_status sta_json_file_load(const char *path, cJSON **out_root, sta_error *err);

#endif
