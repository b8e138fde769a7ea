# SPDX-License-Identifier: MIT
# Point size (render/point_size.h): options, parsing, the footprint's figures (unit);
# strata-view's --point-size options and pictures headless (gl). The rasterisers'
# footprints against their twin are in raster.cmake.
sta_add_test(point_size SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/test_point_size.c LIBS sta_render)
find_program(PYTHON3 python3 REQUIRED)
add_test(NAME point_size.view_options
         COMMAND ${PYTHON3} ${CMAKE_CURRENT_SOURCE_DIR}/tools/check_view_point_size.py
                 ${PROJECT_BINARY_DIR})
set_tests_properties(point_size.view_options PROPERTIES LABELS gl)
