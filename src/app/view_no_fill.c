/* SPDX-License-Identifier: MIT
 * --no-fill-classes: parsed with the --classes list syntax (stream/clip.h). */
#include "app/view_no_fill.h"

#include <string.h>

#include "app/view_options.h"
#include "stream/clip.h"

sta_status sta_view_parse_no_fill(const sta_cli_option *option, const char *value, sta_error *err)
{
    sta_view_args *a = option->dest;
    uint32_t set[8] = { 0 };
    if (strcmp(value, "none") != 0) {
        sta_clip parsed;
        memset(&parsed, 0, sizeof(parsed));
        if (sta_clip_parse_classes(&parsed, value, err) != STA_OK) {
            return sta_cli_fail_value(err, option, value,
                                      "class numbers 0..255 (3,4,5 or 2-5) or none");
        }
        for (unsigned c = 0; c < 256; c++) {
            if (sta_clip_keeps_class(&parsed, c)) {
                set[c / 32] |= 1u << (c % 32);
            }
        }
    }
    a->no_fill_set = true;
    memcpy(a->no_fill, set, sizeof(set));
    return STA_OK;
}
