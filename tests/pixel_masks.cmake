# SPDX-License-Identifier: MIT
# strata-bench's scored pixels and points (the volumetric leave-out, the face rule, the
# HPR rules) on hand-made views (unit).
sta_add_test(pixel_masks SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_pixel_masks.c
             LIBS sta_bench ${M_LIBRARY} LABELS unit)
