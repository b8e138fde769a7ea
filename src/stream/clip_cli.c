/* SPDX-License-Identifier: MIT
 * Command-line callbacks for the clip terms. */
#include "stream/clip_cli.h"

#include "stream/clip.h"

// The clip parsers' messages do not name the option; prefix it.
static sta_status named(const sta_cli_option *option, sta_status status, sta_error *err)
{
    if (status != STA_OK && err) {
        sta_error_prefix(err, "--%s", option->name);
    }
    return status;
}

sta_status sta_clip_cli_box(const sta_cli_option *option, const char *value, sta_error *err)
{
    return named(option, sta_clip_parse_box(option->dest, value, err), err);
}

sta_status sta_clip_cli_classes(const sta_cli_option *option, const char *value, sta_error *err)
{
    return named(option, sta_clip_parse_classes(option->dest, value, err), err);
}

sta_status sta_clip_cli_returns(const sta_cli_option *option, const char *value, sta_error *err)
{
    return named(option, sta_clip_parse_returns(option->dest, value, err), err);
}
