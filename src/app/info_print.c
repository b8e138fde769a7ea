/* SPDX-License-Identifier: MIT
 * Placeholder until strata-info lands. */
#include <stdio.h>
