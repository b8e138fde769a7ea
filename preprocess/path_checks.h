/* SPDX-License-Identifier: MIT
 * The converter's checks of its own paths before any work: the output is not a
 * folder, not one of the inputs (by any name), not overwritten without --force, and
 * no input is given twice.
 */
#ifndef STA_PREPROCESS_PATH_CHECKS_H
#define STA_PREPROCESS_PATH_CHECKS_H

#include <stdbool.h>
#include <stddef.h>

#include "core/status.h"

/* Checks `output` against `inputs` (the same file is found by device and inode, so
 * links and other spellings count). Errors (STA_ERR_ARG, naming the paths): the
 * output is a folder; the output is an input, even with `force`; the output exists
 * and `force` is false; one file is given twice. Inputs that cannot be stat'ed are
 * left to the readers, which name them. */
sta_status sta_path_checks_run(const char *const *inputs, size_t input_count, const char *output,
                               bool force, sta_error *err);

#endif
