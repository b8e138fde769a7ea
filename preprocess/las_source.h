/* SPDX-License-Identifier: MIT
 * What the converter keeps of a LAS input besides its points: header fields and the
 * coordinate-reference-system records (format/strata.h's LAS source block).
 */
#ifndef STA_PREPROCESS_LAS_SOURCE_H
#define STA_PREPROCESS_LAS_SOURCE_H

#include <stdbool.h>

#include "format/strata.h"
#include "inputs.h"

/* The source block's contents and the memory behind them. Zero-initialise. */
typedef struct sta_las_source_keep {
    bool present;                   /* the first input is LAS */
    sta_strata_las_source source;   /* records point into `records` / `data` */
    sta_strata_las_record *records; /* owned */
    uint8_t *data;                  /* owned: all record payloads */
} sta_las_source_keep;

/* Collects the first input's LAS header fields and its LASF_Projection VLRs and
 * EVLRs (GeoTIFF keys, WKT), read from the file. Inputs that are not LAS give
 * present == false. Other VLRs are not kept (see docs/EXPORT.md). Errors:
 * STA_ERR_IO naming the file, STA_ERR_NOMEM. */
sta_status sta_las_source_collect(const sta_input_set *inputs, sta_las_source_keep *out,
                                  sta_error *err);

/* Frees what collect allocated; a zeroed struct is a no-op. */
void sta_las_source_release(sta_las_source_keep *keep);

#endif
