/* SPDX-License-Identifier: MIT
 * The LAS Extra Bytes record (LASF_Spec/4) rebuilt from a scene's extra dimensions.
 */
#ifndef STA_EXPORT_EXPORT_EXTRA_H
#define STA_EXPORT_EXPORT_EXTRA_H

#include <stddef.h>
#include <stdint.h>

#include "core/status.h"
#include "format/strata.h"

/* Builds the Extra Bytes VLR payload (192 bytes per declared dimension) for `count`
 * dimensions. A trailing dimension named "undeclared" of type 0 (what the LAS reader
 * calls bytes no descriptor covers) is left undeclared again. Type 0 dimensions get
 * their size in the options byte; scale and offset set options bits 3 and 4 when
 * they differ from 1 and 0. No-data, minimum and maximum are not kept by .strata and
 * are written as zero. On success *out_data (*out_size bytes, possibly 0 and NULL)
 * is owned by the caller (sta_free). Errors: STA_ERR_NOMEM. */
sta_status sta_export_extra_bytes_vlr(const sta_strata_extra_dim *dims, uint32_t count,
                                      uint8_t **out_data, size_t *out_size, sta_error *err);

#endif
