# SPDX-License-Identifier: MIT
# The live Katz mode's screen cells (visibility/katz_cells.h) and their use by the worker.
sta_add_test(katz_cells SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_katz_cells.c
             LIBS sta_visibility LABELS unit)
