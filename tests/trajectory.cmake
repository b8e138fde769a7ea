# SPDX-License-Identifier: MIT
sta_add_test(trajectory SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_trajectory.c
             LIBS sta_preprocess LABELS unit)
