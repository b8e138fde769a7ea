# SPDX-License-Identifier: MIT
# Picking and measuring: stream/pick, core/measure, render/measure_file and the
# viewer's GLFW-free measuring tools (src/app/view_tools.c, compiled in).
sta_add_test(pick SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_pick.c
             ${PROJECT_SOURCE_DIR}/src/app/view_tools.c LIBS sta_render sta_preprocess)
sta_module_root(test_pick app)
