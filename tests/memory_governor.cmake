# SPDX-License-Identifier: MIT
sta_add_test(memory_governor SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_memory_governor.c LIBS sta_preprocess)
