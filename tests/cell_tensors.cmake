# SPDX-License-Identifier: MIT
sta_add_test(cell_tensors SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_cell_tensors.c
             LIBS sta_preprocess LABELS unit)
