# SPDX-License-Identifier: MIT
sta_add_test(sphere_fit SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_sphere_fit.c
             LIBS sta_preprocess LABELS unit)
