# SPDX-License-Identifier: MIT
sta_add_test(format SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_format.c LIBS sta_format)
