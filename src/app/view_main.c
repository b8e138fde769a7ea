/* SPDX-License-Identifier: MIT
 * strata-view: streaming LOD viewer (window through GLFW, or headless through EGL).
 */
#include <stdio.h>

#include "app/view_headless.h"
#include "app/view_options.h"
#include "app/view_window.h"

int main(int argc, char **argv)
{
    sta_view_args args;
    int parsed = sta_view_parse_args(argc, argv, &args);
    if (parsed != 0) {
        return parsed < 0 ? 0 : parsed;
    }
    if (args.headless) {
        return sta_view_run_headless(&args);
    }
    return sta_view_run_window(&args);
}
