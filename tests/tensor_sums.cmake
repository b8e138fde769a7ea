# SPDX-License-Identifier: MIT
sta_add_test(tensor_sums SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_tensor_sums.c
             LIBS sta_preprocess LABELS unit)
