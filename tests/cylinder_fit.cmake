# SPDX-License-Identifier: MIT
sta_add_test(cylinder_fit SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_cylinder_fit.c
             LIBS sta_preprocess LABELS unit)
