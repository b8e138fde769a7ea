# SPDX-License-Identifier: MIT
sta_add_test(export SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_export.c LIBS sta_export sta_preprocess)
