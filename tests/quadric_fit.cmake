# SPDX-License-Identifier: MIT
sta_add_test(quadric_fit SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_quadric_fit.c
             LIBS sta_preprocess LABELS unit)
