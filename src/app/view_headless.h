/* SPDX-License-Identifier: MIT
 * strata-view --headless: render through EGL to PNG / EXR, or play a camera path.
 */
#ifndef STA_APP_VIEW_HEADLESS_H
#define STA_APP_VIEW_HEADLESS_H

#include "app/view_options.h"

/* Runs the headless viewer; returns the process exit status (0 ok, 1 failed). */
int sta_view_run_headless(const sta_view_args *args);

#endif
