/* SPDX-License-Identifier: MIT
 * Which axis of the inputs points up, for the output header's up_axis
 * (docs/CONVERTER.md, "Up axis").
 */
#ifndef STA_PREPROCESS_UP_AXIS_H
#define STA_PREPROCESS_UP_AXIS_H

#include <stddef.h>

#include "inputs.h"

/* STA_STRATA_UP_Z or STA_STRATA_UP_Y, and in `why` (may be NULL) one line saying how
 * it was decided. LAS inputs are +Z (the format's convention); a set of PLY inputs
 * only is +Y (the convention of scanned models such as the Stanford ones) unless its
 * bounds say +Z: z the largest extent (a z-up figure) or flat in z (map-like data);
 * the rule is io/model_up.h's, which the synth's mesh scene shares. */
int sta_inputs_up_axis(const sta_input_set *set, char *why, size_t why_size);

#endif
