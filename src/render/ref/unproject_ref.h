/* SPDX-License-Identifier: MIT
 * CPU twin of shaders/unproject.comp.
 */
#ifndef STA_RENDER_REF_UNPROJECT_REF_H
#define STA_RENDER_REF_UNPROJECT_REF_H

#include "render/ref/image.h"
#include "render/ref/screen_space.h"

/* depth: 1 channel of reverse-Z depth (0 = empty). out: initialised 4-channel image
 * of the same size, filled with camera-space positions (w = 1) or zeros. */
void sta_unproject_ref(const sta_view_params *view, const sta_image *depth, sta_image *out);

#endif
