# SPDX-License-Identifier: MIT
# strata-bench's truth and metrics (unit) and one end-to-end sweep on a synthetic sphere,
# rendered headless through EGL on Mesa llvmpipe (gl).
sta_add_test(bench SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_bench.c
             LIBS sta_bench sta_preprocess ${M_LIBRARY} LABELS unit)
set_tests_properties(bench.core_end_to_end_sphere bench.live_katz_method_sphere
                     bench.point_sizes_sphere bench.katz_on_drawn_points_sphere
                     bench.default_gaps_follow_the_points_street
                     PROPERTIES LABELS gl)
