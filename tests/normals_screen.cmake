# SPDX-License-Identifier: MIT
sta_add_test(normals_screen SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_normals_screen.c
             LIBS sta_render ${M_LIBRARY} LABELS gl)
