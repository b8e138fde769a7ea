/* SPDX-License-Identifier: MIT
 * A small test scene for GL tests: a sphere (radius 5 m at (0, 10, 0)) in front of a
 * wall (y = 20, 30 m x 20 m), points on a 2^-10 m lattice so coordinates are exact in
 * double at any offset, colour encoding each point's index; written as binary PLY and
 * converted to .strata. Also the headless GL context every GL test runs in.
 */
#ifndef STA_TEST_SCENE_FIXTURE_H
#define STA_TEST_SCENE_FIXTURE_H

#include <stddef.h>

#include "core/camera.h"
#include "render/scene.h"

/* Builds `<tmpdir>/<name>.strata` from `points` points placed at `offset`; the path
 * goes to out_path. Fails the test on error. */
void sta_fixture_build_scene(const char *name, size_t points, const double offset[3],
                             char *out_path, size_t size);

/* A camera 12 m in front of the sphere (plus `offset`), looking at it. */
sta_camera sta_fixture_camera(const double offset[3], int width_px, int height_px);

/* Renders `camera` into `target` frame after frame until the view is complete (every
 * wanted node resident or refused, and in the live Katz mode its set current); returns
 * the last frame's stats. Fails the test on an error or after 5000 frames. */
sta_frame_stats sta_fixture_render_complete(sta_scene *scene, const sta_camera *camera,
                                            sta_render_target *target);

/* cmocka group setup and teardown for GL tests: a headless EGL context (llvmpipe)
 * made current for the group's cases, and destroyed after. */
int sta_fixture_gl_setup(void **state);
int sta_fixture_gl_teardown(void **state);

#endif
