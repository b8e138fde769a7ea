# SPDX-License-Identifier: MIT
sta_add_test(normal_fit SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_normal_fit.c
             LIBS sta_preprocess LABELS unit)
