/* SPDX-License-Identifier: MIT
 * Extra Bytes VLR payload from .strata extra-dimension descriptors (LAS 1.4 R15 2.5). */
#include "export/export_extra.h"

#include <string.h>

#include "core/alloc.h"
#include "core/bytes.h"

#define DESCRIPTOR_SIZE 192u
#define OPTION_SCALE    (1u << 3)
#define OPTION_OFFSET   (1u << 4)

static bool is_undeclared_tail(const sta_strata_extra_dim *d)
{
    return d->data_type == 0 && strcmp(d->name, "undeclared") == 0 && d->description[0] == '\0';
}

sta_status sta_export_extra_bytes_vlr(const sta_strata_extra_dim *dims, uint32_t count,
                                      uint8_t **out_data, size_t *out_size, sta_error *err)
{
    *out_data = NULL;
    *out_size = 0;
    if (count > 0 && is_undeclared_tail(&dims[count - 1])) {
        count--;
    }
    if (count == 0) {
        return STA_OK;
    }
    uint8_t *data = sta_calloc(count, DESCRIPTOR_SIZE);
    if (!data) {
        return sta_fail(err, STA_ERR_NOMEM, "out of memory for the Extra Bytes record");
    }
    for (uint32_t i = 0; i < count; i++) {
        const sta_strata_extra_dim *d = &dims[i];
        uint8_t *p = data + (size_t)i * DESCRIPTOR_SIZE;
        p[2] = d->data_type;
        uint8_t options = 0;
        if (d->data_type == 0) {
            options = (uint8_t)(d->size_bytes <= 255 ? d->size_bytes : 0);
        } else {
            for (int k = 0; k < 3; k++) {
                options |= d->scale[k] != 1.0 ? OPTION_SCALE : 0u;
                options |= d->offset[k] != 0.0 ? OPTION_OFFSET : 0u;
            }
        }
        p[3] = options;
        memcpy(p + 4, d->name, strnlen(d->name, 32));
        for (int k = 0; k < 3; k++) {
            sta_store_f64le(p + 112 + 8 * k, d->data_type == 0 ? 0.0 : d->scale[k]);
            sta_store_f64le(p + 136 + 8 * k, d->data_type == 0 ? 0.0 : d->offset[k]);
        }
        memcpy(p + 160, d->description, strnlen(d->description, 32));
    }
    *out_data = data;
    *out_size = (size_t)count * DESCRIPTOR_SIZE;
    return STA_OK;
}
