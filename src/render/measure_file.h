/* SPDX-License-Identifier: MIT
 * Measurements to and from files: JSON (saved and loaded, the viewer's --measure
 * file) and CSV (exported for spreadsheets). No GL.
 *
 * JSON: {"strata_measurements": 1, "measurements": [{"kind": "distance", "name":
 * "...", "points": [[x, y, z], ...], "values": {...}}, ...]}. Coordinates are in the
 * scene's CRS, written as the shortest decimals that read back to the same doubles;
 * "values" are written for readers and recomputed on load.
 */
#ifndef STA_RENDER_MEASURE_FILE_H
#define STA_RENDER_MEASURE_FILE_H

#include "core/measure.h"

/* Writes `list` as JSON to `path` (through a temporary file, renamed when complete).
 * Errors: STA_ERR_IO naming the file. */
sta_status sta_measure_save_json(const char *path, const sta_measure_list *list, sta_error *err);

/* Appends the measurements of the JSON file `path` to `list`. Errors: STA_ERR_IO,
 * STA_ERR_FORMAT naming the file, the measurement and what is wrong (kind, point
 * count, a coordinate), STA_ERR_NOMEM; on error `list` is unchanged. */
sta_status sta_measure_load_json(const char *path, sta_measure_list *list, sta_error *err);

/* Writes one CSV row per measurement: name, kind, points, the values, and the
 * vertices as "x y z" separated by ';'. Errors: STA_ERR_IO. */
sta_status sta_measure_save_csv(const char *path, const sta_measure_list *list, sta_error *err);

#endif
