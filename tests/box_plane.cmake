# SPDX-License-Identifier: MIT
sta_add_test(box_plane SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_box_plane.c
             LIBS sta_preprocess LABELS unit)
