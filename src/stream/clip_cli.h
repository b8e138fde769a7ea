/* SPDX-License-Identifier: MIT
 * Command-line callbacks (core/cli.h) for the selection terms of stream/clip.h, so
 * strata-export and strata-view read --box/--clip, --classes and --returns alike.
 */
#ifndef STA_STREAM_CLIP_CLI_H
#define STA_STREAM_CLIP_CLI_H

#include "core/cli.h"

/* STA_CLI_CALLBACK parsers; option->dest is a sta_clip. */
sta_status sta_clip_cli_box(const sta_cli_option *option, const char *value, sta_error *err);
sta_status sta_clip_cli_classes(const sta_cli_option *option, const char *value, sta_error *err);
sta_status sta_clip_cli_returns(const sta_cli_option *option, const char *value, sta_error *err);

/* Help texts of the three options (one definition for every program). */
#define STA_CLIP_HELP_BOX                                                                          \
 "keep points inside this box (scene CRS, inclusive): XMIN,YMIN,ZMIN,XMAX,YMAX,ZMAX"
#define STA_CLIP_HELP_CLASSES "keep only these LAS classes: a list of numbers and ranges, 2,6,9-12"
#define STA_CLIP_HELP_RETURNS                                                                      \
 "keep only these returns: a list of first, last, single and return numbers 1..15"

#endif
