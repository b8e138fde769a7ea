/* SPDX-License-Identifier: MIT
 * --no-fill-classes: the LAS classes drawn as points with no surface fill.
 */
#ifndef STA_APP_VIEW_NO_FILL_H
#define STA_APP_VIEW_NO_FILL_H

#include "core/cli.h"

#define STA_VIEW_NO_FILL_HELP                                                                      \
 "classes drawn as points, not filled into a surface (shaded and fill pipelines): "                \
 "a list such as 3,4,5 or 2-5, or none"

/* Parses LIST or "none" into the sta_view_args at option->dest. */
sta_status sta_view_parse_no_fill(const sta_cli_option *option, const char *value, sta_error *err);

#endif
