# SPDX-License-Identifier: MIT
sta_add_test(las_write SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_las_write.c LIBS sta_io)
