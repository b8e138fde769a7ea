# SPDX-License-Identifier: MIT
sta_add_test(clip SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_clip.c LIBS sta_stream sta_preprocess)
