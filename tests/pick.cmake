# SPDX-License-Identifier: MIT
sta_add_test(pick SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_pick.c LIBS sta_render sta_preprocess)
