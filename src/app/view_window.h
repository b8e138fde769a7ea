/* SPDX-License-Identifier: MIT
 * strata-view in a window (GLFW): camera controls, colour keys, path recording.
 */
#ifndef STA_APP_VIEW_WINDOW_H
#define STA_APP_VIEW_WINDOW_H

#include "app/view_options.h"

/* Runs the interactive viewer; returns the process exit status. */
int sta_view_run_window(const sta_view_args *args);

#endif
