# SPDX-License-Identifier: MIT
# The command-line option tables of every program (src/core/cli).
sta_add_test(cli SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_cli.c LIBS sta_core)
