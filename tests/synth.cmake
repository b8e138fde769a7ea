# SPDX-License-Identifier: MIT
sta_add_test(synth SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_synth.c LIBS sta_synth)
